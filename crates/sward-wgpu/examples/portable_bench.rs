//! The portable renderer timed on a GPU: a scene's Bezier field simulated (one fixed step a
//! frame), culled into its distance buckets and drawn as strips at 1920×1080 with the samples
//! of the scene's quality, through wgpu's safe API, with wgpu's timestamps around each pass, as
//! `sward bench` times the Vulkan renderer's — once with the scene's culling tests and once
//! with none. Prints the median and 99th percentile of each pass and of the whole frame.
//!
//! `cargo run --release -p sward-wgpu --example portable_bench -- SCENE.toml BLADES [FRAMES]`
//!
//! The device is wgpu's Vulkan one with the adapter's own limits (a field of millions of
//! blades needs more than WebGPU's default 128 MiB binding).

use std::error::Error;

use glam::Vec2;
use sward_core::{FrameDesc, Scene};
use sward_wgpu::portable::{PortableHeadless, PortablePasses};

/// Frames run before the timed ones.
const WARM_UP: usize = 30;
/// The frame's size, as `sward bench`'s.
const SIZE: [u32; 2] = [1920, 1080];
/// What the timestamps bracket: simulate, cull, draw.
const PASSES: usize = 3;

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(path), Some(blades)) = (args.first(), args.get(1)) else {
        return Err("usage: portable_bench SCENE.toml BLADES [FRAMES]".into());
    };
    let frames: usize = args.get(2).map_or(Ok(200), |f| f.parse())?;
    let scene = Scene::load(std::path::Path::new(path))?.with_overrides(&[("field.blades".into(), blades.clone())])?;
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::VULKAN,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        ..Default::default()
    }))?;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("portable bench"),
        required_features: wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS,
        required_limits: adapter.limits(),
        ..Default::default()
    }))?;
    let info = adapter.get_info();
    println!(
        "{} ({:?}, driver {} {}), {}×{}, quality {}",
        info.name,
        info.backend,
        info.driver,
        info.driver_info,
        SIZE[0],
        SIZE[1],
        scene.quality.preset.name()
    );
    let samples = scene.quality.preset.msaa_samples();
    let mut headless = PortableHeadless::new((adapter, device, queue), SIZE, samples)?;
    let field = scene.grow_field()?;
    headless.upload(&field)?;
    let mut unculled = scene.clone();
    unculled.cull.orientation = false;
    unculled.cull.frustum = false;
    unculled.cull.distance = false;
    for (label, scene) in [("the scene's culling", &scene), ("no culling", &unculled)] {
        let [simulate, cull, draw, frame] = time_frames(&mut headless, scene, field.size, frames)?;
        println!(
            "{} blades, {label}: simulate {:.3} ms (p99 {:.3}), cull {:.3} ({:.3}), draw {:.3} ({:.3}), frame {:.3} ({:.3})",
            field.blades.len(),
            simulate.0,
            simulate.1,
            cull.0,
            cull.1,
            draw.0,
            draw.1,
            frame.0,
            frame.1
        );
    }
    Ok(())
}

/// The median and 99th percentile (ms) of the simulate, cull and draw passes and of the whole
/// frame over `frames` frames after the warm-up.
fn time_frames(
    headless: &mut PortableHeadless,
    scene: &Scene,
    size: Vec2,
    frames: usize,
) -> Result<[(f64, f64); 4], Box<dyn Error>> {
    let (device, queue) = (headless.device.clone(), headless.queue.clone());
    let stamps = PASSES as u32 + 1;
    let bytes = 8 * stamps as u64;
    let queries = device.create_query_set(&wgpu::QuerySetDescriptor {
        label: None,
        ty: wgpu::QueryType::Timestamp,
        count: stamps,
    });
    let buffer = |usage| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: bytes,
            usage,
            mapped_at_creation: false,
        })
    };
    let resolved = buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
    let read = buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST);
    let period = queue.get_timestamp_period() as f64 * 1e-6;
    let mut times: [Vec<f64>; 4] = Default::default();
    for frame in 0..WARM_UP + frames {
        let time = frame as f32 * scene.simulation.step;
        let desc = FrameDesc::of_scene(scene, size, (time, 1), SIZE);
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.write_timestamp(&queries, 0);
        headless.record(&mut encoder, &desc, PortablePasses::SIMULATE)?;
        encoder.write_timestamp(&queries, 1);
        headless.record(&mut encoder, &desc, PortablePasses::CULL)?;
        encoder.write_timestamp(&queries, 2);
        headless.record_draw(&mut encoder)?;
        encoder.write_timestamp(&queries, 3);
        encoder.resolve_query_set(&queries, 0..stamps, &resolved, 0);
        encoder.copy_buffer_to_buffer(&resolved, 0, &read, 0, bytes);
        queue.submit([encoder.finish()]);
        read.slice(..).map_async(wgpu::MapMode::Read, |_| {});
        device.poll(wgpu::PollType::wait_indefinitely())?;
        let at: Vec<u64> = bytemuck::pod_collect_to_vec(&read.slice(..).get_mapped_range().unwrap());
        read.unmap();
        headless.take_fault()?;
        if frame >= WARM_UP {
            for pass in 0..PASSES {
                times[pass].push(at[pass + 1].saturating_sub(at[pass]) as f64 * period);
            }
            times[PASSES].push(at[PASSES].saturating_sub(at[0]) as f64 * period);
        }
    }
    Ok(times.map(|mut t| {
        t.sort_by(f64::total_cmp);
        let at = |q: f64| t[((t.len() - 1) as f64 * q).round() as usize];
        (at(0.5), at(0.99))
    }))
}
