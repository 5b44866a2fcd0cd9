//! The billboards' grass texture on the GPU: sward's painted billboard (`sward_core::billboard`) with
//! its coverage-keeping mip chain, uploaded once into a sampled sRGB image with a trilinear,
//! edge-clamped sampler (binding 14 of the frame's set).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use sward_core::billboard::shipped_grass_texture;

use crate::barrier::{self, Access};
use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::{vk_check, Result};
use crate::image::Image;

pub(crate) struct GrassTexture {
    image: Image,
    sampler: vk::Sampler,
    ctx: Arc<Context>,
}

impl GrassTexture {
    pub fn new(ctx: &Arc<Context>) -> Result<GrassTexture> {
        let painted = shipped_grass_texture();
        let extent = vk::Extent2D {
            width: painted.size,
            height: painted.size,
        };
        let usage = vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST;
        let levels = painted.levels.len() as u32;
        let image = Image::with_mips(ctx, "grass texture", extent, vk::Format::R8G8B8A8_SRGB, usage, levels)?;
        let bytes: Vec<u8> = painted.levels.iter().flatten().flatten().copied().collect();
        let mut staging = Buffer::new(
            ctx,
            "grass texture upload",
            bytes.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        // The mapping may be longer than asked for (allocation granularity).
        staging.mapped_mut().expect("the upload buffer is host visible")[..bytes.len()].copy_from_slice(&bytes);
        let mut offset = 0u64;
        let regions: Vec<vk::BufferImageCopy> = (0..levels)
            .map(|level| {
                let side = painted.level_size(level as usize);
                let region = vk::BufferImageCopy::default()
                    .buffer_offset(offset)
                    .image_subresource(vk::ImageSubresourceLayers {
                        aspect_mask: vk::ImageAspectFlags::COLOR,
                        mip_level: level,
                        base_array_layer: 0,
                        layer_count: 1,
                    })
                    .image_extent(vk::Extent3D {
                        width: side,
                        height: side,
                        depth: 1,
                    });
                offset += 4 * (side * side) as u64;
                region
            })
            .collect();
        ctx.submit_and_wait("uploading the grass texture", |cmd| {
            let d = &ctx.device;
            let colour = vk::ImageAspectFlags::COLOR;
            let to_copy = (vk::ImageLayout::TRANSFER_DST_OPTIMAL, Access::TRANSFER_WRITE);
            barrier::image(
                d,
                cmd,
                image.raw,
                colour,
                (vk::ImageLayout::UNDEFINED, Access::NOTHING),
                to_copy,
            );
            unsafe {
                d.cmd_copy_buffer_to_image(
                    cmd,
                    staging.raw,
                    image.raw,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &regions,
                )
            };
            let sampled = (vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL, Access::SAMPLED_READ);
            barrier::image(d, cmd, image.raw, colour, to_copy, sampled);
        })?;
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(vk::LOD_CLAMP_NONE);
        let sampler =
            unsafe { ctx.device.create_sampler(&info, None) }.map_err(vk_check("creating the grass sampler"))?;
        Ok(GrassTexture {
            image,
            sampler,
            ctx: ctx.clone(),
        })
    }

    /// Its sampler, which the frame's set also binds apart (`bindings::GRASS_SAMPLER`, for the
    /// passes written in WGSL).
    pub fn sampler(&self) -> vk::Sampler {
        self.sampler
    }

    pub fn image_info(&self) -> vk::DescriptorImageInfo {
        vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: self.image.view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        }
    }
}

impl Drop for GrassTexture {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_sampler(self.sampler, None) };
    }
}
