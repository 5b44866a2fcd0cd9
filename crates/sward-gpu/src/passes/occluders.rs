//! The occluder passes and their images: the depth pyramid (Hi-Z) of the ground and the colliders
//! seen from the camera, which the cull pass tests blades against (SPEC §4), and the sun's shadow
//! map, which the blade and ground shaders sample (SPEC §8). The shadow map is two cascades side
//! by side: the near cascade (left; the blades in the ball around the eye, drawn after the cull)
//! and the field cascade (right; terrain and colliders over the whole field, drawn first). Both images have fixed sizes, so they never change under frames in flight; they stay
//! in the GENERAL layout.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::barrier::{self, Access};
use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::{vk_check, Result};
use crate::image::{mip_levels, Image};
use crate::pipelines::{
    compute, compute_set_layout, Builder, ComputeOptions, GraphicsDesc, Pipeline, TargetFormat, View, DEPTH_FORMAT,
    HIZ_FORMAT,
};
use crate::shaders::ShaderSet;
use crate::target::{begin_rendering_in, cleared_depth};

/// Side of the depth pyramid's level 0. Its texels need not be square: the cull pass maps clip
/// space onto it directly.
pub const HIZ_SIZE: u32 = 512;
const _: () = assert!(HIZ_SIZE.is_power_of_two(), "hiz_reduce.comp halves every level exactly");

/// Pyramid levels one dispatch of `hiz_reduce.comp` writes.
const LEVELS_PER_REDUCTION: usize = 3;

/// Dispatches that reduce a pyramid of `levels` levels.
fn reductions(levels: u32) -> u32 {
    (levels - 1).div_ceil(LEVELS_PER_REDUCTION as u32)
}
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

const SQUARE: fn(u32) -> vk::Extent2D = |side| vk::Extent2D {
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
    /// The caller's depth folded into the depth pyramid's level 0 (embedding;
    /// caller_depth.glsl), for the renderer's sample count.
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
        };
        let shadow = TargetFormat {
            color: vk::Format::UNDEFINED,
            depth: DEPTH_FORMAT,
            samples: vk::SampleCountFlags::TYPE_1,
        };
        let caller_depth = match b.target.samples {
            vk::SampleCountFlags::TYPE_1 => "caller_depth.frag",
            _ => "caller_depth_ms.frag",
        };
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
            hiz_ground: b.graphics_into(hiz, &b.opaque(), &["ground.vert", "occluder.frag"])?,
            hiz_colliders: b.graphics_into(hiz, &b.opaque(), &["collider.vert", "occluder.frag"])?,
            hiz_blades: b.graphics_into(hiz, &occluder_strips, &["blade_strip.vert", "occluder.frag"])?,
            hiz_caller_depth: b.graphics_into(hiz, &b.opaque(), &["sky.vert", caller_depth])?,
            shadow_ground: b.graphics_into(shadow, &sun, &["ground.vert"])?,
            shadow_colliders: b.graphics_into(shadow, &sun, &["collider.vert"])?,
            near_blades: b.graphics_into(shadow, &near_strips, &["blade_strip.vert"])?,
            near_instanced: b.graphics_into(shadow, &near_strips, &["instanced.vert"])?,
        })
    }
}

/// The images of the occluder passes and the pipeline that reduces the depth pyramid.
pub struct Occluders {
    hiz: Image,
    /// One view per pyramid level (storage images of the reduction; level 0 the colour target).
    hiz_levels: Vec<vk::ImageView>,
    hiz_depth: Image,
    shadow: Image,
    shadow_size: u32,
    hiz_sampler: vk::Sampler,
    shadow_sampler: vk::Sampler,
    reduce_set_layout: vk::DescriptorSetLayout,
    reduce_layout: vk::PipelineLayout,
    reduce: vk::Pipeline,
    pool: vk::DescriptorPool,
    /// Set k reads level k and writes level k + 1.
    reduce_sets: Vec<vk::DescriptorSet>,
    ctx: Arc<Context>,
}

/// A pass's attachments and the area it draws.
struct Attachments {
    color: Option<vk::ImageView>,
    depth: vk::ImageView,
    area: vk::Rect2D,
}

/// All of a square image `side` texels wide.
fn whole(side: u32) -> vk::Rect2D {
    vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent: SQUARE(side),
    }
}

impl Occluders {
    /// The occluder images, each cascade of the sun's shadow map `shadow_size` texels square.
    pub fn new(ctx: &Arc<Context>, shadow_size: u32) -> Result<Occluders> {
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
        let shadow_usage = depth_usage | vk::ImageUsageFlags::SAMPLED;
        let cascades = vk::Extent2D {
            width: 2 * shadow_size,
            height: shadow_size,
        };
        let shadow = Image::new_2d(ctx, "shadow map", cascades, DEPTH_FORMAT, one, shadow_usage)?;
        let hiz_sampler = sampler(d, false)?;
        let shadow_sampler = sampler(d, true)?;
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
        let spirv = ShaderSet::embedded().get("hiz_reduce.comp").to_vec();
        let reduce = compute(ctx, reduce_layout, &spirv, ComputeOptions::default())?;
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
        let mut occluders = Occluders {
            hiz,
            hiz_levels,
            hiz_depth,
            shadow,
            shadow_size,
            hiz_sampler,
            shadow_sampler,
            reduce_set_layout,
            reduce_layout,
            reduce,
            pool,
            reduce_sets: Vec::new(),
            ctx: ctx.clone(),
        };
        occluders.reduce_sets = occluders.write_reduce_sets()?;
        occluders.set_initial_layouts()?;
        Ok(occluders)
    }

