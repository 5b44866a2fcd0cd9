//! The simulate + cull pass of the Bezier field: the field's buffers on the GPU (blades, collision
//! strengths, visible lists, draw commands, tiles), the compute dispatches that step, cull and
//! order the blades each frame, and reading them back for tests.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use sward_core::commands::{
    COMMAND_BUCKETS, COMMAND_RASTER_DISPATCH, COMMAND_RASTER_RETRY, COMMAND_SORT_DISPATCH, COMMAND_SPLAT_DISPATCH,
    COMMAND_SPLITS, COMMAND_TILE_DISPATCH, DISTANCE_BUCKETS,
};
use sward_core::frame::FrameDesc;
use sward_core::gpu::DrawCommand;
use sward_core::plan::FrameDecisions;
use sward_core::stream::StreamWindow;
use sward_core::tiles::{ActiveTile, Tile, TileGroups};
use sward_core::Blade;

use crate::barrier::{self, Access};
use crate::buffer::{Buffer, STAGING_BYTES};
use crate::context::Context;
use crate::error::{GpuError, Result};
use crate::passes::stream::{box_words, StreamState};
use crate::pipelines::{constants, Builder, ComputeOptions, Pipeline};
use crate::shaders;

/// Size of one draw command in bytes.
const COMMAND_BYTES: u64 = std::mem::size_of::<DrawCommand>() as u64;

/// The most tiles whose list the GPU builds (the tile cull (`tile_cull.wesl`) sorts them in one workgroup's
/// shared memory); the host decides the tiles of larger fields (over 2^25 blades).
pub const TILES_ON_GPU: usize = 8192;
// A streamed window's tiles are always decided on the GPU (the host does not hold their boxes).
const _: () = assert!(sward_core::stream::MAX_TILES as usize <= TILES_ON_GPU);

/// GPU bytes a field needs per blade: the blade, its collision strength, its cull verdict and
/// its place in the ordered list.
pub const FIELD_BYTES_PER_BLADE: u64 = std::mem::size_of::<Blade>() as u64 + 3 * 4;

/// Fail with a clear sentence if `blades` blades do not fit one storage buffer of this device,
/// its dispatch limits, or the GPU memory still free (naming the most that do).
pub fn check_field_fits(ctx: &Context, blades: u64) -> Result<()> {
    let info = &ctx.info;
    let bytes = blades * std::mem::size_of::<Blade>() as u64;
    let limit = info.max_storage_buffer_range;
    if bytes > limit {
        let max_blades = limit / std::mem::size_of::<Blade>() as u64;
        return Err(GpuError::FieldTooLarge {
            blades,
            bytes,
            limit,
            max_blades,
        });
    }
    check_field_memory(ctx.memory.free(), blades)?;
    let max_dispatched = info.max_workgroups_x as u64 * ComputeOptions::default().workgroup as u64;
    if blades > max_dispatched {
        return Err(GpuError::TooManyWorkgroups {
            blades,
            max_blades: max_dispatched,
        });
    }
    Ok(())
}

/// Bytes for a field's draw commands and counts, however many blades it has (at most).
const FIELD_SMALL_BUFFERS: u64 = 1 << 20;

/// GPU bytes a field of `blades` blades needs at most: its buffers, the staging buffer that
/// uploads it and its draw commands and counts.
fn field_bytes(blades: u64) -> u64 {
    let staging = (blades * std::mem::size_of::<Blade>() as u64).min(STAGING_BYTES);
    blades * FIELD_BYTES_PER_BLADE + staging + FIELD_SMALL_BUFFERS
}

/// The most blades whose field fits in `free` bytes (`field_bytes` inverted).
fn most_blades_in(free: u64) -> u64 {
    let blade = std::mem::size_of::<Blade>() as u64;
    let room = free.saturating_sub(FIELD_SMALL_BUFFERS);
    // Fields smaller than the staging buffer stage all their blades at once.
    let staged_whole = room / (FIELD_BYTES_PER_BLADE + blade);
    if staged_whole * blade < STAGING_BYTES {
        staged_whole
    } else {
        room.saturating_sub(STAGING_BYTES) / FIELD_BYTES_PER_BLADE
    }
}

