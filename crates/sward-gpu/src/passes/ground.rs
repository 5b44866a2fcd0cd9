//! The scene around the grass: the ground (an uploaded mesh, or the plane or sphere the vertex
//! shader builds), the collider spheres and the sky. The frame draws them after the grass so
//! depth testing spares their hidden fragments; the occluder passes draw the same ground and
//! colliders into the depth pyramid and the shadow map.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use sward_core::mesh::{HeightGrid, Mesh};

use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::Result;
use crate::pipelines::{Builder, Depth, GraphicsDesc, Pipeline, Stage::Fragment, Stage::Vertex};
use crate::recordings::FrameShape;
use crate::shaders::{COLLIDERS, GROUND, SKY};

/// Vertices of the ground sphere `scenery.wesl` builds (96 rings × 192 segments × 6).
const GROUND_SPHERE_VERTICES: u32 = 96 * 192 * 6;

/// Vertices of one collider sphere `scenery.wesl` builds (16 rings × 32 segments × 6).
const COLLIDER_VERTICES: u32 = 16 * 32 * 6;

/// The pipelines of the scene around the grass.
pub struct ScenePipelines {
    pub sky: Pipeline,
    pub ground: Pipeline,
    /// The collider spheres.
    pub colliders: Pipeline,
}

impl ScenePipelines {
    pub(crate) fn new(b: &Builder) -> Result<ScenePipelines> {
        // The sky is drawn last and only where nothing else is (depth still at the cleared 1.0):
        // fragment work is what a frame runs short of on GPUs with few raster units.
        let sky = GraphicsDesc {
            depth: Depth::BehindEverything,
            ..b.opaque()
        };
        Ok(ScenePipelines {
            sky: b.draw(&sky, &[Vertex(&SKY), Fragment(&SKY)])?,
            ground: b.draw(&b.opaque(), &[Vertex(&GROUND), Fragment(&GROUND)])?,
            colliders: b.draw(&b.opaque(), &[Vertex(&COLLIDERS), Fragment(&COLLIDERS)])?,
        })
    }
}

/// The ground mesh, if the scene grows grass on one (else a placeholder vertex buffer).
pub(crate) struct Ground {
    pub vertices: Buffer,
    indices: Option<(Buffer, u32)>,
    /// The ground as a height grid, where it is one (the instanced grass stands on it).
    pub grid: Option<HeightGrid>,
    ctx: Arc<Context>,
}

impl Ground {
    /// No mesh: the plane or sphere the shaders make themselves.
    pub fn built_by_shaders(ctx: &Arc<Context>) -> Result<Ground> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        Ok(Ground {
            vertices: Buffer::new(ctx, "ground placeholder", 64, usage, MemoryLocation::GpuOnly)?,
            indices: None,
            grid: None,
            ctx: ctx.clone(),
        })
    }

    /// `mesh` on the GPU: its vertices (position, normal as two vec4) for the ground's vertex stage to pull.
    pub fn from_mesh(ctx: &Arc<Context>, mesh: &Mesh) -> Result<Ground> {
        let vertices = mesh.pulled_vertices();
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let vertex_buffer = Buffer::with_data(ctx, "ground vertices", bytemuck::cast_slice(&vertices), storage)?;
        let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
        let index_buffer = Buffer::with_data(
            ctx,
            "ground indices",
            bytemuck::cast_slice(&indices),
            vk::BufferUsageFlags::INDEX_BUFFER,
        )?;
        Ok(Ground {
            vertices: vertex_buffer,
            indices: Some((index_buffer, indices.len() as u32)),
            grid: mesh.height_grid(),
            ctx: ctx.clone(),
        })
    }

    /// Draw the ground with `pipeline`: the uploaded mesh, or the sphere or plane the vertex
    /// shader builds.
    pub fn record(&self, cmd: vk::CommandBuffer, pipeline: vk::Pipeline, shape: &FrameShape) {
        let d = &self.ctx.device;
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            match &self.indices {
                Some((indices, count)) => {
                    d.cmd_bind_index_buffer(cmd, indices.raw, 0, vk::IndexType::UINT32);
                    d.cmd_draw_indexed(cmd, *count, 1, 0, 0, 0);
                }
                None if shape.sphere_ground => d.cmd_draw(cmd, GROUND_SPHERE_VERTICES, 1, 0, 0),
                None => d.cmd_draw(cmd, 6, 1, 0, 0),
            }
        }
    }
}

/// Draw the collider spheres with `pipeline`, one instance each: the pushing ones and the
/// cutters after them, and after those, where `hiding` (the depth pyramid), the spheres that
/// only hide grass.
pub(crate) fn record_colliders(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: vk::Pipeline,
    (shape, hiding): (&FrameShape, bool),
) {
    let [pushing, cutting, hiders] = shape.colliders;
    let colliders = pushing + cutting + if hiding { hiders } else { 0 };
    if colliders > 0 {
        unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            d.cmd_draw(cmd, COLLIDER_VERTICES, colliders, 0, 0);
        }
    }
}

/// Draw the sky where nothing else is (one screen-covering triangle, depth still cleared).
pub(crate) fn record_sky(d: &ash::Device, cmd: vk::CommandBuffer, pipeline: vk::Pipeline) {
    unsafe {
        d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
        d.cmd_draw(cmd, 3, 1, 0, 0);
    }
}