    /// The depth pyramid and the shadow map as the frame's set binds them (8 and 9).
    pub fn image_infos(&self) -> [vk::DescriptorImageInfo; 2] {
        [
            vk::DescriptorImageInfo {
                sampler: self.hiz_sampler,
                image_view: self.hiz.view,
                image_layout: vk::ImageLayout::GENERAL,
            },
            vk::DescriptorImageInfo {
                sampler: self.shadow_sampler,
                image_view: self.shadow.view,
                image_layout: vk::ImageLayout::GENERAL,
            },
        ]
    }

    /// The caller's depth as the frame's set binds it (`bindings::CALLER_DEPTH`), read while the
    /// depth pyramid is drawn.
    pub fn caller_depth_info(&self, view: vk::ImageView) -> vk::DescriptorImageInfo {
        vk::DescriptorImageInfo {
            sampler: self.hiz_sampler,
            image_view: view,
            image_layout: vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL,
        }
    }

    /// A set per reduction: level 3k in, levels 3k + 1 ..= 3k + 3 out (the last level again
    /// where they run out; `hiz_reduce.comp` writes no level past 1 × 1).
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
        self.ctx.submit_and_wait("preparing the occluder images", |cmd| {
            let to = |image: &Image, layout, after| {
                let aspect = crate::image::aspect_of(image.format);
                let from = (vk::ImageLayout::UNDEFINED, Access::NOTHING);
                barrier::image(d, cmd, image.raw, aspect, from, (layout, after));
            };
            to(&self.hiz, vk::ImageLayout::GENERAL, Access::COMPUTE_READ_WRITE);
            to(&self.shadow, vk::ImageLayout::GENERAL, Access::DEPTH_ATTACHMENT);
            to(
                &self.hiz_depth,
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                Access::DEPTH_ATTACHMENT,
            );
        })
    }

    /// Record the shadow pass of `cascade`: `draw` records the casters' draws into its half of
    /// the map, through that cascade's view of the sun.
    pub fn record_shadow(&self, cmd: vk::CommandBuffer, cascade: Cascade, draw: impl FnOnce()) {
        let d = &self.ctx.device;
        // Shaders may still be sampling the map: the previous frame's, or this frame's compute
        // passes reading the field cascade before the near one is drawn.
        barrier::memory(d, cmd, Access::SAMPLED_READ, Access::DEPTH_ATTACHMENT);
        let area = vk::Rect2D {
            offset: vk::Offset2D {
                x: (cascade as u32 * self.shadow_size) as i32,
                y: 0,
            },
            extent: SQUARE(self.shadow_size),
        };
        let target = Attachments {
            color: None,
            depth: self.shadow.view,
            area,
        };
        self.render(cmd, &target, vk::ImageLayout::GENERAL, draw);
        barrier::memory(d, cmd, Access::DEPTH_ATTACHMENT, Access::SAMPLED_READ);
    }

    /// Record the depth pyramid: `draw` records the occluders' draws from the camera into level
    /// 0, then each level is reduced from the one below it, ready for the cull pass.
    pub fn record_hiz(&self, cmd: vk::CommandBuffer, draw: impl FnOnce()) {
        let d = &self.ctx.device;
        barrier::memory(d, cmd, Access::SAMPLED_READ, Access::COLOR_ATTACHMENT);
        let target = Attachments {
            color: Some(self.hiz_levels[0]),
            depth: self.hiz_depth.view,
            area: whole(HIZ_SIZE),
        };
        self.render(cmd, &target, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL, draw);
        barrier::memory(d, cmd, Access::COLOR_ATTACHMENT, Access::COMPUTE_READ_WRITE);
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

    /// Begin rendering into `target`'s area (colour cleared to the far plane, depth to 1, there
    /// only), set the viewport to it, run `draw`, end.
    fn render(&self, cmd: vk::CommandBuffer, target: &Attachments, depth_layout: vk::ImageLayout, draw: impl FnOnce()) {
        let d = &self.ctx.device;
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
}

impl Drop for Occluders {
    fn drop(&mut self) {
        let d = &self.ctx.device;
        unsafe {
            let _ = d.device_wait_idle();
            for view in self.hiz_levels.drain(..) {
                d.destroy_image_view(view, None);
            }
            d.destroy_sampler(self.hiz_sampler, None);
            d.destroy_sampler(self.shadow_sampler, None);
            d.destroy_pipeline(self.reduce, None);
            d.destroy_pipeline_layout(self.reduce_layout, None);
            d.destroy_descriptor_set_layout(self.reduce_set_layout, None);
            d.destroy_descriptor_pool(self.pool, None);
        }
    }
}

/// Nearest-texel sampling clamped to the edge for the pyramid (the cull pass fetches texels
/// itself); for the shadow map a depth-comparing, linearly filtered sampler (2 × 2 PCF in hardware).
fn sampler(d: &ash::Device, compare: bool) -> Result<vk::Sampler> {
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
