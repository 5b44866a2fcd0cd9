//! The offscreen render target: multisampled colour and depth, the resolved image, and a host
//! buffer the finished frame is copied into for PNGs and tests.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::barrier::{self, Access};
use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::Result;
use crate::image::Image;
use crate::pipelines::{DepthDirection, TargetFormat, DEPTH_FORMAT};

/// The attachments a frame renders into (already in attachment layouts).
#[derive(Clone, Copy, Debug)]
pub struct TargetViews {
    /// The colour attachment (multisampled, or the final image).
    pub color: vk::ImageView,
    /// Single-sample image the multisampled colour resolves into, if any.
    pub resolve: Option<vk::ImageView>,
    /// The depth attachment.
    pub depth: vk::ImageView,
    /// Size of the attachments.
    pub extent: vk::Extent2D,
    /// Keep the depth after the frame (for reading it back); otherwise it is discarded.
    pub keep_depth: bool,
    /// The caller drew into these attachments first (its own scene, as an application that adds
    /// sward's grass to its frame): their colour and depth are loaded, not cleared, the grass is
    /// depth-tested against them, and sward draws no sky, ground or colliders of its own.
    pub over_caller: bool,
    /// With `over_caller`, where the cull tests occlusion: the caller's depth, folded into
    /// sward's occlusion pyramid before the cull, so grass the caller's own scene hides is not
    /// drawn at all (rather than drawn and then hidden by the depth test). sward moves the
    /// image from `DEPTH_ATTACHMENT_OPTIMAL` to `DEPTH_READ_ONLY_OPTIMAL` to read it and back
    /// again before it draws, within its frame. `None`: only sward's own occluders.
    pub occlusion: Option<CallerDepth>,
}

/// The caller's depth image, for sward to read ([`TargetViews::occlusion`]): the image behind
/// [`TargetViews::depth`], of the renderer's depth format and sample count, made with
/// `SAMPLED` usage.
#[derive(Clone, Copy, Debug)]
pub struct CallerDepth {
    /// The depth image.
    pub image: vk::Image,
    /// A view of its depth aspect alone (a format with stencil needs its own view for reading:
    /// the attachment's view has both aspects).
    pub view: vk::ImageView,
}

/// sRGB so the shaders light in linear space and the bytes read back are ready for a PNG.
pub const OFFSCREEN_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// An offscreen colour and depth target with a read-back buffer: frames as pixels.
pub struct OffscreenTarget {
    /// The colour attachment.
    pub color: Image,
    /// The single-sample image the colour resolves into (multisampled targets).
    pub resolve: Option<Image>,
    /// The depth attachment.
    pub depth: Image,
    readback: Buffer,
    /// Size in pixels.
    pub extent: vk::Extent2D,
    /// Frames keep their depth for [`OffscreenTarget::read_depth`] (single-sample targets).
    keep_depth: bool,
    ctx: Arc<Context>,
}

