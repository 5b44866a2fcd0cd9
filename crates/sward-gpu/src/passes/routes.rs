//! The draw routes of the Bezier blades (SPEC §10): the same ordered visible list drawn as
//! tessellated patches (the paper's route, the reference picture), as vertex-pulled triangle
//! strips (one indirect command per distance bucket), by mesh shaders (two blades per
//! workgroup, where the device has them), or — the compute route — rasterized by compute
//! (raster_blades.wesl) and, beyond `lod.splat_distance`, splatted by compute into the splat
//! target (optionally the nearest buckets, to `lod.strip_distance`, as strips). All shade with
//! blade_fragment.wesl, so the picture does not depend on the route; `Auto` picks per device. The
//! route itself is a scene value (`sward_core::quality::DrawRoute`, `[quality] route`).
//!
//! Every stage but the tessellation and mesh stages is the core's WGSL; those are GLSL glue around
//! the core's functions (`tessellation.wesl`, written as GLSL by naga), since WGSL has no
//! tessellation stages and naga's mesh stages, which copy their outputs through workgroup memory,
//! drew the H100's meadow 1.7× slower. `Auto` never picks tessellation (nor mesh shaders), though
//! on the H100 (1920×1080, `high`, 2^20) it is the fastest route for the meadow by 1 %: 5.12 ms
//! against the compute route's 5.17 and the strips' 5.46 (cis565: 7.85, 7.79, 7.80); on lavapipe
//! (Mesa 25.0.7, 640×360, 2^14) it is the slowest: the meadow's 330 ms against 215 by strips and
//! 216 by the compute route (cis565: 176, 123, 123). The route stays: it is the paper's, the
//! reference picture every other route is held to (`render.rs`, `routes.rs` tests), and it costs no
//! second copy of anything.

use ash::vk;
use sward_core::commands::{
    COMMAND_BUCKETS, COMMAND_MESH_DISPATCH, COMMAND_OCCLUDERS, COMMAND_SPLITS, DISTANCE_BUCKETS,
};

use crate::context::DeviceInfo;
use crate::error::Result;
use crate::passes::bezier::FieldBuffers;
use crate::pipelines::{
    Builder, Depth, GraphicsDesc, Pipeline, Stage,
    Stage::{Fragment, Glsl, Vertex},
};
use crate::shaders::{BEZIER_STRIPS, BLADE_STRIPS};

pub use sward_core::quality::DrawRoute;

/// The route a device draws with, and — where the route asked for needs what the device lacks —
/// one sentence saying so and which route draws instead. The rule comes from `sward bench
/// --draw-route tessellation,strips,compute` on both devices measured (docs/benchmarks-history.md, "Draw
/// routes"): the compute route was never more than 3 % slower than tessellation and up to 8×
/// faster — NVIDIA H100 at 1920×1080: cis565 2^20 31.8 vs 32.4 ms, meadow 2^20 5.95 vs 5.82 ms,
/// hills 11.1 vs 11.8 ms, prairie 2^24 8.4 vs 68.8 ms (its far blades cost the few raster units
/// as much as near ones; splatted they cost the whole chip almost nothing); lavapipe at 640×640:
/// 10–30 % faster than tessellation. Its rasterizer (`lod.compute_raster`) is the scene's
/// choice, not the route's: it wins only where blades are many and deep ("The compute
/// rasterizer"). Strips alone lost 8 % on the H100's meadow, mesh shaders 13 % (they run on the
/// same few units). So `Auto` is the compute route wherever the device has 64-bit atomics, and
/// strips (faster than tessellation on both devices' shipped scenes but the H100's meadow) where
/// it has not. The bench's copy variant (`copy_blades`) draws the copies by patch index, which
/// only tessellation reads.
pub fn resolve(route: DrawRoute, info: &DeviceInfo, copy_blades: bool) -> (DrawRoute, Option<String>) {
    let fallback = if info.int64_atomics {
        DrawRoute::Compute
    } else {
        DrawRoute::Strips
    };
    let lacking = |needs: &str| {
        let note = format!(
            "the {} draw route needs {needs}, which {} lacks; drawing by the {} route instead",
            route.name(),
            info.name,
            fallback.name()
        );
        (fallback, Some(note))
    };
    match route {
        _ if copy_blades => (DrawRoute::Tessellation, None),
        DrawRoute::Auto => (fallback, None),
        DrawRoute::Mesh if !info.mesh_shaders => lacking("mesh shaders (VK_EXT_mesh_shader)"),
        DrawRoute::Compute if !info.int64_atomics => lacking("64-bit buffer atomics (shaderBufferInt64Atomics)"),
        route => (route, None),
    }
}

/// The routes' graphics pipelines.
pub struct RoutePipelines {
    /// The tessellation route's blades.
    pub tessellated: Pipeline,
    /// The strip route's blades: vertex-pulled triangle strips.
    pub strips: Pipeline,
    /// The mesh route's blades, and the commands that draw them, where the device has mesh
    /// shaders.
    pub mesh: Option<(Pipeline, ash::ext::mesh_shader::Device)>,
    /// The blades as lines, where the device can (fillModeNonSolid), by either hardware route.
    pub tessellated_wireframe: Option<Pipeline>,
    /// The strip route's blades as lines.
    pub strips_wireframe: Option<Pipeline>,
}

