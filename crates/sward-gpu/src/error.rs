//! What can go wrong on the GPU side, each as one sentence a user can act on. Raw `VkResult`s are
//! wrapped with the operation that produced them, never shown alone.

use ash::vk;

/// Everything that can go wrong on the GPU side; each displays as one sentence.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// The Vulkan loader library is missing.
    #[error("the Vulkan loader (libvulkan.so.1) could not be loaded ({0}); install it (Debian/Ubuntu: apt-get install libvulkan1 mesa-vulkan-drivers)")]
    NoLoader(String),
    /// The loader found no driver.
    #[error("no Vulkan driver was found; install one (Debian/Ubuntu: apt-get install mesa-vulkan-drivers for the CPU driver lavapipe, or your GPU vendor's driver)")]
    NoDriver,
    /// No device has what sward needs; the text says what each lacks.
    #[error("no Vulkan device can run sward: {0}; sward needs Vulkan 1.3 with tessellation shaders, multiDrawIndirect, timestamps on graphics and compute queues, dynamic rendering and synchronization2")]
    NoSuitableDevice(String),
    /// `--gpu` named no usable device.
    #[error("--gpu {wanted} matches no usable Vulkan device; usable devices are: {available}")]
    GpuNotFound {
        /// What was asked for.
        wanted: String,
        /// The usable devices, by index and name.
        available: String,
    },
    /// Validation was required but the layer is not installed.
    #[error("the Khronos validation layer (VK_LAYER_KHRONOS_validation) is required here but not installed; install it (Debian/Ubuntu: apt-get install vulkan-validationlayers)")]
    NoValidationLayer,
    /// An allocation did not fit the GPU's memory (or `--gpu-memory`).
    #[error("the GPU ran out of memory while allocating {what} ({bytes} bytes); use fewer blades or a smaller image")]
    OutOfMemory {
        /// What was being allocated.
        what: String,
        /// Its size.
        bytes: u64,
    },
    /// A field does not fit the GPU memory left, but a smaller one does.
    #[error("a field of {blades} blades needs {needs_mib} MiB of GPU memory, but only {free_mib} MiB are free on this GPU; at most {max_blades} blades fit")]
    FieldOutOfMemory {
        /// Blades asked for.
        blades: u64,
        /// Memory they need.
        needs_mib: u64,
        /// Memory left.
        free_mib: u64,
        /// The most blades that fit.
        max_blades: u64,
    },
    /// No field at all fits the GPU memory left.
    #[error("a field of {blades} blades needs {needs_mib} MiB of GPU memory, but only {free_mib} MiB are free on this GPU, too little for any field; use a smaller image")]
    NoRoomForField {
        /// Blades asked for.
        blades: u64,
        /// Memory they need.
        needs_mib: u64,
        /// Memory left.
        free_mib: u64,
    },
    /// An image does not fit the GPU memory left, but a smaller one of its shape does.
    #[error("a {width}×{height} image needs {needs_mib} MiB of GPU memory, but only {free_mib} MiB are free on this GPU; the largest image of that shape that fits is {max_width}×{max_height}")]
    ImageOutOfMemory {
        /// Width asked for.
        width: u32,
        /// Height asked for.
        height: u32,
        /// Memory it needs.
        needs_mib: u64,
        /// Memory left.
        free_mib: u64,
        /// Width of the largest that fits.
        max_width: u32,
        /// Height of the largest that fits.
        max_height: u32,
    },
    /// A field is larger than one storage buffer of the device may be.
    #[error("a field of {blades} blades needs {bytes} bytes of blade storage, more than this GPU's largest storage buffer ({limit} bytes); lower field.blades to at most {max_blades} (--set field.blades={max_blades})")]
    FieldTooLarge {
        /// Blades asked for.
        blades: u64,
        /// Bytes they need.
        bytes: u64,
        /// The device's largest storage buffer.
        limit: u64,
        /// The most blades that fit it.
        max_blades: u64,
    },
    /// A field needs more workgroups than one dispatch may have.
    #[error("a field of {blades} blades needs more compute workgroups than this GPU dispatches at once; lower field.blades to at most {max_blades} (--set field.blades={max_blades})")]
    TooManyWorkgroups {
        /// Blades asked for.
        blades: u64,
        /// The most one dispatch covers.
        max_blades: u64,
    },
    /// The device was lost (a driver crash or timeout).
    #[error("the GPU was lost while {during} (a driver crash or timeout), so sward cannot go on; start it again, and if it happens again use fewer blades or a smaller image")]
    DeviceLost {
        /// What sward was doing.
        during: &'static str,
    },
    /// A pass's shader that does not compile (a shader directory's variant).
    #[error("the shader of the {pass} pass does not compile: {message}")]
    Shader {
        /// The pass.
        pass: String,
        /// naga's or WESL's message.
        message: String,
    },
    /// Any other Vulkan failure, with the operation that met it.
    #[error("{what} failed: {result:?}")]
    Vulkan {
        /// The operation.
        what: &'static str,
        /// Vulkan's result.
        result: vk::Result,
    },
    /// The allocator failed for a reason other than memory.
    #[error("allocating {what} failed: {reason}")]
    Allocation {
        /// What was being allocated.
        what: String,
        /// The allocator's reason.
        reason: String,
    },
}

/// sward-gpu's results.
pub type Result<T> = std::result::Result<T, GpuError>;

/// Attach the operation's name to a raw Vulkan result, mapping the results a user can act on.
pub fn vk_check(what: &'static str) -> impl Fn(vk::Result) -> GpuError {
    move |result| match result {
        vk::Result::ERROR_OUT_OF_DEVICE_MEMORY | vk::Result::ERROR_OUT_OF_HOST_MEMORY => GpuError::OutOfMemory {
            what: what.to_string(),
            bytes: 0,
        },
        vk::Result::ERROR_DEVICE_LOST => GpuError::DeviceLost { during: what },
        result => GpuError::Vulkan { what, result },
    }
}
