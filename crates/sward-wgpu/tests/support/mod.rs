//! What the tests of sward-wgpu share (the `meadow` example includes its parts by path).

// Each test file uses its own part of this module.
#![allow(dead_code)]

pub mod cube;
pub mod readback;

/// What a test needs, said when it finds none.
pub const NEEDS: &str = "this test needs a Vulkan device and the Khronos validation layer \
     (Debian/Ubuntu: apt-get install libvulkan1 mesa-vulkan-drivers vulkan-validationlayers)";

/// A wgpu instance on Vulkan with the validation layer (and the debug messenger sward's
/// context listens on), and its adapter.
pub fn vulkan_adapter() -> (wgpu::Instance, wgpu::Adapter) {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::VULKAN,
        flags: wgpu::InstanceFlags::VALIDATION | wgpu::InstanceFlags::DEBUG,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
        .unwrap_or_else(|e| panic!("{NEEDS}: no wgpu adapter ({e})"));
    (instance, adapter)
}
