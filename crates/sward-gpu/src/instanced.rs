//! The instanced field on the GPU (SPEC §7 [F]): the per-frame patch list (which grid patches to
//! generate), the visible lists of the four levels of detail (32 bytes per blade), their draw
//! commands, and the recording of the generate-and-cull dispatch and the one multi-draw. Its far
//! blades are splatted into the renderer's splat target (`splat.rs`).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use sward_core::gpu::{DrawCommand, FrameUniforms};
use sward_core::instanced::{disk_capacity, lod_capacities, patches, LODS, LOD_SEGMENTS, PATCH_BLADES, SPLAT_LEVEL};
use sward_core::mesh::HeightGrid;

use crate::barrier::{self, Access};
use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::{vk_check, Result};
use crate::pipelines::{Builder, GraphicsDesc, Pipeline, GENERATED_COUNTS_BINDING, INSTANCED_FIRST};

/// Bytes of one visible instanced blade.
const BLADE_BYTES: u64 = 32;
/// The draw command of the billboards (after the four levels and the splat count).
const BILLBOARD_COMMAND: u64 = SPLAT_LEVEL as u64 + 1;

/// The generated grass's pipelines: for each grid (the instanced field's, the billboards') its
/// generate-cull-count pass, the scan of its counts and its placing pass (instanced.comp), and
/// the draws.
pub struct GeneratedPipelines {
    /// The instanced field's grid: count, scan, place.
    pub instanced_cull: [Pipeline; 3],
    /// The instanced blades as triangle strips.
    pub instanced: Pipeline,
    /// Billboards: generated and culled by instanced.comp over their grid, drawn as crossed quads.
    pub billboard_cull: [Pipeline; 3],
    pub billboards: Pipeline,
}

/// A grid's three passes (`billboards`: the billboards' grid).
/// Without 64-bit atomics the pass is built without its splats (the renderer then splats nothing).
fn generate_passes(b: &Builder, billboards: bool) -> Result<[Pipeline; 3]> {
    let generate = if b.ctx.info.int64_atomics {
        "instanced.comp"
    } else {
        "instanced_drawn.comp"
    };
    Ok([
        b.compute_with(generate, [billboards, false])?,
        b.compute_with("generated_scan.comp", [billboards, false])?,
        b.compute_with(generate, [billboards, true])?,
    ])
}

impl GeneratedPipelines {
    pub(crate) fn new(b: &Builder) -> Result<GeneratedPipelines> {
        let strips = GraphicsDesc {
            strip: true,
            ..b.opaque()
        };
        let tufts = GraphicsDesc {
            alpha_to_coverage: true,
            ..b.opaque()
        };
        Ok(GeneratedPipelines {
            instanced_cull: generate_passes(b, false)?,
            instanced: b.graphics(&strips, &["instanced.vert", "blade.frag"])?,
            billboard_cull: generate_passes(b, true)?,
            billboards: b.graphics(&tufts, &["billboard.vert", "billboard.frag"])?,
        })
    }
}

pub(crate) struct InstancedBuffers {
    /// Per frame slot: the patches that frame generates (ivec4 each, host-written).
    patches: Vec<Buffer>,
    patch_capacity: u32,
    /// The visible lists of every level, one after another.
    blades: Buffer,
    blade_capacity: u64,
    /// One draw command per level, then one whose instance count is the splatted blades.
    draws: Buffer,
    /// Per generating workgroup and level, its blades, then their place (generated_counts).
    counts: Buffer,
    count_capacity: u64,
    /// Where each list starts and how many it holds, as the last frame prepared them (the four
    /// levels, then the billboards).
    lists: Vec<(u32, u32)>,
    /// Patches of the instanced field and of the billboards in the frame being recorded (the
    /// billboards' rows follow the field's in the patch list).
    patch_count: u32,
    tuft_patch_count: u32,
    ctx: Arc<Context>,
}

impl InstancedBuffers {
    pub fn new(ctx: &Arc<Context>, sets: &[vk::DescriptorSet]) -> Result<InstancedBuffers> {
        let draws: Vec<DrawCommand> = LOD_SEGMENTS
            .iter()
            .map(|s| DrawCommand {
                vertex_count: 2 * s + 1,
                ..DrawCommand::default()
            })
            .chain([
                // Splatted blades: only counted.
                DrawCommand::default(),
                // Billboards: three quads of two triangles per tuft.
                DrawCommand {
                    vertex_count: 18,
                    ..DrawCommand::default()
                },
            ])
            .collect();
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::INDIRECT_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST
            | vk::BufferUsageFlags::TRANSFER_SRC;
        let mut buffers = InstancedBuffers {
            patches: Vec::new(),
            patch_capacity: 0,
            blades: storage(ctx, "instanced blades", BLADE_BYTES)?,
            blade_capacity: 1,
            draws: Buffer::with_data(ctx, "instanced draw commands", bytemuck::cast_slice(&draws), usage)?,
            counts: storage(ctx, "generated grass counts", 4)?,
            count_capacity: 1,
            lists: Vec::new(),
            patch_count: 0,
            tuft_patch_count: 0,
            ctx: ctx.clone(),
        };
        buffers.grow_patches(sets, 1)?;
        buffers.write_descriptors(sets);
        Ok(buffers)
    }

