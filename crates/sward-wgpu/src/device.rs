//! The wgpu device sward works on: opened on a Vulkan adapter with what sward needs beside what
//! the application asks of wgpu ([`open`]), or an application's device that `open` made,
//! taken back with the draw routes it allows ([`adopt`]).

use std::ffi::CStr;
use std::sync::{Arc, Mutex};

use ash::vk;
use sward_gpu::{Context, ContextDesc, DrawRoute, ExistingDevice, Withheld};
use wgpu::hal::api::Vulkan;

use crate::BridgeError;

/// A wgpu device and queue with sward's context on the same Vulkan device. Fields drop in
/// order: sward's context before the wgpu device it lives on.
pub struct SwardDevice {
    /// sward's context on the device: make renderers on it (`sward_gpu::Renderer`).
    pub context: Arc<Context>,
    /// The application's wgpu device.
    pub device: wgpu::Device,
    /// Its queue (the one sward submits its uploads to).
    pub queue: wgpu::Queue,
    /// The adapter the device was opened on.
    pub adapter: wgpu::Adapter,
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
    let raw = existing.device.handle();
    let sward_desc = ContextDesc {
        // The mesh route needs VK_EXT_mesh_shader enabled through wgpu's own mesh feature; not yet.
        withheld: Withheld {
            mesh_shaders: true,
            int64_atomics: sward_desc.withheld.int64_atomics || !has_int64,
        },
        ..sward_desc.clone()
    };
    let context = Context::from_device(existing, &sward_desc)?;
    OPENED.lock().unwrap_or_else(|e| e.into_inner()).push(Opened {
        raw,
        _device: device.clone(),
        withheld: sward_desc.withheld,
    });
    Ok(SwardDevice {
        context,
        device,
        queue,
        adapter: adapter.clone(),
    })
}

/// The Vulkan devices [`open`] made and nobody adopted yet, with what sward was made to do
/// without. Each is held here until [`adopt`] takes it: while held it cannot be destroyed, so
/// no other device can come to have its raw handle (a handle is reused once its device is gone).
static OPENED: Mutex<Vec<Opened>> = Mutex::new(Vec::new());

/// A device [`open`] made, known by its raw `VkDevice`: unique among the devices alive in the
/// process. `wgpu::Device`'s own equality is not: it compares ids that each wgpu instance
/// counts from the start, so the first device of one instance equals the first of another
/// (a game's own device was taken for one opened for sward in another instance).
struct Opened {
    raw: vk::Device,
    /// Held so that the handle stays this device's.
    _device: wgpu::Device,
    withheld: Withheld,
}

/// sward's context on an application's wgpu `device` and `queue` (from `adapter`): one that
/// [`open`] made and the application kept — handed to Bevy's renderer, say. A device wgpu
/// opened by itself cannot carry sward: wgpu never enables synchronization2, dynamic rendering
/// or tessellation, with which sward records every pass; the error says so.
/// [`SwardDevice::routes`] tells which draw routes the device allows.
pub fn adopt(
    adapter: &wgpu::Adapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
    sward_desc: &ContextDesc,
) -> Result<SwardDevice, BridgeError> {
    let backend = adapter.get_info().backend;
    if backend != wgpu::Backend::Vulkan {
        return Err(BridgeError::NotVulkan(backend));
    }
    let existing = existing_device(adapter, &device)?;
    let raw = existing.device.handle();
    let withheld = {
        let mut opened = OPENED.lock().unwrap_or_else(|e| e.into_inner());
        let at = opened.iter().position(|o| o.raw == raw);
        at.map(|at| opened.swap_remove(at).withheld)
            .ok_or(BridgeError::NotOpenedForSward)?
    };
    let sward_desc = ContextDesc {
        withheld,
        ..sward_desc.clone()
    };
    let context = Context::from_device(existing, &sward_desc)?;
    Ok(SwardDevice {
        context,
        device,
        queue,
        adapter: adapter.clone(),
    })
}

impl SwardDevice {
    /// The draw routes of the Bezier blades this device allows (`Auto` picks the fastest of
    /// them): tessellation and strips always, the compute route where the adapter has 64-bit
    /// atomics; the mesh route not yet (wgpu would have to enable VK_EXT_mesh_shader itself).
    pub fn routes(&self) -> Vec<DrawRoute> {
        allowed_routes(&self.context.info)
    }
}

/// The routes `info`'s device draws by itself (none falls back to another).
pub fn allowed_routes(info: &sward_gpu::DeviceInfo) -> Vec<DrawRoute> {
    DrawRoute::ALL
        .into_iter()
        .filter(|&route| route != DrawRoute::Auto)
        .filter(|&route| sward_gpu::passes::routes::resolve(route, info, false).1.is_none())
        .collect()
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
