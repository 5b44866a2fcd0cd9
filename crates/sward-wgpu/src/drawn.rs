//! The Bezier blades for an application that draws them itself, in its own passes (sward-bevy
//! draws them in Bevy's, lit and shadowed by Bevy): sward's buffers as `wgpu::Buffer`s. Each is
//! a second `VkBuffer` over sward's memory ([`sward_gpu::buffer::Buffer::alias`]), owned by
//! wgpu, so that wgpu binds and tracks it like its own.

use ash::vk;
use sward_gpu::buffer::Buffer;
use wgpu::hal::api::Vulkan;

use crate::BridgeError;

/// The buffers an application's draw of the Bezier blades reads, as wgpu buffers. Its vertex
/// stage draws instance `i` of distance bucket `k`'s command as the drawn blade `i` (two words
/// of four, sward-core `shaders/drawn_blades.wesl`), and the blade it names.
#[derive(Clone, Debug)]
pub struct DrawnBlades {
    /// The blades (`sward_core::gpu::Blade`, 64 bytes each), positions measured from the
    /// frame's origin; a storage buffer.
    pub blades: wgpu::Buffer,
    /// The blades as the last frame drew them (copied before each frame simulates), for
    /// motion vectors; a storage buffer.
    pub previous_blades: wgpu::Buffer,
    /// Each view's list, as the frame culled the blades for its camera.
    pub views: Vec<DrawnView>,
}

/// What one view draws: the blades its camera's cull kept, and the draw commands of them.
#[derive(Clone, Debug)]
pub struct DrawnView {
    /// The drawn blades in draw order; a storage buffer.
    pub drawn: wgpu::Buffer,
    /// The draw commands (`sward_core::gpu::DrawCommand`, 16 bytes each): the distance buckets'
    /// from [`DrawnBlades::FIRST_BUCKET_COMMAND`] on, [`DrawnBlades::BUCKETS`] of them; an
    /// indirect and storage buffer.
    pub draws: wgpu::Buffer,
    /// Per frame in flight, that frame's uniforms for this view (`sward_core::gpu::FrameUniforms`
    /// in blocks: `sward_core::declared::frame_blocks` gives each block's binding, offset and
    /// size); a uniform buffer.
    /// [`crate::GrassRenderer::drawn_blades`] says which the last frame wrote.
    pub uniforms: Vec<wgpu::Buffer>,
}

impl DrawnBlades {
    /// The first distance bucket's draw command in [`DrawnView::draws`].
    pub const FIRST_BUCKET_COMMAND: u32 = sward_core::commands::COMMAND_BUCKETS;
    /// Distance buckets: one draw command each.
    pub const BUCKETS: u32 = sward_core::commands::DISTANCE_BUCKETS;

    /// sward's `blades` and the copy of them last drawn, as wgpu buffers on `device` (the
    /// device sward's context lives on), with each view's.
    pub(crate) fn wrap(
        device: &wgpu::Device,
        blades: &Buffer,
        previous: &Buffer,
        views: Vec<DrawnView>,
    ) -> Result<DrawnBlades, BridgeError> {
        Ok(DrawnBlades {
            blades: wrap(device, blades, "sward: the blades", STORAGE)?,
            previous_blades: wrap(device, previous, "sward: the blades last drawn", STORAGE)?,
            views,
        })
    }
}

impl DrawnView {
    /// A view's list, draw commands and uniforms (one per frame in flight) as wgpu buffers.
    pub(crate) fn wrap(
        device: &wgpu::Device,
        drawn: &Buffer,
        draws: &Buffer,
        uniforms: &[&Buffer],
    ) -> Result<DrawnView, BridgeError> {
        let indirect = (
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::INDIRECT_BUFFER,
        );
        let uniform = (wgpu::BufferUsages::UNIFORM, vk::BufferUsageFlags::UNIFORM_BUFFER);
        Ok(DrawnView {
            drawn: wrap(device, drawn, "sward: the drawn blades", STORAGE)?,
            draws: wrap(device, draws, "sward: the draw commands", indirect)?,
            uniforms: uniforms
                .iter()
                .map(|u| wrap(device, u, "sward: a frame's uniforms", uniform))
                .collect::<Result<_, _>>()?,
        })
    }
}

/// A storage buffer, to wgpu and to Vulkan.
const STORAGE: (wgpu::BufferUsages, vk::BufferUsageFlags) =
    (wgpu::BufferUsages::STORAGE, vk::BufferUsageFlags::STORAGE_BUFFER);

/// `buffer` as a wgpu buffer of `usage`, over the same memory.
fn wrap(
    device: &wgpu::Device,
    buffer: &Buffer,
    label: &str,
    (usage, vk_usage): (wgpu::BufferUsages, vk::BufferUsageFlags),
) -> Result<wgpu::Buffer, BridgeError> {
    let raw = buffer.alias(vk_usage)?;
    // SAFETY: the alias is a new buffer on wgpu's device, made with the usage described, over
    // memory sward holds until its renderer drops (after these: `GrassRenderer` lets them go
    // first); wgpu owns and destroys the alias.
    let hal = unsafe { wgpu::hal::vulkan::Buffer::from_raw(raw) };
    let desc = wgpu::BufferDescriptor {
        label: Some(label),
        size: buffer.size,
        usage,
        mapped_at_creation: false,
    };
    Ok(unsafe { device.create_buffer_from_hal::<Vulkan>(hal, &desc) })
}
