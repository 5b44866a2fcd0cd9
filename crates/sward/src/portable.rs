//! `sward render --renderer wgpu`: a still drawn by the portable renderer (sward-wgpu's
//! `portable`, WGSL through wgpu's safe API) on the wgpu backend asked for, and what it cannot
//! draw (an animation) refused in one sentence that says what it can.

use anyhow::{bail, Context as _};
use sward_wgpu::portable::{open_device_with, portable_limits, PortableHeadless, ShaderModules};

use crate::args::{GpuArgs, RenderArgs};

/// Render `args`'s scene with the portable renderer; `note`, where auto chose it, says why.
pub fn render(args: &RenderArgs, gpu: &GpuArgs, note: Option<String>) -> anyhow::Result<()> {
    if args.animation.is_some() {
        bail!("the portable renderer (--renderer wgpu) writes stills; --animation is drawn by the Vulkan renderer (--renderer vulkan)");
    }
    let scene = args.scene.load()?;
    if let Some(note) = note {
        eprintln!("sward: {note}");
    }
    let ask = |adapter: &sward_wgpu::wgpu::Adapter| (gpu.portable_features(adapter), portable_limits(adapter));
    let device = open_device_with(args.renderer.wgpu_backends(), gpu.validation, ask)?;
    let modules = shader_modules(args.shaders.as_deref())?;
    let modules = gpu.splat_modules(modules)?;
    let samples = scene.quality.preset.msaa_samples();
    let mut headless = PortableHeadless::made_of(device, [args.width, args.height], samples, modules)?;
    let field = scene.grow_field()?;
    headless.upload(&field)?;
    if let Some(beyond) = sward_wgpu::portable::beyond_webgpu_defaults(field.blades.len()) {
        eprintln!("sward: {beyond}");
    }
    // A camera path above the ground starts on the ground under its first point, as with the
    // Vulkan renderer.
    let grid = field.ground.as_ref().and_then(|m| m.height_grid());
    let scene = crate::animation::travelled(&scene, 0.0, grid.as_ref());
    let pixels = headless.render_scene(&scene, field.size, args.steps)?;
    let messages = crate::logging::take_backend_messages();
    if gpu.validation && !messages.is_empty() {
        bail!(
            "wgpu's {:?} backend reported {} problem(s) with validation on, the first: {}",
            headless.adapter.get_info().backend,
            messages.len(),
            messages[0]
        );
    }
    let out = args.out_path();
    image::RgbaImage::from_raw(args.width, args.height, pixels)
        .context("the read-back image has the wrong size")?
        .save(&out)
        .with_context(|| format!("cannot write {}", out.display()))?;
    let info = headless.adapter.get_info();
    println!(
        "wrote {} ({}×{}, {}, {} steps, quality {}, portable renderer on wgpu {:?}, {} with {} {})",
        out.display(),
        args.width,
        args.height,
        crate::render::describe(scene.technique, field.blades.len()),
        args.steps,
        scene.quality.preset.name(),
        info.backend,
        info.name,
        info.driver,
        info.driver_info
    );
    Ok(())
}

/// The core's WESL modules the portable renderer's pipelines are made of: the built-in ones,
/// with those the folder `--shaders` names holds in place of theirs (its GLSL is the Vulkan
/// renderer's alone).
pub fn shader_modules(dir: Option<&std::path::Path>) -> anyhow::Result<ShaderModules> {
    match dir {
        None => Ok(ShaderModules::built_in()),
        Some(dir) => ShaderModules::from_dir(dir).map_err(|e| anyhow::anyhow!("--shaders: {e}")),
    }
}
