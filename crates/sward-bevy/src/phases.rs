//! The grass in Bevy's own passes ([`GrassLighting::Pbr`]): sward simulates, culls and lists
//! the Bezier blades before Bevy renders (one raw region of compute, submitted first), and Bevy
//! draws them as phase items of its main opaque pass, its prepass and deferred G-buffer and its
//! shadow passes, through pipelines made from Bevy's own mesh and prepass pipelines (its view
//! bindings and shader definitions).
//! So the grass is lit by Bevy's PBR — every light, their shadows, ambient light, environment
//! maps, fog, exposure and tonemapping — and casts into Bevy's shadow maps, as a Bevy mesh.
//! The vertex stages pull each blade from sward's buffers (`shaders/blades.wgsl`).
//!
//! Drawn so: the Bezier technique (generated grass, billboards and splats are sward's own
//! pass's), by the strip route, culled for each 3D camera that sees the grass (up to
//! `sward_wgpu::VIEWS_PER_FRAME`), a camera's shadow cascades drawing its list. The lists are
//! the Vulkan renderer's (on the device `render_plugin` opens: `shaders/blades.wgsl`) or the
//! portable passes' (on any device Bevy opens: `shaders/portable_blades.wgsl`, with the
//! shader definition `SWARD_PORTABLE`); the passes' shaders are the same either way.

use bevy::app::SubApp;
use bevy::asset::{embedded_asset, load_embedded_asset, AssetId, AssetServer, Handle};
use bevy::camera::visibility::RenderLayers;
use bevy::core_pipeline::core_3d::{Opaque3d, Opaque3dBatchSetKey, Opaque3dBinKey, CORE_3D_DEPTH_FORMAT};
use bevy::core_pipeline::deferred::Opaque3dDeferred;
use bevy::core_pipeline::prepass::{
    prepass_target_descriptors, Opaque3dPrepass, OpaqueNoLightmap3dBatchSetKey, OpaqueNoLightmap3dBinKey,
};
use bevy::ecs::prelude::*;
use bevy::ecs::query::ROQueryItem;
use bevy::ecs::system::lifetimeless::SRes;
use bevy::ecs::system::{SystemParam, SystemParamItem};
use bevy::log::error;
use bevy::mesh::{Mesh, MeshVertexBufferLayout, MeshVertexBufferLayoutRef, MeshVertexBufferLayouts, PrimitiveTopology};
use bevy::pbr::{
    LightEntity, LightKeyCache, MeshPipeline, MeshPipelineKey, MeshPipelineSystems, PrepassPipeline,
    SetMeshViewBindGroup, SetMeshViewBindingArrayBindGroup, SetPrepassViewBindGroup, SetPrepassViewEmptyBindGroup,
    Shadow, ShadowBatchSetKey, ShadowBinKey, ViewKeyCache,
};
use bevy::render::mesh::allocator::MeshSlabs;
use bevy::render::render_phase::{
    AddRenderCommand, BinnedPhaseItem, BinnedRenderPhase, BinnedRenderPhaseType, DrawFunctionId, DrawFunctions,
    InputUniformIndex, PhaseItem, RenderCommand, RenderCommandResult, SetItemPipeline, TrackedRenderPass,
    ViewBinnedRenderPhases,
};
use bevy::render::render_resource::binding_types::{storage_buffer_read_only_sized, uniform_buffer_sized};
use bevy::render::render_resource::{
    BindGroup, BindGroupEntries, BindGroupLayoutDescriptor, BindGroupLayoutEntries, Buffer, CachedRenderPipelineId,
    CompareFunction, DepthStencilState, FragmentState, MultisampleState, PipelineCache, PrimitiveState,
    RenderPipelineDescriptor, ShaderStages, SpecializedMeshPipeline as _, SpecializedMeshPipelineError,
    SpecializedRenderPipeline, SpecializedRenderPipelines, VertexState,
};
use bevy::render::renderer::RenderDevice;
use bevy::render::sync_world::MainEntity;
use bevy::render::view::ExtractedView;
use bevy::render::{Render, RenderStartup, RenderSystems};
use bevy::shader::{Shader, ShaderDefVal};
use sward_wgpu::portable::engine_bindings;
use sward_wgpu::DrawnBlades;

