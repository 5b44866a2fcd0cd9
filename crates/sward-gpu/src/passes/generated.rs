//! The instanced grass on the GPU (SPEC §7 [F]): the per-frame patch lists (which grid patches to
//! generate, built on the GPU by `patch_cull.wesl`, so the host writes only the frame's
//! uniforms), the visible lists of the four levels of detail (32 bytes per blade), their draw
//! commands, and the recording of the indirect generate-and-cull dispatches and the one
//! multi-draw. Its far blades are splatted into the renderer's splat target (`splat.rs`).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use sward_core::commands::generated::{
    self, BILLBOARD_COMMAND, BILLBOARD_RASTER_DISPATCH, HARDWARE_BILLBOARD_COMMAND, INSTANCED_LISTS, PATCH_DISPATCH,
    PLACE_DISPATCH, RASTER_CHUNK_DISPATCH, RASTER_COMMAND,
};
use sward_core::gpu::{DrawCommand, GeneratedLayout, GeneratedRows, LISTED_BLADE_BYTES as BLADE_BYTES};
use sward_core::instanced::{patch_order, LODS};
use sward_core::plan::FrameDecisions;

use crate::barrier::{self, Access};
use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::{vk_check, Result};
use crate::passes::FrameParts;
use crate::pipelines::{bindings, constants, Builder, GraphicsDesc, Pipeline, Stage::Fragment, Stage::Vertex};
use crate::recordings::FrameShape;
use crate::shaders;

/// instanced_raster.wesl runs chunk by chunk of the rasterized blades' list, nearest first, the
/// splat tiles' farthest depths taken between chunks so that a tile of a blade wholly behind
/// the nearer ones is left.
const RASTER_CHUNKS: usize = generated::RASTER_CHUNKS as usize;

/// The instanced blades' pipelines: both grids' patch lists, the instanced grid's
/// generate-cull-count pass, the scan of its counts and its placing pass (generate_grid.wesl), and
/// the draws (the billboards' are `billboards.rs`'s).
pub struct GeneratedPipelines {
    /// Both grids' patch lists (a workgroup each).
    pub patch_cull: Pipeline,
    /// The instanced grass's grid: count, scan, place.
    pub instanced_cull: [Pipeline; 3],
    /// The instanced blades as triangle strips.
    pub instanced: Pipeline,
    /// The instanced blades rasterized by compute (instanced_raster.wesl, chunk by chunk of
    /// their list), likewise.
    pub instanced_raster: Option<[Pipeline; RASTER_CHUNKS]>,
}

/// A grid's three passes (`billboards`: the billboards' grid): count, scan, place
/// (`generate_grid.wesl`, `generated_scan.wesl`). Without 64-bit atomics the counting pass is
/// built without its splats (the renderer then splats nothing).
pub(crate) fn generate_passes(b: &Builder, billboards: bool) -> Result<[Pipeline; 3]> {
    let count = match b.ctx.info.int64_atomics {
        true => &shaders::GENERATE_SPLATS[billboards as usize],
        false => &shaders::GENERATE_DRAWN,
    };
    let grid = (constants::BILLBOARDS, billboards as u32);
    let workgroup = match billboards {
        true => b.options.workgroup,
        false => b.options.instanced_workgroup_on(&b.ctx.info),
    };
    let sized = (constants::WORKGROUP, workgroup);
    Ok([
        b.compute_wgsl_with(count, &[grid, sized])?,
        b.compute_wgsl_with(&shaders::GENERATED_SCAN, &[grid])?,
        b.compute_wgsl_with(&shaders::GENERATE_PLACE, &[grid, sized])?,
    ])
}

impl GeneratedPipelines {
    pub(crate) fn new(b: &Builder) -> Result<GeneratedPipelines> {
        let strips = GraphicsDesc {
            strip: true,
            ..b.opaque()
        };
        Ok(GeneratedPipelines {
            patch_cull: b.compute_wgsl(&shaders::PATCH_CULL)?,
            instanced_cull: generate_passes(b, false)?,
            instanced: b.draw(
                &strips,
                &[Vertex(&shaders::BLADE_STRIPS), Fragment(&shaders::BLADE_STRIPS)],
            )?,
            instanced_raster: match b.ctx.info.int64_atomics {
                true => {
                    let chunk = |k: u32| b.compute_wgsl_with(&shaders::INSTANCED_RASTER, &[(constants::CHUNK, k)]);
                    Some([chunk(0)?, chunk(1)?, chunk(2)?, chunk(3)?, chunk(4)?])
                }
                false => None,
            },
        })
    }
}

