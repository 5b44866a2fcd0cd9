//! The Vulkan context: instance (with the Khronos validation layer when asked), the device chosen
//! by requirements then score, one graphics+compute queue, the memory allocator, and a sink that
//! collects every validation message so tests can fail on them.

use std::ffi::{c_void, CStr};
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use ash::{ext::debug_utils, khr, vk};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use raw_window_handle::RawDisplayHandle;

use crate::error::{vk_check, GpuError, Result};
use crate::memory::MemoryMeter;

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Whether to load the Khronos validation layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Validation {
    /// Never load it (release builds do this).
    Off,
    /// Load it when installed (debug builds do this).
    IfAvailable,
    /// Fail if it is not installed (tests do this).
    Required,
}

/// How to build a [`Context`].
#[derive(Clone, Debug)]
pub struct ContextDesc {
    /// Whether to load the validation layer.
    pub validation: Validation,
    /// Device index or a case-insensitive part of its name; `None` picks the best.
    pub gpu: Option<String>,
    /// The display windows will be on, if any: enables surfaces and swapchains.
    pub display: Option<RawDisplayHandle>,
    /// Allocate at most this many bytes of GPU memory, as if the device had no more.
    pub memory_budget: Option<u64>,
    /// Optional features to leave unused, as if the device lacked them.
    pub withheld: Withheld,
    /// Treat every queue submission after this many as a lost device: a lost device cannot be
    /// caused on purpose, so tests use this to see that sward ends with one sentence.
    pub lose_device_after: Option<u64>,
}

/// Optional device features sward can do without, withheld on request (`--without`) so a device
/// that has them shows what one that lacks them does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Withheld {
    /// VK_EXT_mesh_shader: without it the mesh draw route is not offered.
    pub mesh_shaders: bool,
    /// 64-bit buffer atomics: without them nothing is splatted or rasterized by compute.
    pub int64_atomics: bool,
}

impl Default for ContextDesc {
    fn default() -> Self {
        let validation = if cfg!(debug_assertions) {
            Validation::IfAvailable
        } else {
            Validation::Off
        };
        Self {
            validation,
            gpu: None,
            display: None,
            memory_budget: None,
            withheld: Withheld::default(),
            lose_device_after: None,
        }
    }
}

/// What a physical device offers, as far as choosing one is concerned.
#[derive(Clone, Debug)]
pub struct DeviceCandidate {
    /// Its index among the instance's physical devices.
    pub index: usize,
    /// Its name.
    pub name: String,
    /// Discrete, integrated, virtual or CPU.
    pub kind: vk::PhysicalDeviceType,
    /// Requirements it fails, by Vulkan name; empty if usable.
    pub missing: Vec<&'static str>,
}

impl DeviceCandidate {
    fn score(&self) -> u32 {
        match self.kind {
            vk::PhysicalDeviceType::DISCRETE_GPU => 4,
            vk::PhysicalDeviceType::INTEGRATED_GPU => 3,
            vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
            vk::PhysicalDeviceType::CPU => 1,
            _ => 0,
        }
    }
}

/// Pick a device: hard requirements first, then `wanted` (index or name part), then the best score
/// (discrete > integrated > virtual > CPU).
pub fn choose_device(candidates: &[DeviceCandidate], wanted: Option<&str>) -> Result<usize> {
    if candidates.is_empty() {
        return Err(GpuError::NoDriver);
    }
    let usable: Vec<&DeviceCandidate> = candidates.iter().filter(|c| c.missing.is_empty()).collect();
    if usable.is_empty() {
        let reasons: Vec<String> = candidates
            .iter()
            .map(|c| format!("{} lacks {}", c.name, c.missing.join(", ")))
            .collect();
        return Err(GpuError::NoSuitableDevice(reasons.join("; ")));
    }
    if let Some(wanted) = wanted {
        let needle = wanted.to_lowercase();
        let found = usable
            .iter()
            .find(|c| wanted.parse::<usize>().ok() == Some(c.index) || c.name.to_lowercase().contains(&needle));
        return found.map(|c| c.index).ok_or_else(|| GpuError::GpuNotFound {
            wanted: wanted.to_string(),
            available: usable
                .iter()
                .map(|c| format!("{}: {}", c.index, c.name))
                .collect::<Vec<_>>()
                .join(", "),
        });
    }
    Ok(usable
        .iter()
        .max_by_key(|c| (c.score(), std::cmp::Reverse(c.index)))
        .unwrap()
        .index)
}

