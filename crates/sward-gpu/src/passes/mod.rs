//! The passes of the grass frame, one module each, each owning its pipelines, buffers and
//! descriptor writes; the renderer (`renderer.rs`) calls them in order:
//!
//! - `depth_pyramid.rs`: the depth pyramid the culls test against (ground, colliders, the
//!   nearest blades, the caller's depth);
//! - `shadows.rs`: the sun's shadow map (its field and near cascades);
//! - `occluders.rs`: what those two share — the pipelines that draw the occluders into them;
//! - `trample.rs`: the trample map, stepped with the simulation;
//! - `bezier.rs`: the Bezier field — tile cull, simulate, cull, order into distance buckets —
//!   and the compute route's splat and rasterizer passes over it;
//! - `stream.rs`: the streamed field's window — the tiles entering it each frame;
//! - `generated.rs`: the instanced blades and the billboards generated each frame around the eye
//!   (patch lists, count, scan, place) and their draws;
//! - `billboards.rs`: the billboards' pipelines (their lists are the generated grass's);
//! - `routes.rs`: the ways the Bezier blades reach the screen (tessellation, strips, mesh,
//!   compute) and their draws;
//! - `splats.rs`: the splat target the compute passes write, its tiles and its resolve;
//! - `ground.rs`: the ground, the sky and the colliders;
//! - `grass_texture.rs`: the billboards' painted grass texture;
//! - `paint.rs`: the paint maps over the ground (where grass grows, how tall);
//! - `drawn_blades.rs`: the listed blades for a renderer that draws them itself;
//! - `draw.rs`: the frame's draw into the caller's target.
//!
//! A pass records from `FrameParts`: the command buffer, the frame's set and what the
//! renderer holds, borrowed for one recording.

pub(crate) mod bezier;
pub(crate) mod billboards;
pub mod depth_pyramid;
pub(crate) mod draw;
pub mod drawn_blades;
pub(crate) mod generated;
pub(crate) mod grass_texture;
pub(crate) mod ground;
pub mod occluders;
pub(crate) mod paint;
pub mod routes;
pub mod shadows;
pub(crate) mod splats;
pub(crate) mod stream;
pub(crate) mod trample;

use ash::vk;

use crate::context::Context;
use crate::frame_pipelines::Pipelines;
use crate::pipelines::TargetFormat;

/// What a frame's passes record from, borrowed from the renderer for one recording: where to
/// (the command buffer, the frame's descriptor set) and with what (the pipelines, and the
/// buffers and images the passes own).
pub(crate) struct FrameParts<'a> {
    pub cmd: vk::CommandBuffer,
    pub set: vk::DescriptorSet,
    pub ctx: &'a Context,
    pub pipelines: &'a Pipelines,
    /// The Bezier field, where one is uploaded.
    pub field: Option<&'a bezier::FieldBuffers>,
    pub ground: &'a ground::Ground,
    pub pyramid: &'a depth_pyramid::DepthPyramid,
    pub shadows: &'a shadows::ShadowMap,
    pub instanced: &'a generated::InstancedBuffers,
    pub splats: &'a splats::SplatTarget,
    /// The formats and samples of the targets (the caller's depth among them).
    pub target_format: TargetFormat,
}

impl FrameParts<'_> {
    /// Bind the frame's set for the pipelines of `bind_point`.
    pub fn bind_set(&self, bind_point: vk::PipelineBindPoint) {
        let layout = self.pipelines.layout();
        unsafe {
            self.ctx
                .device
                .cmd_bind_descriptor_sets(self.cmd, bind_point, layout, 0, &[self.set], &[]);
        }
    }
}