use crate::extract::ExtractedGrass;
use crate::lighting::GrassLighting;
use crate::portable::{GrassRoute, PortableGrass};

/// Bytes of one draw command (`sward_core::gpu::DrawCommand`).
const COMMAND_BYTES: u64 = 16;

/// The grass's phase items, pipelines and bind groups in the render world.
pub(crate) fn build(render_app: &mut SubApp) {
    render_app
        .init_resource::<SpecializedRenderPipelines<GrassPipeline>>()
        .init_resource::<GrassBindGroups>()
        .add_render_command::<Opaque3d, DrawGrass>()
        .add_render_command::<Shadow, DrawGrassDepth>()
        .add_render_command::<Opaque3dPrepass, DrawGrassDepth>()
        .add_render_command::<Opaque3dDeferred, DrawGrassDepth>()
        .add_systems(
            RenderStartup,
            init_grass_pipeline
                .after(MeshPipelineSystems)
                .after(bevy::pbr::init_prepass_pipeline),
        )
        // After the meshes: a deferred view's phase says whether the app renders deferred.
        .add_systems(
            Render,
            queue_grass
                .in_set(RenderSystems::Queue)
                .after(RenderSystems::QueueMeshes),
        );
}

/// The grass's shaders, embedded in the crate.
pub(crate) fn embed(app: &mut bevy::app::App) {
    embedded_asset!(app, "shaders/blades.wgsl");
    embedded_asset!(app, "shaders/blade_pbr.wgsl");
    embedded_asset!(app, "shaders/grass.wgsl");
    embedded_asset!(app, "shaders/grass_shadow.wgsl");
    embedded_asset!(app, "shaders/grass_prepass.wgsl");
    embedded_asset!(app, "shaders/portable_blades.wgsl");
}

/// Where the blades' vertex stages read the blades last drawn (beside `engine_bindings`, whose
/// frame and blades both routes bind where the library has them).
const PREVIOUS_BLADES: u32 = 21;
/// Where the Vulkan route's vertex stages read its drawn-blade records.
const DRAWN_BLADES: u32 = 2;

/// The portable passes' WGSL as a Bevy shader library (`sward::portable`), its bindings at
/// group 2.
fn portable_library() -> Shader {
    let source = format!(
        "#define_import_path sward::portable\n{}",
        sward_wgpu::portable::engine_library(2)
    );
    Shader::from_wgsl(source, "sward/portable.wgsl")
}

/// The blades' bind group: the Vulkan renderer's lists (the frame, the blades, the drawn
/// blades, the blades last drawn) or the portable passes' (`portable`).
fn blades_layout(portable: bool) -> BindGroupLayoutDescriptor {
    let storage = || storage_buffer_read_only_sized(false, None);
    let entries: Vec<_> = match portable {
        false => BindGroupLayoutEntries::with_indices(
            ShaderStages::VERTEX_FRAGMENT,
            (
                (engine_bindings::FRAME, uniform_buffer_sized(false, None)),
                (engine_bindings::BLADES, storage()),
                (DRAWN_BLADES, storage()),
                (PREVIOUS_BLADES, storage()),
            ),
        )
        .to_vec(),
        // Read in the vertex stage alone (the fragment stage finds the colour from the frame),
        // so that Bevy's fragment stage keeps its storage buffers.
        true => BindGroupLayoutEntries::with_indices(
            ShaderStages::VERTEX,
            (
                (
                    engine_bindings::FRAME,
                    uniform_buffer_sized(false, None).visibility(ShaderStages::VERTEX_FRAGMENT),
                ),
                (engine_bindings::BLADES, storage()),
                (engine_bindings::VISIBLE, storage()),
                (engine_bindings::COUNTERS, storage()),
                (engine_bindings::PAINT, storage()),
                (PREVIOUS_BLADES, storage()),
            ),
        )
        .to_vec(),
    };
    BindGroupLayoutDescriptor::new("sward: the blades", &entries)
}

