//! The grass frame: simulate → cull (compaction into draw commands) → draw (sky, ground,
//! tessellated blades), recorded into a command buffer the caller gives, rendering into a target
//! the caller gives. The offscreen path, the tests and the viewer all go through `record_frame`.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use sward_core::gpu::{DrawCommand, FrameUniforms};
use sward_core::tiles::{self, ActiveTile, Tile};
use sward_core::Blade;

use crate::barrier::{self, Access};
use crate::buffer::Buffer;
use crate::context::{Context, DeviceInfo};
use crate::error::{vk_check, GpuError, Result};
use crate::grass_texture::GrassTexture;
use crate::instanced::InstancedBuffers;
use crate::occluders::Occluders;
use crate::pipelines::{
    ComputeOptions, Pipelines, TargetFormat, GRASS_TEXTURE_BINDING, IMAGE_BINDINGS, INSTANCED_BINDINGS,
    STORAGE_BINDINGS,
};
use crate::target::{begin_rendering, cleared_depth};
use crate::timer::{GpuTimer, Stamp};

/// Largest tessellated draw Mesa's lavapipe draws correctly: bigger single draws of patches come
/// out garbled (Mesa 22.3), so on that driver the draw is split into commands of this many patches.
pub const LAVAPIPE_PATCHES_PER_DRAW: u32 = 1024;

/// Fail with a clear sentence if `blades` blades do not fit one storage buffer of this device.
pub fn check_field_fits(info: &DeviceInfo, blades: u64) -> Result<()> {
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
    let max_dispatched = info.max_workgroups_x as u64 * ComputeOptions::default().workgroup as u64;
    if blades > max_dispatched {
        return Err(GpuError::TooManyWorkgroups {
            blades,
            max_blades: max_dispatched,
        });
    }
    Ok(())
}

/// Vertices of the ground sphere `ground.vert` builds (96 rings × 192 segments × 6).
const GROUND_SPHERE_VERTICES: u32 = 96 * 192 * 6;

/// Vertices of one collider sphere `collider.vert` builds (16 rings × 32 segments × 6).
const COLLIDER_VERTICES: u32 = 16 * 32 * 6;

/// Which passes a frame runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Passes {
    pub simulate: bool,
    pub cull: bool,
    pub draw: bool,
}

impl Passes {
    pub const ALL: Passes = Passes {
        simulate: true,
        cull: true,
        draw: true,
    };
    pub const SIMULATE: Passes = Passes {
        simulate: true,
        cull: false,
        draw: false,
    };
    pub const CULL: Passes = Passes {
        simulate: false,
        cull: true,
        draw: false,
    };
}

/// The attachments a frame renders into (already in attachment layouts).
#[derive(Clone, Copy, Debug)]
pub struct TargetViews {
    pub color: vk::ImageView,
    /// Single-sample image the multisampled colour resolves into, if any.
    pub resolve: Option<vk::ImageView>,
    pub depth: vk::ImageView,
    pub extent: vk::Extent2D,
}

#[derive(Clone, Copy, Debug)]
pub struct RendererDesc {
    pub target: TargetFormat,
    pub frames_in_flight: usize,
    /// Patches per indirect draw command; `None` picks per driver (see `LAVAPIPE_PATCHES_PER_DRAW`),
    /// `Some(0)` draws every visible blade with one command.
    pub patches_per_draw: Option<u32>,
    pub compute: ComputeOptions,
    /// Simulate and cull in one dispatch when a frame runs both.
    pub fused: bool,
}

/// The field on the GPU.
struct FieldBuffers {
    blades: Buffer,
    etas: Buffer,
    visible: Buffer,
    draws: Buffer,
    /// Whole culled blades, sized for the field only in the copy variant (else one blade).
    culled: Buffer,
    count: u32,
    /// Number of split draw commands after `draws[0]` (0 when not splitting).
    split_draws: u32,
    /// The field's tiles (one unbounded tile when it came without any).
    tiles: Vec<Tile>,
    /// Per frame slot, the tiles that frame runs (host-written before it is recorded).
    active_tiles: Vec<Buffer>,
    /// Blades per tile at most: the workgroups of one tile row.
    tile_blades: u32,
    /// Tiles the frame being recorded runs (rows of workgroups).
    active_rows: u32,
    /// Blades in those tiles: what the frame simulates.
    simulated_blades: u32,
}

