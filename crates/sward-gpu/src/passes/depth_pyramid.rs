//! The depth pyramid (Hi-Z): the occluders — ground, colliders, the nearest blades the last
//! frame drew, the caller's depth — drawn from the camera into its level 0 as depth, then each
//! level reduced from the one below it (the farthest depth of the texels under it), which the
//! culls test blades and patches against (SPEC §4). The image has a fixed size, so it never
//! changes under frames in flight; it stays in the GENERAL layout.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::barrier::{self, Access};
use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::{vk_check, Result};
use crate::image::{mip_levels, Image};
use crate::passes::occluders::record_occluder_pass;
use crate::passes::occluders::{render_into, sampler, whole, Attachments, SQUARE};
use crate::passes::FrameParts;
use crate::pipelines::{compute_set_layout, compute_wgsl, ComputeOptions, DEPTH_FORMAT, HIZ_FORMAT};
use crate::recordings::FrameShape;
use crate::shaders::{self, ShaderSet};
use crate::target::CallerDepth;

/// Side of the depth pyramid's level 0. Its texels need not be square: the cull pass maps clip
/// space onto it directly.
pub const HIZ_SIZE: u32 = 512;
const _: () = assert!(HIZ_SIZE.is_power_of_two(), "hiz_reduce.wesl halves every level exactly");

/// Pyramid levels one dispatch of `hiz_reduce.wesl` writes.
const LEVELS_PER_REDUCTION: usize = 3;

/// Dispatches that reduce a pyramid of `levels` levels.
fn reductions(levels: u32) -> u32 {
    (levels - 1).div_ceil(LEVELS_PER_REDUCTION as u32)
}

/// The pyramid's image and depth buffer, and the pipeline that reduces it.
pub struct DepthPyramid {
    hiz: Image,
    /// One view per pyramid level (storage images of the reduction; level 0 the colour target).
    hiz_levels: Vec<vk::ImageView>,
    hiz_depth: Image,
    sampler: vk::Sampler,
    reduce_set_layout: vk::DescriptorSetLayout,
    reduce_layout: vk::PipelineLayout,
    reduce: vk::Pipeline,
    pool: vk::DescriptorPool,
    /// Set k reads level k and writes level k + 1.
    reduce_sets: Vec<vk::DescriptorSet>,
    ctx: Arc<Context>,
}

impl DepthPyramid {
    /// The pyramid, `HIZ_SIZE` square at level 0.
    pub fn new(ctx: &Arc<Context>) -> Result<DepthPyramid> {
        let d = &ctx.device;
        // Copied out only by `read_pyramid` (tests).
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::TRANSFER_SRC;
        let levels = mip_levels(HIZ_SIZE);
        let hiz = Image::with_mips(ctx, "depth pyramid", SQUARE(HIZ_SIZE), HIZ_FORMAT, usage, levels)?;
        let hiz_levels = (0..levels).map(|l| hiz.level_view(l)).collect::<Result<Vec<_>>>()?;
        let depth_usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
        let one = vk::SampleCountFlags::TYPE_1;
        let hiz_depth = Image::new_2d(ctx, "occluder depth", SQUARE(HIZ_SIZE), DEPTH_FORMAT, one, depth_usage)?;
        let sampler = sampler(d, false)?;
        let reduce_set_layout = compute_set_layout(
            d,
            vk::DescriptorType::STORAGE_IMAGE,
            &[0, 1, 2, 3],
            "creating the depth pyramid's descriptor set layout",
        )?;
        let set_layouts = [reduce_set_layout];
        let layout_info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
        let reduce_layout = unsafe { d.create_pipeline_layout(&layout_info, None) }
            .map_err(vk_check("creating the depth pyramid's pipeline layout"))?;
        let passes = (&ShaderSet::embedded(), &shaders::HIZ_REDUCE);
        let reduce = compute_wgsl(ctx, reduce_layout, passes, ComputeOptions::default(), &[])?;
        let reductions = reductions(levels);
        let sizes = [vk::DescriptorPoolSize {
            ty: vk::DescriptorType::STORAGE_IMAGE,
            descriptor_count: 4 * reductions,
        }];
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(reductions)
            .pool_sizes(&sizes);
        let pool = unsafe { d.create_descriptor_pool(&pool_info, None) }
            .map_err(vk_check("creating the depth pyramid's descriptor pool"))?;
        let mut pyramid = DepthPyramid {
            hiz,
            hiz_levels,
            hiz_depth,
            sampler,
            reduce_set_layout,
            reduce_layout,
            reduce,
            pool,
            reduce_sets: Vec::new(),
            ctx: ctx.clone(),
        };
        pyramid.reduce_sets = pyramid.write_reduce_sets()?;
        pyramid.set_initial_layouts()?;
        Ok(pyramid)
    }

