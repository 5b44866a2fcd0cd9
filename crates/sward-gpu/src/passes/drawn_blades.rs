//! The listed blades for a renderer that draws them itself (`sward-bevy` draws them in Bevy's
//! own passes, lit by Bevy's lights and shadows): `drawn_blades.wesl` writes, after the ordering,
//! each ordered entry's blade, outline, strip length and colours into a buffer the frame's set
//! binds at `bindings::DRAWN_BLADES`. That renderer reads it beside the blades and draws the
//! distance buckets' commands. Off (one record) until asked for.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::barrier::{self, Access};
use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::Result;
use crate::pipelines::{bindings, Builder, Pipeline};
use crate::shaders;

/// Bytes of one drawn blade: two words of four (`drawn_blades.wesl`).
pub const DRAWN_BLADE_BYTES: u64 = 32;

/// The drawn blades' buffers, where they are asked for: one list per view that draws in the
/// same frame (split screen, a minimap: each camera culls for itself), frame slot `k`'s set
/// pointing at list `k % lists`.
pub(crate) struct DrawnBlades {
    lists: Vec<Buffer>,
    /// Whether each frame writes them.
    pub(crate) on: bool,
    ctx: Arc<Context>,
}

impl DrawnBlades {
    /// Off: one list of one record, so the binding always points somewhere.
    pub fn new(ctx: &Arc<Context>, sets: &[vk::DescriptorSet]) -> Result<DrawnBlades> {
        let drawn = DrawnBlades {
            lists: vec![drawn_buffer(ctx, 1)?],
            on: false,
            ctx: ctx.clone(),
        };
        drawn.write_descriptors(sets);
        Ok(drawn)
    }

    /// Write `lists` lists each frame for a field of `blades` (or stop: `None`), pointing every
    /// set at a buffer that holds them; waits for the GPU where the buffers change.
    pub fn prepare(&mut self, sets: &[vk::DescriptorSet], blades: Option<u32>, lists: usize) -> Result<()> {
        self.on = blades.is_some();
        let lists = if self.on { lists.max(1) } else { 1 };
        let wanted = blades.unwrap_or(0).max(1) as u64 * DRAWN_BLADE_BYTES;
        if self.lists.len() != lists || self.lists.iter().any(|list| list.size != wanted) {
            unsafe { self.ctx.device.device_wait_idle() }.map_err(crate::error::vk_check("waiting for the GPU"))?;
            // The old lists go before the new are made.
            self.lists.clear();
            for _ in 0..lists {
                self.lists.push(drawn_buffer(&self.ctx, wanted / DRAWN_BLADE_BYTES)?);
            }
            self.write_descriptors(sets);
        }
        Ok(())
    }

    /// The list frame slot `slot` writes, where they are written.
    pub fn buffer(&self, slot: usize) -> Option<&Buffer> {
        self.on.then(|| &self.lists[slot % self.lists.len()])
    }

    /// The lists kept (one per view of a frame).
    pub fn lists(&self) -> usize {
        self.lists.len()
    }

    /// The pass's pipeline.
    pub(crate) fn pipeline(b: &Builder) -> Result<Pipeline> {
        b.compute_wgsl(&shaders::DRAWN_BLADES)
    }

    /// The frame's `drawn_blades.wesl` over a field of `blades` (the frame's set bound), once
    /// the list is in order; the draws that read them come after.
    pub fn record(&self, cmd: vk::CommandBuffer, pipeline: vk::Pipeline, (blades, workgroup): (u32, u32)) {
        let d = &self.ctx.device;
        let groups = blades.div_ceil(workgroup).max(1);
        // At most 65535 workgroups along x: the rest in rows.
        let across = groups.min(65535);
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
            d.cmd_dispatch(cmd, across, groups.div_ceil(across), 1);
        }
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
    }

    fn write_descriptors(&self, sets: &[vk::DescriptorSet]) {
        for (k, set) in sets.iter().enumerate() {
            let list = &self.lists[k % self.lists.len()];
            crate::frame_set::point_sets_at(&self.ctx, std::slice::from_ref(set), bindings::DRAWN_BLADES, list);
        }
    }
}

fn drawn_buffer(ctx: &Arc<Context>, blades: u64) -> Result<Buffer> {
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
    Buffer::new(
        ctx,
        "drawn blades",
        blades * DRAWN_BLADE_BYTES,
        usage,
        MemoryLocation::GpuOnly,
    )
}
