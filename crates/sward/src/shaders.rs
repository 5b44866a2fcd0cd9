//! `sward shaders`: the portable renderer's WGSL written out, a file per pipeline, as a browser's
//! WebGPU compiles it (`enable subgroups;` first where a pipeline uses them) — so a WGSL tool (a
//! browser's compiler, Tint) can check what sward ships.

use std::path::Path;

use anyhow::Context as _;
use sward_wgpu::portable::PIPELINES;

/// Write each portable pipeline's whole WGSL to `out/<pipeline>.wgsl`, and say what was written.
pub fn write_wgsl(out: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot make the folder {} for the shaders", out.display()))?;
    for pipeline in PIPELINES {
        let path = out.join(format!("{}.wgsl", pipeline.name));
        let entries = match pipeline.fragment {
            Some(fragment) => format!("entry points `{}` and `{fragment}`", pipeline.entry),
            None => format!("entry point `{}`", pipeline.entry),
        };
        let text = format!(
            "// sward's portable {} pipeline ({entries}): its modules composed, as a browser compiles it.\n{}",
            pipeline.name,
            pipeline.browser_text()?
        );
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))?;
    }
    println!(
        "wrote the WGSL of {} portable pipelines to {}",
        PIPELINES.len(),
        out.display()
    );
    Ok(())
}