impl OffscreenTarget {
    /// A `width` × `height` target of `format`.
    pub fn new(ctx: &Arc<Context>, width: u32, height: u32, format: TargetFormat) -> Result<OffscreenTarget> {
        let extent = vk::Extent2D { width, height };
        let multisampled = format.samples != vk::SampleCountFlags::TYPE_1;
        let color_usage = if multisampled {
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT
        } else {
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC
        };
        let color = Image::new_2d(ctx, "colour target", extent, format.color, format.samples, color_usage)?;
        let resolve = if multisampled {
            let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
            Some(Image::new_2d(
                ctx,
                "resolved colour",
                extent,
                format.color,
                vk::SampleCountFlags::TYPE_1,
                usage,
            )?)
        } else {
            None
        };
        let depth = Image::new_2d(
            ctx,
            "depth target",
            extent,
            format.depth,
            format.samples,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
        )?;
        let bytes = 4 * width as u64 * height as u64;
        let readback = Buffer::new(
            ctx,
            "frame read-back",
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(OffscreenTarget {
            color,
            resolve,
            depth,
            readback,
            extent,
            // Read back as 32-bit floats: only the format that holds them.
            keep_depth: !multisampled && format.depth == DEPTH_FORMAT,
            ctx: ctx.clone(),
        })
    }

    /// The attachments as the renderer takes them.
    pub fn views(&self) -> TargetViews {
        TargetViews {
            color: self.color.view,
            resolve: self.resolve.as_ref().map(|r| r.view),
            depth: self.depth.view,
            extent: self.extent,
            keep_depth: self.keep_depth,
            over_caller: false,
            occlusion: None,
        }
    }

    /// The last frame's depth buffer (Vulkan depth, 0 near to 1 far), top row first — on a
    /// single-sample target; `None` on a multisampled one, whose samples are not resolved.
    pub fn read_depth(&self) -> Result<Option<Vec<f32>>> {
        if !self.keep_depth {
            return Ok(None);
        }
        let bytes = 4 * self.extent.width as u64 * self.extent.height as u64;
        let usage = vk::BufferUsageFlags::TRANSFER_DST;
        let buffer = Buffer::new(&self.ctx, "depth read-back", bytes, usage, MemoryLocation::GpuToCpu)?;
        let layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
        self.ctx.submit_and_wait("reading the depth back", |cmd| {
            let d = &self.ctx.device;
            barrier::image(
                d,
                cmd,
                self.depth.raw,
                vk::ImageAspectFlags::DEPTH,
                (vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL, Access::DEPTH_ATTACHMENT),
                (layout, Access::TRANSFER_READ),
            );
            let region = vk::BufferImageCopy {
                image_subresource: vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::DEPTH,
                    mip_level: 0,
                    base_array_layer: 0,
                    layer_count: 1,
                },
                image_extent: vk::Extent3D {
                    width: self.extent.width,
                    height: self.extent.height,
                    depth: 1,
                },
                ..Default::default()
            };
            unsafe { d.cmd_copy_image_to_buffer(cmd, self.depth.raw, layout, buffer.raw, &[region]) };
            barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
        })?;
        let raw = buffer.mapped().expect("read-back memory is host visible");
        Ok(Some(bytemuck::pod_collect_to_vec(raw)))
    }

    /// Bring every attachment into its attachment layout (contents are cleared by the frame).
    pub fn begin(&self, d: &ash::Device, cmd: vk::CommandBuffer) {
        let undefined = vk::ImageLayout::UNDEFINED;
        for image in std::iter::once(&self.color).chain(self.resolve.as_ref()) {
            barrier::image(
                d,
                cmd,
                image.raw,
                vk::ImageAspectFlags::COLOR,
                (undefined, Access::NOTHING),
                (vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL, Access::COLOR_ATTACHMENT),
            );
        }
        barrier::image(
            d,
            cmd,
            self.depth.raw,
            crate::image::aspect_of(self.depth.format),
            (undefined, Access::NOTHING),
            (vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL, Access::DEPTH_ATTACHMENT),
        );
    }

    /// Copy the finished (resolved) frame into the read-back buffer.
    pub fn finish(&self, d: &ash::Device, cmd: vk::CommandBuffer) {
        let source = self.resolve.as_ref().unwrap_or(&self.color);
        let src_layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
        barrier::image(
            d,
            cmd,
            source.raw,
            vk::ImageAspectFlags::COLOR,
            (vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL, Access::COLOR_ATTACHMENT),
            (src_layout, Access::TRANSFER_READ),
        );
        let region = vk::BufferImageCopy {
            buffer_offset: 0,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            },
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D {
                width: self.extent.width,
                height: self.extent.height,
                depth: 1,
            },
        };
        unsafe { d.cmd_copy_image_to_buffer(cmd, source.raw, src_layout, self.readback.raw, &[region]) };
        barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
    }

    /// The last finished frame as tightly packed RGBA8 (sRGB), top row first.
    pub fn pixels(&self) -> Vec<u8> {
        self.readback
            .mapped()
            .expect("read-back memory is host visible")
            .to_vec()
    }
}

/// A depth attachment in `layout`, cleared to the far plane, kept after the pass only if `store`.
pub(crate) fn cleared_depth(
    view: vk::ImageView,
    layout: vk::ImageLayout,
    store: bool,
) -> vk::RenderingAttachmentInfo<'static> {
    depth_attachment(view, layout, store, vk::AttachmentLoadOp::CLEAR)
}

