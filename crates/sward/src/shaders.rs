//! `sward shaders`: the portable renderer's WGSL written out, a file per pipeline, as a browser's
//! WebGPU compiles it (`enable subgroups;` first where a pipeline uses them) — so a WGSL tool (a
//! browser's compiler, Tint) can check what sward ships.

use std::path::Path;

use anyhow::Context as _;
use sward_core::wgsl::splatting::PORTABLE_SPLATTING;
use sward_wgpu::portable::{PipelineSource, ShaderModules, PIPELINES};

/// Write each portable pipeline's whole WGSL to `out/<pipeline>.wgsl`, and the splatting
/// passes in 32-bit cells (as a browser's device splats: bound once a pass) to
/// `out/narrow/<pipeline>.wgsl`, and say what was written.
pub fn write_wgsl(out: &Path) -> anyhow::Result<()> {
    let narrow = out.join("narrow");
    std::fs::create_dir_all(&narrow)
        .with_context(|| format!("cannot make the folder {} for the shaders", narrow.display()))?;
    for pipeline in PIPELINES {
        write_pipeline(out, pipeline, &ShaderModules::built_in())?;
    }
    let browser_narrow = ShaderModules::built_in()
        .with_narrow_splats(true)
        .with_single_splat_binding(true);
    for pipeline in &PORTABLE_SPLATTING {
        write_pipeline(&narrow, pipeline, &browser_narrow)?;
    }
    println!(
        "wrote the WGSL of {} portable pipelines to {}, and of {} splatting pipelines in 32-bit cells to {}",
        PIPELINES.len(),
        out.display(),
        PORTABLE_SPLATTING.len(),
        narrow.display()
    );
    Ok(())
}

/// Write `pipeline`'s WGSL composed of `modules` to `dir/<pipeline>.wgsl`.
fn write_pipeline(dir: &Path, pipeline: &PipelineSource, modules: &ShaderModules) -> anyhow::Result<()> {
    let path = dir.join(format!("{}.wgsl", pipeline.name));
    let entries = match pipeline.fragment {
        Some(fragment) => format!("entry points `{}` and `{fragment}`", pipeline.entry),
        None => format!("entry point `{}`", pipeline.entry),
    };
    let text = format!(
        "// sward's portable {} pipeline ({entries}): its modules composed, as a browser compiles it.\n{}",
        pipeline.name,
        modules.browser_text(pipeline)?
    );
    std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))
}
