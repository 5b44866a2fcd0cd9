//! The splat target: blades rasterized by compute instead of by the hardware — the instanced
//! field's far blades and, on the compute route, the Bezier blades beyond the hand-over — keep
//! the nearest (depth, colour) per cell with a 64-bit `atomicMin` (one cell per sample on a 4×
//! target). Cleared before the compute passes of a frame that splats, resolved into the frame by
//! one screen-covering triangle (splat_resolve.wesl) that writes colour and depth per covered sample, so
//! splats compose with everything drawn through the depth test and the MSAA resolve.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::barrier::{self, Access};
use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::{vk_check, Result};
use crate::pipelines::{bindings, constants, Builder, Pipeline, Stage::Fragment, Stage::Vertex};
use crate::shaders::{self, SKY, SPLAT_RESOLVE};

/// Bytes of one splat cell: view depth bits above colour.
const SPLAT_BYTES: u64 = 8;
/// Side of a splat tile in cells (splat.wesl `SPLAT_TILE`): the compute rasterizer's occlusion
/// test skips a tile whose farthest depth is nearer than a triangle.
const SPLAT_TILE: u32 = 8;

pub(crate) struct SplatTarget {
    buffer: Buffer,
    /// Cells of the target (the tiles follow them in `buffer`).
    cells: u64,
    /// Whether `buffer` was just made: its tiles are filled once, as hiding nothing.
    pub(crate) fresh: bool,
    capacity: u64,
    /// Splat cells per pixel side: 2 on a 4× MSAA target (one cell per sample, as the standard
    /// sample locations lie one in each quarter of the pixel), else 1.
    scale: u32,
    cell_per_sample: bool,
    /// Tiles of `SPLAT_TILE` × `SPLAT_TILE` cells across and down the target.
    tiles: [u32; 2],
    /// Cells the frame being recorded uses, tiles' farthest depths included (0: it splats
    /// nothing).
    in_use: u64,
    ctx: Arc<Context>,
}

impl SplatTarget {
    pub fn new(ctx: &Arc<Context>, sets: &[vk::DescriptorSet], samples: vk::SampleCountFlags) -> Result<SplatTarget> {
        let target = SplatTarget {
            buffer: cell_buffer(ctx, 1)?,
            cells: 0,
            fresh: true,
            capacity: 1,
            scale: if samples == vk::SampleCountFlags::TYPE_4 { 2 } else { 1 },
            tiles: [0, 0],
            cell_per_sample: samples == vk::SampleCountFlags::TYPE_4 || samples == vk::SampleCountFlags::TYPE_1,
            in_use: 0,
            ctx: ctx.clone(),
        };
        target.write_descriptors(sets);
        Ok(target)
    }

    /// Whether each sample has its own cell (1× and 4× targets), so what compute rasterizes
    /// is antialiased as the hardware would.
    pub fn cell_per_sample(&self) -> bool {
        self.cell_per_sample
    }

    /// Tiles across and down (splat_tiles.wesl's workgroups), as of the last `prepare`.
    pub fn tiles(&self) -> [u32; 2] {
        self.tiles
    }

    /// Splat cells per pixel side.
    pub fn scale(&self) -> u32 {
        self.scale
    }

    /// Whether the frame being recorded splats (the cells are cleared).
    pub fn in_use(&self) -> bool {
        self.in_use > 0
    }

    /// Get ready for a frame of `viewport` pixels that splats (`splatting`) or not: grow the
    /// cells to the viewport (waiting for the GPU: only when the target grows).
    pub fn prepare(&mut self, sets: &[vk::DescriptorSet], viewport: [u32; 2], splatting: bool) -> Result<()> {
        let size = viewport.map(|n| n * self.scale);
        self.tiles = size.map(|n| n.div_ceil(SPLAT_TILE));
        self.cells = size[0] as u64 * size[1] as u64;
        // The cells, then this frame's and the last frame's tiles.
        let cells = self.cells + 2 * self.tiles[0] as u64 * self.tiles[1] as u64;
        self.in_use = if splatting { cells } else { 0 };
        if self.in_use > self.capacity {
            let grown = unsafe { self.ctx.device.device_wait_idle() }
                .map_err(vk_check("waiting for the GPU"))
                .and_then(|_| {
                    // The old cells go first: both may not fit at once.
                    self.buffer = cell_buffer(&self.ctx, 1)?;
                    self.capacity = 1;
                    self.write_descriptors(sets);
                    cell_buffer(&self.ctx, cells)
                });
            let Ok(buffer) = grown else {
                self.in_use = 0;
                return grown.map(|_| ());
            };
            self.buffer = buffer;
            self.capacity = cells;
            self.fresh = true;
            self.write_descriptors(sets);
        }
        Ok(())
    }

