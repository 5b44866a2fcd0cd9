//! The sun's shadow map (SPEC §8), which the blade and ground shaders sample: two cascades side
//! by side — the near cascade (left; the blades in the ball around the eye, drawn after the
//! cull) and the field cascade (right; terrain and colliders over the whole field, drawn
//! first). The image has a fixed size, so it never changes under frames in flight; it stays in
//! the GENERAL layout but while the kept ground is copied in. Where the field cascade's ground
//! stands still (the sun, the ground, a streamed field's window unmoved), it is drawn once into
//! an image of its own and copied in each frame before the colliders: drawing a ground that
//! covers the cascade is most of the pass on a GPU with few raster units (on an H200 the frame
//! is 0.6 ms faster with the meadow's plane, 1.0 with the prairie's terrain). A ground that
//! moves every frame is drawn into the cascade, as before.

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
use crate::target::{begin_rendering_in, depth_attachment};

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

/// The shadow map's image (both cascades), the field cascade's ground as last drawn, and the
/// map's depth-comparing sampler.
pub struct ShadowMap {
    shadow: Image,
    /// The ground alone as the field cascade sees it: drawn where it changed, copied into the
    /// cascade every frame.
    ground: Image,
    size: u32,
    sampler: vk::Sampler,
    ctx: Arc<Context>,
}

impl ShadowMap {
    /// The map, each cascade `size` texels square.
    pub fn new(ctx: &Arc<Context>, size: u32) -> Result<ShadowMap> {
        let drawn = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
        let usage = drawn | vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST;
        let cascades = vk::Extent2D {
            width: 2 * size,
            height: size,
        };
        let one = vk::SampleCountFlags::TYPE_1;
        let shadow = Image::new_2d(ctx, "shadow map", cascades, DEPTH_FORMAT, one, usage)?;
        let copied = drawn | vk::ImageUsageFlags::TRANSFER_SRC;
        let ground = Image::new_2d(ctx, "shadow map ground", SQUARE(size), DEPTH_FORMAT, one, copied)?;
        let map = ShadowMap {
            shadow,
            ground,
            size,
            sampler: sampler(&ctx.device, true)?,
            ctx: ctx.clone(),
        };
        map.ctx.submit_and_wait("preparing the shadow map", |cmd| {
            let aspect = crate::image::aspect_of(map.shadow.format);
            let from = (vk::ImageLayout::UNDEFINED, Access::NOTHING);
            let to = (vk::ImageLayout::GENERAL, Access::DEPTH_ATTACHMENT);
            for image in [map.shadow.raw, map.ground.raw] {
                barrier::image(&map.ctx.device, cmd, image, aspect, from, to);
            }
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

    /// The map's comparison sampler, which the frame's set also binds apart
    /// (`bindings::SHADOW_SAMPLER`, for the passes written in WGSL).
    pub fn sampler(&self) -> vk::Sampler {
        self.sampler
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

    /// Record the field cascade: the ground drawn by `draw_ground` into the map's ground image
    /// where `ground_changed` (else it is as the last frame that drew it left it), copied into
    /// the cascade, then the colliders drawn by `draw_colliders` over it.
    pub fn record_field(
        &self,
        cmd: vk::CommandBuffer,
        ground_changed: bool,
        (draw_ground, draw_colliders): (impl FnOnce(), impl FnOnce()),
    ) {
        let d = &self.ctx.device;
        let whole = vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent: SQUARE(self.size),
        };
        if ground_changed {
            let target = Attachments {
                color: None,
                depth: self.ground.view,
                area: whole,
            };
            render_into(d, cmd, &target, vk::ImageLayout::GENERAL, draw_ground);
        }
        self.copy_ground_in(cmd);
        let depth = depth_attachment(
            self.shadow.view,
            vk::ImageLayout::GENERAL,
            true,
            vk::AttachmentLoadOp::LOAD,
        );
        let area = vk::Rect2D {
            offset: vk::Offset2D {
                x: (Cascade::Field as u32 * self.size) as i32,
                y: 0,
            },
            extent: SQUARE(self.size),
        };
        begin_rendering_in(d, cmd, &[], Some(&depth), area);
        draw_colliders();
        unsafe { d.cmd_end_rendering(cmd) };
        barrier::memory(d, cmd, Access::DEPTH_ATTACHMENT, Access::SAMPLED_READ);
    }

    /// The kept ground copied into the field cascade, each image in the layout a copy takes
    /// for the while (GENERAL serves; the validation layer asks these, for speed) and back
    /// to GENERAL, ready for depth: the ground as drawn, the map as the last frame's shaders
    /// sampled it and its near cascade was drawn.
    fn copy_ground_in(&self, cmd: vk::CommandBuffer) {
        let d = &self.ctx.device;
        let aspect = crate::image::aspect_of(self.shadow.format);
        let general = vk::ImageLayout::GENERAL;
        let (source, target) = (
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        );
        let used = Access {
            stages: Access::SAMPLED_READ.stages | Access::DEPTH_ATTACHMENT.stages,
            access: Access::SAMPLED_READ.access | Access::DEPTH_ATTACHMENT.access,
        };
        let read = (source, Access::TRANSFER_READ);
        let written = (target, Access::TRANSFER_WRITE);
        barrier::image(
            d,
            cmd,
            self.ground.raw,
            aspect,
            (general, Access::DEPTH_ATTACHMENT),
            read,
        );
        barrier::image(d, cmd, self.shadow.raw, aspect, (general, used), written);
        let layers = vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::DEPTH,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        };
        let region = vk::ImageCopy::default()
            .src_subresource(layers)
            .dst_subresource(layers)
            .dst_offset(vk::Offset3D {
                x: (Cascade::Field as u32 * self.size) as i32,
                y: 0,
                z: 0,
            })
            .extent(vk::Extent3D {
                width: self.size,
                height: self.size,
                depth: 1,
            });
        unsafe { d.cmd_copy_image(cmd, self.ground.raw, source, self.shadow.raw, target, &[region]) };
        barrier::image(
            d,
            cmd,
            self.ground.raw,
            aspect,
            read,
            (general, Access::DEPTH_ATTACHMENT),
        );
        barrier::image(
            d,
            cmd,
            self.shadow.raw,
            aspect,
            written,
            (general, Access::DEPTH_ATTACHMENT),
        );
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
