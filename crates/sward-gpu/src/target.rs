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
use crate::pipelines::{TargetFormat, DEPTH_FORMAT};
use crate::renderer::TargetViews;

/// sRGB so the shaders light in linear space and the bytes read back are ready for a PNG.
pub const OFFSCREEN_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

pub struct OffscreenTarget {
    pub color: Image,
    pub resolve: Option<Image>,
    pub depth: Image,
    readback: Buffer,
    pub extent: vk::Extent2D,
}

impl OffscreenTarget {
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
            DEPTH_FORMAT,
            format.samples,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
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
        })
    }

    pub fn views(&self) -> TargetViews {
        TargetViews {
            color: self.color.view,
            resolve: self.resolve.as_ref().map(|r| r.view),
            depth: self.depth.view,
            extent: self.extent,
        }
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
            vk::ImageAspectFlags::DEPTH,
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