    /// The pyramid as the frame's set binds it (`bindings::DEPTH_PYRAMID`).
    pub fn image_info(&self) -> vk::DescriptorImageInfo {
        vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: self.hiz.view,
            image_layout: vk::ImageLayout::GENERAL,
        }
    }

    /// Level 0 as the frame's set binds it for the caller's depth to be folded into
    /// (`bindings::PYRAMID_BASE`, a storage image).
    pub fn base_info(&self) -> vk::DescriptorImageInfo {
        vk::DescriptorImageInfo {
            sampler: vk::Sampler::null(),
            image_view: self.hiz_levels[0],
            image_layout: vk::ImageLayout::GENERAL,
        }
    }

    /// The caller's depth as the frame's set binds it (`bindings::CALLER_DEPTH`), read while the
    /// depth pyramid is drawn.
    pub fn caller_depth_info(&self, view: vk::ImageView) -> vk::DescriptorImageInfo {
        vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: view,
            image_layout: vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL,
        }
    }

    /// A set per reduction: level 3k in, levels 3k + 1 ..= 3k + 3 out (the last level again
    /// where they run out; `hiz_reduce.wesl` writes no level past 1 × 1).
    fn write_reduce_sets(&self) -> Result<Vec<vk::DescriptorSet>> {
        let d = &self.ctx.device;
        let last = self.hiz_levels.len() - 1;
        let layouts = vec![self.reduce_set_layout; reductions(self.hiz_levels.len() as u32) as usize];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.pool)
            .set_layouts(&layouts);
        let sets = unsafe { d.allocate_descriptor_sets(&alloc) }.map_err(vk_check("allocating descriptor sets"))?;
        for (k, set) in sets.iter().enumerate() {
            let infos = [0, 1, 2, 3].map(|j| {
                [vk::DescriptorImageInfo {
                    sampler: vk::Sampler::null(),
                    image_view: self.hiz_levels[(LEVELS_PER_REDUCTION * k + j).min(last)],
                    image_layout: vk::ImageLayout::GENERAL,
                }]
            });
            let writes: Vec<_> = infos
                .iter()
                .enumerate()
                .map(|(binding, info)| {
                    vk::WriteDescriptorSet::default()
                        .dst_set(*set)
                        .dst_binding(binding as u32)
                        .descriptor_type(vk::DescriptorType::STORAGE_IMAGE)
                        .image_info(info)
                })
                .collect();
            self.ctx.update_descriptor_sets(&writes);
        }
        Ok(sets)
    }

    /// Every level of the depth pyramid as the last frame left it, level 0 first, rows of
    /// texels (for tests).
    pub fn read_pyramid(&self) -> Result<Vec<Vec<f32>>> {
        let sides: Vec<u32> = (0..self.hiz_levels.len()).map(|l| (HIZ_SIZE >> l).max(1)).collect();
        let offsets: Vec<u64> = sides
            .iter()
            .scan(0u64, |at, side| {
                let here = *at;
                *at += 4 * (*side as u64).pow(2);
                Some(here)
            })
            .collect();
        let bytes = offsets.last().copied().unwrap_or(0) + 4;
        let usage = vk::BufferUsageFlags::TRANSFER_DST;
        let buffer = Buffer::new(
            &self.ctx,
            "depth pyramid read-back",
            bytes,
            usage,
            MemoryLocation::GpuToCpu,
        )?;
        self.ctx.submit_and_wait("reading the depth pyramid back", |cmd| {
            let d = &self.ctx.device;
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::TRANSFER_READ);
            let regions: Vec<vk::BufferImageCopy> = sides
                .iter()
                .zip(&offsets)
                .enumerate()
                .map(|(level, (side, offset))| vk::BufferImageCopy {
                    buffer_offset: *offset,
                    image_subresource: vk::ImageSubresourceLayers {
                        aspect_mask: vk::ImageAspectFlags::COLOR,
                        mip_level: level as u32,
                        base_array_layer: 0,
                        layer_count: 1,
                    },
                    image_extent: vk::Extent3D {
                        width: *side,
                        height: *side,
                        depth: 1,
                    },
                    ..Default::default()
                })
                .collect();
            unsafe { d.cmd_copy_image_to_buffer(cmd, self.hiz.raw, vk::ImageLayout::GENERAL, buffer.raw, &regions) };
            barrier::memory(d, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
        })?;
        let texels: &[f32] = bytemuck::cast_slice(buffer.mapped().expect("the read-back is host visible"));
        Ok(sides
            .iter()
            .zip(&offsets)
            .map(|(side, offset)| {
                let start = (*offset / 4) as usize;
                texels[start..start + (*side as usize).pow(2)].to_vec()
            })
            .collect())
    }

    fn set_initial_layouts(&self) -> Result<()> {
        let d = &self.ctx.device;
        self.ctx.submit_and_wait("preparing the depth pyramid", |cmd| {
            let from = (vk::ImageLayout::UNDEFINED, Access::NOTHING);
            let color = vk::ImageAspectFlags::COLOR;
            let general = (vk::ImageLayout::GENERAL, Access::COMPUTE_READ_WRITE);
            barrier::image(d, cmd, self.hiz.raw, color, from, general);
            let aspect = crate::image::aspect_of(self.hiz_depth.format);
            let depth = (vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL, Access::DEPTH_ATTACHMENT);
            barrier::image(d, cmd, self.hiz_depth.raw, aspect, from, depth);
        })
    }

    /// Record the depth pyramid: `draw` records the occluders' draws from the camera into level
    /// 0, `fold` (where there is one) the compute pass that folds the caller's depth into it,
    /// then each level is reduced from the one below it, ready for the cull pass.
    pub fn record(&self, cmd: vk::CommandBuffer, draw: impl FnOnce(), fold: Option<impl FnOnce()>) {
        let d = &self.ctx.device;
        barrier::memory(d, cmd, Access::SAMPLED_READ, Access::COLOR_ATTACHMENT);
        let target = Attachments {
            color: Some(self.hiz_levels[0]),
            depth: self.hiz_depth.view,
            area: whole(HIZ_SIZE),
        };
        render_into(d, cmd, &target, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL, draw);
        barrier::memory(d, cmd, Access::COLOR_ATTACHMENT, Access::COMPUTE_READ_WRITE);
        if let Some(fold) = fold {
            fold();
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
        }
        unsafe { d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.reduce) };
        for (k, set) in self.reduce_sets.iter().enumerate() {
            let side = (HIZ_SIZE >> (LEVELS_PER_REDUCTION * k + 1)).max(1);
            unsafe {
                d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, self.reduce_layout, 0, &[*set], &[]);
                d.cmd_dispatch(cmd, side.div_ceil(8), side.div_ceil(8), 1);
            }
            barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::COMPUTE_READ_WRITE);
        }
        barrier::memory(d, cmd, Access::COMPUTE_READ_WRITE, Access::SAMPLED_READ);
    }
}

