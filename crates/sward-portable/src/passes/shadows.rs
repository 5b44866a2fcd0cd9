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
        let module = crate::device_module(device, module, modules);
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

/// The shadow map: both cascades, `size` texels square each, as two layers of one texture (the
/// near cascade first), and its comparison sampler; and the field cascade's ground kept apart,
/// copied into its layer each frame while what places it stays the same (WebGPU copies a depth
/// texture only whole: a layer is a whole subresource).
pub(crate) struct ShadowMap {
    size: u32,
    texture: wgpu::Texture,
    /// Both layers, as the shading samples them.
    view: wgpu::TextureView,
    /// Each layer, as a pass draws into it.
    layers: [wgpu::TextureView; 2],
    sampler: wgpu::Sampler,
    /// The field cascade's ground alone, and what placed it, where it is kept (decided as the
    /// cascade is recorded, once a frame).
    kept: std::sync::Mutex<KeptGround>,
    /// Whether the ground is kept at all: not on wgpu's GL backend, whose copy of a depth
    /// texture into another's layer leaves an incomplete framebuffer (llvmpipe).
    keeps_ground: bool,
}

/// The kept ground, what placed it (`FrameUniforms::shadow_ground_key` and the ground's mesh),
/// and what placed the last frame's.
#[derive(Default)]
struct KeptGround {
    ground: Option<(wgpu::Texture, wgpu::TextureView)>,
    kept: Option<GroundKey>,
    last: Option<GroundKey>,
    /// Whether the field cascade's layer holds the kept ground and nothing over it (no collider
    /// drawn since it was copied in): a frame without colliders then copies nothing.
    in_layer: bool,
}

/// What places the ground in the field cascade: the frame's key and the ground's mesh.
#[derive(Clone, PartialEq)]
pub(crate) struct GroundKey {
    pub placed: Vec<u32>,
    pub mesh: wgpu::Buffer,
}

/// How a frame brings the ground into the field cascade, as the Vulkan renderer's
/// (`ShadowGround`): the kept ground copied in (anew where `changed`: drawn into it first), or
/// drawn into the cascade itself, as a ground that moves every frame (a streamed field's plane
/// under a walking eye) is, at no cost beyond it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FieldGround {
    Kept {
        changed: bool,
    },
    /// The layer already holds the kept ground alone: nothing to copy.
    InLayer,
    Drawn,
}