    /// Whether the instanced field splats its far blades this frame (its splat distance is inside
    /// the cut-off).
    pub fn splats(uniforms: &FrameUniforms) -> bool {
        let params = uniforms.instanced_params();
        uniforms.technique().draws_instanced() && params.splat_distance < params.radius
    }

    /// Work out this frame's patches and list sizes (instanced field and billboards, as the
    /// technique asks), write the patch list of `slot` and the list offsets and capacities into
    /// `uniforms`; grows the buffers (waiting for the GPU) if needed. On a `ground` height grid
    /// (read from the ground vertices, binding 6) blades and tufts stand on it.
    pub fn prepare(
        &mut self,
        sets: &[vk::DescriptorSet],
        slot: usize,
        uniforms: &mut FrameUniforms,
        ground: Option<&HeightGrid>,
    ) -> Result<()> {
        let technique = uniforms.technique();
        let params = uniforms.instanced_params();
        let tufts = uniforms.billboard_params().as_grid();
        let eye = uniforms.camera_position.truncate();
        if let Some(g) = ground {
            uniforms.instanced_ground = glam::Vec4::new(g.min.x, g.min.y, g.max.x, g.max.y);
            uniforms.instanced_ground_cells = glam::UVec4::new(g.nx, g.nz, 0, 0);
        }
        let rows_limit = self.ctx.info.max_workgroups_y as usize;
        // One row of workgroups per patch, in each grid's dispatch.
        let grid_patches = |on: bool, p: &sward_core::instanced::InstancedParams| {
            let mut list = if on {
                patches(&uniforms.view_proj, eye, p, ground)
            } else {
                Vec::new()
            };
            list.truncate(rows_limit);
            list
        };
        let blade_patches = grid_patches(technique.draws_instanced(), &params);
        let tuft_patches = grid_patches(technique.draws_billboards(), &tufts);
        let mut caps = lod_capacities(&params, blade_patches.len());
        let mut tuft_cap = disk_capacity(&tufts, tufts.radius, tuft_patches.len());
        // Keep every list inside one storage buffer of this device.
        let limit = self.ctx.info.max_storage_buffer_range / BLADE_BYTES;
        let total: u64 = caps.iter().map(|&c| c as u64).sum::<u64>() + tuft_cap as u64;
        if total > limit {
            caps = caps.map(|c| (c as u64 * limit / total) as u32);
            tuft_cap = (tuft_cap as u64 * limit / total) as u32;
        }
        let listed: u32 = caps.iter().sum();
        let needed = (listed as u64 + tuft_cap as u64).max(1);
        let mut grown = false;
        let rows = blade_patches.len() + tuft_patches.len();
        if rows as u32 > self.patch_capacity {
            self.grow_patches(sets, rows as u32 * 3 / 2)?;
            grown = true;
        }
        // The counts: two header words, four levels of the field's workgroups and one of the
        // billboards' (a row per patch, at most 1024 / 64 workgroups a row).
        let counts = 2 + (4 * blade_patches.len() as u64 + tuft_patches.len() as u64) * (PATCH_BLADES as u64 / 64);
        if counts > self.count_capacity {
            unsafe { self.ctx.device.device_wait_idle() }.map_err(vk_check("waiting for the GPU"))?;
            self.count_capacity = counts * 3 / 2;
            self.counts = storage(&self.ctx, "generated grass counts", 4 * self.count_capacity)?;
            self.write_descriptors(sets);
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
        let rows: Vec<glam::IVec4> = blade_patches
            .iter()
            .chain(&tuft_patches)
            .map(|p| p.extend(0).extend(0))
            .collect();
        let bytes: &[u8] = bytemuck::cast_slice(&rows);
        self.patches[slot].mapped_mut().expect("the patch list is host visible")[..bytes.len()].copy_from_slice(bytes);
        self.patch_count = blade_patches.len() as u32;
        self.tuft_patch_count = tuft_patches.len() as u32;
        let mut start = 0;
        for (k, cap) in caps.into_iter().enumerate() {
            uniforms.instanced_lists[k] = start;
            uniforms.instanced_caps[k] = cap;
            start += cap;
        }
        uniforms.billboard_meta.x = listed;
        uniforms.billboard_meta.y = tuft_cap;
        uniforms.billboard_meta.z = self.patch_count;
        self.lists = [0, 1, 2, 3]
            .map(|k| (uniforms.instanced_lists[k], uniforms.instanced_caps[k]))
            .into_iter()
            .chain([(listed, tuft_cap)])
            .collect();
        Ok(())
    }

    /// Record the generate-and-cull dispatches: counts reset by transfers, then one row of
    /// workgroups per patch of the instanced field, then per patch of the billboards' grid, then
    /// a barrier for the indirect draws.
    pub fn record_cull(&self, cmd: vk::CommandBuffer, grids: [[vk::Pipeline; 3]; 2], workgroup: u32) {
        let d = &self.ctx.device;
        barrier::memory(d, cmd, Access::DRAW_READ, Access::TRANSFER_WRITE);
        for k in 0..=BILLBOARD_COMMAND {
            // instance_count of command k; the vertex counts stay as uploaded.
            unsafe { d.cmd_fill_buffer(cmd, self.draws.raw, 16 * k + 4, 4, 0) };
        }
        barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::COMPUTE_READ_WRITE);
        let rows = [self.patch_count, self.tuft_patch_count];
        // The field's four listed levels, the billboards' one.
        let levels = [LODS as u32, 1];
        for ((passes, rows), levels) in grids.into_iter().zip(rows).zip(levels) {
            if rows == 0 {
                continue;
            }
            let [count, scan, place] = passes;
            let sizes = [
                (PATCH_BLADES.div_ceil(workgroup), rows),
                (levels, 1),
                (PATCH_BLADES.div_ceil(workgroup), rows),
            ];
            for (pipeline, (x, y)) in [count, scan, place].into_iter().zip(sizes) {
                unsafe {
                    d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
                    d.cmd_dispatch(cmd, x, y, 1);
                }
                barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
            }
        }
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::DRAW_READ);
    }

    /// Record the draw of every level of the instanced field (one indirect call, `drawCount` =
    /// levels) and of the billboards (one indirect call), each where this frame generated any.
    pub fn record_draw(&self, cmd: vk::CommandBuffer, blades: vk::Pipeline, tufts: vk::Pipeline) {
        let d = &self.ctx.device;
        unsafe {
            if self.patch_count > 0 {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, blades);
                d.cmd_draw_indirect(cmd, self.draws.raw, 0, LODS as u32, 16);
            }
            if self.tuft_patch_count > 0 {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, tufts);
                d.cmd_draw_indirect(cmd, self.draws.raw, 16 * BILLBOARD_COMMAND, 1, 16);
            }
        }
    }

    /// Record the instanced blades of the first `levels` levels of detail with `pipeline` (the
    /// shadow map's near cascade: the sun's view of the blades near the eye).
    pub fn record_casters(&self, cmd: vk::CommandBuffer, pipeline: vk::Pipeline, levels: u32) {
        if self.patch_count == 0 || levels == 0 {
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
    /// the four levels of the instanced field, then the billboards; each blade its 32 bytes.
    pub fn read_lists(&self) -> Result<Vec<Vec<[u32; 8]>>> {
        let blades: Vec<[u32; 8]> = bytemuck::pod_collect_to_vec(&self.blades.download()?);
        let draws = self.read_draws()?;
        let commands = [0, 1, 2, 3, BILLBOARD_COMMAND as usize];
        Ok(self
            .lists
            .iter()
            .zip(commands)
            .map(|(&(start, cap), command)| {
                let count = draws[command].instance_count.min(cap) as usize;
                blades[start as usize..start as usize + count].to_vec()
            })
            .collect())
    }

    fn grow_patches(&mut self, sets: &[vk::DescriptorSet], capacity: u32) -> Result<()> {
        unsafe { self.ctx.device.device_wait_idle() }.map_err(vk_check("waiting for the GPU"))?;
        let bytes = capacity.max(1) as u64 * 16;
        self.patches = sets
            .iter()
            .map(|_| {
                let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
                Buffer::new(&self.ctx, "instanced patches", bytes, usage, MemoryLocation::CpuToGpu)
            })
            .collect::<Result<_>>()?;
        self.patch_capacity = capacity.max(1);
        Ok(())
    }

    fn write_descriptors(&self, sets: &[vk::DescriptorSet]) {
        for (set, patches) in sets.iter().zip(&self.patches) {
            let infos = [patches, &self.blades, &self.draws, &self.counts].map(|b| {
                [vk::DescriptorBufferInfo {
                    buffer: b.raw,
                    offset: 0,
                    range: vk::WHOLE_SIZE,
                }]
            });
            let bindings = [
                INSTANCED_FIRST,
                INSTANCED_FIRST + 1,
                INSTANCED_FIRST + 2,
                GENERATED_COUNTS_BINDING,
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
            unsafe { self.ctx.device.update_descriptor_sets(&writes, &[]) };
        }
    }
}

fn storage(ctx: &Arc<Context>, name: &str, bytes: u64) -> Result<Buffer> {
    // Read back by tests (`read_lists`).
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
    Buffer::new(ctx, name, bytes, usage, MemoryLocation::GpuOnly)
}