/// The pipelines, once Bevy's mesh and prepass pipelines exist (at render startup).
fn init_grass_pipeline(
    mut commands: Commands,
    mesh: Res<MeshPipeline>,
    prepass: Res<PrepassPipeline>,
    mut layouts: ResMut<MeshVertexBufferLayouts>,
    assets: Res<AssetServer>,
    portable: Option<Res<PortableGrass>>,
    route: Option<Res<GrassRoute>>,
) {
    // No pipelines where there is no grass: their layouts may be beyond the device's limits.
    if route.is_none_or(|r| matches!(*r, GrassRoute::Unavailable(_))) {
        return;
    }
    let portable = portable.is_some();
    commands.insert_resource(GrassPipeline {
        mesh: mesh.clone(),
        prepass: prepass.clone(),
        blades: blades_layout(portable),
        portable,
        shader: load_embedded_asset!(assets.as_ref(), "shaders/grass.wgsl"),
        shadow_shader: load_embedded_asset!(assets.as_ref(), "shaders/grass_shadow.wgsl"),
        prepass_shader: load_embedded_asset!(assets.as_ref(), "shaders/grass_prepass.wgsl"),
        _libraries: [
            load_embedded_asset!(assets.as_ref(), "shaders/blades.wgsl"),
            load_embedded_asset!(assets.as_ref(), "shaders/blade_pbr.wgsl"),
            load_embedded_asset!(assets.as_ref(), "shaders/portable_blades.wgsl"),
            assets.add(portable_library()),
        ],
        mesh_layout: layouts.insert(position_only()),
    });
}

/// A vertex layout of positions only: Bevy's mesh pipeline is specialized for it, then its
/// vertex input is taken away (the blades are pulled from sward's buffers).
fn position_only() -> MeshVertexBufferLayout {
    let mut mesh = Mesh::new(PrimitiveTopology::TriangleStrip, Default::default());
    mesh.insert_attribute(Mesh::ATTRIBUTE_POSITION, vec![[0.0f32; 3]; 3]);
    let mut layouts = MeshVertexBufferLayouts::default();
    (*mesh.get_mesh_vertex_buffer_layout(&mut layouts).0).clone()
}

/// The grass's pipelines: Bevy's mesh pipeline (main pass) or prepass pipeline (shadows) with
/// sward's blades bound at group 2 and its shaders.
#[derive(Resource)]
pub(crate) struct GrassPipeline {
    mesh: MeshPipeline,
    prepass: PrepassPipeline,
    blades: BindGroupLayoutDescriptor,
    /// Whether the blades come from the portable passes' lists.
    portable: bool,
    shader: Handle<Shader>,
    shadow_shader: Handle<Shader>,
    prepass_shader: Handle<Shader>,
    /// Held so that the grass shaders' imports stay loaded.
    _libraries: [Handle<Shader>; 4],
    mesh_layout: MeshVertexBufferLayoutRef,
}

/// Which of Bevy's passes a grass pipeline draws in.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub(crate) enum GrassPass {
    /// A camera's main opaque pass (forward).
    Main,
    /// A light's shadow map.
    Shadow,
    /// A camera's prepass: depth, and normals and motion vectors where the camera has them.
    Prepass,
    /// A deferred camera's G-buffer (with its prepass targets).
    Deferred,
}

/// A grass pipeline: the view's mesh key, the pass, and whether Bevy's shadows fall on the
/// grass.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) struct GrassKey {
    mesh: MeshPipelineKey,
    pass: GrassPass,
    receives: bool,
}

impl SpecializedRenderPipeline for GrassPipeline {
    type Key = GrassKey;

    fn specialize(&self, key: GrassKey) -> RenderPipelineDescriptor {
        let made = match key.pass {
            GrassPass::Shadow => return self.shadow_pipeline(key.mesh),
            GrassPass::Main => self.main_pipeline(key),
            GrassPass::Prepass | GrassPass::Deferred => self.prepass_pipeline(key),
        };
        made.unwrap_or_else(|e| {
            // Not for a layout of positions: Bevy's mesh pipeline takes every such layout.
            error!("sward's grass has no pipeline for a view: {e}");
            self.shadow_pipeline(key.mesh)
        })
    }
}

impl GrassPipeline {
    /// The shader definitions that say whose lists the blades come from.
    fn blade_defs(&self) -> Vec<ShaderDefVal> {
        match self.portable {
            true => vec!["SWARD_PORTABLE".into()],
            false => Vec::new(),
        }
    }