/// The chosen device, for logs, bench reports and workarounds.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    /// The device's name.
    pub name: String,
    /// The driver's name.
    pub driver_name: String,
    /// The driver's version, as the driver words it.
    pub driver_info: String,
    /// Which driver (Vulkan's id): some workarounds depend on it.
    pub driver_id: vk::DriverId,
    /// Discrete, integrated, virtual or CPU.
    pub kind: vk::PhysicalDeviceType,
    /// The Vulkan version the device supports.
    pub api_version: String,
    /// Nanoseconds per timestamp tick.
    pub timestamp_period: f32,
    /// Subgroup ballot and vote are available in compute shaders.
    pub subgroup_ballot: bool,
    /// Wireframe (fillModeNonSolid) is available.
    pub wireframe: bool,
    /// Largest range one storage buffer binding may cover, in bytes.
    pub max_storage_buffer_range: u64,
    /// Most workgroups one dispatch may have along x.
    pub max_workgroups_x: u32,
    /// Most workgroups along y in one dispatch (rows of tiles or patches).
    pub max_workgroups_y: u32,
    /// Most invocations one compute workgroup may have along x (and in all).
    pub max_workgroup_invocations: u32,
    /// Most bytes of shared memory one compute workgroup may declare.
    pub max_workgroup_shared: u32,
    /// Pipeline statistics queries (primitives and fragments counted by the GPU) are available.
    pub pipeline_statistics: bool,
    /// Sample counts a colour and depth target may both have (MSAA levels).
    pub sample_counts: vk::SampleCountFlags,
    /// Mesh shaders (VK_EXT_mesh_shader) are available: the mesh draw route can run.
    pub mesh_shaders: bool,
    /// 64-bit atomics on storage buffers are available: blades can be splatted and rasterized by
    /// compute (the compute route, the instanced grass's far blades).
    pub int64_atomics: bool,
    /// Secondary command buffers may run while the primary has a query open (inheritedQueries):
    /// a frame's passes can be kept recorded and replayed into any caller's command buffer.
    pub inherited_queries: bool,
}

impl DeviceInfo {
    /// The most samples per pixel this device renders with, at most `wanted` (1 always works).
    pub fn samples_up_to(&self, wanted: u32) -> vk::SampleCountFlags {
        [8, 4, 2]
            .into_iter()
            .filter(|&n| n <= wanted)
            .map(vk::SampleCountFlags::from_raw)
            .find(|&s| self.sample_counts.contains(s))
            .unwrap_or(vk::SampleCountFlags::TYPE_1)
    }
}

/// Instance, device, queue and allocator. Resources hold an `Arc<Context>` and free themselves in
/// `Drop`, so the context is destroyed last.
pub struct Context {
    allocator: ManuallyDrop<Arc<Mutex<Allocator>>>,
    /// The logical device.
    pub device: ash::Device,
    /// The one graphics, compute and transfer queue sward submits to.
    pub queue: vk::Queue,
    /// The queue's family.
    pub queue_family: u32,
    /// The physical device chosen.
    pub physical_device: vk::PhysicalDevice,
    /// What the device is and can do.
    pub info: DeviceInfo,
    command_pool: Mutex<vk::CommandPool>,
    /// GPU memory allocated against the device's (or the budget's) limit.
    pub memory: MemoryMeter,
    /// Queue submissions so far, and after how many the device counts as lost (tests).
    submissions: AtomicU64,
    /// Descriptor writes so far: a command buffer that bound a set written since is stale.
    descriptor_writes: AtomicU64,
    lose_device_after: Option<u64>,
    messenger: Option<(debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    validation_messages: Arc<Mutex<Vec<String>>>,
    /// Whether sward created the device and instance (and destroys them): not when its caller
    /// gave them ([`Context::from_device`]).
    owned: bool,
    /// The Vulkan instance.
    pub instance: ash::Instance,
    /// The Vulkan loader.
    pub entry: ash::Entry,
}

impl Context {
    /// Create a context with no surface (headless); the viewer adds its swapchain on top.
    pub fn new(desc: &ContextDesc) -> Result<Arc<Context>> {
        let entry = unsafe { ash::Entry::load() }.map_err(|e| GpuError::NoLoader(e.to_string()))?;
        let validation = validation_wanted(&entry, desc.validation)?;
        let messages = Arc::new(Mutex::new(Vec::new()));
        let surface_extensions = match desc.display {
            Some(display) => {
                ash_window::enumerate_required_extensions(display).map_err(vk_check("finding surface extensions"))?
            }
            None => &[],
        };
        let presents = desc.display.is_some();
        let instance = create_instance(&entry, validation, surface_extensions)?;
        let messenger = if validation {
            Some(create_messenger(&entry, &instance, &messages)?)
        } else {
            None
        };
        let (physical_device, queue_family) = match pick_physical_device(&instance, desc.gpu.as_deref(), presents) {
            Ok(pick) => pick,
            Err(e) => {
                destroy_instance(&instance, &messenger);
                return Err(e);
            }
        };
        let info = withhold(describe(&instance, physical_device), desc.withheld);
        log::info!(
            "GPU: {} ({:?}), driver {} {}, Vulkan {}",
            info.name,
            info.kind,
            info.driver_name,
            info.driver_info,
            info.api_version
        );
        let extensions = if presents { vec![khr::swapchain::NAME] } else { vec![] };
        let device = create_device(&instance, physical_device, queue_family, &info, &extensions)?;
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let vulkan = ExistingDevice {
            allocator: None,
            entry,
            instance,
            physical_device,
            device,
            queue_family,
            queue,
            debug_utils: validation,
        };
        let parts = Parts {
            vulkan,
            info,
            messenger,
            messages,
            owned: true,
        };
        parts.assemble(desc)
    }

