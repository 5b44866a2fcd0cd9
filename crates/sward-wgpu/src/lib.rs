//! sward on a wgpu device. [`open`] opens a `wgpu::Device` on a Vulkan adapter with everything
//! sward needs enabled beside what the application asks of wgpu — tessellation included, which
//! wgpu itself never enables — and makes sward's [`Context`] on the very same `VkDevice` and
//! queue, so sward's renderer and the application's wgpu work share one device.
//!
//! # Safety contract
//!
//! sward and wgpu share the device and its one queue. The application must:
//! - drop the [`SwardDevice`]'s context (and every sward renderer made on it) before the
//!   `wgpu::Device` — [`SwardDevice`] drops its fields in that order;
//! - not submit wgpu work on another thread while sward uploads or reads back (sward submits
//!   on the shared queue from the thread that calls it: `Renderer::upload`, read-backs);
//! - make sward's images and buffers known to wgpu only through what this crate hands out.

use std::ffi::CStr;
use std::sync::Arc;

use ash::vk;
use sward_gpu::{Context, ContextDesc, ExistingDevice, Withheld};
use wgpu::hal::api::Vulkan;

/// What went wrong opening sward on a wgpu adapter: one sentence each.
#[derive(Debug, thiserror::Error)]
pub enum BridgeError {
    /// The adapter is not on wgpu's Vulkan backend.
    #[error("the wgpu adapter is on the {0:?} backend; sward runs on Vulkan only (create the wgpu instance with Backends::VULKAN)")]
    NotVulkan(wgpu::Backend),
    /// The Vulkan device could not be created with what sward and the application ask.
    #[error("the Vulkan device could not be opened with what sward needs beside the application's wgpu features: {0}")]
    DeviceCreation(vk::Result),
    /// wgpu refused the device.
    #[error("wgpu did not take the device: {0}")]
    Wgpu(String),
    /// sward could not work on the device (a feature it needs is missing).
    #[error(transparent)]
    Sward(#[from] sward_gpu::GpuError),
}

/// A wgpu device and queue with sward's context on the same Vulkan device. Fields drop in
/// order: sward's context before the wgpu device it lives on.
pub struct SwardDevice {
    /// sward's context on the device: make renderers on it (`sward_gpu::Renderer`).
    pub context: Arc<Context>,
    /// The application's wgpu device.
    pub device: wgpu::Device,
    /// Its queue (the one sward submits its uploads to).
    pub queue: wgpu::Queue,
}

/// Open `adapter` (wgpu's Vulkan backend) as a wgpu device with `desc`'s features and limits
/// and, beside them, everything sward needs; then sward's context on it (`sward` validates
/// with the layer where the wgpu instance has it and `sward_desc.validation` asks).
pub fn open(
    adapter: &wgpu::Adapter,
    desc: &wgpu::DeviceDescriptor,
    sward_desc: &ContextDesc,
) -> Result<SwardDevice, BridgeError> {
    let backend = adapter.get_info().backend;
    if backend != wgpu::Backend::Vulkan {
        return Err(BridgeError::NotVulkan(backend));
    }
    // 64-bit atomics (the compute route and the splats) where the adapter has them: asked of
    // wgpu, which chains their feature struct itself.
    let int64 = wgpu::Features::SHADER_INT64 | wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX;
    let has_int64 = adapter.features().contains(int64);
    let features = desc.required_features | if has_int64 { int64 } else { wgpu::Features::empty() };
    let open = unsafe { open_raw(adapter, features, &desc.required_limits, &desc.memory_hints) }?;
    let desc = wgpu::DeviceDescriptor {
        required_features: features,
        ..desc.clone()
    };
    let (device, queue) =
        unsafe { adapter.create_device_from_hal(open, &desc) }.map_err(|e| BridgeError::Wgpu(e.to_string()))?;
    let existing = existing_device(adapter, &device)?;
    let sward_desc = ContextDesc {
        // The mesh route needs VK_EXT_mesh_shader enabled through wgpu's own mesh feature; not yet.
        withheld: Withheld {
            mesh_shaders: true,
            int64_atomics: sward_desc.withheld.int64_atomics || !has_int64,
        },
        ..sward_desc.clone()
    };
    let context = Context::from_device(existing, &sward_desc)?;
    Ok(SwardDevice { context, device, queue })
}

/// The `VkDevice` made on the adapter with wgpu's extensions and feature chain for `features`,
/// the core features sward needs added to wgpu's, and the Vulkan 1.3 features sward needs that
/// wgpu's chain lacks; handed to wgpu as its own device.
///
/// # Safety
/// `adapter` is on the Vulkan backend.
unsafe fn open_raw(
    adapter: &wgpu::Adapter,
    features: wgpu::Features,
    limits: &wgpu::Limits,
    hints: &wgpu::MemoryHints,
) -> Result<wgpu::hal::OpenDevice<Vulkan>, BridgeError> {
    let hal = unsafe { adapter.as_hal::<Vulkan>() }.ok_or(BridgeError::NotVulkan(adapter.get_info().backend))?;
    let instance = hal.shared_instance().raw_instance();
    let physical = hal.raw_physical_device();
    let extensions: Vec<&'static CStr> = hal.required_device_extensions(features);
    let names: Vec<_> = extensions.iter().map(|e| e.as_ptr()).collect();
    let mut chain = hal.physical_device_features(&extensions, features);
    let core = sward_core_features(chain.get_core(), unsafe {
        instance.get_physical_device_features(physical)
    });
    // wgpu's family 0 and its one queue (wgpu-hal opens no other).
    let priorities = [1.0];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(0)
        .queue_priorities(&priorities)];
    let info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_extension_names(&names);
    let mut info = chain.add_to_device_create(info);
    // What wgpu chained already (its structs, some with the bit sward needs off) and what it
    // did not: a struct may appear once in the chain.
    unsafe { enable_in_chain(info.p_next) };
    let mut dynamic = vk::PhysicalDeviceDynamicRenderingFeatures::default().dynamic_rendering(true);
    let mut sync2 = vk::PhysicalDeviceSynchronization2Features::default().synchronization2(true);
    let mut demote =
        vk::PhysicalDeviceShaderDemoteToHelperInvocationFeatures::default().shader_demote_to_helper_invocation(true);
    info = info
        .push_next(&mut dynamic)
        .push_next(&mut sync2)
        .push_next(&mut demote);
    info.p_enabled_features = &core;
    let device = unsafe { instance.create_device(physical, &info, None) }.map_err(BridgeError::DeviceCreation)?;
    unsafe { hal.device_from_raw(device, None, &extensions, features, limits, hints, 0, 0) }
        .map_err(|e| BridgeError::Wgpu(e.to_string()))
}

