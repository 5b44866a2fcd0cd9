//! Shared by the GPU tests: a validated context (or a failure that says what to install), a
//! check that the validation layer stayed silent, a compute renderer, a copy of the shaders
//! (compiled at run time, or changed first), and random test material.
#![allow(dead_code)]

use std::sync::Arc;

use sward_core::Blade;
use sward_gpu::{Context, ContextDesc, Validation, Withheld};

pub mod parity_cases;
pub mod seams;
#[allow(unused_imports)]
pub use parity_cases::{random_blades, unit};

/// An offscreen renderer for compute tests: one frame in flight, `patches_per_draw` patches per
/// draw command (0: one command), simulate and cull `fused` or not.
pub fn renderer(ctx: &Arc<Context>, patches_per_draw: u32, fused: bool) -> sward_gpu::Renderer {
    let desc = sward_gpu::RendererDesc {
        target: sward_gpu::headless::HEADLESS_FORMAT,
        frames_in_flight: 1,
        patches_per_draw: Some(patches_per_draw),
        compute: Default::default(),
        fused,
        shadow_map_size: sward_gpu::passes::shadows::SHADOW_SIZE,
    };
    sward_gpu::Renderer::new(ctx, &desc).expect("renderer")
}

/// A context with the Khronos validation layer on. No device is a failure, never a skip.
pub fn context() -> Arc<Context> {
    context_without(Withheld::default())
}

/// `context()` as if the device lacked the optional features `withheld` names.
pub fn context_without(withheld: Withheld) -> Arc<Context> {
    let desc = ContextDesc {
        validation: Validation::Required,
        gpu: std::env::var("SWARD_GPU").ok(),
        display: None,
        withheld,
        ..ContextDesc::default()
    };
    Context::new(&desc).unwrap_or_else(|e| {
        panic!(
            "this test needs a Vulkan device and the Khronos validation layer, and could not get them: {e}. \
             On Debian/Ubuntu: apt-get install libvulkan1 mesa-vulkan-drivers vulkan-validationlayers"
        )
    })
}

/// `scene` grown, simulated `steps` steps and drawn at `width`×`height` (4× MSAA), the Bezier
/// blades by `route`, with `patches_per_draw` patches per tessellated command (`None`: per
/// driver); fails on any validation message.
pub fn render_by_route(
    scene: &sward_core::Scene,
    [width, height]: [u32; 2],
    steps: u32,
    patches_per_draw: Option<u32>,
    route: sward_gpu::DrawRoute,
) -> Vec<u8> {
    let ctx = context();
    let field = scene.grow_field().unwrap();
    let mut headless = sward_gpu::Headless::new(&ctx, width, height, patches_per_draw).unwrap();
    let mut scene = scene.clone();
    scene.quality.route = route;
    let note = headless.renderer.set_route(route);
    assert!(note.is_none(), "the route exists on this device: {note:?}");
    assert_eq!(
        headless.renderer.route(),
        route,
        "the route asked for is the route drawn"
    );
    headless.renderer.upload(&field).unwrap();
    headless.renderer.upload_ground(field.ground.as_ref()).unwrap();
    let pixels = headless.render_scene(&scene, field.size, steps).unwrap();
    drop(headless);
    assert_validation_clean(&ctx);
    pixels
}

/// The frame of `scene` with only `blade`, drawn at `width`×`height` by the tessellation route
/// without simulating, over a field 400 units wide (so the ground in sight is the field's);
/// fails on any validation message.
pub fn render_one_blade(scene: &sward_core::Scene, blade: Blade, [width, height]: [u32; 2]) -> Vec<u8> {
    let ctx = context();
    let mut headless = sward_gpu::Headless::new(&ctx, width, height, None).unwrap();
    let mut scene = scene.clone();
    scene.quality.route = sward_gpu::DrawRoute::Tessellation;
    headless.renderer.upload_field(&[blade], &[]).unwrap();
    let pixels = headless.render_scene(&scene, glam::Vec2::splat(400.0), 0).unwrap();
    drop(headless);
    assert_validation_clean(&ctx);
    pixels
}

/// The shipped shaders, copied to the tests' folder `name` (to compile at run time, as the
/// viewer's hot reload does, or to change before compiling).
pub fn copy_of_shaders(name: &str) -> std::path::PathBuf {
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let dst = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    // Afresh: the folder outlives the run, and a module an earlier checkout's test patched into
    // it would stand in for the built-in one (a shader folder's WESL modules replace them).
    let _ = std::fs::remove_dir_all(&dst);
    std::fs::create_dir_all(&dst).unwrap();
    for entry in std::fs::read_dir(src).unwrap().flatten() {
        std::fs::copy(entry.path(), dst.join(entry.file_name())).unwrap();
    }
    dst
}

/// Fail on any validation message reported so far.
pub fn assert_validation_clean(ctx: &Context) {
    assert!(ctx.validating(), "the validation layer is not active");
    let messages = ctx.take_validation_messages();
    assert!(
        messages.is_empty(),
        "{} validation message(s):\n{}",
        messages.len(),
        messages.join("\n")
    );
}

/// Save RGBA image `image` of `size` as `name` under the tests' scratch `render-tests` folder,
/// for a person to look at.
pub fn save_rgba(name: &str, [width, height]: [u32; 2], image: &[u8]) {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("render-tests");
    std::fs::create_dir_all(&dir).unwrap();
    image::RgbaImage::from_raw(width, height, image.to_vec())
        .unwrap()
        .save(dir.join(name))
        .unwrap();
}
