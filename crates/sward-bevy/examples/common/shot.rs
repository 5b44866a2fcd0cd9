//! The examples' headless pictures: a camera drawing into an image of a given size, read back
//! and written to a PNG.

use std::error::Error;
use std::sync::{Arc, Mutex};

use bevy::asset::RenderAssetUsages;
use bevy::prelude::*;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::window::ExitCondition;
use bevy::winit::WinitPlugin;

/// Bevy's default plugins without a window, on a Vulkan device opened for sward, or
/// (`bevy_device`) on the device Bevy opens itself.
pub fn headless_plugins(bevy_device: bool) -> Result<bevy::app::PluginGroupBuilder, Box<dyn Error>> {
    let plugins = match bevy_device {
        // The device Bevy opens itself: sward's portable passes.
        true => DefaultPlugins.build(),
        #[cfg(feature = "vulkan")]
        false => DefaultPlugins.set(sward_bevy::render_plugin()?),
        #[cfg(not(feature = "vulkan"))]
        false => return Err("sward's Vulkan device needs sward-bevy's `vulkan` feature".into()),
    };
    Ok(plugins
        .set(WindowPlugin {
            primary_window: None,
            exit_condition: ExitCondition::DontExit,
            ..default()
        })
        .disable::<WinitPlugin>())
}

/// An sRGB image of `size` to render into, readable back.
pub fn target_image(images: &mut Assets<Image>, size: [u32; 2]) -> Handle<Image> {
    let mut image = Image::new_target_texture(size[0], size[1], TextureFormat::Rgba8UnormSrgb, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    image.asset_usage = RenderAssetUsages::RENDER_WORLD;
    images.add(image)
}

/// Read `target` (an image of `size`) back after the frames the app has drawn, and write it
/// to `out`.
pub fn shoot(app: &mut App, target: Handle<Image>, size: [u32; 2], out: &str) -> Result<(), Box<dyn Error>> {
    let shot = Arc::new(Mutex::new(Vec::new()));
    let sink = shot.clone();
    let readback = app
        .world_mut()
        .spawn(Readback::texture(target))
        .observe(move |event: On<ReadbackComplete>| *sink.lock().unwrap() = event.data.clone())
        .id();
    // Frames for the read-back to come (more where the GPU is behind).
    for _ in 0..600 {
        app.update();
        if !shot.lock().unwrap().is_empty() {
            break;
        }
    }
    // No read-back left waiting when the app goes.
    app.world_mut().despawn(readback);
    app.update();
    let bytes = unpadded(&shot.lock().unwrap(), size);
    let image = image::RgbaImage::from_raw(size[0], size[1], bytes).ok_or("no frame was read back")?;
    image.save(out)?;
    println!("wrote {out}");
    Ok(())
}

/// The read-back's rows without the padding that rounds each up to 256 bytes (wgpu's copy
/// alignment), where the width needs it.
fn unpadded(bytes: &[u8], [width, height]: [u32; 2]) -> Vec<u8> {
    let row = width as usize * 4;
    let padded = bytes.len() / (height as usize).max(1);
    if padded <= row {
        return bytes.to_vec();
    }
    bytes
        .chunks(padded)
        .flat_map(|r| &r[..row.min(r.len())])
        .copied()
        .collect()
}
