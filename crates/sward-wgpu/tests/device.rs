//! sward on a wgpu device (lavapipe in CI): the device wgpu opens through `sward_wgpu::open`
//! serves wgpu and sward at once, with no validation message, and sward draws on it what it
//! draws on a device of its own.

mod support;

use std::sync::Arc;

use support::{vulkan_adapter, NEEDS};
use sward_core::Scene;
use sward_gpu::{Context, ContextDesc, Headless, Validation};

fn validating() -> ContextDesc {
    ContextDesc {
        validation: Validation::Required,
        ..ContextDesc::default()
    }
}

/// A small meadow, simulated 20 steps and drawn at 160×120 on `ctx`.
fn meadow_on(ctx: &Arc<Context>) -> Vec<u8> {
    let mut scene = Scene::default();
    scene.field.blades = 2048;
    scene.validate("test").unwrap();
    let field = scene.grow_field().unwrap();
    let mut headless = Headless::new(ctx, 160, 120, None).unwrap();
    headless.renderer.upload(&field).unwrap();
    headless.render_scene(&scene, field.size, 20).unwrap()
}

fn assert_clean(ctx: &Context) {
    assert!(ctx.validating(), "the validation layer is not active");
    let messages = ctx.take_validation_messages();
    assert!(messages.is_empty(), "validation:\n{}", messages.join("\n"));
}

#[test]
fn a_wgpu_device_opened_for_sward_serves_both_and_sward_draws_on_it_as_on_its_own() {
    let (_instance, adapter) = vulkan_adapter();
    let shared = sward_wgpu::open(&adapter, &wgpu::DeviceDescriptor::default(), &validating())
        .unwrap_or_else(|e| panic!("{NEEDS}: {e}"));
    // wgpu works on it: a buffer written, copied and read back.
    let words: Vec<u8> = (0..64u8).collect();
    let source = shared.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("source"),
        size: 64,
        usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let read = shared.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read"),
        size: 64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    shared.queue.write_buffer(&source, 0, &words);
    let mut encoder = shared
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    encoder.copy_buffer_to_buffer(&source, 0, &read, 0, 64);
    shared.queue.submit([encoder.finish()]);
    read.slice(..).map_async(wgpu::MapMode::Read, |r| r.expect("mapped"));
    shared.device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    assert_eq!(&read.slice(..).get_mapped_range().unwrap()[..], &words[..]);
    // sward draws on it what it draws on a device of its own (the same driver: the same pixels).
    let on_wgpu = meadow_on(&shared.context);
    let own = Context::new(&validating()).unwrap_or_else(|e| panic!("{NEEDS}: {e}"));
    let on_own = meadow_on(&own);
    let differing = on_wgpu.iter().zip(&on_own).filter(|(a, b)| a.abs_diff(**b) > 2).count();
    assert!(
        differing * 1000 < on_own.len(),
        "{differing} of {} channel values differ between the wgpu device and sward's own",
        on_own.len()
    );
    let grass = on_wgpu
        .as_chunks::<4>()
        .0
        .iter()
        .filter(|p| p[1] > p[0] && p[1] > p[2])
        .count();
    assert!(grass > 1000, "little grass drawn on the wgpu device: {grass} pixels");
    assert_clean(&shared.context);
    assert_clean(&own);
}

#[test]
fn a_device_on_another_backend_is_named() {
    let err = sward_wgpu::BridgeError::NotVulkan(wgpu::Backend::Gl).to_string();
    assert!(err.contains("Gl") && err.contains("Vulkan only"), "{err}");
}

/// A game's device, opened by wgpu itself in an instance of its own, is not taken for one
/// `open` made in another instance that nobody adopted yet (wgpu's devices compare equal
/// across instances: each instance counts its devices' ids from the start), and the device
/// `open` made is still adopted.
#[test]
fn a_device_wgpu_opened_itself_is_not_taken_for_one_opened_for_sward() {
    let (_ours, adapter) = vulkan_adapter();
    let opened = sward_wgpu::open(&adapter, &wgpu::DeviceDescriptor::default(), &validating())
        .unwrap_or_else(|e| panic!("{NEEDS}: {e}"));
    let (device, queue) = (opened.device.clone(), opened.queue.clone());
    drop(opened);
    let (_games, game_adapter) = vulkan_adapter();
    let (game_device, game_queue) = pollster::block_on(game_adapter.request_device(&wgpu::DeviceDescriptor::default()))
        .unwrap_or_else(|e| panic!("{NEEDS}: {e}"));
    let taken = sward_wgpu::adopt(&game_adapter, game_device, game_queue, &validating());
    assert!(
        matches!(taken, Err(sward_wgpu::BridgeError::NotOpenedForSward)),
        "the game's own device was adopted as sward's: {:?}",
        taken.err()
    );
    let adopted = sward_wgpu::adopt(&adapter, device, queue, &validating())
        .unwrap_or_else(|e| panic!("the device opened for sward was not adopted: {e}"));
    assert_clean(&adopted.context);
}
