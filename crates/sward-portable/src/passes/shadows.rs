//! The sun's shadow map on the portable renderer (SPEC §8), as the Vulkan renderer draws it
//! (its `passes/shadows.rs`): two cascades side by side in one depth texture — the near one
//! (left: the Bezier blades of the buckets that cast and the instanced grass's levels that begin
//! within the blade-shadow distance, where the frame casts blade shadows) and the field one
//! (right: the ground and the colliders) — drawn depth only through the sun's eyes before the
//! camera's draw, whose shading reads it (shading.wesl `sunlight`). Where the far field is
//! splatted, the field cascade is drawn before the splatting passes (which shade with it) and the
//! near cascade after them, as the Vulkan renderer orders them. Both cascades are drawn each
//! frame that has shadows: the Vulkan renderer's kept ground (the field cascade's ground drawn
//! once while it stands still) is not done here yet.

use sward_core::commands::DISTANCE_BUCKETS;
use sward_core::declared::{bindings, constants};
use sward_core::flags::{VIEW_SUN_FIELD, VIEW_SUN_NEAR};
use sward_core::instanced::LODS;
use sward_core::plan::FrameDecisions;

use super::draw::{DrawInputs, COLLIDER_VERTICES};
use crate::shaders::{PipelineSource, ShaderModules, SHADOW_SOURCES};
use crate::{catch_errors, shader_module, Bindable, Bound, PortableError, Reading, FRAME};

/// The shadow map's depth format.
const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// What a frame casts into the shadow map, as its plan decided.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Casting {
    /// Whether the map is drawn (and the shading reads it).
    pub shadows: bool,
    /// The side of each cascade, in texels.
    pub size: u32,
    /// The Bezier buckets whose blades cast into the near cascade (the nearest ones).
    pub buckets: u32,
    /// The instanced grass's levels that cast into it.
    pub levels: u32,
}

impl Casting {
    /// What frame `decided` casts, at `size` texels a cascade.
    pub fn of(decided: &FrameDecisions, size: u32) -> Casting {
        let near = decided.blade_shadows;
        Casting {
            shadows: decided.shadows,
            size,
            buckets: if near {
                decided.casting[0].min(DISTANCE_BUCKETS)
            } else {
                0
            },
            levels: if near { decided.casting[1].min(LODS as u32) } else { 0 },
        }
    }
}

/// The casters' pipelines: depth only, biased against shadow acne as the Vulkan renderer's.
#[derive(Clone)]
pub(crate) struct ShadowPipelines {
    ground: Reading<wgpu::RenderPipeline>,
    colliders: Reading<wgpu::RenderPipeline>,
    blades: Reading<wgpu::RenderPipeline>,
    generated: Reading<wgpu::RenderPipeline>,
}

impl ShadowPipelines {
    pub fn new(device: &wgpu::Device, modules: &ShaderModules) -> Result<ShadowPipelines, PortableError> {
        let [ground, colliders, blades, generated] = &SHADOW_SOURCES;
        let list = wgpu::PrimitiveTopology::TriangleList;
        let strip = wgpu::PrimitiveTopology::TriangleStrip;
        let make = |source, topology, view| caster_pipeline(device, (source, modules), topology, view);
        Ok(ShadowPipelines {
            ground: make(ground, list, VIEW_SUN_FIELD)?,
            colliders: make(colliders, list, VIEW_SUN_FIELD)?,
            blades: make(blades, strip, VIEW_SUN_NEAR)?,
            generated: make(generated, strip, VIEW_SUN_NEAR)?,
        })
    }
}

/// A caster's pipeline from vertex stage `source`, drawing through the eyes `view` names.
fn caster_pipeline(
    device: &wgpu::Device,
    (source, modules): (&PipelineSource, &ShaderModules),
    topology: wgpu::PrimitiveTopology,
    view: u32,
) -> Result<Reading<wgpu::RenderPipeline>, PortableError> {
    let module = shader_module(source, modules)?;
    let id = constants::VIEW.to_string();
    let overrides = [(id.as_str(), f64::from(view))];
    let pipeline = catch_errors(device, source.name, || {
        let module = device.create_shader_module(module);
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(source.name),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some(source.entry),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &overrides,
                    ..Default::default()
                },
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState {
                topology,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: SHADOW_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: wgpu::DepthBiasState {
                    constant: 2,
                    slope_scale: 2.5,
                    clamp: 0.0,
                },
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        })
    })?;
    Reading::new(pipeline, &modules.text(source)?, &[source.entry])
}