    /// sward in a Vulkan device its caller created and keeps owning (an application that adds
    /// sward's grass to its own frame): the device must have been made by [`create_device_for`]
    /// (or enable at least what it enables). sward allocates from it through the caller's
    /// allocator where [`ExistingDevice::allocator`] gives one, else through its own; it submits
    /// its uploads and read-backs to `queue` (the frame itself goes into the caller's
    /// command buffer: [`crate::Renderer::record_frame`]) and, when dropped, destroys only what it
    /// made — never the device or the instance.
    pub fn from_device(existing: ExistingDevice, desc: &ContextDesc) -> Result<Arc<Context>> {
        let (entry, instance, physical_device) = (&existing.entry, &existing.instance, existing.physical_device);
        let found = candidate(instance, 0, physical_device, false);
        if !found.missing.is_empty() {
            return Err(GpuError::NoSuitableDevice(format!(
                "{} lacks {}",
                found.name,
                found.missing.join(", ")
            )));
        }
        let messages = Arc::new(Mutex::new(Vec::new()));
        // The caller's instance reports to sward where it has the validation layer's messenger.
        let messenger = if desc.validation != Validation::Off && existing.debug_utils {
            Some(create_messenger(entry, instance, &messages)?)
        } else {
            None
        };
        let info = withhold(describe(instance, physical_device), desc.withheld);
        let parts = Parts {
            vulkan: existing,
            info,
            messenger,
            messages,
            owned: false,
        };
        parts.assemble(desc)
    }

    /// The memory allocator (locked while the guard lives).
    pub fn allocator(&self) -> std::sync::MutexGuard<'_, Allocator> {
        self.allocator.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Bytes of GPU memory allocated now through the allocator (buffers and images, each at its
    /// allocation's size): what `sward bench` reports for both renderers, counted the same way
    /// (the portable renderer's wgpu allocates with the same allocator on Vulkan). Where the
    /// allocator is shared with an application, its allocations count too.
    pub fn allocated_bytes(&self) -> u64 {
        self.allocator().generate_report().total_allocated_bytes
    }

    /// The `count` largest allocations now, by name, largest first (where the memory goes).
    pub fn largest_allocations(&self, count: usize) -> Vec<(String, u64)> {
        let report = self.allocator().generate_report();
        let all = report.allocations.into_iter().map(|a| (a.name, a.size)).collect();
        sward_core::memory::largest(all, count)
    }

    /// The allocator, shared with code that needs its own handle (the UI renderer). Whoever holds a
    /// clone must drop it before the context.
    pub fn shared_allocator(&self) -> Arc<Mutex<Allocator>> {
        Arc::clone(&self.allocator)
    }

    /// Whether the validation layer is loaded and reporting.
    pub fn validating(&self) -> bool {
        self.messenger.is_some()
    }

    /// Take every validation message reported so far (warnings and errors).
    pub fn take_validation_messages(&self) -> Vec<String> {
        std::mem::take(&mut *self.validation_messages.lock().unwrap_or_else(|e| e.into_inner()))
    }

    /// Record commands with `record`, submit them and wait for them to finish.
    pub fn submit_and_wait(&self, what: &'static str, record: impl FnOnce(vk::CommandBuffer)) -> Result<()> {
        let pool = self.command_pool.lock().unwrap_or_else(|e| e.into_inner());
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(*pool)
            .command_buffer_count(1);
        let cmd = unsafe { self.device.allocate_command_buffers(&alloc) }.map_err(vk_check(what))?[0];
        let result = unsafe { self.device.create_fence(&vk::FenceCreateInfo::default(), None) }
            .map_err(vk_check(what))
            .and_then(|fence| {
                let waited = self.record_submit_wait(cmd, fence, what, record);
                unsafe { self.device.destroy_fence(fence, None) };
                waited.map(|_| ())
            });
        unsafe { self.device.free_command_buffers(*pool, &[cmd]) };
        result
    }

    /// Record `cmd` with `record`, submit it signalling `fence` (unsignalled) and wait for it.
    /// Returns the host's time from beginning the buffer until the submission returned (the
    /// frame's host work, without the wait).
    fn record_submit_wait(
        &self,
        cmd: vk::CommandBuffer,
        fence: vk::Fence,
        what: &'static str,
        record: impl FnOnce(vk::CommandBuffer),
    ) -> Result<std::time::Duration> {
        let d = &self.device;
        let start = std::time::Instant::now();
        unsafe {
            let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            d.begin_command_buffer(cmd, &begin).map_err(vk_check(what))?;
            record(cmd);
            d.end_command_buffer(cmd).map_err(vk_check(what))?;
            let cmds = [cmd];
            let submit = vk::SubmitInfo::default().command_buffers(&cmds);
            self.submit(&[submit], fence).map_err(vk_check(what))?;
            let submitted = start.elapsed();
            d.wait_for_fences(&[fence], true, u64::MAX).map_err(vk_check(what))?;
            Ok(submitted)
        }
    }
}

/// One command buffer (in a pool of its own) and a fence, kept for a loop of frames that each
/// record, submit and wait: headless images and the bench. The buffer is recorded anew each
/// frame, as the viewer's frames in flight are, so the bench's host time is a frame loop's
/// rather than that of allocating and freeing a buffer per frame.
pub struct FrameCommands {
    ctx: Arc<Context>,
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
}

impl FrameCommands {
    /// A command buffer and fence on `ctx`'s queue.
    pub fn new(ctx: &Arc<Context>) -> Result<FrameCommands> {
        let d = &ctx.device;
        let what = "creating a frame's command buffer";
        let pool = command_pool(d, ctx.queue_family, what)?;
        let mut commands = FrameCommands {
            ctx: ctx.clone(),
            pool,
            cmd: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
        };
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .command_buffer_count(1);
        commands.cmd = unsafe { d.allocate_command_buffers(&alloc) }.map_err(vk_check(what))?[0];
        commands.fence = unsafe { d.create_fence(&vk::FenceCreateInfo::default(), None) }.map_err(vk_check(what))?;
        Ok(commands)
    }

