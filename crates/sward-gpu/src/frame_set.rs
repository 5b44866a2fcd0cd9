//! The frame's one descriptor set per frame in flight, and the uniforms buffer each points at:
//! which buffers and images the passes see at each binding (`pipelines.rs` lays them out).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use sward_core::declared;

use crate::buffer::Buffer;
use crate::context::Context;
use crate::error::{vk_check, Result};
use crate::passes::depth_pyramid::DepthPyramid;
use crate::passes::grass_texture::GrassTexture;
use crate::passes::shadows::ShadowMap;
use crate::pipelines::{bindings, IMAGE_BINDINGS, INSTANCED_BINDINGS, STORAGE_BINDINGS};

/// Per frame in flight: its uniforms and the descriptor set that points at them.
pub(crate) struct FrameSlot {
    pub uniforms: Buffer,
    pub set: vk::DescriptorSet,
    /// The caller's-depth binding points at the caller's image (else at the placeholder).
    holds_caller_depth: bool,
}

/// The descriptor sets of every frame in flight.
pub(crate) struct FrameSets {
    pub slots: Vec<FrameSlot>,
    /// What the caller's-depth binding points at while the caller gives none: some drivers
    /// read every binding of a set when it is bound, so none is left unwritten.
    caller_depth_placeholder: vk::DescriptorImageInfo,
    pool: vk::DescriptorPool,
    ctx: Arc<Context>,
}

