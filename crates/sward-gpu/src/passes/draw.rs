//! The frame's draw into the caller's target: the rendering begun over what the caller drew or
//! cleared, then the draws front to back — the Bezier blades by their route, the generated
//! grass, the splats resolved, then (where sward draws the whole picture) the colliders, the
//! ground and the sky, so depth testing rejects hidden ground and sky before they are shaded.

use ash::vk;

use crate::passes::ground::{record_colliders, record_sky};
use crate::passes::routes::{record_blades, DrawRoute};
use crate::passes::FrameParts;
use crate::pipelines::TargetFormat;
use crate::recordings::FrameShape;
use crate::target::{begin_rendering_with, depth_attachment_facing, set_viewport_facing, TargetViews};

/// Begin rendering into the caller's target with `flags`: over what the caller drew, or
/// cleared.
pub(crate) fn begin_draw(
    (d, cmd): (&ash::Device, vk::CommandBuffer),
    target: &TargetViews,
    (format, flags): (TargetFormat, vk::RenderingFlags),
) {
    let clear_color = vk::ClearValue {
        color: vk::ClearColorValue {
            float32: [0.0, 0.0, 0.0, 1.0],
        },
    };
    // Over the caller's own drawing: load what it drew, and store the depth for it.
    let load = if target.over_caller {
        vk::AttachmentLoadOp::LOAD
    } else {
        vk::AttachmentLoadOp::CLEAR
    };
    let mut color = vk::RenderingAttachmentInfo::default()
        .image_view(target.color)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(load)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(clear_color);
    if let Some(resolve) = target.resolve {
        color = color
            .resolve_mode(vk::ResolveModeFlags::AVERAGE)
            .resolve_image_view(resolve)
            .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL);
        // The caller's multisampled image lives on after sward's frame (its later passes
        // load it); sward's own is only resolved.
        if !target.over_caller {
            color = color.store_op(vk::AttachmentStoreOp::DONT_CARE);
        }
    }
    let depth = depth_attachment_facing(
        target.depth,
        vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
        (target.keep_depth || target.over_caller, load),
        format.depth_direction,
    );
    let area = vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent: target.extent,
    };
    begin_rendering_with(d, cmd, (&[color], Some(&depth)), area, flags);
}

/// The frame's draws, inside the rendering `begin_draw` began into a target of `extent` (over
/// the caller's picture: `over_caller`), the Bezier blades by `route` (as lines: `wireframe`).
pub(crate) fn record_draws(
    parts: &FrameParts,
    shape: &FrameShape,
    (extent, over_caller): (vk::Extent2D, bool),
    (route, wireframe): (DrawRoute, bool),
) {
    let (d, cmd) = (&parts.ctx.device, parts.cmd);
    let area = vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent,
    };
    set_viewport_facing(d, cmd, area, parts.target_format.depth_direction);
    let p = parts.pipelines;
    parts.bind_set(vk::PipelineBindPoint::GRAPHICS);
    if let Some(field) = parts.field {
        let first_computed = shape.buckets[0];
        record_blades(d, cmd, &p.routes, field, route, first_computed, wireframe);
    }
    if shape.generated {
        let g = &p.generated;
        let billboards = p.billboards.draws.passes(shape.billboard_depth_prepass);
        parts
            .instanced
            .record_draw(cmd, g.instanced.raw, billboards, shape.billboards_rasterized);
    }
    parts.splats.record_resolve(cmd, p.splats.resolve.raw);
    if !over_caller {
        record_colliders(d, cmd, p.scene.colliders.raw, (shape, false));
        parts.ground.record(cmd, p.scene.ground.raw, shape);
        record_sky(d, cmd, p.scene.sky.raw);
    }
}