/// The raw pipelines a frame generates its grass with (`InstancedBuffers::record_cull`).
pub(crate) struct GeneratedPasses {
    pub patch_cull: vk::Pipeline,
    /// Per grid (the instanced grass's, the billboards'): count, scan, place.
    pub grids: [[vk::Pipeline; 3]; 2],
    /// The splat tiles' farthest depths between the rasterizer's chunks.
    pub raster_tiles: Option<vk::Pipeline>,
    /// The compute rasterizers of the instanced blades (chunk by chunk) and of the billboards, where
    /// the frame uses them.
    pub blade_raster: Option<[vk::Pipeline; RASTER_CHUNKS]>,
    pub billboard_raster: Option<vk::Pipeline>,
}

pub(crate) struct InstancedBuffers {
    /// The patches each grid generates this frame (ivec4 rows, written by patch_cull.wesl),
    /// then the ring order it walks (written once per layout).
    patches: Buffer,
    /// Rows for each grid's list (as many as it may keep), then the ring order of offsets
    /// around the eye's patch, for the larger reach of the two.
    layout: GeneratedRows,
    order_len: u32,
    /// The visible lists of every level, one after another.
    blades: Buffer,
    blade_capacity: u64,
    /// One draw command per level, then one whose instance count is the splatted blades.
    draws: Buffer,
    /// Per generating workgroup and level, its blades, then their place (generated_counts).
    counts: Buffer,
    count_capacity: u64,
    /// Each grid's generating workgroups per patch: the instanced grass's, the billboards'.
    patch_groups: [u32; 2],
    /// Where each list starts and how many it holds, as the last frame prepared them.
    lists: GeneratedLayout,
    /// Whether the frame being recorded generates the instanced grass, the billboards.
    grids: [bool; 2],
    ctx: Arc<Context>,
}

impl InstancedBuffers {
    /// `patch_groups`: each grid's generating workgroups per patch (`ComputeOptions::patch_groups_on`).
    pub fn new(ctx: &Arc<Context>, sets: &[vk::DescriptorSet], patch_groups: [u32; 2]) -> Result<InstancedBuffers> {
        let draws = generated::initial();
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::INDIRECT_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        let buffers = InstancedBuffers {
            patches: patch_buffer(ctx, GeneratedRows::default())?.0,
            layout: GeneratedRows::default(),
            order_len: 1,
            blades: storage(ctx, "instanced blades", BLADE_BYTES)?,
            blade_capacity: 1,
            draws: Buffer::with_data(ctx, "instanced draw commands", bytemuck::cast_slice(&draws), usage)?,
            counts: storage(ctx, "generated grass counts", 4)?,
            count_capacity: 1,
            patch_groups,
            lists: GeneratedLayout::default(),
            grids: [false; 2],
            ctx: ctx.clone(),
        };
        buffers.write_descriptors(sets);
        Ok(buffers)
    }