impl FrameSets {
    pub fn new(ctx: &Arc<Context>, layout: vk::DescriptorSetLayout, frames: u32) -> Result<FrameSets> {
        let sizes = [
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::UNIFORM_BUFFER,
                descriptor_count: bindings::FRAME_BLOCKS.len() as u32 * frames,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_BUFFER,
                // The field's and the instanced grass's, the ordered list, the counts, the
                // trample map, the paint, the drawn blades and the splat cells' words.
                descriptor_count: (STORAGE_BINDINGS + INSTANCED_BINDINGS + 6) * frames,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::SAMPLER,
                // The shadow map's comparison sampler and the grass texture's sampler.
                descriptor_count: 2 * frames,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                // The occluders' images, the grass texture and the caller's depth.
                descriptor_count: (IMAGE_BINDINGS + 2) * frames,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_IMAGE,
                // The depth pyramid's level 0.
                descriptor_count: frames,
            },
        ];
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(frames)
            .pool_sizes(&sizes);
        let pool = unsafe { ctx.device.create_descriptor_pool(&pool_info, None) }
            .map_err(vk_check("creating the descriptor pool"))?;
        let mut sets = FrameSets {
            slots: Vec::new(),
            caller_depth_placeholder: vk::DescriptorImageInfo::default(),
            pool,
            ctx: ctx.clone(),
        };
        let layouts = vec![layout; frames as usize];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        let raw_sets =
            unsafe { ctx.device.allocate_descriptor_sets(&alloc) }.map_err(vk_check("allocating descriptor sets"))?;
        sets.slots = raw_sets
            .into_iter()
            .map(|set| {
                let size = declared::FRAME_BYTES as u64;
                let usage = vk::BufferUsageFlags::UNIFORM_BUFFER;
                let uniforms = Buffer::new(ctx, "frame uniforms", size, usage, MemoryLocation::CpuToGpu)?;
                Ok(FrameSlot {
                    uniforms,
                    set,
                    holds_caller_depth: false,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(sets)
    }

    pub fn raw_sets(&self) -> Vec<vk::DescriptorSet> {
        self.slots.iter().map(|s| s.set).collect()
    }

    /// Point slot `k`'s frame blocks at their places in its uniforms, bindings 1..=7 at
    /// `storage` and the ordered list's binding at `ordered`.
    pub fn write_buffers(&self, k: usize, storage: &[&Buffer; STORAGE_BINDINGS as usize], ordered: &Buffer) {
        let slot = &self.slots[k];
        let blocks = declared::frame_blocks().map(|(binding, offset, range)| {
            let info = vk::DescriptorBufferInfo {
                buffer: slot.uniforms.raw,
                offset,
                range,
            };
            (binding, vk::DescriptorType::UNIFORM_BUFFER, [info])
        });
        let buffers = (1..)
            .zip(storage.iter().copied())
            .chain(std::iter::once((bindings::ORDERED, ordered)))
            .map(|(binding, b)| (binding, vk::DescriptorType::STORAGE_BUFFER, [buffer_info(b)]));
        let infos: Vec<(u32, vk::DescriptorType, [vk::DescriptorBufferInfo; 1])> = blocks.chain(buffers).collect();
        let writes: Vec<vk::WriteDescriptorSet> = infos
            .iter()
            .map(|(binding, kind, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(slot.set)
                    .dst_binding(*binding)
                    .descriptor_type(*kind)
                    .buffer_info(info)
            })
            .collect();
        self.ctx.update_descriptor_sets(&writes);
    }

    /// Point every slot's ground binding at `vertices`.
    pub fn write_ground(&self, vertices: &Buffer) {
        point_sets_at(&self.ctx, &self.raw_sets(), bindings::GROUND, vertices);
    }

    /// Point every slot's depth-pyramid and shadow-map bindings (the map's sampler's too) at
    /// them, the grass texture's bindings (its sampler's too) at the grass texture, the caller's-depth binding at the
    /// depth pyramid (its placeholder: an image that is always there) and the pyramid-base
    /// binding at its level 0.
    pub fn write_images(&mut self, (pyramid, shadows): (&DepthPyramid, &ShadowMap), grass: &GrassTexture) {
        let hiz = pyramid.image_info();
        self.caller_depth_placeholder = hiz;
        use vk::DescriptorType as Kind;
        let images = [
            (bindings::DEPTH_PYRAMID, Kind::COMBINED_IMAGE_SAMPLER, hiz),
            (bindings::SHADOW_MAP, Kind::COMBINED_IMAGE_SAMPLER, shadows.image_info()),
            (
                bindings::GRASS_TEXTURE,
                Kind::COMBINED_IMAGE_SAMPLER,
                grass.image_info(),
            ),
            (bindings::CALLER_DEPTH, Kind::COMBINED_IMAGE_SAMPLER, hiz),
            (bindings::SHADOW_SAMPLER, Kind::SAMPLER, sampler_only(shadows.sampler())),
            (bindings::GRASS_SAMPLER, Kind::SAMPLER, sampler_only(grass.sampler())),
            (bindings::PYRAMID_BASE, Kind::STORAGE_IMAGE, pyramid.base_info()),
        ]
        .map(|(binding, kind, info)| (binding, kind, [info]));
        let writes: Vec<vk::WriteDescriptorSet> = self
            .slots
            .iter()
            .flat_map(|slot| {
                images.iter().map(move |(binding, kind, info)| {
                    vk::WriteDescriptorSet::default()
                        .dst_set(slot.set)
                        .dst_binding(*binding)
                        .descriptor_type(*kind)
                        .image_info(info)
                })
            })
            .collect();
        self.ctx.update_descriptor_sets(&writes);
    }

    /// Point slot `k`'s caller's-depth binding at `caller` (its depth this frame), or back at
    /// the placeholder once the caller gives none (its image may be gone). Before the frame
    /// binds the set. Written every frame the caller gives its depth: a view's handle may be
    /// reused once the caller destroys it, so a handle seen before proves nothing.
    pub fn point_caller_depth(&mut self, k: usize, caller: Option<vk::DescriptorImageInfo>) {
        let slot = &mut self.slots[k];
        if caller.is_none() && !slot.holds_caller_depth {
            return;
        }
        slot.holds_caller_depth = caller.is_some();
        let info = [caller.unwrap_or(self.caller_depth_placeholder)];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(slot.set)
            .dst_binding(bindings::CALLER_DEPTH)
            .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
            .image_info(&info);
        self.ctx.update_descriptor_sets(&[write]);
    }
}

fn buffer_info(buffer: &Buffer) -> vk::DescriptorBufferInfo {
    vk::DescriptorBufferInfo {
        buffer: buffer.raw,
        offset: 0,
        range: vk::WHOLE_SIZE,
    }
}

impl Drop for FrameSets {
    fn drop(&mut self) {
        unsafe {
            let _ = self.ctx.device.device_wait_idle();
            self.ctx.device.destroy_descriptor_pool(self.pool, None);
        }
    }
}

/// Point binding `binding` of every set in `sets` at all of `buffer` (a storage buffer): what a
/// pass that owns its buffer does when the buffer is made or replaced.
pub(crate) fn point_sets_at(ctx: &Context, sets: &[vk::DescriptorSet], binding: u32, buffer: &Buffer) {
    let info = [buffer_info(buffer)];
    let writes: Vec<vk::WriteDescriptorSet> = sets
        .iter()
        .map(|set| {
            vk::WriteDescriptorSet::default()
                .dst_set(*set)
                .dst_binding(binding)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .buffer_info(&info)
        })
        .collect();
    ctx.update_descriptor_sets(&writes);
}

/// A sampler as a descriptor of its own (`vk::DescriptorType::SAMPLER`).
fn sampler_only(sampler: vk::Sampler) -> vk::DescriptorImageInfo {
    vk::DescriptorImageInfo {
        sampler,
        image_view: vk::ImageView::null(),
        image_layout: vk::ImageLayout::UNDEFINED,
    }
}