    /// Record the buffer anew with `record`, submit it and wait for it to finish. Returns the
    /// host's time from beginning the buffer until the submission returned.
    pub fn submit_and_wait(
        &mut self,
        what: &'static str,
        record: impl FnOnce(vk::CommandBuffer),
    ) -> Result<std::time::Duration> {
        unsafe { self.ctx.device.reset_fences(&[self.fence]) }.map_err(vk_check(what))?;
        self.ctx.record_submit_wait(self.cmd, self.fence, what, record)
    }
}

impl Drop for FrameCommands {
    fn drop(&mut self) {
        let d = &self.ctx.device;
        unsafe {
            // A frame that failed may have left work queued.
            let _ = d.device_wait_idle();
            d.destroy_fence(self.fence, None);
            d.destroy_command_pool(self.pool, None);
        }
    }
}

/// A Vulkan device its caller created and keeps owning, for [`Context::from_device`].
pub struct ExistingDevice {
    /// The Vulkan loader the instance was created with.
    pub entry: ash::Entry,
    /// The caller's instance (Vulkan 1.3).
    pub instance: ash::Instance,
    /// The physical device the device was created on.
    pub physical_device: vk::PhysicalDevice,
    /// The caller's device, created by [`create_device_for`] or with at least what it enables.
    pub device: ash::Device,
    /// A queue family with graphics, compute and timestamps.
    pub queue_family: u32,
    /// A queue of that family for sward's uploads and read-backs.
    pub queue: vk::Queue,
    /// The instance was created with VK_EXT_debug_utils (and the validation layer): sward
    /// collects the layer's messages like its own context's, where `ContextDesc::validation`
    /// asks.
    pub debug_utils: bool,
    /// The caller's memory allocator (`gpu_allocator`, re-exported as
    /// [`crate::gpu_allocator`] so the versions match), made on this device: sward allocates
    /// its buffers and images from it and frees them all before the context is dropped. `None`:
    /// sward makes an allocator of its own on the device.
    pub allocator: Option<Arc<Mutex<Allocator>>>,
}

/// Everything a context is made of, before its allocator and command pool.
struct Parts {
    vulkan: ExistingDevice,
    info: DeviceInfo,
    messenger: Option<(debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    messages: Arc<Mutex<Vec<String>>>,
    owned: bool,
}

impl Parts {
    /// The context: an allocator and a command pool on the device, the memory meter.
    fn assemble(self, desc: &ContextDesc) -> Result<Arc<Context>> {
        let mut v = self.vulkan;
        let heaps = unsafe { v.instance.get_physical_device_memory_properties(v.physical_device) };
        let allocator = match v.allocator.take() {
            Some(callers) => callers,
            None => Arc::new(Mutex::new(own_allocator(&v)?)),
        };
        let command_pool = command_pool(&v.device, v.queue_family, "creating a command pool")?;
        Ok(Arc::new(Context {
            allocator: ManuallyDrop::new(allocator),
            device: v.device,
            queue: v.queue,
            queue_family: v.queue_family,
            physical_device: v.physical_device,
            info: self.info,
            command_pool: Mutex::new(command_pool),
            memory: MemoryMeter::new(&heaps, desc.memory_budget),
            submissions: AtomicU64::new(0),
            descriptor_writes: AtomicU64::new(0),
            lose_device_after: desc.lose_device_after,
            messenger: self.messenger,
            validation_messages: self.messages,
            owned: self.owned,
            instance: v.instance,
            entry: v.entry,
        }))
    }
}

impl Context {
    /// Submit to the queue, as every submission of sward's goes: a lost device (real, or after
    /// `ContextDesc::lose_device_after` submissions) is VK_ERROR_DEVICE_LOST here.
    pub fn submit(&self, submits: &[vk::SubmitInfo], fence: vk::Fence) -> std::result::Result<(), vk::Result> {
        let n = self.submissions.fetch_add(1, Ordering::AcqRel);
        if self.lose_device_after.is_some_and(|after| n >= after) {
            return Err(vk::Result::ERROR_DEVICE_LOST);
        }
        unsafe { self.device.queue_submit(self.queue, submits, fence) }
    }