    /// Work out this frame's list sizes (instanced grass and billboards, on the grids `decided`
    /// generates, drawn as it says) from the most patches each grid may keep, and return
    /// where the lists start and what they hold and the patch buffer's layout; the patches
    /// themselves are the GPU's to pick (`record_cull`). Grows the buffers (waiting for the GPU)
    /// only when the grids' reach or density asks for more than they hold, never from what a
    /// frame kept.
    pub fn prepare(&mut self, sets: &[vk::DescriptorSet], decided: &FrameDecisions) -> Result<GeneratedLayout> {
        self.grids = decided.grids;
        // One row of workgroups per patch, in each grid's dispatch.
        let rows_limit = self.ctx.info.max_workgroups_y.min(u16::MAX as u32);
        let kept = GeneratedRows::of(decided, rows_limit);
        if !self.layout.holds(&kept) {
            unsafe { self.ctx.device.device_wait_idle() }.map_err(vk_check("waiting for the GPU"))?;
            let grown = self.layout.max(&kept);
            (self.patches, self.order_len) = patch_buffer(&self.ctx, grown)?;
            self.layout = grown;
            self.write_descriptors(sets);
        }
        let [instanced_rows, billboard_rows] = self.layout.rows;
        // Every list inside one storage buffer of this device.
        let binding = self.ctx.info.max_storage_buffer_range;
        let (lists, needed) = GeneratedLayout::of(decided, &kept, (&self.layout, self.order_len), (binding, None));
        let limit = binding / BLADE_BYTES;
        // The counts: two header words, five lists of the field's workgroups and one of the
        // billboards' (a row of each grid's workgroups per patch).
        let [instanced_groups, billboard_groups] = self.patch_groups.map(u64::from);
        let counts = 2
            + INSTANCED_LISTS as u64 * instanced_rows as u64 * instanced_groups
            + billboard_rows as u64 * billboard_groups;
        let mut grown = false;
        if counts > self.count_capacity {
            unsafe { self.ctx.device.device_wait_idle() }.map_err(vk_check("waiting for the GPU"))?;
            self.count_capacity = counts * 3 / 2;
            self.counts = storage(&self.ctx, "generated grass counts", 4 * self.count_capacity)?;
            grown = true;
        }
        if needed > self.blade_capacity {
            unsafe { self.ctx.device.device_wait_idle() }.map_err(vk_check("waiting for the GPU"))?;
            self.blade_capacity = (needed * 3 / 2).min(limit).max(needed);
            self.blades = storage(&self.ctx, "instanced blades", self.blade_capacity * BLADE_BYTES)?;
            grown = true;
        }
        if grown {
            self.write_descriptors(sets);
        }
        self.lists = lists;
        Ok(lists)
    }

