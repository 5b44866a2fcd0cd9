//! The sun's shadow map (SPEC §8), which the blade and ground shaders sample: two cascades side
//! by side — the near cascade (left; the blades in the ball around the eye, drawn after the
//! cull) and the field cascade (right; terrain and colliders over the whole field, drawn
//! first). The image has a fixed size, so it never changes under frames in flight; it stays in
//! the GENERAL layout.

use std::sync::Arc;

use ash::vk;

use crate::barrier::{self, Access};
use crate::context::Context;
use crate::error::Result;
use crate::image::Image;
use crate::passes::occluders::{render_into, sampler, Attachments, SQUARE};
use crate::passes::routes;
use crate::passes::FrameParts;
use crate::pipelines::DEPTH_FORMAT;
use crate::recordings::FrameShape;

/// Side of each cascade of the sun's shadow map at quality `high`.
pub const SHADOW_SIZE: u32 = 2048;

/// One of the shadow map's two cascades.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cascade {
    /// The ball around the eye: the blades there.
    Near = 0,
    /// The whole field: terrain and colliders.
    Field = 1,
}

/// The shadow map's image (both cascades) and its depth-comparing sampler.
pub struct ShadowMap {
    shadow: Image,
    size: u32,
    sampler: vk::Sampler,
    ctx: Arc<Context>,
}

impl ShadowMap {
    /// The map, each cascade `size` texels square.
    pub fn new(ctx: &Arc<Context>, size: u32) -> Result<ShadowMap> {
        let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
        let cascades = vk::Extent2D {
            width: 2 * size,
            height: size,
        };
        let one = vk::SampleCountFlags::TYPE_1;
        let shadow = Image::new_2d(ctx, "shadow map", cascades, DEPTH_FORMAT, one, usage)?;
        let map = ShadowMap {
            shadow,
            size,
            sampler: sampler(&ctx.device, true)?,
            ctx: ctx.clone(),
        };
        map.ctx.submit_and_wait("preparing the shadow map", |cmd| {
            let aspect = crate::image::aspect_of(map.shadow.format);
            let from = (vk::ImageLayout::UNDEFINED, Access::NOTHING);
            let to = (vk::ImageLayout::GENERAL, Access::DEPTH_ATTACHMENT);
            barrier::image(&map.ctx.device, cmd, map.shadow.raw, aspect, from, to);
        })?;
        Ok(map)
    }

    /// The map as the frame's set binds it (`bindings::SHADOW_MAP`).
    pub fn image_info(&self) -> vk::DescriptorImageInfo {
        vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: self.shadow.view,
            image_layout: vk::ImageLayout::GENERAL,
        }
    }

    /// Record the shadow pass of `cascade`: `draw` records the casters' draws into its half of
    /// the map, through that cascade's view of the sun.
    pub fn record(&self, cmd: vk::CommandBuffer, cascade: Cascade, draw: impl FnOnce()) {
        let d = &self.ctx.device;
        // Shaders may still be sampling the map: the previous frame's, or this frame's compute
        // passes reading the field cascade before the near one is drawn.
        barrier::memory(d, cmd, Access::SAMPLED_READ, Access::DEPTH_ATTACHMENT);
        let area = vk::Rect2D {
            offset: vk::Offset2D {
                x: (cascade as u32 * self.size) as i32,
                y: 0,
            },
            extent: SQUARE(self.size),
        };
        let target = Attachments {
            color: None,
            depth: self.shadow.view,
            area,
        };
        render_into(d, cmd, &target, vk::ImageLayout::GENERAL, draw);
        barrier::memory(d, cmd, Access::DEPTH_ATTACHMENT, Access::SAMPLED_READ);
    }
}

impl Drop for ShadowMap {
    fn drop(&mut self) {
        let d = &self.ctx.device;
        unsafe {
            let _ = d.device_wait_idle();
            d.destroy_sampler(self.sampler, None);
        }
    }
}

/// The shadow map's near cascade, once this frame's visible lists are ordered (`ordered`): the
/// Bezier blades of the distance buckets that cast (`shape.casting`; as strips, whatever their
/// route: the same surface) and the instanced levels that begin within the cascade's reach.
/// Only blades: the field cascade holds the terrain and the colliders, and drawing the ground
/// again into this one cost more than the blades (H100, 4096² at `ultra`). Before the compute
/// route's draws, which shade with it. Blades cast only where the cull kept them (SPEC §4:
/// frustum, orientation, occlusion), so a blade just off screen casts no shadow into the view.
pub(crate) fn record_near_shadows(parts: &FrameParts, shape: &FrameShape, ordered: bool) {
    let o = &parts.pipelines.occluders;
    let draw = || {
        parts.bind_set(vk::PipelineBindPoint::GRAPHICS);
        if let (Some(field), true) = (parts.field, ordered) {
            routes::record_blade_casters(&parts.ctx.device, parts.cmd, o.near_blades.raw, field, shape.casting[0]);
        }
        if shape.generated {
            parts
                .instanced
                .record_casters(parts.cmd, o.near_instanced.raw, shape.casting[1]);
        }
    };
    parts.shadows.record(parts.cmd, Cascade::Near, draw);
}
