//! The splat target: blades rasterized by compute instead of by the hardware — the instanced
//! field's far blades and, on the compute route, the Bezier blades beyond the hand-over — keep
//! the nearest (depth, colour) per cell with a 64-bit `atomicMin` (one cell per sample on a 4×
//! target). Cleared before the compute passes of a frame that splats, resolved into the frame by
//! one screen-covering triangle (splat.frag) that writes colour and depth per covered sample, so
//! splats compose with everything drawn through the depth test and the MSAA resolve.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use sward_core::gpu::FrameUniforms;

use crate::barrier::{self, Access};
use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::{vk_check, Result};
use crate::pipelines::{Builder, Pipeline, SPLAT_BINDING};

/// Bytes of one splat cell: view depth bits above colour.
const SPLAT_BYTES: u64 = 8;

pub(crate) struct SplatTarget {
    cells: Buffer,
    capacity: u64,
    /// Splat cells per pixel side: 2 on a 4× MSAA target (one cell per sample, as the standard
    /// sample locations lie one in each quarter of the pixel), else 1.
    scale: u32,
    /// Cells the frame being recorded uses (0: it splats nothing).
    in_use: u64,
    ctx: Arc<Context>,
}

impl SplatTarget {
    pub fn new(ctx: &Arc<Context>, sets: &[vk::DescriptorSet], samples: vk::SampleCountFlags) -> Result<SplatTarget> {
        let target = SplatTarget {
            cells: cell_buffer(ctx, 1)?,
            capacity: 1,
            scale: if samples == vk::SampleCountFlags::TYPE_4 { 2 } else { 1 },
            in_use: 0,
            ctx: ctx.clone(),
        };
        target.write_descriptors(sets);
        Ok(target)
    }

    /// Get ready for a frame that splats (`splatting`) or not: tell the shaders the cell scale
    /// and grow the cells to the viewport (waiting for the GPU: only when the target grows).
    pub fn prepare(&mut self, sets: &[vk::DescriptorSet], uniforms: &mut FrameUniforms, splatting: bool) -> Result<()> {
        uniforms.instanced_meta.z = self.scale;
        let cells = (uniforms.viewport.x * uniforms.viewport.y) as u64 * (self.scale as u64).pow(2);
        self.in_use = if splatting { cells } else { 0 };
        if self.in_use > self.capacity {
            unsafe { self.ctx.device.device_wait_idle() }.map_err(vk_check("waiting for the GPU"))?;
            self.cells = cell_buffer(&self.ctx, cells)?;
            self.capacity = cells;
            self.write_descriptors(sets);
        }
        Ok(())
    }

    /// Every cell empty (depth and colour all ones, above anything splatted), before the frame's
    /// compute passes splat into it.
    pub fn record_clear(&self, cmd: vk::CommandBuffer) {
        if self.in_use == 0 {
            return;
        }
        let d = &self.ctx.device;
        // The previous frame's resolve may still read the cells.
        barrier::memory(d, cmd, Access::DRAW_READ, Access::TRANSFER_WRITE);
        unsafe { d.cmd_fill_buffer(cmd, self.cells.raw, 0, self.in_use * SPLAT_BYTES, u32::MAX) };
        barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::COMPUTE_READ_WRITE);
    }

    /// Resolve the splats into the frame: one screen-covering triangle (none when this frame
    /// splats nothing).
    pub fn record_resolve(&self, cmd: vk::CommandBuffer, pipeline: vk::Pipeline) {
        if self.in_use == 0 {
            return;
        }
        let d = &self.ctx.device;
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            d.cmd_draw(cmd, 3, 1, 0, 0);
        }
    }

    fn write_descriptors(&self, sets: &[vk::DescriptorSet]) {
        let info = [vk::DescriptorBufferInfo {
            buffer: self.cells.raw,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let writes: Vec<vk::WriteDescriptorSet> = sets
            .iter()
            .map(|set| {
                vk::WriteDescriptorSet::default()
                    .dst_set(*set)
                    .dst_binding(SPLAT_BINDING)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(&info)
            })
            .collect();
        unsafe { self.ctx.device.update_descriptor_sets(&writes, &[]) };
    }
}

/// The resolve: a screen-covering triangle whose fragments take their pixel's cells, tested and
/// writing depth like any drawn surface.
pub(crate) fn resolve_pipeline(b: &Builder) -> Result<Pipeline> {
    b.graphics(&b.opaque(), &["sky.vert", "splat.frag"])
}

/// The splat cells: cleared by a fill each frame that splats.
fn cell_buffer(ctx: &Arc<Context>, cells: u64) -> Result<Buffer> {
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
    Buffer::new(ctx, "splat cells", cells * SPLAT_BYTES, usage, MemoryLocation::GpuOnly)
}