    /// Record the patch lists and the generate-and-cull dispatches: counts reset by transfers,
    /// patch_cull.wesl (a workgroup per grid), then per grid its counting pass (a row of
    /// workgroups per kept patch, dispatched indirectly from patch_cull's size), the scan of its
    /// counts and its placing pass (over the rows that may hold listed blades); then the compute
    /// rasterizers of the instanced blades (chunk by chunk, `passes.raster_tiles` between
    /// chunks over the splat target's `tiles` where the frame splats) and of the billboards, where
    /// this frame rasterizes them by compute, each once its grid's lists are placed; then a
    /// barrier for the indirect draws.
    pub fn record_cull(&self, cmd: vk::CommandBuffer, passes: &GeneratedPasses, tiles: Option<[u32; 2]>) {
        let d = &self.ctx.device;
        barrier::memory(d, cmd, Access::DRAW_READ, Access::TRANSFER_WRITE);
        for k in (0..=BILLBOARD_COMMAND).chain([HARDWARE_BILLBOARD_COMMAND, RASTER_COMMAND]) {
            // instance_count of command k; the vertex counts stay as uploaded.
            unsafe { d.cmd_fill_buffer(cmd, self.draws.raw, 16 * u64::from(k) + 4, 4, 0) };
        }
        barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::COMPUTE_READ_WRITE);
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, passes.patch_cull);
            d.cmd_dispatch(cmd, 2, 1, 1);
        }
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::INDIRECT_COMPUTE_READ);
        // The field's lists (four levels, its rasterized blades), the billboards' one.
        let levels = [INSTANCED_LISTS, 1];
        for (g, (grid, levels)) in passes.grids.into_iter().zip(levels).enumerate() {
            if !self.grids[g] {
                continue;
            }
            let [count, scan, place] = grid;
            self.dispatch(cmd, count, u64::from(PATCH_DISPATCH) + g as u64);
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
            unsafe {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, scan);
                d.cmd_dispatch(cmd, levels, 1, 1);
            }
            // The scans also write the rasterizers' dispatch sizes into the buffer the placing
            // pass's own dispatch size is read from.
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::INDIRECT_COMPUTE_READ);
            self.dispatch(cmd, place, u64::from(PLACE_DISPATCH) + g as u64);
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
        }
        if let (true, Some(chunks)) = (self.grids[0], passes.blade_raster) {
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::INDIRECT_COMPUTE_READ);
            self.record_chunks(cmd, &chunks, passes.raster_tiles.zip(tiles));
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
        }
        if let (true, Some(raster)) = (self.grids[1], passes.billboard_raster) {
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::INDIRECT_COMPUTE_READ);
            self.dispatch(cmd, raster, u64::from(BILLBOARD_RASTER_DISPATCH));
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
        }
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::DRAW_READ);
    }

    /// The instanced blades' compute rasterizer chunk by chunk of its list, nearest first, each
    /// after the splat tiles' farthest depths of what the chunks before it drew (`tiles`: the
    /// tiles pass and the tiles across and down, eight side by side per workgroup).
    fn record_chunks(&self, cmd: vk::CommandBuffer, passes: &[vk::Pipeline], tiles: Option<(vk::Pipeline, [u32; 2])>) {
        let d = &self.ctx.device;
        for (k, &pass) in passes.iter().enumerate() {
            if k > 0 {
                if let Some((tiles_pass, [across, down])) = tiles {
                    barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
                    unsafe {
                        d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, tiles_pass);
                        d.cmd_dispatch(cmd, across.div_ceil(8), down, 1);
                    }
                }
                barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
            }
            self.dispatch(cmd, pass, u64::from(RASTER_CHUNK_DISPATCH) + k as u64);
        }
    }

    /// Bind `pipeline` and dispatch it indirectly with the size in draw command `command`.
    fn dispatch(&self, cmd: vk::CommandBuffer, pipeline: vk::Pipeline, command: u64) {
        let d = &self.ctx.device;
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
            d.cmd_dispatch_indirect(cmd, self.draws.raw, command * 16);
        }
    }

    /// Record the draw of every level of the instanced grass (one indirect call, `drawCount` =
    /// levels) and of the billboards (one indirect call per pass of `billboards`, null ones skipped),
    /// each where this frame generated any.
    ///
    /// Where the frame rasterizes billboards by compute (`rasterized`), the hardware draws only the
    /// billboards billboard_raster.wesl left to it.
    pub fn record_draw(
        &self,
        cmd: vk::CommandBuffer,
        blades: vk::Pipeline,
        billboards: [vk::Pipeline; 2],
        rasterized: bool,
    ) {
        let d = &self.ctx.device;
        unsafe {
            if self.grids[0] {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, blades);
                d.cmd_draw_indirect(cmd, self.draws.raw, 0, LODS as u32, 16);
            }
            if self.grids[1] {
                let command = match rasterized {
                    true => HARDWARE_BILLBOARD_COMMAND,
                    false => BILLBOARD_COMMAND,
                };
                for pass in billboards.into_iter().filter(|p| *p != vk::Pipeline::null()) {
                    d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pass);
                    d.cmd_draw_indirect(cmd, self.draws.raw, 16 * u64::from(command), 1, 16);
                }
            }
        }
    }

    /// Record the instanced blades of the first `levels` levels of detail with `pipeline` (the
    /// shadow map's near cascade: the sun's view of the blades near the eye).
    pub fn record_casters(&self, cmd: vk::CommandBuffer, pipeline: vk::Pipeline, levels: u32) {
        if !self.grids[0] || levels == 0 {
            return;
        }
        let d = &self.ctx.device;
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            d.cmd_draw_indirect(cmd, self.draws.raw, 0, levels.min(LODS as u32), 16);
        }
    }

    /// The draw commands as the GPU holds them now (`instance_count` = visible blades per level;
    /// the last one, never drawn, counts the splatted blades).
    pub fn read_draws(&self) -> Result<Vec<DrawCommand>> {
        Ok(bytemuck::pod_collect_to_vec(&self.draws.download()?))
    }

    /// The visible lists of the last frame prepared as the GPU holds them now, in draw order:
    /// the four levels of the instanced grass, then the billboards; each blade its 32 bytes.
    pub fn read_lists(&self) -> Result<Vec<Vec<[u32; 8]>>> {
        let blades: Vec<[u32; 8]> = bytemuck::pod_collect_to_vec(&self.blades.download()?);
        let draws = self.read_draws()?;
        let commands = [0, 1, 2, 3, BILLBOARD_COMMAND as usize];
        let lists = self.lists.levels.into_iter().chain([self.lists.billboards]);
        Ok(lists
            .zip(commands)
            .map(|([start, cap], command)| {
                let count = draws[command].instance_count.min(cap) as usize;
                blades[start as usize..start as usize + count].to_vec()
            })
            .collect())
    }

    /// The patch lists the GPU built in the last frame recorded, as it holds them now: the
    /// instanced grass's, then the billboards'.
    pub fn read_patches(&self) -> Result<[Vec<glam::IVec2>; 2]> {
        let rows: Vec<glam::IVec4> = bytemuck::pod_collect_to_vec(&self.patches.download()?);
        let draws = self.read_draws()?;
        let first = [0, self.layout.rows[0] as usize];
        Ok([0, 1].map(|g| {
            let kept = if self.grids[g] {
                draws[PATCH_DISPATCH as usize + g].instance_count as usize
            } else {
                0
            };
            rows[first[g]..first[g] + kept]
                .iter()
                .map(|r| r.truncate().truncate())
                .collect()
        }))
    }

    fn write_descriptors(&self, sets: &[vk::DescriptorSet]) {
        for set in sets {
            let infos = [&self.patches, &self.blades, &self.draws, &self.counts].map(|b| {
                [vk::DescriptorBufferInfo {
                    buffer: b.raw,
                    offset: 0,
                    range: vk::WHOLE_SIZE,
                }]
            });
            let bindings = [
                bindings::PATCHES,
                bindings::PATCHES + 1,
                bindings::PATCHES + 2,
                bindings::GENERATED_COUNTS,
            ];
            let writes: Vec<vk::WriteDescriptorSet> = infos
                .iter()
                .zip(bindings)
                .map(|(info, binding)| {
                    vk::WriteDescriptorSet::default()
                        .dst_set(*set)
                        .dst_binding(binding)
                        .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                        .buffer_info(info)
                })
                .collect();
            self.ctx.update_descriptor_sets(&writes);
        }
    }
}