/// Fail if a field of `blades` blades needs more than `free` bytes, naming the most that fit.
fn check_field_memory(free: u64, blades: u64) -> Result<()> {
    let needs = field_bytes(blades);
    if needs <= free {
        return Ok(());
    }
    const MIB: u64 = 1 << 20;
    let (needs_mib, free_mib) = (needs.div_ceil(MIB), free / MIB);
    Err(match most_blades_in(free) {
        0 => GpuError::NoRoomForField {
            blades,
            needs_mib,
            free_mib,
        },
        max_blades => GpuError::FieldOutOfMemory {
            blades,
            needs_mib,
            free_mib,
            max_blades,
        },
    })
}

/// The field pass's compute pipelines.
pub struct FieldPipelines {
    pub simulate: Pipeline,
    pub cull: Pipeline,
    /// Simulate and cull in one dispatch (blades read once).
    pub simulate_cull: Pipeline,
    /// After the cull: each distance bucket's start and strip command; each cull workgroup's
    /// count per bucket, those counts summed over the workgroups before it; then the list in
    /// order (the same order every run).
    pub order_buckets: Pipeline,
    pub order_counts: Pipeline,
    pub order_scan: Pipeline,
    pub order_blades: Pipeline,
    /// Then each run of the drawn part sorted by exact distance (order.wesl `order_sort`).
    pub order_sort: Pipeline,
    /// Before them all: the tiles the frame runs (the tile cull (`tile_cull.wesl`)).
    pub tile_cull: Pipeline,
    /// Before that, where the field streams: the blades of the tiles entering the window
    /// (stream.wesl `make_entering_tiles`).
    pub stream_tiles: Pipeline,
    /// Before that, in the frame a streamed field's origin moves: every blade moved to the new
    /// origin (the core's `stream.wesl` `rebase_field`).
    pub rebase_field: Pipeline,
    /// The compute route's passes, where the device has 64-bit atomics.
    pub compute_route: Option<ComputeRoutePipelines>,
}

/// The compute route's passes: they keep the nearest sample per splat cell by 64-bit atomics.
pub struct ComputeRoutePipelines {
    /// The far buckets' Bezier blades splatted.
    pub splat_blades: Pipeline,
    /// The near and middle buckets' Bezier blades rasterized, first and second pass (each
    /// followed by the splat tiles' farthest depths, `splats::TilePipelines::bezier`).
    pub raster_blades: [Pipeline; 2],
}

impl ComputeRoutePipelines {
    fn new(b: &Builder) -> Result<ComputeRoutePipelines> {
        Ok(ComputeRoutePipelines {
            splat_blades: b.compute_wgsl(&shaders::SPLAT_BLADES)?,
            raster_blades: [
                b.compute_wgsl(&shaders::RASTER_BLADES)?,
                b.compute_wgsl_with(&shaders::RASTER_BLADES, &[(constants::SECOND_PASS, 1)])?,
            ],
        })
    }
}

impl FieldPipelines {
    pub(crate) fn new(b: &Builder) -> Result<FieldPipelines> {
        let variant = shaders::cull_variant(b.cull_subgroups(), b.options.copy_blades);
        Ok(FieldPipelines {
            simulate: b.compute_wgsl(&shaders::SIMULATE)?,
            cull: b.compute_wgsl(&shaders::CULL[variant])?,
            simulate_cull: b.compute_wgsl(&shaders::SIMULATE_CULL[variant])?,
            order_buckets: b.compute_wgsl(&shaders::ORDER[0])?,
            order_counts: b.compute_wgsl(&shaders::ORDER[1])?,
            order_scan: b.compute_wgsl(&shaders::ORDER[2])?,
            order_blades: b.compute_wgsl(&shaders::ORDER[3])?,
            order_sort: b.compute_wgsl(&shaders::ORDER[4])?,
            tile_cull: b.compute_wgsl(&shaders::TILE_CULL)?,
            stream_tiles: b.compute_wgsl(&shaders::STREAM_TILES)?,
            rebase_field: b.compute_wgsl(&shaders::REBASE_FIELD)?,
            compute_route: b
                .ctx
                .info
                .int64_atomics
                .then(|| ComputeRoutePipelines::new(b))
                .transpose()?,
        })
    }
}