impl Drop for DepthPyramid {
    fn drop(&mut self) {
        let d = &self.ctx.device;
        unsafe {
            let _ = d.device_wait_idle();
            for view in self.hiz_levels.drain(..) {
                d.destroy_image_view(view, None);
            }
            d.destroy_sampler(self.sampler, None);
            d.destroy_pipeline(self.reduce, None);
            d.destroy_pipeline_layout(self.reduce_layout, None);
            d.destroy_descriptor_set_layout(self.reduce_set_layout, None);
            d.destroy_descriptor_pool(self.pool, None);
        }
    }
}

/// The frame's depth pyramid: the occluders drawn and reduced, with the caller's depth folded
/// in where it gives it (the image read in `DEPTH_READ_ONLY_OPTIMAL` and handed back in
/// `DEPTH_ATTACHMENT_OPTIMAL`).
pub(crate) fn record_depth_pyramid(parts: &FrameParts, shape: &FrameShape, caller_depth: Option<CallerDepth>) {
    let (d, cmd) = (&parts.ctx.device, parts.cmd);
    let aspect = crate::image::aspect_of(parts.target_format.depth);
    let attachment = (vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL, Access::DEPTH_ATTACHMENT);
    let read = (vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL, Access::SAMPLED_READ);
    if let Some(depth) = caller_depth {
        barrier::image(d, cmd, depth.image, aspect, attachment, read);
    }
    record_occluder_pass(parts, shape, caller_depth);
    if let Some(depth) = caller_depth {
        barrier::image(d, cmd, depth.image, aspect, read, attachment);
    }
}

/// Fold the caller's depth into the depth pyramid's level 0 (caller_depth_fold.wesl): a
/// level-0 texel per `LANES` (16) invocations, 256 a workgroup.
pub(crate) fn record_caller_depth_fold(parts: &FrameParts) {
    let texels = HIZ_SIZE.pow(2);
    parts.bind_set(vk::PipelineBindPoint::COMPUTE);
    let d = &parts.ctx.device;
    unsafe {
        d.cmd_bind_pipeline(
            parts.cmd,
            vk::PipelineBindPoint::COMPUTE,
            parts.pipelines.occluders.hiz_caller_depth.raw,
        );
        d.cmd_dispatch(parts.cmd, (texels * 16).div_ceil(256), 1, 1);
    }
}