impl ShadowMap {
    /// A map of `size` texels a cascade (1: a placeholder the shading never reads, bound where
    /// the frame has no shadows).
    pub fn new(device: &wgpu::Device, size: u32) -> ShadowMap {
        let texture = depth_texture(device, "sward shadow map", size, 2);
        // Linear: 2 × 2 comparisons filtered, as the Vulkan renderer's.
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("sward shadow sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let layer = |k: u32| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: k,
                array_layer_count: Some(1),
                ..Default::default()
            })
        };
        ShadowMap {
            size,
            view: texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            }),
            layers: [layer(0), layer(1)],
            texture,
            sampler,
            kept: Default::default(),
            keeps_ground: true,
        }
    }

    /// The map, keeping the field cascade's ground or (`keeps` false) drawing it every frame.
    pub fn keeping_ground(self, keeps: bool) -> ShadowMap {
        ShadowMap {
            keeps_ground: keeps,
            ..self
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

    /// How the frame placing its ground as `key` brings it into the field cascade, and the kept
    /// ground where it is copied from: the kept one where `key` placed it; kept anew where the
    /// ground stood still since the last frame; else drawn into the cascade.
    fn keep_ground(
        &self,
        device: &wgpu::Device,
        key: &GroundKey,
    ) -> (FieldGround, Option<(wgpu::Texture, wgpu::TextureView)>) {
        if !self.keeps_ground {
            return (FieldGround::Drawn, None);
        }
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        let in_layer = std::mem::take(&mut kept.in_layer);
        let how = if kept.kept.as_ref() == Some(key) && in_layer {
            FieldGround::InLayer
        } else if kept.kept.as_ref() == Some(key) {
            FieldGround::Kept { changed: false }
        } else if kept.last.as_ref() == Some(key) {
            kept.kept = Some(key.clone());
            FieldGround::Kept { changed: true }
        } else {
            FieldGround::Drawn
        };
        kept.last = Some(key.clone());
        if matches!(how, FieldGround::Drawn | FieldGround::InLayer) {
            return (how, None);
        }
        let size = self.size;
        let ground = kept.ground.get_or_insert_with(|| {
            let texture = depth_texture(device, "sward kept shadow ground", size, 1);
            let view = texture.create_view(&Default::default());
            (texture, view)
        });
        (how, Some(ground.clone()))
    }

    /// Say whether the field cascade's layer was left holding the kept ground alone.
    fn left_in_layer(&self, alone: bool) {
        self.kept.lock().unwrap_or_else(|e| e.into_inner()).in_layer = alone;
    }

    /// Bytes the map holds (with the kept ground).
    pub fn bytes(&self) -> u64 {
        let layer = u64::from(self.size) * u64::from(self.size) * 4;
        let kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        2 * layer + kept.ground.as_ref().map_or(0, |_| layer)
    }
}

/// A depth texture of `layers` layers, `size` texels square, drawn into, sampled and copied.
fn depth_texture(device: &wgpu::Device, label: &str, size: u32, layers: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: SHADOW_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
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

/// Record the frame's shadow map where it `casting` has shadows: the field cascade's ground
/// (kept, copied in, as `ground` places it) and colliders, then the near cascade's blades
/// (`cascades` says which), from what the camera's draw reads (`inputs`).
pub(crate) fn record_shadows(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    (pipelines, map): (&ShadowPipelines, &ShadowMap),
    (inputs, ground): (&DrawInputs, &GroundKey),
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
    if cascades != Cascades::Near {
        let ground_pass = |pass: &mut wgpu::RenderPass| {
            pass.set_pipeline(&pipelines.ground);
            pass.set_bind_group(0, &group(&pipelines.ground), &[]);
            inputs.scenery.record_ground(pass, inputs.drawn.sphere_ground);
        };
        let (how, kept) = map.keep_ground(device, ground);
        if let (FieldGround::Kept { changed }, Some((texture, view))) = (how, &kept) {
            if changed {
                ground_pass(&mut depth_pass(encoder, view, true));
            }
            let layer = wgpu::Extent3d {
                width: map.size,
                height: map.size,
                depth_or_array_layers: 1,
            };
            encoder.copy_texture_to_texture(whole_layer(texture, 0), whole_layer(&map.texture, 1), layer);
        }
        let colliders = inputs.drawn.colliders;
        if how == FieldGround::Drawn || colliders > 0 {
            let mut pass = depth_pass(encoder, &map.layers[1], how == FieldGround::Drawn);
            if how == FieldGround::Drawn {
                ground_pass(&mut pass);
            }
            if colliders > 0 {
                pass.set_pipeline(&pipelines.colliders);
                pass.set_bind_group(0, &group(&pipelines.colliders), &[]);
                pass.draw(0..COLLIDER_VERTICES, 0..colliders);
            }
        }
        map.left_in_layer(how != FieldGround::Drawn && colliders == 0);
    }
    if cascades == Cascades::Field {
        return;
    }
    // The near cascade: the blades that cast, where any do (the shading reads it only then).
    if casting.buckets == 0 && casting.levels == 0 {
        return;
    }
    let mut pass = depth_pass(encoder, &map.layers[0], true);
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

/// Layer `z` of `texture` as a copy takes it, whole.
fn whole_layer(texture: &wgpu::Texture, z: u32) -> wgpu::TexelCopyTextureInfo<'_> {
    wgpu::TexelCopyTextureInfo {
        texture,
        mip_level: 0,
        origin: wgpu::Origin3d { x: 0, y: 0, z },
        aspect: wgpu::TextureAspect::All,
    }
}

/// A depth-only pass into `view`, cleared first or over what it holds.
fn depth_pass<'a>(
    encoder: &'a mut wgpu::CommandEncoder,
    view: &wgpu::TextureView,
    clear: bool,
) -> wgpu::RenderPass<'a> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("sward portable shadow map"),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations {
                load: match clear {
                    true => wgpu::LoadOp::Clear(1.0),
                    false => wgpu::LoadOp::Load,
                },
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        ..Default::default()
    })
}