/// Which compute passes a frame runs over the field.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FieldWork {
    pub simulate: bool,
    pub cull: bool,
    /// Simulate and cull in one dispatch.
    pub fused: bool,
    /// Put the visible list in draw order (not in the bench's copy variant, which draws copies).
    pub order: bool,
    /// Rasterize and splat buckets by compute (the compute route).
    pub splat: bool,
    /// Where the frame rasterizes blades by compute: the splat target's tiles across and down
    /// (the workgroups that take their farthest depths after each rasterizer pass).
    pub raster_tiles: Option<([vk::Pipeline; 2], [u32; 2])>,
    /// Invocations per workgroup of the simulate and cull passes.
    pub workgroup: u32,
}

/// The Bezier field on the GPU.
pub(crate) struct FieldBuffers {
    pub blades: Buffer,
    pub etas: Buffer,
    /// The cull's verdict per cull invocation (a visible id with its distance bucket, or none).
    pub visible: Buffer,
    /// Visible ids in draw order, nearest bucket first.
    pub ordered: Buffer,
    pub draws: Buffer,
    /// Whole culled blades in the copy variant; else each cull workgroup's count per distance
    /// bucket (the ordering passes).
    pub culled: Buffer,
    pub count: u32,
    /// Number of split draw commands from `COMMAND_SPLITS` on (0 when not splitting).
    pub split_draws: u32,
    /// The field's tiles (one unbounded tile when it came without any), grouped.
    tiles: TileGroups,
    /// Per frame slot, the tiles that frame runs (host-written before it is recorded).
    pub active_tiles: Vec<Buffer>,
    /// Blades per tile at most: the workgroups of one tile row.
    tile_blades: u32,
    /// Whether the tile cull (`tile_cull.wesl`) decides the tiles each frame (else the host does).
    tiles_on_gpu: bool,
    /// Where the host decides: the tiles the frame being recorded runs, and their blades.
    host_tiles: (u32, u32),
    /// Where the field streams: the window's slots (`passes/stream.rs`).
    stream: Option<StreamState>,
    ctx: Arc<Context>,
}

