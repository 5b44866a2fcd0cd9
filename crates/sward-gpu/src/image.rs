//! GPU images with one view, freed in `Drop`: the render targets (multisampled colour, depth,
//! resolved colour).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use crate::buffer::allocation_error;
use crate::context::Context;
use crate::error::{vk_check, Result};

pub struct Image {
    pub raw: vk::Image,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    allocation: Option<Allocation>,
    ctx: Arc<Context>,
}

impl Image {
    pub fn new_2d(
        ctx: &Arc<Context>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        samples: vk::SampleCountFlags,
        usage: vk::ImageUsageFlags,
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
            .mip_levels(1)
            .array_layers(1)
            .samples(samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let raw = unsafe { d.create_image(&info, None) }.map_err(vk_check("creating an image"))?;
        let requirements = unsafe { d.get_image_memory_requirements(raw) };
        let bytes = requirements.size;
        let allocation = ctx
            .allocator()
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location: MemoryLocation::GpuOnly,
                linear: false,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|e| {
                unsafe { d.destroy_image(raw, None) };
                allocation_error(name, bytes, e)
            })?;
        unsafe { d.bind_image_memory(raw, allocation.memory(), allocation.offset()) }
            .map_err(vk_check("binding image memory"))?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(subresource_range(aspect_of(format)));
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
            let _ = self.ctx.allocator().free(allocation);
        }
        unsafe { self.ctx.device.destroy_image(self.raw, None) };
    }
}

pub fn aspect_of(format: vk::Format) -> vk::ImageAspectFlags {
    match format {
        vk::Format::D32_SFLOAT | vk::Format::D16_UNORM => vk::ImageAspectFlags::DEPTH,
        _ => vk::ImageAspectFlags::COLOR,
    }
}

pub fn subresource_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}
