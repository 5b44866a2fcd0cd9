//! What the occluder passes share: the pipelines that draw the occluders — ground, colliders,
//! blades — into the depth pyramid (`depth_pyramid.rs`, from the camera) and into the sun's
//! shadow map (`shadows.rs`, from the sun), and the rendering both passes begin into their
//! images.

use ash::vk;

use crate::barrier::{self, Access};
use crate::error::{vk_check, Result};
use crate::passes::depth_pyramid::{record_caller_depth_fold, record_depth_pyramid};
use crate::passes::ground::record_colliders;
use crate::passes::routes;
use crate::passes::shadows::Cascade;
use crate::passes::FrameParts;
use crate::pipelines::{
    constants, Builder, DepthDirection, GraphicsDesc, Pipeline,
    Stage::{Fragment, Vertex},
    TargetFormat, View, DEPTH_FORMAT, HIZ_FORMAT,
};
use crate::recordings::{FrameShape, ShadowGround};
use crate::shaders::{self, BEZIER_STRIPS, BLADE_STRIPS, COLLIDERS, GROUND, OCCLUDER_DEPTH};
use crate::target::CallerDepth;
use crate::target::{begin_rendering_in, cleared_depth};

/// A square extent `side` texels wide.
pub(crate) const SQUARE: fn(u32) -> vk::Extent2D = |side| vk::Extent2D {
    width: side,
    height: side,
};

/// The occluders drawn into the depth pyramid's level 0 (depth as colour) and into the sun's
/// shadow map's field cascade (depth only, biased), and the blades into its near cascade.
pub struct OccluderPipelines {
    /// The ground into the depth pyramid's level 0.
    pub hiz_ground: Pipeline,
    /// The colliders into the depth pyramid's level 0.
    pub hiz_colliders: Pipeline,
    /// The nearest blades the last frame drew, narrowed, into the depth pyramid's level 0.
    pub hiz_blades: Pipeline,
    /// The caller's depth folded into the depth pyramid's level 0 by compute (embedding;
    /// caller_depth_fold.wesl), for the renderer's sample count.
    pub hiz_caller_depth: Pipeline,
    /// The ground into the shadow map's field cascade.
    pub shadow_ground: Pipeline,
    /// The colliders into the shadow map's field cascade.
    pub shadow_colliders: Pipeline,
    /// The Bezier blades as the strip route cuts them, and the instanced blades.
    pub near_blades: Pipeline,
    /// The instanced blades into the near cascade.
    pub near_instanced: Pipeline,
}

impl OccluderPipelines {
    pub(crate) fn new(b: &Builder) -> Result<OccluderPipelines> {
        let hiz = TargetFormat {
            color: HIZ_FORMAT,
            depth: DEPTH_FORMAT,
            samples: vk::SampleCountFlags::TYPE_1,
            depth_direction: DepthDirection::Forward,
        };
        let shadow = TargetFormat {
            color: vk::Format::UNDEFINED,
            depth: DEPTH_FORMAT,
            samples: vk::SampleCountFlags::TYPE_1,
            depth_direction: DepthDirection::Forward,
        };
        let caller_depth = match b.target.samples {
            vk::SampleCountFlags::TYPE_1 => &shaders::CALLER_DEPTH_FOLD[0],
            _ => &shaders::CALLER_DEPTH_FOLD[1],
        };
        let reversed = (b.target.depth_direction == DepthDirection::Reverse) as u32;
        let sun = GraphicsDesc {
            view: View::Sun,
            ..b.opaque()
        };
        let occluder_strips = GraphicsDesc {
            view: View::Occluder,
            strip: true,
            ..b.opaque()
        };
        let near_strips = GraphicsDesc {
            view: View::SunNear,
            strip: true,
            ..b.opaque()
        };
        Ok(OccluderPipelines {
            hiz_ground: b.draw_into(hiz, &b.opaque(), &[Vertex(&GROUND), Fragment(&OCCLUDER_DEPTH)])?,
            hiz_colliders: b.draw_into(hiz, &b.opaque(), &[Vertex(&COLLIDERS), Fragment(&OCCLUDER_DEPTH)])?,
            hiz_blades: b.draw_into(
                hiz,
                &occluder_strips,
                &[Vertex(&BEZIER_STRIPS), Fragment(&OCCLUDER_DEPTH)],
            )?,
            hiz_caller_depth: b.compute_wgsl_with(caller_depth, &[(constants::REVERSED_DEPTH, reversed)])?,
            shadow_ground: b.draw_into(shadow, &sun, &[Vertex(&GROUND)])?,
            shadow_colliders: b.draw_into(shadow, &sun, &[Vertex(&COLLIDERS)])?,
            near_blades: b.draw_into(shadow, &near_strips, &[Vertex(&BEZIER_STRIPS)])?,
            near_instanced: b.draw_into(shadow, &near_strips, &[Vertex(&BLADE_STRIPS)])?,
        })
    }
}

