//! GPU buffers: a `vk::Buffer` with its memory, freed in `Drop`; uploads and read-backs through
//! a staging buffer when the memory is not visible to the host.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use crate::context::Context;
use crate::error::{vk_check, GpuError, Result};

pub struct Buffer {
    pub raw: vk::Buffer,
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
        let allocation = ctx
            .allocator()
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location,
                linear: true,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|e| {
                unsafe { d.destroy_buffer(raw, None) };
                allocation_error(name, size, e)
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

    /// Bytes the host can write directly (only for host-visible buffers).
    pub fn mapped_mut(&mut self) -> Option<&mut [u8]> {
        self.allocation.as_mut()?.mapped_slice_mut()
    }

    pub fn mapped(&self) -> Option<&[u8]> {
        self.allocation.as_ref()?.mapped_slice()
    }

    /// Copy `data` into the buffer at `offset` and wait for it.
    pub fn upload(&self, offset: u64, data: &[u8]) -> Result<()> {
        if data.is_empty() {
            return Ok(());
        }
        let mut staging = Buffer::new(
            &self.ctx,
            "staging upload",
            data.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        staging.mapped_mut().expect("staging memory is host visible")[..data.len()].copy_from_slice(data);
        let region = vk::BufferCopy {
            src_offset: 0,
            dst_offset: offset,
            size: data.len() as u64,
        };
        self.ctx.submit_and_wait("uploading a buffer", |cmd| unsafe {
            self.ctx.device.cmd_copy_buffer(cmd, staging.raw, self.raw, &[region]);
        })
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
            let _ = self.ctx.allocator().free(allocation);
        }
        unsafe { self.ctx.device.destroy_buffer(self.raw, None) };
    }
}

pub(crate) fn allocation_error(name: &str, bytes: u64, e: gpu_allocator::AllocationError) -> GpuError {
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
