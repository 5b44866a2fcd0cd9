//! GPU images with one view, freed in `Drop`: the render targets (multisampled colour, depth,
//! resolved colour).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::Allocation;
use gpu_allocator::MemoryLocation;

use crate::buffer::{allocate, free};
use crate::context::Context;
use crate::error::{vk_check, Result};

/// A 2D image with its memory and a view of it, freed when dropped.
pub struct Image {
    /// The Vulkan image.
    pub raw: vk::Image,
    /// A view of every level.
    pub view: vk::ImageView,
    /// Its format.
    pub format: vk::Format,
    /// Its size in pixels.
    pub extent: vk::Extent2D,
    allocation: Option<Allocation>,
    ctx: Arc<Context>,
}

impl Image {
    /// A single-level 2D image of `extent`, `format` and `samples`, for `usage`.
    pub fn new_2d(
        ctx: &Arc<Context>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        samples: vk::SampleCountFlags,
        usage: vk::ImageUsageFlags,
    ) -> Result<Image> {
        Self::with_levels(ctx, name, extent, format, samples, usage, 1)
    }

    /// A single-sample image with `levels` mip levels; `view` sees them all.
    pub fn with_mips(
        ctx: &Arc<Context>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        levels: u32,
    ) -> Result<Image> {
        Self::with_levels(ctx, name, extent, format, vk::SampleCountFlags::TYPE_1, usage, levels)
    }

    /// A view of one mip level.
    pub fn level_view(&self, level: u32) -> Result<vk::ImageView> {
        let range = vk::ImageSubresourceRange {
            base_mip_level: level,
            ..subresource_range(aspect_of(self.format))
        };
        let info = vk::ImageViewCreateInfo::default()
            .image(self.raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(self.format)
            .subresource_range(range);
        unsafe { self.ctx.device.create_image_view(&info, None) }.map_err(vk_check("creating an image view"))
    }

    fn with_levels(
        ctx: &Arc<Context>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        samples: vk::SampleCountFlags,
        usage: vk::ImageUsageFlags,
        levels: u32,
    ) -> Result<Image> {
        let d = &ctx.device;
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            })
            .mip_levels(levels)
            .array_layers(1)
            .samples(samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let raw = unsafe { d.create_image(&info, None) }.map_err(vk_check("creating an image"))?;
        let requirements = unsafe { d.get_image_memory_requirements(raw) };
        let allocation = allocate(ctx, name, requirements, MemoryLocation::GpuOnly, false).inspect_err(|_| unsafe {
            d.destroy_image(raw, None);
        })?;
        unsafe { d.bind_image_memory(raw, allocation.memory(), allocation.offset()) }
            .map_err(vk_check("binding image memory"))?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(vk::ImageSubresourceRange {
                level_count: levels,
                ..subresource_range(aspect_of(format))
            });
        let view = unsafe { d.create_image_view(&view_info, None) }.map_err(vk_check("creating an image view"))?;
        Ok(Image {
            raw,
            view,
            format,
            extent,
            allocation: Some(allocation),
            ctx: ctx.clone(),
        })
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_image_view(self.view, None) };
        if let Some(allocation) = self.allocation.take() {
            free(&self.ctx, allocation);
        }
        unsafe { self.ctx.device.destroy_image(self.raw, None) };
    }
}

/// Number of mip levels down to 1 × 1 of a `size` × `size` image.
pub fn mip_levels(size: u32) -> u32 {
    u32::BITS - size.max(1).leading_zeros()
}

/// The aspects (colour, or depth) of a `format`.
pub fn aspect_of(format: vk::Format) -> vk::ImageAspectFlags {
    match format {
        vk::Format::D32_SFLOAT | vk::Format::D16_UNORM | vk::Format::X8_D24_UNORM_PACK32 => vk::ImageAspectFlags::DEPTH,
        vk::Format::D16_UNORM_S8_UINT | vk::Format::D24_UNORM_S8_UINT | vk::Format::D32_SFLOAT_S8_UINT => {
            vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
        }
        vk::Format::S8_UINT => vk::ImageAspectFlags::STENCIL,
        _ => vk::ImageAspectFlags::COLOR,
    }
}

/// The whole of an image of one level and one layer, of `aspect`.
pub fn subresource_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}
