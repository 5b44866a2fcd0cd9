//! The portable renderer's depth pyramid (Hi-Z): the occluders — the ground, the collider
//! spheres, the nearest blades the last frame listed — drawn from the camera as the bits of
//! their depth (an integer target renders on every backend) and copied into level 0 of a storage
//! buffer (pyramid.wesl says why a buffer), then each level reduced from the one below it (the
//! farthest depth of the 2 × 2 texels under a texel), for the cull's occlusion test (SPEC §4). Where the caller gives its own
//! depth of the view (an engine's scene), it is folded into level 0 before the reduction. Its
//! size is fixed, as the Vulkan renderer's, so one pyramid serves every frame.

use sward_core::declared::bindings;

use super::draw::{bind, render_pipeline, Attachments, DrawInputs};
use crate::shaders::{ShaderModules, PYRAMID_SOURCES};
use crate::{compute_pipeline, dispatch, BindGroups, Bound, Groups, PortableError, Reading, FRAME};

/// Which field's occluders a pyramid's pass draws: the first (clearing the pyramid, drawing
/// the colliders) or one added to it; a field alone in its pyramid draws its ground whole.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Occluders {
    /// The only field: its ground drawn as far as it is drawn in the frame, as the Vulkan
    /// renderer's. Beyond its field a plane hides none of its grass, but a hole in level 0
    /// (the screen's edge, where it shows the ground past the field) makes every coarser texel
    /// over it hide nothing, so blades there behind nearer ones are kept (cis565 2^16 on
    /// lavapipe: 1,466 listed with the plane cut at the field's edge, 1,348 whole, the Vulkan
    /// renderer 1,356).
    Alone,
    First,
    Added,
}

/// Side of the pyramid's level 0 (the Vulkan renderer's `HIZ_SIZE`): clip space is mapped onto
/// it whatever the view's aspect.
pub const PYRAMID_SIZE: u32 = 512;
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
/// The blade occluders' draw command (buckets.wesl `COMMAND_OCCLUDERS`).
const OCCLUDER_COMMAND: u64 = 64;
/// Levels of the pyramid, from PYRAMID_SIZE square down to one texel.
const LEVELS: u32 = PYRAMID_SIZE.ilog2() + 1;

/// Texels of the pyramid's levels before level `level` (pyramid_levels.wesl `pyramid_start`).
fn level_start(level: u32) -> u64 {
    (0..level).map(|k| ((PYRAMID_SIZE >> k) as u64).pow(2)).sum()
}

/// The pipelines that fill a depth pyramid, and each level's uniform: one set for every view.
#[derive(Clone)]
pub(crate) struct PyramidPipelines {
    /// Per level, which it is (the reduction's uniform).
    steps: Vec<wgpu::Buffer>,
    /// The blades, the ground, the colliders into the occluder image.
    /// The blades, the ground within its field, the colliders, the ground whole.
    occluders: [Reading<wgpu::RenderPipeline>; 4],
    /// Level 0 from the occluders, a level from the one below.
    reduce: Reading<wgpu::ComputePipeline>,
}

/// One view's pyramid: its levels, and the image and depth its occluders are drawn into.
/// Cloned, the same pyramid (the fields of a view culled together share one).
#[derive(Clone)]
pub(crate) struct DepthPyramid {
    /// Every level, one after another (pyramid_levels.wesl), for the cull.
    pub levels: wgpu::Buffer,
    /// The occluders' depth bits, as drawn.
    occluder_image: wgpu::TextureView,
    depth: wgpu::TextureView,
}

impl PyramidPipelines {
    pub fn new(device: &wgpu::Device, modules: &ShaderModules) -> Result<PyramidPipelines, PortableError> {
        let step = |level: u32| {
            wgpu::util::DeviceExt::create_buffer_init(
                device,
                &wgpu::util::BufferInitDescriptor {
                    label: Some("sward depth pyramid level"),
                    contents: bytemuck::cast_slice(&[level, PYRAMID_SIZE, 0, 0]),
                    usage: wgpu::BufferUsages::UNIFORM,
                },
            )
        };
        let target = Attachments {
            color: Some(FORMAT),
            depth: wgpu::TextureFormat::Depth32Float,
            samples: 1,
        };
        let [blades, ground, colliders, reduce, whole_ground] = &PYRAMID_SOURCES;
        let strip = wgpu::PrimitiveTopology::TriangleStrip;
        let list = wgpu::PrimitiveTopology::TriangleList;
        Ok(PyramidPipelines {
            steps: (0..LEVELS).map(step).collect(),
            occluders: [
                render_pipeline(device, (blades, modules), &target, strip, true)?,
                render_pipeline(device, (ground, modules), &target, list, true)?,
                render_pipeline(device, (colliders, modules), &target, list, true)?,
                render_pipeline(device, (whole_ground, modules), &target, list, true)?,
            ],
            reduce: compute_pipeline(device, reduce, modules)?,
        })
    }