/// wgpu's core features with sward's added: tessellation (the tessellation route), multi-draw
/// indirect, 64-bit integers, and where the device has them wireframe, pipeline statistics and
/// queries inherited by secondary command buffers.
fn sward_core_features(
    wgpu: vk::PhysicalDeviceFeatures,
    has: vk::PhysicalDeviceFeatures,
) -> vk::PhysicalDeviceFeatures {
    vk::PhysicalDeviceFeatures {
        tessellation_shader: vk::TRUE,
        multi_draw_indirect: vk::TRUE,
        shader_int64: vk::TRUE,
        fill_mode_non_solid: has.fill_mode_non_solid,
        pipeline_statistics_query: has.pipeline_statistics_query,
        inherited_queries: has.inherited_queries,
        ..wgpu
    }
}

/// Turn on, in the feature structs wgpu chained, the bits sward needs of them: shader draw
/// parameters (gl_DrawID) and maintenance4 (workgroup sizes by specialisation).
///
/// # Safety
/// `next` is a valid `pNext` chain of mutable structs (as `add_to_device_create` builds).
unsafe fn enable_in_chain(mut next: *const std::ffi::c_void) {
    while !next.is_null() {
        let base = next as *mut vk::BaseOutStructure;
        match unsafe { (*base).s_type } {
            vk::StructureType::PHYSICAL_DEVICE_SHADER_DRAW_PARAMETERS_FEATURES => unsafe {
                (*(base as *mut vk::PhysicalDeviceShaderDrawParametersFeatures)).shader_draw_parameters = vk::TRUE;
            },
            vk::StructureType::PHYSICAL_DEVICE_MAINTENANCE_4_FEATURES => unsafe {
                (*(base as *mut vk::PhysicalDeviceMaintenance4Features)).maintenance4 = vk::TRUE;
            },
            _ => {}
        }
        next = unsafe { (*base).p_next } as *const std::ffi::c_void;
    }
}

/// sward's view of the wgpu device: wgpu's instance, loader, physical device, device and queue.
fn existing_device(adapter: &wgpu::Adapter, device: &wgpu::Device) -> Result<ExistingDevice, BridgeError> {
    let not_vulkan = || BridgeError::NotVulkan(adapter.get_info().backend);
    let hal_adapter = unsafe { adapter.as_hal::<Vulkan>() }.ok_or_else(not_vulkan)?;
    let hal_device = unsafe { device.as_hal::<Vulkan>() }.ok_or_else(not_vulkan)?;
    let shared = hal_adapter.shared_instance();
    Ok(ExistingDevice {
        entry: shared.entry().clone(),
        instance: shared.raw_instance().clone(),
        physical_device: hal_adapter.raw_physical_device(),
        device: hal_device.raw_device().clone(),
        queue_family: hal_device.queue_family_index(),
        queue: hal_device.raw_queue(),
        debug_utils: shared.extensions().contains(&ash::ext::debug_utils::NAME),
        allocator: None,
    })
}