impl FieldBuffers {
    /// `blades` on the GPU, every blade at η = 0, with `frame_slots` tile lists and draw commands
    /// split every `patches_per_draw` patches (0: not split), culled by workgroups of `workgroup`;
    /// where `stream` is given, the window of tiles the blades stream into.
    pub fn new(
        ctx: &Arc<Context>,
        (blades, tiles, stream): (&[Blade], &[Tile], Option<StreamWindow>),
        frame_slots: usize,
        patches_per_draw: u32,
        (copy_blades, workgroup): (bool, u32),
    ) -> Result<FieldBuffers> {
        check_field_fits(ctx, blades.len() as u64)?;
        let count = blades.len() as u32;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        let split_draws = if patches_per_draw > 0 {
            count.div_ceil(patches_per_draw)
        } else {
            0
        };
        let mut draws = vec![DrawCommand::default(); (COMMAND_SPLITS + split_draws) as usize];
        draws[0].instance_count = 1;
        let list = |name: &str, entries: u64| Buffer::new(ctx, name, 4 * entries, storage, MemoryLocation::GpuOnly);
        let tiles = field_tiles(tiles, count);
        // The cull runs a row of workgroups per tile, as many as the largest tile needs.
        let tile_blades = tiles.iter().map(|t| t.count).max().unwrap_or(0);
        let groups = tile_blades.div_ceil(workgroup) as u64 * tiles.len() as u64;
        let culled_bytes = if copy_blades {
            count.max(1) as u64 * std::mem::size_of::<Blade>() as u64
        } else {
            (groups * DISTANCE_BUCKETS as u64 * 4).max(4)
        };
        let tiles_on_gpu = decided_on_gpu(&tiles);
        let boxes = if tiles_on_gpu { tile_boxes(&tiles) } else { Vec::new() };
        let list_bytes = tiles.len().max(1) * std::mem::size_of::<ActiveTile>();
        let streaming = stream.as_ref().map_or(0, StreamState::extra_bytes);
        let tile_bytes = (list_bytes + boxes.len() * std::mem::size_of::<ActiveTile>() + streaming) as u64;
        let active_tiles = (0..frame_slots)
            .map(|_| {
                // Where the field streams, the buffer holds the entering tiles' dispatch too.
                let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::INDIRECT_BUFFER;
                let mut list = Buffer::new(ctx, "active tiles", tile_bytes, usage, MemoryLocation::CpuToGpu)?;
                let mapped = list.mapped_mut().expect("the tile list is host visible");
                let boxes: &[u8] = bytemuck::cast_slice(&boxes);
                mapped[list_bytes..list_bytes + boxes.len()].copy_from_slice(boxes);
                Ok(list)
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(FieldBuffers {
            blades: Buffer::with_data(ctx, "blades", bytemuck::cast_slice(blades), storage)?,
            etas: Buffer::with_data(ctx, "collision strengths", &vec![0u8; 4 * blades.len()], storage)?,
            visible: list("cull verdicts", (groups * workgroup as u64).max(count as u64))?,
            ordered: list("ordered visible blades", count as u64)?,
            draws: Buffer::with_data(
                ctx,
                "draw commands",
                bytemuck::cast_slice(&draws),
                storage | vk::BufferUsageFlags::INDIRECT_BUFFER,
            )?,
            culled: Buffer::new(
                ctx,
                "culled blades or counts",
                culled_bytes,
                storage,
                MemoryLocation::GpuOnly,
            )?,
            count,
            split_draws,
            tile_blades,
            tiles: TileGroups::new(tiles),
            active_tiles,
            tiles_on_gpu,
            host_tiles: (0, 0),
            stream: stream.map(|w| StreamState::new(w, workgroup)),
            ctx: ctx.clone(),
        })
    }

    /// The window the field streams into, where it streams.
    pub fn stream_window(&self) -> Option<StreamWindow> {
        self.stream.as_ref().map(StreamState::window)
    }

    /// Where the field streams, make the tiles under `strokes` anew next frame; returns how
    /// many (none where it does not stream).
    pub fn remake_tiles_under(&mut self, strokes: &[sward_core::paint::Stroke], texel: f32) -> usize {
        self.stream.as_mut().map_or(0, |s| s.remake_under(strokes, texel))
    }

    /// The frame origin the field's blades are held around and how far it moved in the last
    /// prepared frame (`FramePlan::origin`): zero unless the field streams.
    pub fn origin(&self) -> [glam::Vec2; 2] {
        self.stream.as_ref().map_or([glam::Vec2::ZERO; 2], StreamState::origin)
    }

    /// Whether the GPU decides the tiles (the tile cull (`tile_cull.wesl`)): the host writes no list per frame,
    /// and a frame's commands do not change with the camera.
    pub fn tiles_on_gpu(&self) -> bool {
        self.tiles_on_gpu
    }

    /// The frame's tile words (`FramePlan::tiles`); where the host decides the tiles (a
    /// field too large for the tile cull (`tile_cull.wesl`)), each tile's fate for the view `desc` describes
    /// (with the casters of the blade shadows `decided` keeps), the tiles to run written into
    /// the slot's list.
    ///
    /// Where the field streams, the tiles entering the window around this frame's eye are listed
    /// for `make_entering_tiles` (stream.wesl) and every tile's box is rewritten, over ground from `ground[0]`
    /// to `ground[1]`; only a frame that `steps` the grass moves the window.
    pub fn prepare_tiles(
        &mut self,
        slot: usize,
        (desc, decided): (&FrameDesc, &FrameDecisions),
        (workgroup, steps): (u32, bool),
        ground: [f32; 2],
    ) -> [u32; 2] {
        let row = self.tile_blades.div_ceil(workgroup);
        if let Some(stream) = self.stream.as_mut() {
            let buffer = self.active_tiles[slot]
                .mapped_mut()
                .expect("the tile list is host visible");
            stream.prepare(desc, ground, buffer, steps);
        }
        if self.tiles_on_gpu {
            return [self.tiles.tiles().len() as u32, row];
        }
        let toward_sun = decided.toward_sun(desc);
        let view_proj = desc.camera.view_projection();
        let margin = desc.cull.tile_margin;
        let active = self
            .tiles
            .active(&view_proj, desc.camera.eye, margin, desc.cull.tiles, toward_sun);
        let bytes: &[u8] = bytemuck::cast_slice(&active);
        let buffer = self.active_tiles[slot]
            .mapped_mut()
            .expect("the tile list is host visible");
        buffer[..bytes.len()].copy_from_slice(bytes);
        self.host_tiles = (active.len() as u32, active.iter().map(|t| t.count).sum());
        [0, row]
    }

    /// The tiles slot `slot`'s last frame ran, as its list holds them (after the frame's fence).
    pub fn read_active_tiles(&self, slot: usize) -> Result<Vec<ActiveTile>> {
        let draws: Vec<DrawCommand> = bytemuck::pod_collect_to_vec(&self.draws.download()?);
        let rows = draws[COMMAND_TILE_DISPATCH as usize].instance_count as usize;
        let list = self.active_tiles[slot].mapped().expect("the tile list is host visible");
        Ok(bytemuck::pod_collect_to_vec(
            &list[..rows * std::mem::size_of::<ActiveTile>()],
        ))
    }

    /// The frame's tiles and the simulate and cull passes' dispatch size: decided by
    /// the tile cull (`tile_cull.wesl`), or written as the host decided them.
    fn record_tiles(&self, cmd: vk::CommandBuffer, p: &FieldPipelines, row: u32) {
        let d = &self.ctx.device;
        if self.tiles_on_gpu {
            // The last frame's passes may still read the list.
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
            unsafe {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, p.tile_cull.raw);
                d.cmd_dispatch(cmd, 1, 1, 1);
            }
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::INDIRECT_COMPUTE_READ);
        } else {
            let (rows, simulated) = self.host_tiles;
            let command = DrawCommand {
                vertex_count: row,
                instance_count: rows,
                first_vertex: 1,
                first_instance: simulated,
            };
            barrier::memory(d, cmd, Access::INDIRECT_COMPUTE_READ, Access::TRANSFER_WRITE);
            let offset = COMMAND_TILE_DISPATCH as u64 * COMMAND_BYTES;
            unsafe { d.cmd_update_buffer(cmd, self.draws.raw, offset, bytemuck::bytes_of(&command)) };
            barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::INDIRECT_COMPUTE_READ);
        }
    }

    /// Record the frame's compute passes over the field: simulate and/or cull (fused where asked)
    /// and the ordering of the visible list; `stamp` marks where simulation ends. The compute
    /// route's draws follow separately (`record_compute_draws`), once the near shadows are in.
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        (slot, set, layout): (usize, vk::DescriptorSet, vk::PipelineLayout),
        p: &FieldPipelines,
        work: FieldWork,
        stamp: &dyn Fn(),
    ) {
        let d = &self.ctx.device;
        // The previous frame's draw may still read what this frame's compute passes write.
        barrier::memory(d, cmd, Access::DRAW_READ, Access::COMPUTE_READ_WRITE);
        unsafe { d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, layout, 0, &[set], &[]) };
        self.record_stream(cmd, slot, p);
        // One row of workgroups per tile the frame runs.
        self.record_tiles(cmd, p, self.tile_blades.div_ceil(work.workgroup));
        let tiles = self.draws.raw;
        let dispatch = |pipeline: vk::Pipeline| unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
            d.cmd_dispatch_indirect(cmd, tiles, COMMAND_TILE_DISPATCH as u64 * COMMAND_BYTES);
        };
        if work.simulate && work.cull && work.fused {
            self.reset_draw_counts(cmd);
            dispatch(p.simulate_cull.raw);
            // One pass: its time shows as simulate; cull shows the ordering and generated grass.
            stamp();
            self.record_order(cmd, p, work);
            return;
        }
        if work.simulate {
            dispatch(p.simulate.raw);
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
        }
        stamp();
        if work.cull {
            self.reset_draw_counts(cmd);
            dispatch(p.cull.raw);
            self.record_order(cmd, p, work);
        }
    }

    /// Where the field streams: the blades of the tiles entering the window this frame, made
    /// before anything reads them (an indirect dispatch the host sized: none when none enter).
    fn record_stream(&self, cmd: vk::CommandBuffer, slot: usize, p: &FieldPipelines) {
        let Some(stream) = self.stream.as_ref() else {
            return;
        };
        let d = &self.ctx.device;
        let tiles = self.active_tiles[slot].raw;
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::INDIRECT_COMPUTE_READ);
        unsafe {
            // The blades held carried to a moved origin first: the entering tiles are made there.
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, p.rebase_field.raw);
            d.cmd_dispatch_indirect(cmd, tiles, stream.rebase_offset());
        }
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, p.stream_tiles.raw);
            d.cmd_dispatch_indirect(cmd, tiles, stream.command_offset());
        }
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
    }

    /// Zero the visible count and the buckets' counts with a transfer, never from a shader: a
    /// reset by invocation 0 races with the other workgroups (SPEC §5.1).
    fn reset_draw_counts(&self, cmd: vk::CommandBuffer) {
        let d = &self.ctx.device;
        barrier::memory(d, cmd, Access::DRAW_READ, Access::TRANSFER_WRITE);
        unsafe {
            d.cmd_fill_buffer(cmd, self.draws.raw, 0, 4, 0);
            let buckets = COMMAND_BUCKETS as u64 * COMMAND_BYTES;
            d.cmd_fill_buffer(cmd, self.draws.raw, buckets, DISTANCE_BUCKETS as u64 * COMMAND_BYTES, 0);
        }
        barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::COMPUTE_READ_WRITE);
    }

    /// After the cull: the buckets' draw commands (and split commands), then, where asked, the
    /// visible list moved into draw order.
    fn record_order(&self, cmd: vk::CommandBuffer, p: &FieldPipelines, work: FieldWork) {
        let d = &self.ctx.device;
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, p.order_buckets.raw);
            d.cmd_dispatch(cmd, 1, 1, 1);
        }
        if work.order {
            // The counting and placing passes run the cull's grid.
            self.indirect(cmd, p.order_counts.raw, COMMAND_TILE_DISPATCH);
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
            unsafe {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, p.order_scan.raw);
                d.cmd_dispatch(cmd, DISTANCE_BUCKETS, 1, 1);
            }
            self.indirect(cmd, p.order_blades.raw, COMMAND_TILE_DISPATCH);
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
            self.indirect(cmd, p.order_sort.raw, COMMAND_SORT_DISPATCH);
        }
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::DRAW_READ);
    }

    /// A compute dispatch whose size an earlier pass wrote into draw command `command`.
    fn indirect(&self, cmd: vk::CommandBuffer, pipeline: vk::Pipeline, command: u32) {
        let d = &self.ctx.device;
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::INDIRECT_COMPUTE_READ);
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
            d.cmd_dispatch_indirect(cmd, self.draws.raw, command as u64 * COMMAND_BYTES);
        }
    }

    /// The compute route's draws, once the list is in order and the near shadows are in (they
    /// shade what they draw): the rasterizer's passes where the frame rasterizes, then the far
    /// buckets splatted.
    pub fn record_compute_draws(
        &self,
        cmd: vk::CommandBuffer,
        (set, layout): (vk::DescriptorSet, vk::PipelineLayout),
        pipelines: &FieldPipelines,
        work: FieldWork,
    ) {
        // Without the compute route's pipelines the renderer splats nothing (`FramePlan::splats`).
        let Some(p) = pipelines.compute_route.as_ref() else {
            return;
        };
        if !(work.cull && work.order && work.splat) {
            return;
        }
        let d = &self.ctx.device;
        unsafe { d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, layout, 0, &[set], &[]) };
        if let Some((tile_passes, tiles)) = work.raster_tiles {
            self.record_raster_passes(cmd, p, tile_passes, tiles);
        }
        self.indirect(cmd, p.splat_blades.raw, COMMAND_SPLAT_DISPATCH);
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::DRAW_READ);
    }

    /// The compute rasterizer's two passes, each followed by the splat tiles' farthest depths:
    /// the first pass draws what the last frame's tiles show, the second what this frame's
    /// tiles show of the rest (raster_blades.wesl).
    fn record_raster_passes(
        &self,
        cmd: vk::CommandBuffer,
        p: &ComputeRoutePipelines,
        tile_passes: [vk::Pipeline; 2],
        tiles: [u32; 2],
    ) {
        let d = &self.ctx.device;
        for (pass, command) in [COMMAND_RASTER_DISPATCH, COMMAND_RASTER_RETRY].into_iter().enumerate() {
            self.indirect(cmd, p.raster_blades[pass].raw, command);
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
            // Eight tiles side by side per workgroup.
            unsafe {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, tile_passes[pass]);
                d.cmd_dispatch(cmd, tiles[0].div_ceil(8), tiles[1], 1);
            }
        }
    }

    /// Record a copy of the visible-blade count (after this frame's cull) into `dst` at byte 0,
    /// and of the blades the frame simulated at byte 4.
    pub fn record_copy_visible_count(&self, cmd: vk::CommandBuffer, dst: &Buffer) {
        let d = &self.ctx.device;
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::TRANSFER_READ);
        let simulated = COMMAND_TILE_DISPATCH as u64 * COMMAND_BYTES + 12;
        let regions = [(0, 0), (simulated, 4)].map(|(src_offset, dst_offset)| vk::BufferCopy {
            src_offset,
            dst_offset,
            size: 4,
        });
        unsafe { d.cmd_copy_buffer(cmd, self.draws.raw, dst.raw, &regions) };
        barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
    }

    /// The visible blade ids the last cull wrote, in draw order, and every draw command.
    pub fn read_visible(&self) -> Result<(Vec<u32>, Vec<DrawCommand>)> {
        let draws: Vec<DrawCommand> = bytemuck::pod_collect_to_vec(&self.draws.download()?);
        let ids: Vec<u32> = bytemuck::pod_collect_to_vec(&self.ordered.download()?);
        let count = draws[0].vertex_count as usize;
        Ok((ids[..count.min(ids.len())].to_vec(), draws))
    }
}