    /// Write descriptors, as every descriptor write of sward's goes: counted, so a frame kept
    /// recorded (`recordings.rs`) is recorded anew once a set it binds has changed.
    pub fn update_descriptor_sets(&self, writes: &[vk::WriteDescriptorSet]) {
        self.descriptor_writes.fetch_add(1, Ordering::AcqRel);
        unsafe { self.device.update_descriptor_sets(writes, &[]) };
    }

    /// How many times descriptors were written so far.
    pub fn descriptor_writes(&self) -> u64 {
        self.descriptor_writes.load(Ordering::Acquire)
    }
}

/// A command pool on queue family `family` whose buffers are reset one by one (each recorded
/// anew from time to time); `what` names the work in an error.
pub(crate) fn command_pool(device: &ash::Device, family: u32, what: &'static str) -> Result<vk::CommandPool> {
    let info = vk::CommandPoolCreateInfo::default()
        .queue_family_index(family)
        .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
    unsafe { device.create_command_pool(&info, None) }.map_err(vk_check(what))
}

/// An allocator of sward's own on the device.
fn own_allocator(v: &ExistingDevice) -> Result<Allocator> {
    Allocator::new(&AllocatorCreateDesc {
        instance: v.instance.clone(),
        device: v.device.clone(),
        physical_device: v.physical_device,
        debug_settings: Default::default(),
        buffer_device_address: false,
        allocation_sizes: Default::default(),
    })
    .map_err(|e| GpuError::Allocation {
        what: "the memory allocator".into(),
        reason: e.to_string(),
    })
}

impl Drop for Context {
    fn drop(&mut self) {
        unsafe {
            let _ = self.device.device_wait_idle();
            ManuallyDrop::drop(&mut self.allocator);
            self.device
                .destroy_command_pool(*self.command_pool.get_mut().unwrap_or_else(|e| e.into_inner()), None);
            if self.owned {
                self.device.destroy_device(None);
            }
        }
        if self.owned {
            destroy_instance(&self.instance, &self.messenger);
        } else if let Some((loader, messenger)) = &self.messenger {
            unsafe { loader.destroy_debug_utils_messenger(*messenger, None) };
        }
    }
}

fn destroy_instance(instance: &ash::Instance, messenger: &Option<(debug_utils::Instance, vk::DebugUtilsMessengerEXT)>) {
    unsafe {
        if let Some((loader, messenger)) = messenger {
            loader.destroy_debug_utils_messenger(*messenger, None);
        }
        instance.destroy_instance(None);
    }
}

fn validation_wanted(entry: &ash::Entry, validation: Validation) -> Result<bool> {
    if validation == Validation::Off {
        return Ok(false);
    }
    let layers = unsafe { entry.enumerate_instance_layer_properties() }.unwrap_or_default();
    let installed = layers.iter().any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER));
    match (installed, validation) {
        (false, Validation::Required) => Err(GpuError::NoValidationLayer),
        (false, _) => {
            log::warn!("validation requested but VK_LAYER_KHRONOS_validation is not installed; running without it");
            Ok(false)
        }
        (true, _) => Ok(true),
    }
}

fn create_instance(
    entry: &ash::Entry,
    validation: bool,
    extra_extensions: &[*const std::ffi::c_char],
) -> Result<ash::Instance> {
    let app = vk::ApplicationInfo::default()
        .application_name(c"sward")
        .engine_name(c"sward")
        .api_version(vk::API_VERSION_1_3);
    let layers = if validation {
        vec![VALIDATION_LAYER.as_ptr()]
    } else {
        vec![]
    };
    let mut extensions = extra_extensions.to_vec();
    if validation {
        extensions.push(debug_utils::NAME.as_ptr());
        extensions.push(ash::ext::validation_features::NAME.as_ptr());
    }
    // With validation, synchronization validation too: a missing or too weak barrier between
    // simulate, cull, the indirect draws, the splat buffer and read-back is reported like any
    // other message (and fails the tests).
    let sync = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
    let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&sync);
    let mut info = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_layer_names(&layers)
        .enabled_extension_names(&extensions);
    if validation {
        info = info.push_next(&mut features);
    }
    unsafe { entry.create_instance(&info, None) }.map_err(|e| match e {
        vk::Result::ERROR_INCOMPATIBLE_DRIVER => GpuError::NoDriver,
        e => vk_check("creating the Vulkan instance")(e),
    })
}