    /// The blades in a camera's opaque pass: Bevy's mesh pipeline for the view, its vertex
    /// input taken away, sward's blades bound at group 2, its shaders.
    fn main_pipeline(&self, key: GrassKey) -> Result<RenderPipelineDescriptor, SpecializedMeshPipelineError> {
        let mut desc = self.mesh.specialize(key.mesh, &self.mesh_layout)?;
        if key.receives {
            desc.vertex.shader_defs.push("GRASS_RECEIVES_SHADOWS".into());
        }
        desc.vertex.shader_defs.extend(self.blade_defs());
        desc.label = Some("sward: the blades".into());
        desc.vertex.shader = self.shader.clone();
        desc.vertex.buffers.clear();
        if let Some(fragment) = desc.fragment.as_mut() {
            fragment.shader = self.shader.clone();
            fragment.shader_defs = desc.vertex.shader_defs.clone();
        }
        desc.layout.truncate(2);
        desc.layout.push(self.blades.clone());
        // Either side of a blade is seen.
        desc.primitive.cull_mode = None;
        Ok(desc)
    }

    /// The blades in a camera's prepass or deferred G-buffer, as Bevy's prepass pipeline draws a
    /// mesh there: the view's shader definitions (from Bevy's mesh pipeline, as the main pass
    /// has them) made a prepass's, its targets (normals, motion vectors, G-buffer) as the view
    /// has them.
    fn prepass_pipeline(&self, key: GrassKey) -> Result<RenderPipelineDescriptor, SpecializedMeshPipelineError> {
        let mesh = key.mesh;
        let mut defs = self.mesh.specialize(mesh, &self.mesh_layout)?.vertex.shader_defs;
        defs.retain(|def| !matches!(def, ShaderDefVal::Bool(name, _) if name == "MESH_PIPELINE"));
        defs.push("PREPASS_PIPELINE".into());
        if key.receives {
            defs.push("GRASS_RECEIVES_SHADOWS".into());
        }
        defs.extend(self.blade_defs());
        // Nothing of a material's is bound: its group is out of the way of sward's.
        defs.push(ShaderDefVal::UInt("MATERIAL_BIND_GROUP".into(), 3));
        let [normals, motion, deferred] = [
            MeshPipelineKey::NORMAL_PREPASS,
            MeshPipelineKey::MOTION_VECTOR_PREPASS,
            MeshPipelineKey::DEFERRED_PREPASS,
        ]
        .map(|flag| mesh.contains(flag));
        if normals || deferred {
            defs.push("NORMAL_PREPASS_OR_DEFERRED_PREPASS".into());
        }
        if motion || deferred {
            defs.push("MOTION_VECTOR_PREPASS_OR_DEFERRED_PREPASS".into());
        }
        let mut targets = prepass_target_descriptors(normals, motion, deferred);
        if targets.iter().all(Option::is_none) {
            targets.clear();
        } else {
            defs.push("PREPASS_FRAGMENT".into());
        }
        let view_layout = match motion {
            true => self.prepass.view_layout_motion_vectors.clone(),
            false => self.prepass.view_layout_no_motion_vectors.clone(),
        };
        Ok(RenderPipelineDescriptor {
            label: Some("sward: the blades' prepass".into()),
            layout: vec![view_layout, self.prepass.empty_layout.clone(), self.blades.clone()],
            vertex: VertexState {
                shader: self.prepass_shader.clone(),
                shader_defs: defs.clone(),
                ..Default::default()
            },
            fragment: (!targets.is_empty()).then(|| FragmentState {
                shader: self.prepass_shader.clone(),
                shader_defs: defs,
                targets,
                ..Default::default()
            }),
            primitive: PrimitiveState {
                topology: PrimitiveTopology::TriangleStrip,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(depth_written()),
            multisample: MultisampleState {
                count: mesh.msaa_samples(),
                ..Default::default()
            },
            ..Default::default()
        })
    }

    /// The blades into a shadow map: depth only, as Bevy's prepass pipeline draws a mesh there.
    fn shadow_pipeline(&self, key: MeshPipelineKey) -> RenderPipelineDescriptor {
        RenderPipelineDescriptor {
            label: Some("sward: the blades' shadows".into()),
            layout: vec![
                self.prepass.view_layout_no_motion_vectors.clone(),
                self.prepass.empty_layout.clone(),
                self.blades.clone(),
            ],
            vertex: VertexState {
                shader: self.shadow_shader.clone(),
                shader_defs: self.blade_defs(),
                ..Default::default()
            },
            fragment: None,
            primitive: PrimitiveState {
                topology: PrimitiveTopology::TriangleStrip,
                cull_mode: None,
                // The sun's cascades keep what lies before their near plane.
                unclipped_depth: key.contains(MeshPipelineKey::UNCLIPPED_DEPTH_ORTHO)
                    && self.prepass.depth_clip_control_supported,
                ..Default::default()
            },
            depth_stencil: Some(depth_written()),
            ..Default::default()
        }
    }
}

/// Depth as Bevy's prepasses write it: reverse Z, nearer is greater.
fn depth_written() -> DepthStencilState {
    DepthStencilState {
        format: CORE_3D_DEPTH_FORMAT,
        depth_write_enabled: Some(true),
        depth_compare: Some(CompareFunction::GreaterEqual),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// sward's buffers bound for the grass's draws: per view that culls for itself, one bind group
/// per frame in flight and its draw commands; the frame being drawn; and which list each of
/// Bevy's views draws (a camera its own, its shadow cascades its list too).
#[derive(Resource, Default)]
pub(crate) struct GrassBindGroups {
    views: Vec<ViewGroups>,
    frame: usize,
    list_of: bevy::platform::collections::HashMap<Entity, usize>,
    /// The wgpu buffers the groups were made of (made again when sward's change).
    made_of: Option<(Vec<wgpu::Buffer>, usize)>,
    /// Bytes into each view's draw commands where the distance buckets' begin.
    first_command: u64,
}

/// The portable passes' buffers Bevy's draws read: the blades, the blades last drawn, the paint
/// maps, and per view its frame's uniforms, visible list, counters and draw commands.
pub(crate) struct PortableBuffers {
    pub blades: wgpu::Buffer,
    pub previous: wgpu::Buffer,
    pub paint: wgpu::Buffer,
    pub views: Vec<[wgpu::Buffer; 4]>,
}

/// One view's bind groups (one per frame in flight) and draw commands.
struct ViewGroups {
    groups: Vec<BindGroup>,
    draws: Buffer,
}

impl GrassBindGroups {
    /// Bind `drawn`'s buffers (every view's, every frame's uniforms), where they changed; this
    /// frame wrote `frame`'s uniforms, and Bevy's view `entity` draws list `list_of[entity]`.
    pub(crate) fn bind(
        &mut self,
        (drawn, frame): (&DrawnBlades, usize),
        list_of: bevy::platform::collections::HashMap<Entity, usize>,
        (device, cache, pipeline): (&RenderDevice, &PipelineCache, &GrassPipeline),
    ) {
        let made_of = (vec![drawn.blades.clone()], drawn.views.len());
        self.first_command = DrawnBlades::FIRST_BUCKET_COMMAND as u64 * COMMAND_BYTES;
        if self.made_of.as_ref() != Some(&made_of) {
            let layout = cache.get_bind_group_layout(&pipeline.blades);
            let blades = Buffer::from(drawn.blades.clone());
            let before = Buffer::from(drawn.previous_blades.clone());
            self.views = drawn
                .views
                .iter()
                .map(|view| {
                    let listed = Buffer::from(view.drawn.clone());
                    let group = |uniforms: &wgpu::Buffer| {
                        let uniforms = Buffer::from(uniforms.clone());
                        device.create_bind_group(
                            "sward: the blades",
                            &layout,
                            &BindGroupEntries::with_indices((
                                (engine_bindings::FRAME, uniforms.as_entire_binding()),
                                (engine_bindings::BLADES, blades.as_entire_binding()),
                                (DRAWN_BLADES, listed.as_entire_binding()),
                                (PREVIOUS_BLADES, before.as_entire_binding()),
                            )),
                        )
                    };
                    ViewGroups {
                        groups: view.uniforms.iter().map(group).collect(),
                        draws: Buffer::from(view.draws.clone()),
                    }
                })
                .collect();
            self.made_of = Some(made_of);
        }
        self.frame = frame;
        self.list_of = list_of;
    }

    /// Bind the portable passes' `buffers` (one bind group per view, made again where the
    /// buffers changed), and Bevy's view `entity` draws list `list_of[entity]`.
    pub(crate) fn bind_portable(
        &mut self,
        buffers: PortableBuffers,
        list_of: bevy::platform::collections::HashMap<Entity, usize>,
        (device, cache, pipeline): (&RenderDevice, &PipelineCache, &GrassPipeline),
    ) {
        let shared = [&buffers.blades, &buffers.previous, &buffers.paint];
        let made_of: Vec<wgpu::Buffer> = shared
            .into_iter()
            .chain(buffers.views.iter().flatten())
            .cloned()
            .collect();
        let made_of = (made_of, buffers.views.len());
        self.first_command = 0;
        if self.made_of.as_ref() != Some(&made_of) {
            let layout = cache.get_bind_group_layout(&pipeline.blades);
            let [blades, previous, paint] = shared.map(|b| Buffer::from(b.clone()));
            self.views = buffers
                .views
                .iter()
                .map(|view| {
                    let [frame, visible, counters, draws] = view.clone().map(Buffer::from);
                    let entries = BindGroupEntries::with_indices((
                        (engine_bindings::FRAME, frame.as_entire_binding()),
                        (engine_bindings::BLADES, blades.as_entire_binding()),
                        (engine_bindings::VISIBLE, visible.as_entire_binding()),
                        (engine_bindings::COUNTERS, counters.as_entire_binding()),
                        (engine_bindings::PAINT, paint.as_entire_binding()),
                        (PREVIOUS_BLADES, previous.as_entire_binding()),
                    ));
                    ViewGroups {
                        groups: vec![device.create_bind_group("sward: the portable blades", &layout, &entries)],
                        draws,
                    }
                })
                .collect();
            self.made_of = Some(made_of);
        }
        self.frame = 0;
        self.list_of = list_of;
    }

    /// The bind group and draw commands Bevy's view `view` draws with this frame.
    fn of(&self, view: Entity) -> Option<(&BindGroup, &Buffer, u64)> {
        let list = self.list_of.get(&view).copied().unwrap_or(0);
        let view = self.views.get(list)?;
        Some((view.groups.get(self.frame)?, &view.draws, self.first_command))
    }

    /// Nothing to draw (the grass left, or is drawn by sward's own pass).
    pub(crate) fn clear(&mut self) {
        *self = GrassBindGroups::default();
    }
}

/// The render-world entity the grass's phase items stand for, and the main world's grass.
#[derive(Resource, Clone, Copy)]
pub(crate) struct GrassItem {
    pub render: Entity,
    pub main: MainEntity,
}

/// The grass's phases in Bevy: each camera's opaque, prepass and deferred phases, each light
/// view's shadow phase.
#[derive(SystemParam)]
struct GrassPhases<'w> {
    opaque: ResMut<'w, ViewBinnedRenderPhases<Opaque3d>>,
    prepass: ResMut<'w, ViewBinnedRenderPhases<Opaque3dPrepass>>,
    deferred: ResMut<'w, ViewBinnedRenderPhases<Opaque3dDeferred>>,
    shadows: ResMut<'w, ViewBinnedRenderPhases<Shadow>>,
    opaque_draws: Res<'w, DrawFunctions<Opaque3d>>,
    prepass_draws: Res<'w, DrawFunctions<Opaque3dPrepass>>,
    deferred_draws: Res<'w, DrawFunctions<Opaque3dDeferred>>,
    shadow_draws: Res<'w, DrawFunctions<Shadow>>,
}

/// Each view's grass items, where the grass is drawn in Bevy's passes and the view sees it:
/// a forward camera's opaque phase (and its prepass, where it has one), a deferred camera's
/// deferred phase and prepass, every shadow view's phase where the grass casts.
#[allow(clippy::too_many_arguments)]
fn queue_grass(
    mut commands: Commands,
    extracted: Res<ExtractedGrass>,
    pipeline: Option<Res<GrassPipeline>>,
    mut pipelines: ResMut<SpecializedRenderPipelines<GrassPipeline>>,
    cache: Res<PipelineCache>,
    mut phases: GrassPhases,
    keys: (Res<ViewKeyCache>, Res<LightKeyCache>),
    views: Query<(&ExtractedView, Option<&RenderLayers>, Has<LightEntity>)>,
    item: Option<ResMut<GrassItem>>,
) {
    let Some(pipeline) = pipeline else { return };
    let item = match (item, extracted.entity) {
        (Some(mut item), Some(main)) => {
            item.main = MainEntity::from(main);
            *item
        }
        (None, Some(main)) => {
            let item = GrassItem {
                render: commands.spawn_empty().id(),
                main: MainEntity::from(main),
            };
            commands.insert_resource(item);
            item
        }
        (Some(item), None) => *item,
        (None, None) => return,
    };
    let drawn = extracted.present && extracted.visible && extracted.lighting == GrassLighting::Pbr;
    let topology = MeshPipelineKey::from_primitive_topology_and_strip_index(PrimitiveTopology::TriangleStrip, None);
    for (view, layers, is_light) in &views {
        let entity = view.retained_view_entity;
        let sees = drawn && layers.cloned().unwrap_or_default().intersects(&extracted.layers);
        let key = match is_light {
            false => keys.0.get(&entity).copied(),
            true => keys.1.get(&entity).map(|k| *k | MeshPipelineKey::DEPTH_PREPASS),
        };
        let Some(key) = key.map(|k| k | topology) else { continue };
        let mut pipeline_for = |pass: GrassPass, wanted: bool| {
            let key = GrassKey {
                mesh: key,
                pass,
                receives: extracted.shadows[1],
            };
            (sees && wanted).then(|| pipelines.specialize(&cache, &pipeline, key))
        };
        if is_light {
            // A shadow view sees the grass only where it casts.
            let id = pipeline_for(GrassPass::Shadow, extracted.shadows[0]);
            let draw = phases.shadow_draws.read().id::<DrawGrassDepth>();
            place_item(phases.shadows.get_mut(&entity), item, id.map(|id| (id, draw)));
            continue;
        }
        // On a deferred camera the grass joins the G-buffer where the app renders its meshes
        // there (Bevy draws a view's deferred phase only where it holds a mesh); else it is
        // drawn forward, as a forward material on that camera is.
        let deferred = key.contains(MeshPipelineKey::DEFERRED_PREPASS)
            && phases.deferred.get(&entity).is_some_and(|phase| {
                !phase.multidrawable_meshes.is_empty()
                    || !phase.batchable_meshes.is_empty()
                    || !phase.unbatchable_meshes.is_empty()
            });
        let prepass = key.intersects(
            MeshPipelineKey::DEPTH_PREPASS | MeshPipelineKey::NORMAL_PREPASS | MeshPipelineKey::MOTION_VECTOR_PREPASS,
        );
        let main = pipeline_for(GrassPass::Main, !deferred);
        let draw = phases.opaque_draws.read().id::<DrawGrass>();
        place_item(phases.opaque.get_mut(&entity), item, main.map(|id| (id, draw)));
        let early = pipeline_for(GrassPass::Prepass, prepass && !deferred);
        let draw = phases.prepass_draws.read().id::<DrawGrassDepth>();
        place_item(phases.prepass.get_mut(&entity), item, early.map(|id| (id, draw)));
        let gbuffer = pipeline_for(GrassPass::Deferred, deferred);
        let draw = phases.deferred_draws.read().id::<DrawGrassDepth>();
        place_item(phases.deferred.get_mut(&entity), item, gbuffer.map(|id| (id, draw)));
    }
}

/// The grass's item in a view's phase (`phase`, where the view has it): taken out, and put back
/// with `drawn`'s pipeline and draw function where the view draws it.
fn place_item<P: GrassPhaseItem>(
    phase: Option<&mut BinnedRenderPhase<P>>,
    item: GrassItem,
    drawn: Option<(CachedRenderPipelineId, DrawFunctionId)>,
) {
    let Some(phase) = phase else { return };
    phase.remove(item.main);
    if let Some((pipeline, draw)) = drawn {
        let (batch, bin) = P::keys(pipeline, draw);
        let at = (item.render, item.main);
        phase.add(
            batch,
            bin,
            at,
            InputUniformIndex::default(),
            BinnedRenderPhaseType::NonMesh,
        );
    }
}

/// A phase of Bevy's the grass has an item in: its keys for the grass's item (no mesh, no
/// material).
trait GrassPhaseItem: BinnedPhaseItem {
    fn keys(pipeline: CachedRenderPipelineId, draw: DrawFunctionId) -> (Self::BatchSetKey, Self::BinKey);
}

impl GrassPhaseItem for Opaque3d {
    fn keys(pipeline: CachedRenderPipelineId, draw_function: DrawFunctionId) -> (Self::BatchSetKey, Self::BinKey) {
        let batch = Opaque3dBatchSetKey {
            draw_function,
            pipeline,
            material_bind_group_index: None,
            lightmap_slab: None,
            slabs: MeshSlabs::default(),
        };
        (batch, Opaque3dBinKey { asset_id: no_mesh() })
    }
}

impl GrassPhaseItem for Shadow {
    fn keys(pipeline: CachedRenderPipelineId, draw_function: DrawFunctionId) -> (Self::BatchSetKey, Self::BinKey) {
        let batch = ShadowBatchSetKey {
            pipeline,
            draw_function,
            material_bind_group_index: None,
            slabs: MeshSlabs::default(),
        };
        (batch, ShadowBinKey { asset_id: no_mesh() })
    }
}

/// The prepass's and the deferred G-buffer's keys.
fn no_lightmap_keys(
    pipeline: CachedRenderPipelineId,
    draw_function: DrawFunctionId,
) -> (OpaqueNoLightmap3dBatchSetKey, OpaqueNoLightmap3dBinKey) {
    let batch = OpaqueNoLightmap3dBatchSetKey {
        pipeline,
        draw_function,
        material_bind_group_index: None,
        slabs: MeshSlabs::default(),
    };
    (batch, OpaqueNoLightmap3dBinKey { asset_id: no_mesh() })
}

impl GrassPhaseItem for Opaque3dPrepass {
    fn keys(pipeline: CachedRenderPipelineId, draw: DrawFunctionId) -> (Self::BatchSetKey, Self::BinKey) {
        no_lightmap_keys(pipeline, draw)
    }
}

impl GrassPhaseItem for Opaque3dDeferred {
    fn keys(pipeline: CachedRenderPipelineId, draw: DrawFunctionId) -> (Self::BatchSetKey, Self::BinKey) {
        no_lightmap_keys(pipeline, draw)
    }
}

/// The asset an item that is no mesh stands for (Bevy draws a non-mesh item by itself).
fn no_mesh() -> bevy::asset::UntypedAssetId {
    AssetId::<Mesh>::invalid().untyped()
}

/// The grass in a camera's main opaque pass.
type DrawGrass = (
    SetItemPipeline,
    SetMeshViewBindGroup<0>,
    SetMeshViewBindingArrayBindGroup<1>,
    DrawBlades,
);

/// The grass in a shadow view, a camera's prepass or its deferred G-buffer (Bevy's prepass
/// view bindings).
type DrawGrassDepth = (
    SetItemPipeline,
    SetPrepassViewBindGroup<0>,
    SetPrepassViewEmptyBindGroup<1>,
    DrawBlades,
);

/// Bind sward's buffers and draw every distance bucket's command: each a strip per blade.
struct DrawBlades;

impl<P: PhaseItem> RenderCommand<P> for DrawBlades {
    type Param = SRes<GrassBindGroups>;
    type ViewQuery = Entity;
    type ItemQuery = ();

    fn render<'w>(
        _: &P,
        view: ROQueryItem<'w, '_, Self::ViewQuery>,
        _: Option<ROQueryItem<'w, '_, Self::ItemQuery>>,
        groups: SystemParamItem<'w, '_, Self::Param>,
        pass: &mut TrackedRenderPass<'w>,
    ) -> RenderCommandResult {
        let Some((group, draws, offset)) = groups.into_inner().of(view) else {
            return RenderCommandResult::Skip;
        };
        pass.set_bind_group(2, group, &[]);
        // A draw per bucket: one multi-draw of the 64 commands drew nothing on lavapipe (through
        // wgpu, where sward's own multi-draw of them draws), the same commands one by one do.
        for bucket in 0..DrawnBlades::BUCKETS as u64 {
            pass.draw_indirect(draws, offset + bucket * COMMAND_BYTES);
        }
        RenderCommandResult::Success
    }
}