/// Per frame in flight: its uniforms and the descriptor set that points at them.
struct FrameSlot {
    uniforms: Buffer,
    set: vk::DescriptorSet,
}

pub struct Renderer {
    field: Option<FieldBuffers>,
    slots: Vec<FrameSlot>,
    descriptor_pool: vk::DescriptorPool,
    pub pipelines: Pipelines,
    /// Draw blades as lines (if the device has a wireframe pipeline).
    pub wireframe: bool,
    /// Simulate and cull in one dispatch when a frame runs both.
    pub fused: bool,
    patches_per_draw: u32,
    ground: GroundBuffers,
    occluders: Occluders,
    instanced: InstancedBuffers,
    /// Kept alive for binding 14 of every set.
    _grass_texture: GrassTexture,
    /// What the field's bindings point at while there is no field.
    unused: Buffer,
    ctx: Arc<Context>,
}

/// The ground mesh, if the scene grows grass on one (else a placeholder vertex buffer).
struct GroundBuffers {
    vertices: Buffer,
    indices: Option<(Buffer, u32)>,
    /// The ground as a height grid, where it is one (the instanced field stands on it).
    grid: Option<sward_core::mesh::HeightGrid>,
}

impl Renderer {
    pub fn new(ctx: &Arc<Context>, desc: &RendererDesc) -> Result<Renderer> {
        let pipelines = Pipelines::new(ctx, desc.target, desc.compute)?;
        let frames = desc.frames_in_flight.max(1) as u32;
        let sizes = [
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::UNIFORM_BUFFER,
                descriptor_count: frames,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_BUFFER,
                descriptor_count: (STORAGE_BINDINGS + INSTANCED_BINDINGS) * frames,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                // The occluders' images and the grass texture.
                descriptor_count: (IMAGE_BINDINGS + 1) * frames,
            },
        ];
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(frames)
            .pool_sizes(&sizes);
        let descriptor_pool = unsafe { ctx.device.create_descriptor_pool(&pool_info, None) }
            .map_err(vk_check("creating the descriptor pool"))?;
        let layouts = vec![pipelines.set_layout; frames as usize];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(descriptor_pool)
            .set_layouts(&layouts);
        let sets =
            unsafe { ctx.device.allocate_descriptor_sets(&alloc) }.map_err(vk_check("allocating descriptor sets"))?;
        let slots = sets
            .into_iter()
            .map(|set| {
                let size = std::mem::size_of::<FrameUniforms>() as u64;
                let uniforms = Buffer::new(
                    ctx,
                    "frame uniforms",
                    size,
                    vk::BufferUsageFlags::UNIFORM_BUFFER,
                    MemoryLocation::CpuToGpu,
                )?;
                Ok(FrameSlot { uniforms, set })
            })
            .collect::<Result<Vec<_>>>()?;
        let patches_per_draw = desc
            .patches_per_draw
            .unwrap_or(if ctx.info.driver_id == vk::DriverId::MESA_LLVMPIPE {
                LAVAPIPE_PATCHES_PER_DRAW
            } else {
                0
            });
        let placeholder = |name: &str| {
            let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
            Buffer::new(ctx, name, 64, usage, MemoryLocation::GpuOnly)
        };
        // Until a field is uploaded every binding still points somewhere valid: frames without
        // Bezier blades (the instanced field alone) bind the same set. This buffer outlives every
        // set that points at it; the ground's own placeholder is replaced by a ground mesh.
        let unused = placeholder("unused binding")?;
        for slot in &slots {
            write_buffer_descriptors(ctx, slot, &[&unused; STORAGE_BINDINGS as usize]);
        }
        let occluders = Occluders::new(ctx)?;
        let grass_texture = GrassTexture::new(ctx)?;
        write_image_descriptors(ctx, &slots, &occluders, &grass_texture);
        let sets: Vec<vk::DescriptorSet> = slots.iter().map(|s| s.set).collect();
        let instanced = InstancedBuffers::new(ctx, &sets, desc.target.samples)?;
        Ok(Renderer {
            occluders,
            instanced,
            _grass_texture: grass_texture,
            unused,
            ground: GroundBuffers {
                vertices: placeholder("ground placeholder")?,
                indices: None,
                grid: None,
            },
            field: None,
            slots,
            descriptor_pool,
            pipelines,
            wireframe: false,
            patches_per_draw,
            fused: desc.fused,
            ctx: ctx.clone(),
        })
    }

    pub fn blade_count(&self) -> u32 {
        self.field.as_ref().map_or(0, |f| f.count)
    }

    /// Blades in the tiles the last recorded frame ran (all of them without tile culling).
    pub fn simulated_blades(&self) -> u32 {
        self.field.as_ref().map_or(0, |f| f.simulated_blades)
    }

    /// Put a field on the GPU (replacing any previous one), every blade at η = 0. `tiles` are the
    /// field's tiles (`sward_core::tiles::build`); with none, the whole field is one tile. No
    /// blades: no field (frames draw only what else the scene has).
    pub fn upload_field(&mut self, blades: &[Blade], tiles: &[Tile]) -> Result<()> {
        unsafe { self.ctx.device.device_wait_idle() }.map_err(vk_check("waiting for the GPU"))?;
        self.field = None;
        if blades.is_empty() {
            // The sets must not keep pointing at the field just freed; the ground stays.
            let mut storage = [&self.unused; STORAGE_BINDINGS as usize];
            storage[5] = &self.ground.vertices;
            for slot in &self.slots {
                write_buffer_descriptors(&self.ctx, slot, &storage);
            }
            return Ok(());
        }
        let ctx = &self.ctx;
        check_field_fits(&ctx.info, blades.len() as u64)?;
        let count = blades.len() as u32;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        let split_draws = if self.patches_per_draw > 0 {
            count.div_ceil(self.patches_per_draw)
        } else {
            0
        };
        let mut draws = vec![DrawCommand::default(); 1 + split_draws as usize];
        draws[0].instance_count = 1;
        let field = FieldBuffers {
            blades: Buffer::with_data(ctx, "blades", bytemuck::cast_slice(blades), storage)?,
            etas: Buffer::with_data(ctx, "collision strengths", &vec![0u8; 4 * blades.len()], storage)?,
            visible: Buffer::new(
                ctx,
                "visible blades",
                4 * count as u64,
                storage,
                MemoryLocation::GpuOnly,
            )?,
            draws: Buffer::with_data(
                ctx,
                "draw commands",
                bytemuck::cast_slice(&draws),
                storage | vk::BufferUsageFlags::INDIRECT_BUFFER,
            )?,
            culled: {
                let copies = if self.pipelines.options.copy_blades {
                    count.max(1)
                } else {
                    1
                };
                let bytes = copies as u64 * std::mem::size_of::<Blade>() as u64;
                Buffer::new(ctx, "culled blade copies", bytes, storage, MemoryLocation::GpuOnly)?
            },
            count,
            split_draws,
            tiles: field_tiles(tiles, count),
            active_tiles: Vec::new(),
            tile_blades: 0,
            active_rows: 0,
            simulated_blades: 0,
        };
        let mut field = field;
        field.tile_blades = field.tiles.iter().map(|t| t.count).max().unwrap_or(0);
        let tile_bytes = (field.tiles.len().max(1) * std::mem::size_of::<ActiveTile>()) as u64;
        for _ in &self.slots {
            let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
            let buffer = Buffer::new(ctx, "active tiles", tile_bytes, usage, MemoryLocation::CpuToGpu)?;
            field.active_tiles.push(buffer);
        }
        for (k, slot) in self.slots.iter().enumerate() {
            self.write_descriptors(slot, &field, &field.active_tiles[k]);
        }
        self.field = Some(field);
        Ok(())
    }

    fn write_descriptors(&self, slot: &FrameSlot, field: &FieldBuffers, active_tiles: &Buffer) {
        let storage = [
            &field.blades,
            &field.etas,
            &field.visible,
            &field.draws,
            &field.culled,
            &self.ground.vertices,
            active_tiles,
        ];
        write_buffer_descriptors(&self.ctx, slot, &storage);
    }

    /// Record one frame into `cmd`, using frame slot `slot` (< frames in flight; the caller makes
    /// sure that slot's previous frame has finished). `uniforms.modes.z` is set here.
    pub fn record_frame(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        uniforms: &FrameUniforms,
        passes: Passes,
        target: Option<&TargetViews>,
        timer: Option<&GpuTimer>,
    ) {
        let mut uniforms = *uniforms;
        uniforms.modes.z = self.patches_per_draw;
        let technique = uniforms.technique();
        // The instanced field and the billboards: generated on the GPU each frame.
        let generated = (technique.draws_instanced() || technique.draws_billboards()) && passes.cull;
        if generated {
            let sets: Vec<vk::DescriptorSet> = self.slots.iter().map(|s| s.set).collect();
            let grid = self.ground.grid.as_ref();
            if let Err(e) = self.instanced.prepare(&sets, slot, &mut uniforms, grid) {
                log::error!("the instanced field is skipped this frame: {e}");
            }
        }
        let frame_slot = &mut self.slots[slot];
        frame_slot.uniforms.mapped_mut().expect("uniforms are host visible")[..std::mem::size_of::<FrameUniforms>()]
            .copy_from_slice(bytemuck::bytes_of(&uniforms));
        let set = frame_slot.set;
        let stamp = |s: Stamp| {
            if let Some(timer) = timer {
                timer.stamp(cmd, s);
            }
        };
        if let Some(field) = self.field.as_mut() {
            write_active_tiles(field, slot, &uniforms);
        }
        let occlusion = uniforms.modes.x & 16 != 0;
        if self.field.is_some() && passes.cull && occlusion {
            self.record_occluders(cmd, set, &uniforms, false);
        }
        let drawn = passes.draw && target.is_some();
        if drawn && uniforms.shading_extra.w > 0.0 {
            // Before the compute passes: the splatted far field is shaded there, shadows included.
            self.record_occluders(cmd, set, &uniforms, true);
        }
        stamp(Stamp::Occluded);
        if let Some(field) = self.field.as_ref() {
            self.record_compute(cmd, set, field, passes, uniforms.counts.y > 0, &stamp);
        } else {
            stamp(Stamp::Simulated);
        }
        if generated {
            let d = &self.ctx.device;
            let layout = self.pipelines.layout;
            unsafe { d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, layout, 0, &[set], &[]) };
            let workgroup = self.pipelines.options.workgroup;
            let pipelines = [self.pipelines.instanced_cull, self.pipelines.billboard_cull];
            self.instanced.record_cull(cmd, pipelines, workgroup);
        }
        stamp(Stamp::Culled);
        if let (true, Some(target)) = (passes.draw, target) {
            self.draw(cmd, set, self.field.as_ref(), target, &uniforms, generated);
        }
        stamp(Stamp::Drawn);
    }

    fn record_compute(
        &self,
        cmd: vk::CommandBuffer,
        set: vk::DescriptorSet,
        field: &FieldBuffers,
        passes: Passes,
        has_steps: bool,
        stamp: &dyn Fn(Stamp),
    ) {
        let d = &self.ctx.device;
        // The previous frame's draw may still read what this frame's compute passes write.
        barrier::memory(d, cmd, Access::DRAW_READ, Access::COMPUTE_READ_WRITE);
        let layout = self.pipelines.layout;
        unsafe { d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, layout, 0, &[set], &[]) };
        // One row of workgroups per active tile.
        let groups = field.tile_blades.div_ceil(self.pipelines.options.workgroup);
        let tile_rows = field.active_rows;
        let dispatch = |pipeline: vk::Pipeline| unsafe {
            if tile_rows > 0 && groups > 0 {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
                d.cmd_dispatch(cmd, groups, tile_rows, 1);
            }
        };
        let simulate = passes.simulate && has_steps;
        if simulate && passes.cull && self.fused {
            self.reset_draw_counts(cmd, field);
            dispatch(self.pipelines.simulate_cull);
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::DRAW_READ);
            // One pass: its time shows as simulate; cull shows only the instanced field's.
            stamp(Stamp::Simulated);
            return;
        }
        if simulate {
            dispatch(self.pipelines.simulate);
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
        }
        stamp(Stamp::Simulated);
        if passes.cull {
            self.reset_draw_counts(cmd, field);
            dispatch(self.pipelines.cull);
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::DRAW_READ);
        }
    }

    /// Zero the visible count (and the split commands) with a transfer, never from a shader: a
    /// reset by invocation 0 races with the other workgroups (SPEC §5.1).
    fn reset_draw_counts(&self, cmd: vk::CommandBuffer, field: &FieldBuffers) {
        let d = &self.ctx.device;
        barrier::memory(d, cmd, Access::DRAW_READ, Access::TRANSFER_WRITE);
        unsafe {
            d.cmd_fill_buffer(cmd, field.draws.raw, 0, 4, 0);
            if field.split_draws > 0 {
                d.cmd_fill_buffer(cmd, field.draws.raw, 16, 16 * field.split_draws as u64, 0);
            }
        }
        barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::COMPUTE_READ_WRITE);
    }

    fn draw(
        &self,
        cmd: vk::CommandBuffer,
        set: vk::DescriptorSet,
        field: Option<&FieldBuffers>,
        target: &TargetViews,
        uniforms: &FrameUniforms,
        generated: bool,
    ) {
        let d = &self.ctx.device;
        let clear_color = vk::ClearValue {
            color: vk::ClearColorValue {
                float32: [0.0, 0.0, 0.0, 1.0],
            },
        };
        let mut color = vk::RenderingAttachmentInfo::default()
            .image_view(target.color)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(clear_color);
        if let Some(resolve) = target.resolve {
            color = color
                .resolve_mode(vk::ResolveModeFlags::AVERAGE)
                .resolve_image_view(resolve)
                .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .store_op(vk::AttachmentStoreOp::DONT_CARE);
        }
        let depth = cleared_depth(target.depth, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL, false);
        begin_rendering(d, cmd, &[color], Some(&depth), target.extent);
        let p = &self.pipelines;
        unsafe {
            d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, p.layout, 0, &[set], &[]);
            // Front to back, so depth testing rejects hidden ground and sky before shading.
            if let Some(field) = field {
                let blades = p.blades_wireframe.filter(|_| self.wireframe).unwrap_or(p.blades);
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, blades);
                if field.split_draws > 0 {
                    d.cmd_draw_indirect(cmd, field.draws.raw, 16, field.split_draws, 16);
                } else {
                    d.cmd_draw_indirect(cmd, field.draws.raw, 0, 1, 16);
                }
            }
        }
        if generated {
            self.instanced.record_draw(cmd, p.instanced, p.billboards);
            self.instanced.record_splats(cmd, p.splat);
        }
        self.draw_colliders(cmd, p.colliders, uniforms);
        self.draw_ground(cmd, p.ground, uniforms);
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, p.sky);
            d.cmd_draw(cmd, 3, 1, 0, 0);
            d.cmd_end_rendering(cmd);
        }
    }

    /// Record the occluders (ground, colliders) into the depth pyramid (`sun` false; the cull pass
    /// reads it) or the sun's shadow map (`sun` true; blade and ground shading read it).
    fn record_occluders(&self, cmd: vk::CommandBuffer, set: vk::DescriptorSet, uniforms: &FrameUniforms, sun: bool) {
        let p = &self.pipelines;
        let draw = || {
            let d = &self.ctx.device;
            unsafe { d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, p.layout, 0, &[set], &[]) };
            let (ground, colliders) = if sun {
                (p.shadow_ground, p.shadow_colliders)
            } else {
                (p.occluder_ground, p.occluder_colliders)
            };
            self.draw_ground(cmd, ground, uniforms);
            self.draw_colliders(cmd, colliders, uniforms);
        };
        if sun {
            self.occluders.record_shadow(cmd, draw);
        } else {
            self.occluders.record_hiz(cmd, draw);
        }
    }

    /// Draw the ground with `pipeline`: the uploaded mesh, or the sphere or plane the vertex
    /// shader builds.
    fn draw_ground(&self, cmd: vk::CommandBuffer, pipeline: vk::Pipeline, uniforms: &FrameUniforms) {
        let d = &self.ctx.device;
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            match &self.ground.indices {
                Some((indices, count)) => {
                    d.cmd_bind_index_buffer(cmd, indices.raw, 0, vk::IndexType::UINT32);
                    d.cmd_draw_indexed(cmd, *count, 1, 0, 0, 0);
                }
                None if uniforms.surface.w > 0.0 => d.cmd_draw(cmd, GROUND_SPHERE_VERTICES, 1, 0, 0),
                None => d.cmd_draw(cmd, 6, 1, 0, 0),
            }
        }
    }

    /// Draw the collider spheres with `pipeline`, one instance each.
    fn draw_colliders(&self, cmd: vk::CommandBuffer, pipeline: vk::Pipeline, uniforms: &FrameUniforms) {
        let colliders = uniforms.counts.z;
        if colliders > 0 {
            let d = &self.ctx.device;
            unsafe {
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                d.cmd_draw(cmd, COLLIDER_VERTICES, colliders, 0, 0);
            }
        }
    }

    /// Put the ground mesh on the GPU (`None`: the plane or sphere the shaders make themselves).
    /// Call after [`Renderer::upload_field`].
    pub fn upload_ground(&mut self, mesh: Option<&sward_core::mesh::Mesh>) -> Result<()> {
        unsafe { self.ctx.device.device_wait_idle() }.map_err(vk_check("waiting for the GPU"))?;
        let Some(mesh) = mesh else {
            self.ground.indices = None;
            self.ground.grid = None;
            return Ok(());
        };
        let vertices: Vec<glam::Vec4> = mesh
            .positions
            .iter()
            .zip(&mesh.normals)
            .flat_map(|(p, n)| [p.extend(1.0), n.extend(0.0)])
            .collect();
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let vertex_buffer = Buffer::with_data(&self.ctx, "ground vertices", bytemuck::cast_slice(&vertices), storage)?;
        let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
        let index_buffer = Buffer::with_data(
            &self.ctx,
            "ground indices",
            bytemuck::cast_slice(&indices),
            vk::BufferUsageFlags::INDEX_BUFFER,
        )?;
        self.ground = GroundBuffers {
            vertices: vertex_buffer,
            indices: Some((index_buffer, indices.len() as u32)),
            grid: mesh.height_grid(),
        };
        let info = [vk::DescriptorBufferInfo {
            buffer: self.ground.vertices.raw,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let writes: Vec<_> = self
            .slots
            .iter()
            .map(|slot| {
                vk::WriteDescriptorSet::default()
                    .dst_set(slot.set)
                    .dst_binding(6)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(&info)
            })
            .collect();
        unsafe { self.ctx.device.update_descriptor_sets(&writes, &[]) };
        Ok(())
    }

    /// Swap in new pipelines (shader hot reload); waits for the GPU to stop using the old ones.
    pub fn replace_pipelines(&mut self, pipelines: Pipelines) -> Result<()> {
        unsafe { self.ctx.device.device_wait_idle() }.map_err(vk_check("waiting for the GPU"))?;
        self.pipelines = pipelines;
        Ok(())
    }

    /// Record a copy of the visible-blade count (after this frame's cull) into `dst` at byte 0,
    /// for reading once the frame's fence has signalled.
    pub fn record_copy_visible_count(&self, cmd: vk::CommandBuffer, dst: &Buffer) {
        let Some(field) = &self.field else { return };
        let d = &self.ctx.device;
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::TRANSFER_READ);
        let region = vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size: 4,
        };
        unsafe { d.cmd_copy_buffer(cmd, field.draws.raw, dst.raw, &[region]) };
        barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
    }

    /// Run compute passes only (no target) and wait: for tests and simulation warm-up.
    pub fn run_compute(&mut self, uniforms: &FrameUniforms, passes: Passes) -> Result<()> {
        let ctx = self.ctx.clone();
        ctx.submit_and_wait("running the compute passes", |cmd| {
            self.record_frame(cmd, 0, uniforms, Passes { draw: false, ..passes }, None, None);
        })
    }

    /// The instanced field's draw commands as the GPU holds them now: `instance_count` of
    /// command k is the number of blades visible at level k.
    pub fn read_instanced_draws(&self) -> Result<Vec<DrawCommand>> {
        self.instanced.read_draws()
    }

    /// The blades as the GPU holds them now.
    pub fn read_blades(&self) -> Result<Vec<Blade>> {
        self.read(|f| &f.blades)
    }

    /// The collision strengths η as the GPU holds them now.
    pub fn read_etas(&self) -> Result<Vec<f32>> {
        self.read(|f| &f.etas)
    }

    /// The visible blade ids the last cull wrote, and every draw command (`[0]`: all in one).
    pub fn read_visible(&self) -> Result<(Vec<u32>, Vec<DrawCommand>)> {
        let draws: Vec<DrawCommand> = self.read(|f| &f.draws)?;
        let ids: Vec<u32> = self.read(|f| &f.visible)?;
        let count = draws[0].vertex_count as usize;
        Ok((ids[..count.min(ids.len())].to_vec(), draws))
    }

    fn read<T: bytemuck::Pod>(&self, which: impl Fn(&FieldBuffers) -> &Buffer) -> Result<Vec<T>> {
        match &self.field {
            Some(field) => Ok(bytemuck::pod_collect_to_vec(&which(field).download()?)),
            None => Ok(Vec::new()),
        }
    }
}