unsafe extern "system" fn on_validation_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    sink: *mut c_void,
) -> vk::Bool32 {
    let text = unsafe {
        if data.is_null() || (*data).p_message.is_null() {
            "(no message)".to_string()
        } else {
            CStr::from_ptr((*data).p_message).to_string_lossy().into_owned()
        }
    };
    log::error!("Vulkan validation ({severity:?}): {text}");
    // SAFETY: `sink` is the Mutex inside the context's Arc, which outlives the messenger.
    let sink = unsafe { &*(sink as *const Mutex<Vec<String>>) };
    sink.lock().unwrap_or_else(|e| e.into_inner()).push(text);
    vk::FALSE
}

fn create_messenger(
    entry: &ash::Entry,
    instance: &ash::Instance,
    sink: &Arc<Mutex<Vec<String>>>,
) -> Result<(debug_utils::Instance, vk::DebugUtilsMessengerEXT)> {
    let loader = debug_utils::Instance::new(entry, instance);
    let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
        .message_type(vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION | vk::DebugUtilsMessageTypeFlagsEXT::GENERAL)
        .pfn_user_callback(Some(on_validation_message))
        .user_data(Arc::as_ptr(sink) as *mut c_void);
    let messenger = unsafe { loader.create_debug_utils_messenger(&info, None) }
        .map_err(vk_check("creating the validation messenger"))?;
    Ok((loader, messenger))
}

/// The queue family with graphics, compute and timestamps.
fn queue_family(instance: &ash::Instance, device: vk::PhysicalDevice) -> Option<u32> {
    let families = unsafe { instance.get_physical_device_queue_family_properties(device) };
    families
        .iter()
        .position(|f| {
            f.queue_flags
                .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
                && f.timestamp_valid_bits > 0
        })
        .map(|i| i as u32)
}

fn candidate(instance: &ash::Instance, index: usize, device: vk::PhysicalDevice, presents: bool) -> DeviceCandidate {
    let props = unsafe { instance.get_physical_device_properties(device) };
    let mut features11 = vk::PhysicalDeviceVulkan11Features::default();
    let mut features12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut features13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut features = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut features13)
        .push_next(&mut features12)
        .push_next(&mut features11);
    let mut missing = Vec::new();
    if props.api_version < vk::API_VERSION_1_3 {
        missing.push("Vulkan 1.3");
    } else {
        unsafe { instance.get_physical_device_features2(device, &mut features) };
        let f = features.features;
        let checks = [
            (f.tessellation_shader, "tessellationShader"),
            (f.multi_draw_indirect, "multiDrawIndirect"),
            (
                props.limits.timestamp_compute_and_graphics,
                "timestampComputeAndGraphics",
            ),
            (features13.dynamic_rendering, "dynamicRendering"),
            (features13.synchronization2, "synchronization2"),
            (features11.shader_draw_parameters, "shaderDrawParameters"),
            (f.shader_int64, "shaderInt64"),
        ];
        missing.extend(checks.iter().filter(|(ok, _)| *ok == vk::FALSE).map(|(_, name)| *name));
    }
    if presents && !supports_swapchain(instance, device) {
        missing.push("VK_KHR_swapchain");
    }
    if queue_family(instance, device).is_none() {
        missing.push("a queue with graphics, compute and timestamps");
    }
    let name = props
        .device_name_as_c_str()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    DeviceCandidate {
        index,
        name,
        kind: props.device_type,
        missing,
    }
}

fn supports_swapchain(instance: &ash::Instance, device: vk::PhysicalDevice) -> bool {
    let extensions = unsafe { instance.enumerate_device_extension_properties(device) }.unwrap_or_default();
    extensions
        .iter()
        .any(|e| e.extension_name_as_c_str() == Ok(khr::swapchain::NAME))
}