/// A patch buffer of `layout`: zeroed rows for both grids' lists, then the ring order for its
/// reach; and that order's length.
fn patch_buffer(ctx: &Arc<Context>, layout: GeneratedRows) -> Result<(Buffer, u32)> {
    let order = patch_order(layout.reach);
    let rows: Vec<glam::IVec4> = std::iter::repeat_n(glam::IVec4::ZERO, (layout.rows[0] + layout.rows[1]) as usize)
        .chain(order.iter().map(|o| o.extend(0).extend(0)))
        .collect();
    // Host-visible: written here while a frame is being recorded, where no upload can be
    // submitted. Read back by tests (`read_patches`).
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
    let bytes: &[u8] = bytemuck::cast_slice(&rows);
    let mut buffer = Buffer::new(
        ctx,
        "generated grass patches",
        bytes.len() as u64,
        usage,
        MemoryLocation::CpuToGpu,
    )?;
    buffer.mapped_mut().expect("the patch buffer is host visible")[..bytes.len()].copy_from_slice(bytes);
    Ok((buffer, order.len() as u32))
}

fn storage(ctx: &Arc<Context>, name: &str, bytes: u64) -> Result<Buffer> {
    // Read back by tests (`read_lists`).
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
    Buffer::new(ctx, name, bytes, usage, MemoryLocation::GpuOnly)
}

/// Generate and cull the instanced grass and the billboards (after the trample map), splatting
/// into the splat target's tiles where the frame splats them.
pub(crate) fn record_generated(parts: &FrameParts, shape: &FrameShape) {
    parts.bind_set(vk::PipelineBindPoint::COMPUTE);
    let p = parts.pipelines;
    let g = &p.generated;
    let raw = |passes: &[Pipeline; 3]| passes.each_ref().map(|p| p.raw);
    let passes = GeneratedPasses {
        patch_cull: g.patch_cull.raw,
        grids: [raw(&g.instanced_cull), raw(&p.billboards.cull)],
        raster_tiles: p.splats.tiles.as_ref().map(|t| t.generated.raw),
        blade_raster: g
            .instanced_raster
            .as_ref()
            .filter(|_| shape.blades_rasterized)
            .map(|chunks| chunks.each_ref().map(|p| p.raw)),
        billboard_raster: p
            .billboards
            .raster
            .as_ref()
            .filter(|_| shape.billboards_rasterized)
            .map(|p| p.raw),
    };
    let tiles = shape.generated_splats.then(|| parts.splats.tiles());
    parts.instanced.record_cull(parts.cmd, &passes, tiles);
}