/// Point binding 0 of `slot`'s set at its uniforms and bindings 1..=7 at `storage`.
fn write_buffer_descriptors(ctx: &Context, slot: &FrameSlot, storage: &[&Buffer; STORAGE_BINDINGS as usize]) {
    let buffers = std::iter::once(&slot.uniforms).chain(storage.iter().copied());
    let infos: Vec<[vk::DescriptorBufferInfo; 1]> = buffers
        .map(|b| {
            [vk::DescriptorBufferInfo {
                buffer: b.raw,
                offset: 0,
                range: vk::WHOLE_SIZE,
            }]
        })
        .collect();
    let writes: Vec<vk::WriteDescriptorSet> = infos
        .iter()
        .enumerate()
        .map(|(binding, info)| {
            let kind = if binding == 0 {
                vk::DescriptorType::UNIFORM_BUFFER
            } else {
                vk::DescriptorType::STORAGE_BUFFER
            };
            vk::WriteDescriptorSet::default()
                .dst_set(slot.set)
                .dst_binding(binding as u32)
                .descriptor_type(kind)
                .buffer_info(info)
        })
        .collect();
    unsafe { ctx.device.update_descriptor_sets(&writes, &[]) };
}

/// Point bindings 8 and 9 of every frame slot's set at the depth pyramid and the shadow map, and
/// binding 14 at the grass texture.
fn write_image_descriptors(ctx: &Context, slots: &[FrameSlot], occluders: &Occluders, grass: &GrassTexture) {
    let [hiz, shadow] = occluders.image_infos();
    let infos = [
        (1 + STORAGE_BINDINGS, [hiz]),
        (2 + STORAGE_BINDINGS, [shadow]),
        (GRASS_TEXTURE_BINDING, [grass.image_info()]),
    ];
    let writes: Vec<vk::WriteDescriptorSet> = slots
        .iter()
        .flat_map(|slot| {
            infos.iter().map(move |(binding, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(slot.set)
                    .dst_binding(*binding)
                    .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                    .image_info(info)
            })
        })
        .collect();
    unsafe { ctx.device.update_descriptor_sets(&writes, &[]) };
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

/// Decide each tile's fate for this frame's view and write the tiles to run into the slot's list.
fn write_active_tiles(field: &mut FieldBuffers, slot: usize, uniforms: &FrameUniforms) {
    let culling = uniforms.modes.x & 8 != 0;
    let eye = uniforms.camera_position.truncate();
    let active = tiles::active(&field.tiles, &uniforms.view_proj, eye, uniforms.coarse_cull.x, culling);
    let bytes: &[u8] = bytemuck::cast_slice(&active);
    let buffer = field.active_tiles[slot]
        .mapped_mut()
        .expect("the tile list is host visible");
    buffer[..bytes.len()].copy_from_slice(bytes);
    field.active_rows = active.len() as u32;
    field.simulated_blades = active.iter().map(|t| t.count).sum();
}

impl Drop for Renderer {
    fn drop(&mut self) {
        unsafe {
            let _ = self.ctx.device.device_wait_idle();
            self.ctx.device.destroy_descriptor_pool(self.descriptor_pool, None);
        }
    }
}