/// A depth attachment in `layout`, loaded by `load`, kept after the pass only if `store`.
pub(crate) fn depth_attachment(
    view: vk::ImageView,
    layout: vk::ImageLayout,
    store: bool,
    load: vk::AttachmentLoadOp,
) -> vk::RenderingAttachmentInfo<'static> {
    depth_attachment_facing(view, layout, (store, load), DepthDirection::Forward)
}

/// [`depth_attachment`] of a target whose depth runs `direction` (cleared to its far plane).
pub(crate) fn depth_attachment_facing(
    view: vk::ImageView,
    layout: vk::ImageLayout,
    (store, load): (bool, vk::AttachmentLoadOp),
    direction: DepthDirection,
) -> vk::RenderingAttachmentInfo<'static> {
    vk::RenderingAttachmentInfo::default()
        .image_view(view)
        .image_layout(layout)
        .load_op(load)
        .store_op(if store {
            vk::AttachmentStoreOp::STORE
        } else {
            vk::AttachmentStoreOp::DONT_CARE
        })
        .clear_value(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: direction.far(),
                stencil: 0,
            },
        })
}

/// Begin dynamic rendering into `colors` and `depth` (if any) over the whole of `extent`, with
/// the viewport and scissor (dynamic in every sward pipeline) set to match.
pub fn begin_rendering(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    colors: &[vk::RenderingAttachmentInfo],
    depth: Option<&vk::RenderingAttachmentInfo>,
    extent: vk::Extent2D,
) {
    let area = vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent,
    };
    begin_rendering_in(d, cmd, colors, depth, area);
}

/// Begin dynamic rendering into `area` of the attachments (cleared there only, where they
/// clear), the viewport and scissor set to it.
pub fn begin_rendering_in(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    colors: &[vk::RenderingAttachmentInfo],
    depth: Option<&vk::RenderingAttachmentInfo>,
    area: vk::Rect2D,
) {
    begin_rendering_with(d, cmd, (colors, depth), area, vk::RenderingFlags::empty());
    set_viewport(d, cmd, area);
}

/// Begin dynamic rendering into `area` of the attachments with `flags`
/// (`CONTENTS_SECONDARY_COMMAND_BUFFERS`: the drawing is a secondary command buffer's, which
/// sets its own viewport).
pub(crate) fn begin_rendering_with(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    (colors, depth): (&[vk::RenderingAttachmentInfo], Option<&vk::RenderingAttachmentInfo>),
    area: vk::Rect2D,
    flags: vk::RenderingFlags,
) {
    let mut rendering = vk::RenderingInfo::default()
        .flags(flags)
        .render_area(area)
        .layer_count(1)
        .color_attachments(colors);
    if let Some(depth) = depth {
        rendering = rendering.depth_attachment(depth);
    }
    unsafe { d.cmd_begin_rendering(cmd, &rendering) };
}

/// Set the viewport and scissor (dynamic in every sward pipeline) to `area`.
pub(crate) fn set_viewport(d: &ash::Device, cmd: vk::CommandBuffer, area: vk::Rect2D) {
    set_viewport_facing(d, cmd, area, DepthDirection::Forward);
}

/// Set the viewport and scissor to `area` of a target whose depth runs `direction`: a reversed
/// target's depth range is mirrored (minDepth 1, maxDepth 0, which Vulkan allows), so sward's
/// forward depths land there as `1 − z`.
pub(crate) fn set_viewport_facing(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    area: vk::Rect2D,
    direction: DepthDirection,
) {
    let far = direction.far();
    let viewport = vk::Viewport {
        x: area.offset.x as f32,
        y: area.offset.y as f32,
        width: area.extent.width as f32,
        height: area.extent.height as f32,
        min_depth: 1.0 - far,
        max_depth: far,
    };
    unsafe {
        d.cmd_set_viewport(cmd, 0, &[viewport]);
        d.cmd_set_scissor(cmd, 0, &[area]);
    }
}

/// GPU bytes per pixel of an offscreen target of `samples` samples: colour and depth per sample,
/// the resolved colour (multisampled targets) and the read-back.
pub fn bytes_per_pixel(samples: vk::SampleCountFlags) -> u64 {
    let samples = samples.as_raw() as u64;
    let resolve = if samples > 1 { 4 } else { 0 };
    samples * (4 + 4) + resolve + 4
}
