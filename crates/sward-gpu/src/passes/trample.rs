//! The trample map on the GPU (`sward_core::trample`): its texels, a storage buffer the frame's
//! set binds at `bindings::TRAMPLE` and keeps from frame to frame, and the record of the core's
//! WGSL trample pass (sward-core `trample.wesl`), which lets the grass recover and stamps
//! the colliders once a frame, before the generated grass is made from it.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use sward_core::trample::{Texel, TrampleParams};

use crate::barrier::{self, Access};
use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::Result;
use crate::pipelines::bindings;
use crate::recordings::FrameShape;
use crate::shaders;

/// Bytes of one texel: the push (two floats) and its cell's tag, padded to 16.
const TEXEL_BYTES: u64 = 16;

/// The map's texels and what they were made for.
pub(crate) struct TrampleTexels {
    buffer: Buffer,
    /// The resolution and texel size (bits) the texels hold; a change starts the map upright.
    made_for: (u32, u32),
    /// Whether the next frame must clear the texels first.
    pub(crate) fresh: bool,
    ctx: Arc<Context>,
}

impl TrampleTexels {
    /// A map of one texel, until a frame asks for one.
    pub fn new(ctx: &Arc<Context>) -> Result<TrampleTexels> {
        Ok(TrampleTexels {
            buffer: texel_buffer(ctx, 1)?,
            made_for: (0, 0),
            fresh: true,
            ctx: ctx.clone(),
        })
    }

    /// Fit the texels to the frame's map (`map`, where it runs), pointing every set at a new
    /// buffer where it grows (a parameter change: waits for the GPU).
    pub fn prepare(&mut self, sets: &[vk::DescriptorSet], map: Option<&TrampleParams>) -> Result<()> {
        let Some(map) = map else {
            return Ok(());
        };
        let words = (map.resolution, map.texel_size().to_bits());
        if words.0 == 0 || words == self.made_for {
            return Ok(());
        }
        let texels = words.0 as u64 * words.0 as u64;
        if texels * TEXEL_BYTES > self.buffer.size {
            unsafe { self.ctx.device.device_wait_idle() }.map_err(crate::error::vk_check("waiting for the GPU"))?;
            self.buffer = texel_buffer(&self.ctx, 1)?;
            self.write_descriptors(sets);
            self.buffer = texel_buffer(&self.ctx, texels)?;
            self.write_descriptors(sets);
        }
        self.made_for = words;
        self.fresh = true;
        Ok(())
    }

    /// The map's pass (trample.wesl), before both grids of generated grass are made.
    pub(crate) fn pipeline(b: &crate::pipelines::Builder) -> Result<crate::pipelines::Pipeline> {
        b.compute_wgsl(&shaders::TRAMPLE)
    }

    /// Point every set's trample binding at the texels.
    pub fn write_descriptors(&self, sets: &[vk::DescriptorSet]) {
        crate::frame_set::point_sets_at(&self.ctx, sets, bindings::TRAMPLE, &self.buffer);
    }

    /// The frame's trample pass (its set bound; the frame's map on), after the texels are
    /// cleared where they are new; the generated grass reads them after it.
    pub fn record(&mut self, cmd: vk::CommandBuffer, pipeline: vk::Pipeline, shape: &FrameShape) {
        let n = shape.trample_texels;
        let d = &self.ctx.device;
        // The last frame's generated grass and draws may still read the texels.
        barrier::memory(d, cmd, Access::DRAW_READ, Access::COMPUTE_READ_WRITE);
        if self.fresh {
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::TRANSFER_WRITE);
            unsafe { d.cmd_fill_buffer(cmd, self.buffer.raw, 0, vk::WHOLE_SIZE, 0) };
            barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::COMPUTE_READ_WRITE);
            self.fresh = false;
        }
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
            d.cmd_dispatch(cmd, n.div_ceil(16), n.div_ceil(16), 1);
        }
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
    }

    /// Every texel as the GPU holds it now, row by row (for tests).
    pub fn read(&self) -> Result<Vec<Texel>> {
        let words: Vec<[u32; 4]> = bytemuck::pod_collect_to_vec(&self.buffer.download()?);
        let texels = self.made_for.0 as usize * self.made_for.0 as usize;
        Ok(words.iter().take(texels).map(|&w| Texel::from_words(w)).collect())
    }
}

fn texel_buffer(ctx: &Arc<Context>, texels: u64) -> Result<Buffer> {
    let usage =
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::TRANSFER_SRC;
    Buffer::new(ctx, "trample map", texels * TEXEL_BYTES, usage, MemoryLocation::GpuOnly)
}
