//! Bevy's render device, opened with what sward needs: the adapter Bevy would pick, every
//! feature and limit Bevy asks of it, and sward's Vulkan features beside them
//! ([`sward_wgpu::open`]), handed to Bevy's `RenderPlugin` as its device.

use bevy::render::renderer::{RenderAdapter, RenderAdapterInfo, RenderDevice, RenderInstance, RenderQueue};
use bevy::render::settings::RenderCreation;
use bevy::render::RenderPlugin;
use sward_wgpu::BridgeError;

/// Bevy's `RenderPlugin` on a Vulkan device that carries sward: put it into `DefaultPlugins`
/// (`DefaultPlugins.set(sward_bevy::render_plugin()?)`). Fails with one sentence where there is
/// no Vulkan adapter or it lacks what sward needs.
pub fn render_plugin() -> Result<RenderPlugin, BridgeError> {
    render_plugin_with(wgpu_flags())
}

/// [`render_plugin`] with wgpu's instance flags as given (tests ask for the validation layer:
/// `VALIDATION | DEBUG`).
pub fn render_plugin_with(flags: wgpu::InstanceFlags) -> Result<RenderPlugin, BridgeError> {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = wgpu::Backends::VULKAN;
    desc.flags = flags;
    let instance = wgpu::Instance::new(desc);
    // Once, as the app is built, before any frame (the `vulkan` feature: native only).
    #[allow(clippy::disallowed_methods)]
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        ..Default::default()
    }))
    .map_err(|e| BridgeError::Wgpu(format!("no Vulkan adapter for Bevy's renderer ({e})")))?;
    let info = adapter.get_info();
    // What Bevy asks of an adapter it opens itself: everything it has.
    let mut features = adapter.features();
    if info.device_type == wgpu::DeviceType::DiscreteGpu {
        features.remove(wgpu::Features::MAPPABLE_PRIMARY_BUFFERS);
    }
    let device_desc = wgpu::DeviceDescriptor {
        label: Some("Bevy and sward"),
        required_features: features,
        required_limits: adapter.limits(),
        experimental_features: unsafe { wgpu::ExperimentalFeatures::enabled() },
        ..Default::default()
    };
    // sward's own context here is let go at once: the plugin takes the device back
    // (`sward_wgpu::adopt`) once Bevy holds it.
    let sward = sward_wgpu::open(&adapter, &device_desc, &Default::default())?;
    let device = sward.device.clone();
    let queue = sward.queue.clone();
    drop(sward);
    Ok(RenderPlugin {
        render_creation: RenderCreation::manual(
            RenderDevice::from(device),
            RenderQueue::new(queue),
            RenderAdapterInfo::new(info),
            RenderAdapter::new(adapter),
            RenderInstance::new(instance),
        ),
        ..Default::default()
    })
}

/// wgpu's instance flags as Bevy sets them: from the environment (`WGPU_VALIDATION`, …).
fn wgpu_flags() -> wgpu::InstanceFlags {
    wgpu::InstanceFlags::from_build_config().with_env()
}
