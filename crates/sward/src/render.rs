//! `sward render` and `sward info`: headless frames to PNG files (a still, or an animation by
//! `animation.rs`).

use anyhow::{bail, Context as _};
use sward_core::instanced::Technique;
use sward_core::quality::DrawRoute;
use sward_gpu::target::OFFSCREEN_FORMAT;
use sward_gpu::{Context, Headless, RendererDesc};
use sward_wgpu::wgpu;

use crate::animation::{self, Capture};
use crate::args::{GpuArgs, RenderArgs, RendererArg};

pub fn render(args: &RenderArgs, gpu: &GpuArgs) -> anyhow::Result<()> {
    if let Some(n) = &args.frames {
        bail!("render counts the simulation steps before its frame with --steps {n}; --frames is the number of frames `view` and `bench` draw");
    }
    // A wgpu backend asked for picks the portable renderer, whichever `--renderer auto` finds.
    let portable_asked = args.renderer.wgpu_backend.is_some();
    match args.renderer.renderer {
        RendererArg::Wgpu => crate::portable::render(args, gpu, None),
        RendererArg::Auto if portable_asked => crate::portable::render(args, gpu, None),
        RendererArg::Vulkan => {
            gpu.check_splat_cells(false)?;
            render_vulkan(args, Context::new(&gpu.context_desc())?)
        }
        RendererArg::Auto => match Context::new(&gpu.context_desc()) {
            Ok(ctx) => {
                gpu.check_splat_cells(false)?;
                render_vulkan(args, ctx)
            }
            Err(e) => {
                let note =
                    format!("no Vulkan device sward can use ({e}); drawing with the portable renderer on wgpu instead");
                crate::portable::render(args, gpu, Some(note))
            }
        },
    }
}

/// Render `args`'s scene with sward's Vulkan renderer on `ctx`.
fn render_vulkan(args: &RenderArgs, ctx: std::sync::Arc<Context>) -> anyhow::Result<()> {
    let scene = args.scene.load()?;
    let quality = scene.quality.preset;
    let desc = RendererDesc {
        patches_per_draw: args.patches_per_draw,
        ..RendererDesc::for_quality(&ctx.info, OFFSCREEN_FORMAT, quality, 1)
    };
    let mut headless = Headless::with_desc(&ctx, args.width, args.height, &desc)?;
    if let Some(shaders) = &args.shaders {
        crate::bench::use_shaders_from(&mut headless, shaders)?;
    }
    // The frames ask for the scene's route; a route this device lacks is said once, here.
    if let Some(note) = headless.renderer.set_route(scene.quality.route) {
        eprintln!("sward: {note}");
    }
    // After the image: the field gets what memory the image leaves.
    sward_gpu::renderer::check_field_fits(&ctx, scene.bezier_blades() as u64)?;
    let field = scene.grow_field()?;
    log::info!(
        "rendering {} ({} blades) at {}×{} on {}",
        scene.name,
        field.blades.len(),
        args.width,
        args.height,
        ctx.info.name
    );
    headless.renderer.upload(&field)?;
    headless.renderer.upload_ground(field.ground.as_ref())?;
    // A camera path above the ground starts on the ground under its first point.
    let grid = field.ground.as_ref().and_then(|m| m.height_grid());
    let scene = animation::travelled(&scene, 0.0, grid.as_ref());
    let out = args.out_path();
    let what = match args.animation {
        Some(frames) => {
            let capture = Capture {
                out: &out,
                frames,
                fps: args.fps,
                warmup: args.steps,
                orbit: args.orbit,
                sequence: args.sequence,
                ground: grid.as_ref(),
            };
            animation::capture(&mut headless, &scene, field.size, &capture)?;
            format!("{frames} frames at {} fps after {} steps", args.fps, args.steps)
        }
        None => {
            let pixels = headless.render_scene(&scene, field.size, args.steps)?;
            let image = image::RgbaImage::from_raw(args.width, args.height, pixels)
                .context("the read-back image has the wrong size")?;
            image
                .save(&out)
                .with_context(|| format!("cannot write {}", out.display()))?;
            format!("{} steps", args.steps)
        }
    };
    check_validation(&ctx)?;
    let blades = describe(scene.technique, field.blades.len());
    println!(
        "wrote {} ({}×{}, {blades}, {what}, quality {}, {} route, {} with {} {})",
        out.display(),
        args.width,
        args.height,
        quality.name(),
        headless.renderer.route().name(),
        ctx.info.name,
        ctx.info.driver_name,
        ctx.info.driver_info
    );
    Ok(())
}