    /// Every cell empty (depth and colour all ones, above anything splatted), before the frame's
    /// compute passes splat into it.
    /// The last frame's tiles are kept (the compute rasterizer's first pass reads them); a new
    /// buffer's are filled too.
    pub fn record_clear(&mut self, cmd: vk::CommandBuffer) {
        if self.in_use == 0 {
            return;
        }
        let d = &self.ctx.device;
        // The previous frame's resolve may still read the cells.
        barrier::memory(d, cmd, Access::DRAW_READ, Access::TRANSFER_WRITE);
        let cleared = if self.fresh { self.capacity } else { self.cells };
        self.fresh = false;
        unsafe { d.cmd_fill_buffer(cmd, self.buffer.raw, 0, cleared * SPLAT_BYTES, u32::MAX) };
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
        for binding in [bindings::SPLAT_CELLS, bindings::SPLAT_WORDS] {
            crate::frame_set::point_sets_at(&self.ctx, sets, binding, &self.buffer);
        }
    }
}

/// GPU bytes per pixel of a `samples`-sampled splat target: its cells and, rounded up, its two
/// frames' tiles.
pub(crate) fn bytes_per_pixel(samples: vk::SampleCountFlags) -> u64 {
    let cells = if samples == vk::SampleCountFlags::TYPE_4 { 4 } else { 1 };
    let tiles = (2 * cells * SPLAT_BYTES).div_ceil((SPLAT_TILE * SPLAT_TILE) as u64);
    cells * SPLAT_BYTES + tiles
}

/// The splat target's pipelines: its resolve into the frame, and its tiles' farthest depths,
/// which the compute rasterizers test against.
pub struct SplatPipelines {
    /// A screen-covering triangle whose fragments take their pixel's cells, tested and writing
    /// depth like any drawn surface.
    pub resolve: Pipeline,
    /// Each splat tile's farthest depth (splat_tiles.wesl), where the device splats (64-bit
    /// atomics).
    pub tiles: Option<TilePipelines>,
}

/// splat_tiles.wesl's passes: after the Bezier blades' compute rasterizer's first and second
/// passes, and between the chunks of the instanced blades' compute rasterizer.
pub struct TilePipelines {
    pub bezier: [Pipeline; 2],
    pub generated: Pipeline,
}

impl SplatPipelines {
    pub(crate) fn new(b: &Builder) -> Result<SplatPipelines> {
        let tiles = |b: &Builder| -> Result<TilePipelines> {
            Ok(TilePipelines {
                bezier: [
                    b.compute_wgsl(&shaders::SPLAT_TILES)?,
                    b.compute_wgsl_with(&shaders::SPLAT_TILES, &[(constants::SECOND_PASS, 1)])?,
                ],
                generated: b.compute_wgsl_with(&shaders::SPLAT_TILES, &[(constants::GENERATED, 1)])?,
            })
        };
        Ok(SplatPipelines {
            // The resolve stays GLSL: naga 30 writes WGSL's `sample_mask` output as a plain word
            // where Vulkan asks for an array of them (gfx-rs/wgpu#7311), and the validation layer
            // refuses the module (the WGSL resolve drew the same bytes on lavapipe and ran as
            // fast on the H100 otherwise).
            resolve: b.draw(&b.opaque(), &[Vertex(&SKY), Fragment(&SPLAT_RESOLVE)])?,
            tiles: b.ctx.info.int64_atomics.then(|| tiles(b)).transpose()?,
        })
    }
}

/// The splat cells: cleared by a fill each frame that splats.
fn cell_buffer(ctx: &Arc<Context>, cells: u64) -> Result<Buffer> {
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
    Buffer::new(ctx, "splat cells", cells * SPLAT_BYTES, usage, MemoryLocation::GpuOnly)
}
