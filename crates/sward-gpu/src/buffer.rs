//! GPU buffers: a `vk::Buffer` with its memory, freed in `Drop`; uploads and read-backs through
//! a staging buffer when the memory is not visible to the host.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use crate::context::Context;
use crate::error::{vk_check, GpuError, Result};

/// A buffer and its memory, freed when dropped.
pub struct Buffer {
    /// The Vulkan buffer.
    pub raw: vk::Buffer,
    /// Its size in bytes.
    pub size: u64,
    allocation: Option<Allocation>,
    ctx: Arc<Context>,
}

impl Buffer {
    /// A buffer of `size` bytes; `name` appears in errors and allocator reports.
    pub fn new(
        ctx: &Arc<Context>,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Buffer> {
        let d = &ctx.device;
        let info = vk::BufferCreateInfo::default()
            .size(size.max(4))
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let raw = unsafe { d.create_buffer(&info, None) }.map_err(vk_check("creating a buffer"))?;
        let requirements = unsafe { d.get_buffer_memory_requirements(raw) };
        let allocation = allocate(ctx, name, requirements, location, true).inspect_err(|_| unsafe {
            d.destroy_buffer(raw, None);
        })?;
        unsafe { d.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) }
            .map_err(vk_check("binding buffer memory"))?;
        Ok(Buffer {
            raw,
            size,
            allocation: Some(allocation),
            ctx: ctx.clone(),
        })
    }

    /// A device-local buffer filled with `data` (copied through a staging buffer).
    pub fn with_data(ctx: &Arc<Context>, name: &str, data: &[u8], usage: vk::BufferUsageFlags) -> Result<Buffer> {
        let buffer = Buffer::new(
            ctx,
            name,
            data.len() as u64,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        buffer.upload(0, data)?;
        Ok(buffer)
    }

    /// A second `vk::Buffer` of this one's size and `usage` over this one's memory, for another
    /// owner of the device (wgpu) to hold and destroy: both see the same bytes. The alias must
    /// not be used once this buffer is dropped.
    pub fn alias(&self, usage: vk::BufferUsageFlags) -> Result<vk::Buffer> {
        let d = &self.ctx.device;
        let allocation = self
            .allocation
            .as_ref()
            .expect("a buffer holds its memory until dropped");
        let info = vk::BufferCreateInfo::default()
            .size(self.size.max(4))
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let raw = unsafe { d.create_buffer(&info, None) }.map_err(vk_check("creating a buffer"))?;
        unsafe { d.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) }
            .map_err(vk_check("binding buffer memory"))
            .inspect_err(|_| unsafe { d.destroy_buffer(raw, None) })?;
        Ok(raw)
    }

    /// Bytes the host can write directly (only for host-visible buffers).
    pub fn mapped_mut(&mut self) -> Option<&mut [u8]> {
        self.allocation.as_mut()?.mapped_slice_mut()
    }

    /// Bytes the host can read directly (only for host-visible buffers).
    pub fn mapped(&self) -> Option<&[u8]> {
        self.allocation.as_ref()?.mapped_slice()
    }

    /// Copy `data` into the buffer at `offset` and wait for it, through a staging buffer of at
    /// most `STAGING_BYTES`, so a large field needs no second copy of itself on the GPU.
    pub fn upload(&self, offset: u64, data: &[u8]) -> Result<()> {
        if data.is_empty() {
            return Ok(());
        }
        let mut staging = Buffer::new(
            &self.ctx,
            "staging upload",
            (data.len() as u64).min(STAGING_BYTES),
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        for (k, chunk) in data.chunks(STAGING_BYTES as usize).enumerate() {
            staging.mapped_mut().expect("staging memory is host visible")[..chunk.len()].copy_from_slice(chunk);
            let region = vk::BufferCopy {
                src_offset: 0,
                dst_offset: offset + k as u64 * STAGING_BYTES,
                size: chunk.len() as u64,
            };
            self.ctx.submit_and_wait("uploading a buffer", |cmd| unsafe {
                self.ctx.device.cmd_copy_buffer(cmd, staging.raw, self.raw, &[region]);
            })?;
        }
        Ok(())
    }

    /// Copy the whole buffer back to the host (the buffer needs TRANSFER_SRC usage).
    pub fn download(&self) -> Result<Vec<u8>> {
        let staging = Buffer::new(
            &self.ctx,
            "staging download",
            self.size,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let region = vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size: self.size,
        };
        self.ctx.submit_and_wait("reading a buffer back", |cmd| unsafe {
            self.ctx.device.cmd_copy_buffer(cmd, self.raw, staging.raw, &[region]);
        })?;
        Ok(staging.mapped().expect("read-back memory is host visible")[..self.size as usize].to_vec())
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        if let Some(allocation) = self.allocation.take() {
            free(&self.ctx, allocation);
        }
        unsafe { self.ctx.device.destroy_buffer(self.raw, None) };
    }
}

/// Largest staging buffer an upload uses.
pub const STAGING_BYTES: u64 = 32 << 20;

/// Allocate memory for `requirements`, counted against the context's memory limit first: past
/// it, the error is the same as the driver's out-of-memory.
pub(crate) fn allocate(
    ctx: &Context,
    name: &str,
    requirements: vk::MemoryRequirements,
    location: MemoryLocation,
    linear: bool,
) -> Result<Allocation> {
    if !ctx.memory.reserve(requirements.size) {
        return Err(GpuError::OutOfMemory {
            what: name.to_string(),
            bytes: requirements.size,
        });
    }
    ctx.allocator()
        .allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        })
        .map_err(|e| {
            ctx.memory.release(requirements.size);
            allocation_error(name, requirements.size, e)
        })
}

/// Free what `allocate` gave, and its count against the limit.
pub(crate) fn free(ctx: &Context, allocation: Allocation) {
    ctx.memory.release(allocation.size());
    let _ = ctx.allocator().free(allocation);
}

fn allocation_error(name: &str, bytes: u64, e: gpu_allocator::AllocationError) -> GpuError {
    match e {
        gpu_allocator::AllocationError::OutOfMemory => GpuError::OutOfMemory {
            what: name.to_string(),
            bytes,
        },
        e => GpuError::Allocation {
            what: name.to_string(),
            reason: e.to_string(),
        },
    }
}
