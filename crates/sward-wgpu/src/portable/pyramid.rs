//! The portable renderer's depth pyramid (Hi-Z): the occluders — the ground, the collider
//! spheres, the nearest blades the last frame listed — drawn from the camera into its level 0
//! (the bits of their depth: an integer target renders on every backend), then each level reduced from the one below it (the farthest depth of the 2 × 2 texels
//! under a texel), for the cull's occlusion test (SPEC §4). Its size is fixed, as the Vulkan
//! renderer's, so one pyramid serves every frame.

use super::draw::{bind, render_pipeline, Attachments, DrawInputs};
use super::shaders::PYRAMID_SOURCES;
use super::{compute_pipeline, PortableError};

/// Side of the pyramid's level 0 (the Vulkan renderer's `HIZ_SIZE`): clip space is mapped onto
/// it whatever the view's aspect.
pub const PYRAMID_SIZE: u32 = 512;
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// Vertices of a blade occluder's flat strip (buckets.wgsl: 2 × (OCCLUDER_SEGMENTS + 1)).
const OCCLUDER_COMMAND: u64 = 64;

/// The pyramid, the depth its occluders are tested with, and the pipelines that fill it.
pub(crate) struct DepthPyramid {
    /// Every level, for the cull.
    pub all_levels: wgpu::TextureView,
    /// One view per level.
    levels: Vec<wgpu::TextureView>,
    texture: wgpu::Texture,
    depth: wgpu::TextureView,
    /// The blades, the ground, the colliders into level 0.
    occluders: [wgpu::RenderPipeline; 3],
    /// A level from the one below.
    reduce: wgpu::ComputePipeline,
}

impl DepthPyramid {
    pub fn new(device: &wgpu::Device) -> Result<DepthPyramid, PortableError> {
        let levels = PYRAMID_SIZE.ilog2() + 1;
        let size = wgpu::Extent3d {
            width: PYRAMID_SIZE,
            height: PYRAMID_SIZE,
            depth_or_array_layers: 1,
        };
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("sward depth pyramid"),
            size,
            mip_level_count: levels,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let depth = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("sward depth pyramid's depth"),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Depth32Float,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let level = |k| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                base_mip_level: k,
                mip_level_count: Some(1),
                ..Default::default()
            })
        };
        let target = Attachments {
            color: Some(FORMAT),
            depth: wgpu::TextureFormat::Depth32Float,
            samples: 1,
        };
        let [blades, ground, colliders, reduce] = &PYRAMID_SOURCES;
        let strip = wgpu::PrimitiveTopology::TriangleStrip;
        let list = wgpu::PrimitiveTopology::TriangleList;
        Ok(DepthPyramid {
            all_levels: texture.create_view(&Default::default()),
            texture: texture.clone(),
            levels: (0..levels).map(level).collect(),
            depth: depth.create_view(&Default::default()),
            occluders: [
                render_pipeline(device, blades, &target, strip, true)?,
                render_pipeline(device, ground, &target, list, true)?,
                render_pipeline(device, colliders, &target, list, true)?,
            ],
            reduce: compute_pipeline(device, reduce)?,
        })
    }

    /// Level `level` as it stands, row by row: the bits of each texel's farthest depth.
    pub fn read_level(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        level: u32,
    ) -> Result<Vec<u32>, PortableError> {
        let side = (PYRAMID_SIZE >> level).max(1);
        let row = (side * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sward pyramid read-back"),
            size: row as u64 * side as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &self.texture,
                mip_level: level,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &staging,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(side),
                },
            },
            wgpu::Extent3d {
                width: side,
                height: side,
                depth_or_array_layers: 1,
            },
        );
        queue.submit([encoder.finish()]);
        let bytes = super::field::map_read(device, &staging)?;
        Ok(bytes
            .chunks(row as usize)
            .flat_map(|r| {
                r[..side as usize * 4]
                    .chunks_exact(4)
                    .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            })
            .collect())
    }

    /// Record the occluders into level 0 and the reduction of every level above it.
    pub fn record(&self, device: &wgpu::Device, encoder: &mut wgpu::CommandEncoder, inputs: &DrawInputs) {
        self.record_occluders(device, encoder, inputs);
        for k in 1..self.levels.len() {
            let reduce = [(0, &self.levels[k - 1]), (1, &self.levels[k])];
            dispatch_level(device, encoder, &self.reduce, reduce, (PYRAMID_SIZE >> k).max(1));
        }
    }

    /// The ground, the colliders (those that only hide grass too) and the nearest blades the
    /// last frame listed, into level 0 as depth.
    fn record_occluders(&self, device: &wgpu::Device, encoder: &mut wgpu::CommandEncoder, inputs: &DrawInputs) {
        let DrawInputs {
            frame,
            field,
            scenery,
            drawn,
        } = inputs;
        let [blades, ground, colliders] = &self.occluders;
        let blade_group = bind(device, blades, &[(0, frame), (1, &field.blades), (3, &field.visible)]);
        let ground_group = bind(device, ground, &[(0, frame), (7, scenery.ground_vertices())]);
        let collider_group = bind(device, colliders, &[(0, frame)]);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sward depth pyramid's occluders"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.levels[0],
                resolve_target: None,
                depth_slice: None,
                ops: wgpu::Operations {
                    // The far plane's depth, as bits: nothing occludes there.
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: 1.0f32.to_bits() as f64,
                        g: 0.0,
                        b: 0.0,
                        a: 0.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        if field.count() > 0 {
            pass.set_pipeline(blades);
            pass.set_bind_group(0, &blade_group, &[]);
            pass.draw_indirect(
                &field.draws,
                OCCLUDER_COMMAND * std::mem::size_of::<sward_core::gpu::DrawCommand>() as u64,
            );
        }
        let spheres = drawn.colliders + drawn.hiders;
        if spheres > 0 {
            pass.set_pipeline(colliders);
            pass.set_bind_group(0, &collider_group, &[]);
            pass.draw(0..super::draw::COLLIDER_VERTICES, 0..spheres);
        }
        pass.set_pipeline(ground);
        pass.set_bind_group(0, &ground_group, &[]);
        scenery.record_ground(&mut pass, drawn.sphere_ground);
    }
}

/// Dispatch `pipeline` over a level `side` texels square, with `views` at their bindings.
fn dispatch_level(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::ComputePipeline,
    views: [(u32, &wgpu::TextureView); 2],
    side: u32,
) {
    let entries = views.map(|(binding, view)| wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::TextureView(view),
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let mut pass = encoder.begin_compute_pass(&Default::default());
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, &bind, &[]);
    pass.dispatch_workgroups(side.div_ceil(8), side.div_ceil(8), 1);
}