/// Whether the tile cull (`tile_cull.wesl`) can decide these tiles: few enough for its sort, and bounded.
fn decided_on_gpu(tiles: &[Tile]) -> bool {
    tiles.len() <= TILES_ON_GPU && tiles.iter().all(|t| t.min.is_finite() && t.max.is_finite())
}

/// Every tile's box as the tile cull (`tile_cull.wesl`) reads it after the list.
fn tile_boxes(tiles: &[Tile]) -> Vec<ActiveTile> {
    tiles.iter().flat_map(box_words).collect()
}

/// The tiles the renderer keeps for a field: `tiles`, or one unbounded tile of all `count` blades.
fn field_tiles(tiles: &[Tile], count: u32) -> Vec<Tile> {
    if !tiles.is_empty() {
        return tiles.to_vec();
    }
    vec![Tile {
        first: 0,
        count,
        min: glam::Vec3::splat(f32::MIN),
        max: glam::Vec3::splat(f32::MAX),
    }]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_most_blades_named_fit_and_one_more_does_not() {
        for free in [
            2 << 20,
            5 << 20,
            23 << 20,
            40 << 20,
            70 << 20,
            71 << 20,
            500 << 20,
            80 << 30,
        ] {
            let most = most_blades_in(free);
            assert!(most > 0, "{free}");
            assert!(check_field_memory(free, most).is_ok(), "{free}: {most}");
            assert!(check_field_memory(free, most + 1).is_err(), "{free}: {most}");
        }
        assert_eq!(most_blades_in(0), 0);
    }
}