/// Every physical device of a Vulkan instance, in the order `--gpu` numbers them: what it is
/// (its index, name, kind and what it lacks of sward's needs; usable where that is empty) and
/// what it offers. Fails only where there is no Vulkan loader or driver.
pub fn list_devices() -> Result<Vec<(DeviceCandidate, DeviceInfo)>> {
    let entry = unsafe { ash::Entry::load() }.map_err(|e| GpuError::NoLoader(e.to_string()))?;
    let instance = create_instance(&entry, false, &[])?;
    let devices = unsafe { instance.enumerate_physical_devices() }.map_err(|_| GpuError::NoDriver);
    let listed = devices.map(|devices| {
        devices
            .into_iter()
            .enumerate()
            .map(|(index, device)| (candidate(&instance, index, device, false), describe(&instance, device)))
            .collect()
    });
    destroy_instance(&instance, &None);
    listed
}

fn pick_physical_device(
    instance: &ash::Instance,
    wanted: Option<&str>,
    presents: bool,
) -> Result<(vk::PhysicalDevice, u32)> {
    let devices = unsafe { instance.enumerate_physical_devices() }.map_err(|_| GpuError::NoDriver)?;
    let candidates: Vec<DeviceCandidate> = devices
        .iter()
        .enumerate()
        .map(|(i, d)| candidate(instance, i, *d, presents))
        .collect();
    let chosen = devices[choose_device(&candidates, wanted)?];
    Ok((
        chosen,
        queue_family(instance, chosen).expect("usable devices have a queue family"),
    ))
}

fn describe(instance: &ash::Instance, device: vk::PhysicalDevice) -> DeviceInfo {
    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
    let mut props2 = vk::PhysicalDeviceProperties2::default()
        .push_next(&mut driver)
        .push_next(&mut subgroup);
    unsafe { instance.get_physical_device_properties2(device, &mut props2) };
    let props = props2.properties;
    let features = unsafe { instance.get_physical_device_features(device) };
    let v = props.api_version;
    DeviceInfo {
        name: props
            .device_name_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        driver_name: driver
            .driver_name_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        driver_info: driver
            .driver_info_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        driver_id: driver.driver_id,
        kind: props.device_type,
        api_version: format!(
            "{}.{}.{}",
            vk::api_version_major(v),
            vk::api_version_minor(v),
            vk::api_version_patch(v)
        ),
        timestamp_period: props.limits.timestamp_period,
        subgroup_ballot: subgroup.supported_stages.contains(vk::ShaderStageFlags::COMPUTE)
            && subgroup.supported_operations.contains(
                vk::SubgroupFeatureFlags::BALLOT | vk::SubgroupFeatureFlags::VOTE | vk::SubgroupFeatureFlags::BASIC,
            ),
        wireframe: features.fill_mode_non_solid == vk::TRUE,
        max_storage_buffer_range: props.limits.max_storage_buffer_range as u64,
        max_workgroups_x: props.limits.max_compute_work_group_count[0],
        max_workgroups_y: props.limits.max_compute_work_group_count[1],
        max_workgroup_invocations: props.limits.max_compute_work_group_size[0]
            .min(props.limits.max_compute_work_group_invocations),
        max_workgroup_shared: props.limits.max_compute_shared_memory_size,
        pipeline_statistics: features.pipeline_statistics_query == vk::TRUE,
        sample_counts: props.limits.framebuffer_color_sample_counts & props.limits.framebuffer_depth_sample_counts,
        mesh_shaders: has_mesh_shaders(instance, device),
        int64_atomics: has_int64_atomics(instance, device),
        inherited_queries: features.inherited_queries == vk::TRUE,
    }
}

/// `info` as if the device lacked the features `withheld` names.
fn withhold(mut info: DeviceInfo, withheld: Withheld) -> DeviceInfo {
    info.mesh_shaders &= !withheld.mesh_shaders;
    info.int64_atomics &= !withheld.int64_atomics;
    info
}

/// Whether the device has 64-bit atomics on storage buffers (shaderBufferInt64Atomics).
fn has_int64_atomics(instance: &ash::Instance, device: vk::PhysicalDevice) -> bool {
    let mut features12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut features12);
    unsafe { instance.get_physical_device_features2(device, &mut features) };
    features12.shader_buffer_int64_atomics == vk::TRUE
}

/// Whether the device has VK_EXT_mesh_shader with its mesh (not necessarily task) stage.
fn has_mesh_shaders(instance: &ash::Instance, device: vk::PhysicalDevice) -> bool {
    let extensions = unsafe { instance.enumerate_device_extension_properties(device) }.unwrap_or_default();
    let listed = extensions
        .iter()
        .any(|e| e.extension_name_as_c_str() == Ok(ash::ext::mesh_shader::NAME));
    if !listed {
        return false;
    }
    let mut mesh = vk::PhysicalDeviceMeshShaderFeaturesEXT::default();
    let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut mesh);
    unsafe { instance.get_physical_device_features2(device, &mut features) };
    mesh.mesh_shader == vk::TRUE
}

