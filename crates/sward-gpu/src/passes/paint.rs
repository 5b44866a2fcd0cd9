//! The paint on the GPU (`sward_core::paint`): its maps' texels, a storage buffer the frame's
//! set binds at `bindings::PAINT`, where they lie over the ground and the paint's noise (packed
//! into each frame's uniforms). Every pass that grows, places or tints grass reads them through the core's
//! shading.wesl `paint_map_at`.

use std::sync::Arc;

use ash::vk;
use sward_core::gpu::PaintArea;
use sward_core::paint::GroundPaint;

use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::{vk_check, Result};
use crate::pipelines::bindings;

/// The paint the renderer holds.
pub(crate) struct PaintTexels {
    buffer: Buffer,
    /// Where the uploaded maps lie (`None`: nothing painted; the buffer holds one texel).
    pub(crate) area: Option<PaintArea>,
    ctx: Arc<Context>,
}

impl PaintTexels {
    /// Nothing painted: one full texel, so the binding always points somewhere.
    pub fn new(ctx: &Arc<Context>, sets: &[vk::DescriptorSet]) -> Result<PaintTexels> {
        let paint = PaintTexels {
            buffer: texel_buffer(ctx, &[NO_PAINT])?,
            area: None,
            ctx: ctx.clone(),
        };
        paint.write_descriptors(sets);
        Ok(paint)
    }

    /// Hold `paint` (or nothing painted) from the next frame on; waits for the GPU.
    pub fn upload(&mut self, sets: &[vk::DescriptorSet], paint: Option<&GroundPaint>) -> Result<()> {
        unsafe { self.ctx.device.device_wait_idle() }.map_err(vk_check("waiting for the GPU"))?;
        let texels = paint
            .and_then(|p| p.map.as_ref())
            .map_or(&[NO_PAINT][..], |m| &m.texels);
        self.buffer = texel_buffer(&self.ctx, texels)?;
        self.area = paint.map(PaintArea::of);
        self.write_descriptors(sets);
        Ok(())
    }

    fn write_descriptors(&self, sets: &[vk::DescriptorSet]) {
        crate::frame_set::point_sets_at(&self.ctx, sets, bindings::PAINT, &self.buffer);
    }
}

/// A texel where nothing is painted (never read: the frame says there is no map).
const NO_PAINT: [u32; 4] = [u32::MAX, 0x0080_8080, u32::MAX, 0];

fn texel_buffer(ctx: &Arc<Context>, texels: &[[u32; 4]]) -> Result<Buffer> {
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
    Buffer::with_data(ctx, "paint maps", bytemuck::cast_slice(texels), usage)
}