    /// Record `pyramid`'s level 0 copied from its occluders (with the caller's depth folded
    /// in where it gives it: `caller`) and each level above it reduced.
    pub fn reduce(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        (pyramid, caller): (&DepthPyramid, Option<&CallerFold>),
        groups: &BindGroups,
    ) {
        let resources: Vec<[(u32, Bound); 3]> = self
            .steps
            .iter()
            .map(|step| {
                [
                    (bindings::OCCLUDER_DEPTH, Bound::View(&pyramid.occluder_image)),
                    (bindings::DEPTH_PYRAMID, Bound::Buffer(&pyramid.levels)),
                    (bindings::PYRAMID_STEP, Bound::Buffer(step)),
                ]
            })
            .collect();
        let mut levels: Vec<_> = resources
            .iter()
            .enumerate()
            .map(|(level, bound)| {
                let side = (PYRAMID_SIZE >> level).max(1).div_ceil(8);
                (&self.reduce, &bound[..], Groups::Direct([side, side]))
            })
            .collect();
        let folding = caller.map(|fold| {
            let [_, levels, level_0] = resources[0];
            (fold, [levels, level_0, (fold.binding, Bound::View(&fold.depth))])
        });
        if let Some((fold, bound)) = &folding {
            // After level 0 is copied, before level 1 is reduced from it.
            let side = PYRAMID_SIZE.div_ceil(8);
            levels.insert(1, (&fold.pipeline, &bound[..], Groups::Direct([side, side])));
        }
        dispatch((device, groups), encoder, &levels);
    }

    /// The ground, the colliders (those that only hide grass too) and the nearest blades the
    /// last frame listed, as depth, into the occluder image level 0 is copied from: the
    /// `First` field's clear it and bring the colliders, each field `Added` after draws over
    /// them (its own ground and blades, where its frame places them).
    pub fn record_occluders(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        pyramid: &DepthPyramid,
        inputs: &DrawInputs,
        which: Occluders,
    ) {
        let DrawInputs {
            frame,
            field,
            lists,
            scenery,
            drawn,
            groups,
            ..
        } = inputs;
        let [blades, own_ground, colliders, whole_ground] = &self.occluders;
        let ground = match which {
            Occluders::Alone => whole_ground,
            Occluders::First | Occluders::Added => own_ground,
        };
        let bind = |pipeline, buffers: &[(u32, &wgpu::Buffer)]| bind((device, *groups), pipeline, buffers);
        let blade_group = bind(
            blades,
            &[
                (FRAME, frame),
                (bindings::BLADES, &field.blades),
                (bindings::VISIBLE, &lists.visible),
                (bindings::CULL_COUNTERS, &lists.counters),
            ],
        );
        let ground_group = bind(ground, &[(FRAME, frame), (bindings::GROUND, scenery.ground_vertices())]);
        let collider_group = bind(colliders, &[(FRAME, frame)]);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("sward depth pyramid's occluders"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &pyramid.occluder_image,
                resolve_target: None,
                depth_slice: None,
                ops: wgpu::Operations {
                    // The far plane's depth, as bits: nothing occludes there.
                    load: match which {
                        Occluders::Alone | Occluders::First => wgpu::LoadOp::Clear(wgpu::Color {
                            r: 1.0f32.to_bits() as f64,
                            g: 0.0,
                            b: 0.0,
                            a: 0.0,
                        }),
                        Occluders::Added => wgpu::LoadOp::Load,
                    },
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &pyramid.depth,
                // Kept for the fields added after the first (a 512² target: nothing to save).
                depth_ops: Some(wgpu::Operations {
                    load: match which {
                        Occluders::Alone | Occluders::First => wgpu::LoadOp::Clear(1.0),
                        Occluders::Added => wgpu::LoadOp::Load,
                    },
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        if field.count() > 0 {
            pass.set_pipeline(blades);
            pass.set_bind_group(0, &blade_group, &[]);
            pass.draw_indirect(
                &lists.draws,
                OCCLUDER_COMMAND * std::mem::size_of::<sward_core::gpu::DrawCommand>() as u64,
            );
        }
        let spheres = match which {
            Occluders::Alone | Occluders::First => drawn.colliders + drawn.hiders,
            // The colliders are the world's: the first field drew them.
            Occluders::Added => 0,
        };
        if spheres > 0 {
            pass.set_pipeline(colliders);
            pass.set_bind_group(0, &collider_group, &[]);
            pass.draw(0..crate::passes::draw::COLLIDER_VERTICES, 0..spheres);
        }
        pass.set_pipeline(ground);
        pass.set_bind_group(0, &ground_group, &[]);
        scenery.record_ground(&mut pass, drawn.sphere_ground);
    }
}

/// The caller's depth of a view, folded into its pyramid (caller_depth.wesl): the pipeline for
/// its sample count, the binding it reads the depth at, the depth.
#[derive(Clone)]
pub(crate) struct CallerFold {
    pub pipeline: Reading<wgpu::ComputePipeline>,
    pub binding: u32,
    pub depth: wgpu::TextureView,
}

impl DepthPyramid {
    pub fn new(device: &wgpu::Device) -> DepthPyramid {
        let size = wgpu::Extent3d {
            width: PYRAMID_SIZE,
            height: PYRAMID_SIZE,
            depth_or_array_layers: 1,
        };
        let image = |label, format, usage| {
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            });
            texture.create_view(&Default::default())
        };
        let drawn = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        DepthPyramid {
            levels: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sward depth pyramid"),
                size: 4 * level_start(LEVELS),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            occluder_image: image("sward occluders", FORMAT, drawn),
            depth: image(
                "sward occluders' depth",
                wgpu::TextureFormat::Depth32Float,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            ),
        }
    }

    /// Bytes of GPU memory the pyramid holds.
    pub fn bytes(&self) -> u64 {
        self.levels.size() + 2 * 4 * (PYRAMID_SIZE as u64).pow(2)
    }

    #[cfg(feature = "blocking")]
    /// Level `level` as it stands, row by row: the bits of each texel's farthest depth.
    pub fn read_level(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        level: u32,
    ) -> Result<Vec<u32>, PortableError> {
        let bytes = crate::field::read_range(
            device,
            queue,
            &self.levels,
            4 * level_start(level)..4 * level_start(level + 1),
        )?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }
}