impl RoutePipelines {
    pub(crate) fn new(b: &Builder) -> Result<RoutePipelines> {
        let tessellated = GraphicsDesc {
            tessellated: true,
            depth: Depth::TestAndWrite,
            ..b.opaque()
        };
        let strips = GraphicsDesc {
            strip: true,
            ..b.opaque()
        };
        let fragment = Fragment(&BLADE_STRIPS);
        let tessellated_stages = [Glsl("blade.vert"), Glsl("blade.tesc"), Glsl("blade.tese"), fragment];
        let strip_stages = [Vertex(&BEZIER_STRIPS), Fragment(&BEZIER_STRIPS)];
        let wire = |desc: &GraphicsDesc, stages: &[Stage]| {
            let lines = GraphicsDesc {
                wireframe: true,
                ..*desc
            };
            b.ctx.info.wireframe.then(|| b.draw(&lines, stages)).transpose()
        };
        let mesh = if b.ctx.info.mesh_shaders {
            // No vertex input: the mesh stage makes its own vertices and triangles.
            let pipeline = b.draw(&b.opaque(), &[Glsl("blade.mesh"), fragment])?;
            Some((
                pipeline,
                ash::ext::mesh_shader::Device::new(&b.ctx.instance, &b.ctx.device),
            ))
        } else {
            None
        };
        Ok(RoutePipelines {
            tessellated: b.draw(&tessellated, &tessellated_stages)?,
            strips: b.draw(&strips, &strip_stages)?,
            mesh,
            tessellated_wireframe: wire(&tessellated, &tessellated_stages)?,
            strips_wireframe: wire(&strips, &strip_stages)?,
        })
    }
}

/// Record the Bezier blades' draw by `route` (a resolved route), inside the frame's rendering;
/// the buckets from `first_computed` on are left to the compute passes.
pub(crate) fn record_blades(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    pipelines: &RoutePipelines,
    field: &FieldBuffers,
    route: DrawRoute,
    first_computed: u32,
    wireframe: bool,
) {
    const STRIDE: u32 = std::mem::size_of::<sward_core::gpu::DrawCommand>() as u32;
    let wire = |solid: &Pipeline, lines: &Option<Pipeline>| lines.as_ref().filter(|_| wireframe).unwrap_or(solid).raw;
    unsafe {
        match route {
            DrawRoute::Strips | DrawRoute::Compute => {
                if first_computed == 0 {
                    return;
                }
                let strips = wire(&pipelines.strips, &pipelines.strips_wireframe);
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, strips);
                let offset = (COMMAND_BUCKETS * STRIDE) as u64;
                d.cmd_draw_indirect(cmd, field.draws.raw, offset, first_computed, STRIDE);
            }
            DrawRoute::Mesh => {
                let Some((pipeline, mesh)) = &pipelines.mesh else {
                    return; // resolve() keeps the route from a device without mesh shaders
                };
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw);
                let offset = (COMMAND_MESH_DISPATCH * STRIDE) as u64;
                mesh.cmd_draw_mesh_tasks_indirect(cmd, field.draws.raw, offset, 1, STRIDE);
            }
            DrawRoute::Tessellation | DrawRoute::Auto => {
                let blades = wire(&pipelines.tessellated, &pipelines.tessellated_wireframe);
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, blades);
                if field.split_draws > 0 {
                    let offset = (COMMAND_SPLITS * STRIDE) as u64;
                    d.cmd_draw_indirect(cmd, field.draws.raw, offset, field.split_draws, STRIDE);
                } else {
                    d.cmd_draw_indirect(cmd, field.draws.raw, 0, 1, STRIDE);
                }
            }
        }
    }
}

/// Record the Bezier blades of the first `buckets` distance buckets into the shadow map's near
/// cascade (inside its rendering) with `pipeline`, the strip route's blades seen by the sun.
pub(crate) fn record_blade_casters(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: vk::Pipeline,
    field: &FieldBuffers,
    buckets: u32,
) {
    record_bucket_commands(d, cmd, pipeline, field, COMMAND_BUCKETS, buckets);
}

/// The depth pyramid's blade occluders: the nearest visible blades of the last frame's ordered
/// list, up to `cull.blade_occluders` (`COMMAND_OCCLUDERS`, one command per distance bucket, as
/// the ordering pass cut them), drawn as narrowed strips.
pub(crate) fn record_blade_occluders(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: vk::Pipeline,
    field: &FieldBuffers,
) {
    record_bucket_commands(d, cmd, pipeline, field, COMMAND_OCCLUDERS, DISTANCE_BUCKETS);
}

/// Draw with `pipeline` the first `buckets` of the per-bucket strip commands that start at
/// command `first` (`gl_DrawID` is the bucket).
fn record_bucket_commands(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    pipeline: vk::Pipeline,
    field: &FieldBuffers,
    first: u32,
    buckets: u32,
) {
    const STRIDE: u32 = std::mem::size_of::<sward_core::gpu::DrawCommand>() as u32;
    let buckets = buckets.min(DISTANCE_BUCKETS);
    if buckets == 0 {
        return;
    }
    unsafe {
        d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
        d.cmd_draw_indirect(cmd, field.draws.raw, (first * STRIDE) as u64, buckets, STRIDE);
    }
}
