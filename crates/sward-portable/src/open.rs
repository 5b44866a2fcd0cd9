//! Opening a device for the portable renderer without a window: the adapter on the backends
//! asked for, with the features and limits the renderer uses. It waits on wgpu's futures, so it
//! is built only with the `blocking` feature (a browser opens its device with `await`).

use crate::adapter::{adapter_sentence, portable_features, portable_limits};
use crate::PortableError;

/// A device on one of `backends` with WebGPU's default limits, raised where the adapter has
/// more ([`portable_limits`]), and the optional features the portable renderer uses where the
/// adapter has them ([`portable_features`]), and the adapter it is of. The primary
/// backends (Vulkan, Metal, DX12) are tried before GL. `validation` turns on the backend's own
/// checks (Vulkan's validation layer, GL's debug output).
pub fn open_device(
    backends: wgpu::Backends,
    validation: bool,
) -> Result<(wgpu::Adapter, wgpu::Device, wgpu::Queue), PortableError> {
    let webgpu = |adapter: &wgpu::Adapter| (portable_features(adapter), portable_limits(adapter));
    open_device_with(backends, validation, webgpu)
}

/// What the portable renderer makes of the first adapter wgpu finds on `backends`, in one
/// sentence (for `sward info`); None where there is none.
pub fn describe_adapter(backends: wgpu::Backends) -> Option<String> {
    find_adapter(backends, false)
        .ok()
        .map(|adapter| adapter_sentence(&adapter))
}

/// [`open_device`] asking for the features and limits `ask` chooses for the adapter found (a
/// benchmark's timestamps, a large field's bindings).
pub fn open_device_with(
    backends: wgpu::Backends,
    validation: bool,
    ask: impl FnOnce(&wgpu::Adapter) -> (wgpu::Features, wgpu::Limits),
) -> Result<(wgpu::Adapter, wgpu::Device, wgpu::Queue), PortableError> {
    let primary = backends & wgpu::Backends::PRIMARY;
    let adapter = match (primary.is_empty(), backends - primary) {
        (false, rest) if !rest.is_empty() => {
            find_adapter(primary, validation).or_else(|_| find_adapter(rest, validation))
        }
        _ => find_adapter(backends, validation),
    }
    .map_err(|e| PortableError::NoAdapter(backend_names(backends), e.to_string()))?;
    let (required_features, required_limits) = ask(&adapter);
    let (device, queue) = pollster_block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("sward portable"),
        required_features,
        required_limits,
        ..Default::default()
    }))
    .map_err(|e| PortableError::NoDevice(adapter.get_info().name, e.to_string()))?;
    Ok((adapter, device, queue))
}

/// The first adapter wgpu finds on `backends`.
fn find_adapter(backends: wgpu::Backends, validation: bool) -> Result<wgpu::Adapter, wgpu::RequestAdapterError> {
    // Validation without wgpu's debug flag: with it, wgpu attaches the WGSL text to the SPIR-V
    // as source language WGSL, which some validation layers (Debian 12's) reject.
    let flags = match validation {
        true => wgpu::InstanceFlags::VALIDATION,
        false => wgpu::InstanceFlags::empty(),
    };
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends,
        flags,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    pollster_block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
}

/// `backends` as a reader says them: "Vulkan or GL".
fn backend_names(backends: wgpu::Backends) -> String {
    let names = [
        (wgpu::Backends::VULKAN, "Vulkan"),
        (wgpu::Backends::METAL, "Metal"),
        (wgpu::Backends::DX12, "DX12"),
        (wgpu::Backends::GL, "GL"),
        (wgpu::Backends::BROWSER_WEBGPU, "WebGPU"),
    ];
    let named: Vec<&str> = names
        .iter()
        .filter(|(b, _)| backends.contains(*b))
        .map(|(_, n)| *n)
        .collect();
    named.join(" or ")
}

/// Wait for a future on this thread (wgpu's native futures are ready once the device is
/// polled, which request_adapter and request_device do themselves).
fn pollster_block_on<F: std::future::Future>(future: F) -> F::Output {
    let mut future = std::pin::pin!(future);
    let waker = std::task::Waker::noop();
    let mut context = std::task::Context::from_waker(waker);
    loop {
        if let std::task::Poll::Ready(value) = future.as_mut().poll(&mut context) {
            return value;
        }
        std::thread::yield_now();
    }
}