/// With `--validation`, any validation message is a failure.
pub fn check_validation(ctx: &Context) -> anyhow::Result<()> {
    let messages = ctx.take_validation_messages();
    if ctx.validating() && !messages.is_empty() {
        bail!(
            "the Vulkan validation layer reported {} problem(s), the first: {}",
            messages.len(),
            messages[0]
        );
    }
    Ok(())
}

pub fn info(gpu: &GpuArgs) -> anyhow::Result<()> {
    let ctx = Context::new(&gpu.context_desc())?;
    let i = &ctx.info;
    println!("device: {} ({:?})", i.name, i.kind);
    println!("driver: {} {} ({:?})", i.driver_name, i.driver_info, i.driver_id);
    println!("vulkan: {}", i.api_version);
    println!(
        "subgroup ballot in compute: {}, wireframe: {}",
        i.subgroup_ballot, i.wireframe
    );
    println!(
        "mesh shaders (mesh route): {}, 64-bit atomics (compute route, splats): {}",
        i.mesh_shaders, i.int64_atomics
    );
    println!("GPU memory sward may use: {} MiB", ctx.memory.limit() >> 20);
    println!();
    print_devices(&sward_gpu::list_devices()?);
    println!();
    println!("wgpu adapters (--renderer wgpu --wgpu-backend vulkan|gl|metal|dx12):");
    for backend in [
        wgpu::Backends::VULKAN,
        wgpu::Backends::METAL,
        wgpu::Backends::DX12,
        wgpu::Backends::GL,
    ] {
        if let Some(said) = sward_wgpu::portable::describe_adapter(backend) {
            println!("{said}");
        }
    }
    Ok(())
}

/// Every Vulkan device with the index `--gpu` takes, its driver, and the draw routes it allows
/// (or what it lacks).
fn print_devices(devices: &[(sward_gpu::DeviceCandidate, sward_gpu::DeviceInfo)]) {
    println!("Vulkan devices (--gpu INDEX or a part of the name picks one):");
    for (device, info) in devices {
        let what = match device.missing.is_empty() {
            true => format!("draw routes: {}", allowed_routes(info).join(", ")),
            false => format!("not usable: lacks {}", device.missing.join(", ")),
        };
        println!(
            "  {}: {} ({:?}), driver {} {}; {what}",
            device.index, info.name, info.kind, info.driver_name, info.driver_info
        );
    }
}

/// The draw routes of the Bezier blades `info`'s device draws by itself.
fn allowed_routes(info: &sward_gpu::DeviceInfo) -> Vec<&'static str> {
    DrawRoute::ALL
        .into_iter()
        .filter(|&route| route != DrawRoute::Auto)
        .filter(|&route| sward_gpu::passes::routes::resolve(route, info, false).1.is_none())
        .map(|route| route.name())
        .collect()
}

/// What a frame of `technique` shows, for the one-line report.
pub(crate) fn describe(technique: Technique, blades: usize) -> String {
    let mut parts = Vec::new();
    if technique.draws_bezier() {
        parts.push(format!("{blades} blades"));
    }
    if technique.draws_instanced() {
        parts.push("the instanced grass".to_string());
    }
    if technique.draws_billboards() {
        parts.push("billboards".to_string());
    }
    parts.join(" and ")
}
