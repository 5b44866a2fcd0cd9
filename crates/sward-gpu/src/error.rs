//! What can go wrong on the GPU side, each as one sentence a user can act on. Raw `VkResult`s are
//! wrapped with the operation that produced them, never shown alone.

use ash::vk;

#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error("the Vulkan loader (libvulkan.so.1) could not be loaded ({0}); install it (Debian/Ubuntu: apt-get install libvulkan1 mesa-vulkan-drivers)")]
    NoLoader(String),
    #[error("no Vulkan driver was found; install one (Debian/Ubuntu: apt-get install mesa-vulkan-drivers for the CPU driver lavapipe, or your GPU vendor's driver)")]
    NoDriver,
    #[error("no Vulkan device can run sward: {0}; sward needs Vulkan 1.3 with tessellation shaders, multiDrawIndirect, timestamps on graphics and compute queues, dynamic rendering and synchronization2")]
    NoSuitableDevice(String),
    #[error("--gpu {wanted} matches no usable Vulkan device; usable devices are: {available}")]
    GpuNotFound { wanted: String, available: String },
    #[error("the Khronos validation layer (VK_LAYER_KHRONOS_validation) is required here but not installed; install it (Debian/Ubuntu: apt-get install vulkan-validationlayers)")]
    NoValidationLayer,
    #[error("the GPU ran out of memory while allocating {what} ({bytes} bytes); use fewer blades or a smaller image")]
    OutOfMemory { what: String, bytes: u64 },
    #[error("a field of {blades} blades needs {needs_mib} MiB of GPU memory, but only {free_mib} MiB are free on this GPU; at most {max_blades} blades fit")]
    FieldOutOfMemory {
        blades: u64,
        needs_mib: u64,
        free_mib: u64,
        max_blades: u64,
    },
    #[error("a field of {blades} blades needs {needs_mib} MiB of GPU memory, but only {free_mib} MiB are free on this GPU, too little for any field; use a smaller image")]
    NoRoomForField { blades: u64, needs_mib: u64, free_mib: u64 },
    #[error("a {width}×{height} image needs {needs_mib} MiB of GPU memory, but only {free_mib} MiB are free on this GPU; the largest image of that shape that fits is {max_width}×{max_height}")]
    ImageOutOfMemory {
        width: u32,
        height: u32,
        needs_mib: u64,
        free_mib: u64,
        max_width: u32,
        max_height: u32,
    },
    #[error("a field of {blades} blades needs {bytes} bytes of blade storage, more than this GPU's largest storage buffer ({limit} bytes); use at most {max_blades} blades")]
    FieldTooLarge {
        blades: u64,
        bytes: u64,
        limit: u64,
        max_blades: u64,
    },
    #[error("a field of {blades} blades needs more compute workgroups than this GPU dispatches at once; use at most {max_blades} blades")]
    TooManyWorkgroups { blades: u64, max_blades: u64 },
    #[error("the {route} draw route needs {needs}, which {device} lacks; its routes are {available}")]
    RouteUnavailable {
        route: &'static str,
        needs: &'static str,
        device: String,
        available: String,
    },
    #[error("the GPU was lost while {during} (a driver crash or timeout), so sward cannot go on; start it again, and if it happens again use fewer blades or a smaller image")]
    DeviceLost { during: &'static str },
    #[error("{what} failed: {result:?}")]
    Vulkan { what: &'static str, result: vk::Result },
    #[error("allocating {what} failed: {reason}")]
    Allocation { what: String, reason: String },
}

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