/// Create a logical device on `physical` with one queue of `queue_family`, everything sward
/// needs enabled and `extensions` besides (e.g. VK_KHR_swapchain): for an application that
/// owns its device and adds sward to it ([`Context::from_device`]). The caller destroys it.
pub fn create_device_for(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    queue_family: u32,
    extensions: &[&CStr],
) -> Result<ash::Device> {
    let info = describe(instance, physical);
    create_device(instance, physical, queue_family, &info, extensions)
}

fn create_device(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    family: u32,
    info: &DeviceInfo,
    extra_extensions: &[&CStr],
) -> Result<ash::Device> {
    let priorities = [1.0];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(family)
        .queue_priorities(&priorities)];
    let features = vk::PhysicalDeviceFeatures::default()
        .tessellation_shader(true)
        .multi_draw_indirect(true)
        .shader_int64(true)
        .fill_mode_non_solid(info.wireframe)
        .pipeline_statistics_query(info.pipeline_statistics)
        // A frame's passes are kept recorded in a secondary command buffer and replayed into
        // the caller's, which may have a query open (the bench counts fragments).
        .inherited_queries(info.inherited_queries);
    let mut features13 = vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(true)
        .synchronization2(true)
        // Required by Vulkan 1.3; `discard` compiles to demote-to-helper (splat_resolve.wesl).
        .shader_demote_to_helper_invocation(true)
        // Core in 1.3; needed for workgroup sizes set by specialisation (LocalSizeId).
        .maintenance4(true);
    // gl_DrawID picks the instanced grass's level in its multi-draw.
    let mut features11 = vk::PhysicalDeviceVulkan11Features::default().shader_draw_parameters(true);
    // The splatted far field keeps the nearest (depth, colour) per pixel with a 64-bit atomicMin.
    let mut features12 = vk::PhysicalDeviceVulkan12Features::default().shader_buffer_int64_atomics(info.int64_atomics);
    // The mesh draw route, where the device has it; nothing else depends on it.
    let mut mesh = vk::PhysicalDeviceMeshShaderFeaturesEXT::default().mesh_shader(true);
    let mut features2 = vk::PhysicalDeviceFeatures2::default()
        .features(features)
        .push_next(&mut features13)
        .push_next(&mut features12)
        .push_next(&mut features11);
    let mut extensions: Vec<*const std::ffi::c_char> = extra_extensions.iter().map(|e| e.as_ptr()).collect();
    if info.mesh_shaders {
        extensions.push(ash::ext::mesh_shader::NAME.as_ptr());
        features2 = features2.push_next(&mut mesh);
    }
    let create = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_extension_names(&extensions)
        .push_next(&mut features2);
    unsafe { instance.create_device(physical, &create, None) }.map_err(vk_check("creating the Vulkan device"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn device(index: usize, name: &str, kind: vk::PhysicalDeviceType, missing: Vec<&'static str>) -> DeviceCandidate {
        DeviceCandidate {
            index,
            name: name.into(),
            kind,
            missing,
        }
    }

    #[test]
    fn a_device_without_tessellation_is_refused_by_name() {
        let only = [device(
            0,
            "TinyGPU",
            vk::PhysicalDeviceType::INTEGRATED_GPU,
            vec!["tessellationShader"],
        )];
        let e = choose_device(&only, None).unwrap_err().to_string();
        assert!(
            e.contains("TinyGPU lacks tessellationShader") && e.contains("sward needs"),
            "{e}"
        );
    }

    #[test]
    fn discrete_beats_cpu_and_gpu_flag_overrides() {
        let all = [
            device(0, "llvmpipe", vk::PhysicalDeviceType::CPU, vec![]),
            device(1, "Big GPU", vk::PhysicalDeviceType::DISCRETE_GPU, vec![]),
            device(2, "Old GPU", vk::PhysicalDeviceType::DISCRETE_GPU, vec!["Vulkan 1.3"]),
        ];
        assert_eq!(choose_device(&all, None).unwrap(), 1);
        assert_eq!(choose_device(&all, Some("LLVM")).unwrap(), 0);
        assert_eq!(choose_device(&all, Some("0")).unwrap(), 0);
        let e = choose_device(&all, Some("Old")).unwrap_err().to_string();
        assert!(e.contains("0: llvmpipe") && e.contains("1: Big GPU"), "{e}");
        assert!(matches!(choose_device(&[], None), Err(GpuError::NoDriver)));
    }
}