/// The shadow map: both cascades, `size` texels square each, and its comparison sampler.
pub(crate) struct ShadowMap {
    size: u32,
    view: wgpu::TextureView,
    sampler: wgpu::Sampler,
}

impl ShadowMap {
    /// A map of `size` texels a cascade (1: a placeholder the shading never reads, bound where
    /// the frame has no shadows).
    pub fn new(device: &wgpu::Device, size: u32) -> ShadowMap {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("sward shadow map"),
            size: wgpu::Extent3d {
                width: 2 * size,
                height: size,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: SHADOW_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        // Linear: 2 × 2 comparisons filtered, as the Vulkan renderer's.
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("sward shadow sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        ShadowMap {
            size,
            view: texture.create_view(&Default::default()),
            sampler,
        }
    }

    /// The side of each cascade.
    pub fn size(&self) -> u32 {
        self.size
    }

    /// The map and its sampler as the draws bind them.
    pub fn bound(&self) -> [(u32, Bound<'_>); 2] {
        [
            (bindings::SHADOW_MAP, Bound::View(&self.view)),
            (bindings::SHADOW_SAMPLER, Bound::Sampler(&self.sampler)),
        ]
    }

    /// Bytes the map holds.
    pub fn bytes(&self) -> u64 {
        2 * u64::from(self.size) * u64::from(self.size) * 4
    }
}

/// Which of the shadow map's cascades a render pass draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Cascades {
    /// Both, the map cleared first.
    Both,
    /// The field cascade alone (the ground and the colliders), the map cleared first: what the
    /// splatting passes shade the far field with, drawn before them.
    Field,
    /// The near cascade alone (the blades that cast), over the field cascade drawn before.
    Near,
}

/// Record the frame's shadow map where it `casting` has shadows: the field cascade's ground and
/// colliders, then the near cascade's blades (`cascades` says which), from what the camera's
/// draw reads (`inputs`).
pub(crate) fn record_shadows(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    (pipelines, map): (&ShadowPipelines, &ShadowMap),
    inputs: &DrawInputs,
    (casting, cascades): (Casting, Cascades),
) {
    if !casting.shadows {
        return;
    }
    let b = Bound::Buffer;
    let resources = [
        (FRAME, b(inputs.frame)),
        (bindings::GROUND, b(inputs.scenery.ground_vertices())),
        (bindings::PAINT, b(inputs.scenery.paint())),
        (bindings::BLADES, b(&inputs.field.blades)),
        (bindings::VISIBLE, b(&inputs.lists.visible)),
        (bindings::CULL_COUNTERS, b(&inputs.lists.counters)),
        (bindings::GENERATED_BLADES, b(inputs.generated.listed())),
    ];
    let group =
        |pipeline: &Reading<wgpu::RenderPipeline>| inputs.groups.of(device, Bindable::Render(pipeline), &resources);
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("sward portable shadow map"),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &map.view,
            depth_ops: Some(wgpu::Operations {
                load: match cascades {
                    Cascades::Near => wgpu::LoadOp::Load,
                    Cascades::Both | Cascades::Field => wgpu::LoadOp::Clear(1.0),
                },
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        ..Default::default()
    });
    let side = map.size as f32;
    if cascades != Cascades::Near {
        // The field cascade, the right half.
        pass.set_viewport(side, 0.0, side, side, 0.0, 1.0);
        pass.set_pipeline(&pipelines.ground);
        pass.set_bind_group(0, &group(&pipelines.ground), &[]);
        inputs.scenery.record_ground(&mut pass, inputs.drawn.sphere_ground);
        if inputs.drawn.colliders > 0 {
            pass.set_pipeline(&pipelines.colliders);
            pass.set_bind_group(0, &group(&pipelines.colliders), &[]);
            pass.draw(0..COLLIDER_VERTICES, 0..inputs.drawn.colliders);
        }
    }
    if cascades == Cascades::Field {
        return;
    }
    // The near cascade, the left half: the blades that cast.
    pass.set_viewport(0.0, 0.0, side, side, 0.0, 1.0);
    if casting.buckets > 0 && inputs.field.count() > 0 {
        pass.set_pipeline(&pipelines.blades);
        pass.set_bind_group(0, &group(&pipelines.blades), &[]);
        pass.multi_draw_indirect(&inputs.lists.draws, 0, casting.buckets);
    }
    if casting.levels > 0 && inputs.generated.generates()[0] {
        pass.set_pipeline(&pipelines.generated);
        pass.set_bind_group(0, &group(&pipelines.generated), &[]);
        pass.multi_draw_indirect(inputs.generated.draws(), 0, casting.levels);
    }
}