/// A pass's attachments and the area it draws.
pub(crate) struct Attachments {
    pub color: Option<vk::ImageView>,
    pub depth: vk::ImageView,
    pub area: vk::Rect2D,
}

/// All of a square image `side` texels wide.
pub(crate) fn whole(side: u32) -> vk::Rect2D {
    vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent: SQUARE(side),
    }
}

/// Begin rendering into `target`'s area (colour cleared to the far plane, depth to 1, there
/// only), set the viewport to it, run `draw`, end.
pub(crate) fn render_into(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    target: &Attachments,
    depth_layout: vk::ImageLayout,
    draw: impl FnOnce(),
) {
    let colors: Vec<vk::RenderingAttachmentInfo> = target
        .color
        .iter()
        .map(|view| {
            vk::RenderingAttachmentInfo::default()
                .image_view(*view)
                .image_layout(vk::ImageLayout::GENERAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(vk::ClearValue {
                    color: vk::ClearColorValue {
                        float32: [1.0, 0.0, 0.0, 0.0],
                    },
                })
        })
        .collect();
    // The shadow map is the pass's product; the pyramid's depth buffer is only a means.
    let depth = cleared_depth(target.depth, depth_layout, target.color.is_none());
    begin_rendering_in(d, cmd, &colors, Some(&depth), target.area);
    draw();
    unsafe { d.cmd_end_rendering(cmd) };
}

/// Nearest-texel sampling clamped to the edge for the pyramid (the cull pass fetches texels
/// itself); for the shadow map a depth-comparing, linearly filtered sampler (2 × 2 PCF in hardware).
pub(crate) fn sampler(d: &ash::Device, compare: bool) -> Result<vk::Sampler> {
    let filter = if compare {
        vk::Filter::LINEAR
    } else {
        vk::Filter::NEAREST
    };
    let info = vk::SamplerCreateInfo::default()
        .mag_filter(filter)
        .min_filter(filter)
        .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
        .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .compare_enable(compare)
        .compare_op(vk::CompareOp::LESS_OR_EQUAL)
        .max_lod(vk::LOD_CLAMP_NONE);
    unsafe { d.create_sampler(&info, None) }.map_err(vk_check("creating a sampler"))
}

/// The occluders into the depth pyramid (when the cull tests occlusion) and the shadow map's
/// field cascade (when the frame is drawn with shadows, into a target: `drawn`). The field
/// cascade comes before the compute passes: the splatted far field is shaded there, shadows
/// included.
pub(crate) fn record_occluders(parts: &FrameParts, shape: &FrameShape, drawn: bool, caller_depth: Option<CallerDepth>) {
    if shape.depth_pyramid {
        record_depth_pyramid(parts, shape, caller_depth);
    }
    if drawn && shape.shadows {
        record_field_cascade(parts, shape);
    }
}

/// The shadow map's field cascade (blade and ground shading read it): the ground — drawn into
/// it, or kept in an image of its own, drawn again there only where what places it changed,
/// and copied in (`shape.shadow_ground`) — and the colliders.
fn record_field_cascade(parts: &FrameParts, shape: &FrameShape) {
    let (d, cmd) = (&parts.ctx.device, parts.cmd);
    let o = &parts.pipelines.occluders;
    let ground = || {
        parts.bind_set(vk::PipelineBindPoint::GRAPHICS);
        parts.ground.record(cmd, o.shadow_ground.raw, shape);
    };
    let colliders = || {
        parts.bind_set(vk::PipelineBindPoint::GRAPHICS);
        // The spheres that only hide grass go into the depth pyramid, not the sun's map.
        record_colliders(d, cmd, o.shadow_colliders.raw, (shape, false));
    };
    match shape.shadow_ground {
        ShadowGround::Drawn => parts.shadows.record(cmd, Cascade::Field, || {
            ground();
            colliders();
        }),
        ShadowGround::Kept { changed } => parts.shadows.record_field(cmd, changed, (ground, colliders)),
    }
}

/// Record the occluders (ground, colliders, the nearest blades the last frame drew) into the
/// depth pyramid, which the cull passes read.
pub(crate) fn record_occluder_pass(parts: &FrameParts, shape: &FrameShape, caller_depth: Option<CallerDepth>) {
    let (d, cmd) = (&parts.ctx.device, parts.cmd);
    let draw = || {
        parts.bind_set(vk::PipelineBindPoint::GRAPHICS);
        let o = &parts.pipelines.occluders;
        parts.ground.record(cmd, o.hiz_ground.raw, shape);
        record_colliders(d, cmd, o.hiz_colliders.raw, (shape, true));
        if let (true, Some(field)) = (shape.blade_occluders, parts.field) {
            routes::record_blade_occluders(d, cmd, o.hiz_blades.raw, field);
        }
    };
    // The blade occluders are the last frame's nearest visible blades, as its ordering pass
    // left them.
    barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::DRAW_READ);
    let fold = caller_depth.map(|_| || record_caller_depth_fold(parts));
    parts.pyramid.record(cmd, draw, fold);
}
