//! The library from Rust: load a scene file, change it from code, grow its field and render a
//! still with sward-gpu's headless renderer — what `sward render` does, in a page.
//!
//! `cargo run --release -p sward-gpu --example scene -- [SCENE.toml] [OUT.png]`
//! (default: the shipped meadow, written to `scene-example.png`).

use std::path::PathBuf;

use sward_core::wind::WindKind;
use sward_core::Scene;
use sward_gpu::{Context, ContextDesc, Headless};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let shipped = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes/meadow.toml");
    let path = args.next().map_or(shipped, PathBuf::from);
    let out = args.next().unwrap_or_else(|| "scene-example.png".into());

    // A scene file, then changed from code: fewer blades, a gusty wind, the camera lower.
    let mut scene = Scene::load(&path)?;
    scene.field.blades = 20_000;
    scene.wind[0].kind = WindKind::Noise;
    scene.wind[0].strength *= 2.0;
    scene.camera.position.y *= 0.7;
    scene.validate("the example's changes")?;

    // The GPU: sward picks the best device; the renderer draws into an offscreen target.
    let ctx = Context::new(&ContextDesc::default())?;
    let (width, height) = (960, 540);
    let mut headless = Headless::new(&ctx, width, height, None)?;
    let field = scene.grow_field()?;
    headless.renderer.upload(&field)?;
    headless.renderer.upload_ground(field.ground.as_ref())?;

    // Two seconds of simulation at the scene's fixed step, then one frame, read back as RGBA8.
    let steps = (2.0 / scene.simulation.step).round() as u32;
    let pixels = headless.render_scene(&scene, field.size, steps)?;
    let image = image::RgbaImage::from_raw(width, height, pixels).ok_or("the frame has the wrong size")?;
    image.save(&out)?;
    println!("wrote {out}: {} blades on {}", field.blades.len(), ctx.info.name);
    Ok(())
}
