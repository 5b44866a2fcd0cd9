//! The grass in Bevy's own passes ([`GrassLighting::Pbr`]): sward simulates, culls and lists
//! the Bezier blades before Bevy renders (one raw region of compute, submitted first), and Bevy
//! draws them as phase items of its main opaque pass, its prepass and deferred G-buffer and its
//! shadow passes, through pipelines made from Bevy's own mesh and prepass pipelines (its view
//! bindings and shader definitions).
//! So the grass is lit by Bevy's PBR — every light, their shadows, ambient light, environment
//! maps, fog, exposure and tonemapping — and casts into Bevy's shadow maps, as a Bevy mesh.
//! The vertex stages pull each blade from sward's buffers (`shaders/blades.wesl`).
//!
//! Drawn so, in four parts ([`GrassPart`]), each a phase item of its own, culled for each 3D
//! camera that sees the grass (up to `sward_wgpu::VIEWS_PER_FRAME`), a camera's shadow cascades
//! drawing its lists:
//! - the Bezier blades by the strip route, from the Vulkan renderer's lists
//!   (`shaders/blades.wesl`) or the portable passes' (`shaders/portable_blades.wesl`, with the
//!   shader definition `SWARD_PORTABLE`);
//! - from the portable passes, the generated grass's four levels and the billboards
//!   (`shaders/far_grass.wesl`), which cast within the grass's shadow distance of the camera;
//! - where the device has 64-bit atomic min and max, the far field the portable passes splatted
//!   for the camera's first view beyond its splat distances (and the grass's shadow distance:
//!   `frames::splat_beyond_shadows`): a screen-covering triangle resolves its cells
//!   (`shaders/splat_resolve.wesl`, `shaders/splat_prepass.wesl`), lit by Bevy's PBR as the
//!   drawn grass is, its depth written, into the main pass, the prepass (normals, motion vectors
//!   from the camera's motion) and the deferred G-buffer; not into shadow maps.
//!
//! On the device Bevy opens the portable passes list every technique; on the device
//! `render_plugin` opens the Vulkan renderer lists the Bezier technique, and the portable passes
//! every other (the Vulkan renderer's generated grass, billboards and splats are for its own
//! pass).

use bevy::app::SubApp;
use bevy::asset::{AssetId, AssetServer, Handle};
use bevy::camera::visibility::RenderLayers;
use bevy::core_pipeline::core_3d::{Opaque3d, Opaque3dBatchSetKey, Opaque3dBinKey, CORE_3D_DEPTH_FORMAT};
use bevy::core_pipeline::deferred::Opaque3dDeferred;
use bevy::core_pipeline::prepass::{
    prepass_target_descriptors, MotionVectorPrepass, Opaque3dPrepass, OpaqueNoLightmap3dBatchSetKey,
    OpaqueNoLightmap3dBinKey,
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
use bevy::platform::collections::HashMap;
use bevy::render::mesh::allocator::MeshSlabs;
use bevy::render::render_phase::{
    AddRenderCommand, BinnedPhaseItem, BinnedRenderPhase, BinnedRenderPhaseType, DrawFunctionId, DrawFunctions,
    InputUniformIndex, PhaseItem, RenderCommand, RenderCommandResult, SetItemPipeline, TrackedRenderPass,
    ViewBinnedRenderPhases,
};
use bevy::render::render_resource::binding_types::{
    sampler, storage_buffer_read_only_sized, texture_2d, uniform_buffer_sized,
};
use bevy::render::render_resource::{
    BindGroup, BindGroupEntries, BindGroupEntry, BindGroupLayoutDescriptor, BindGroupLayoutEntries,
    BindGroupLayoutEntry, BindingResource, Buffer, BufferBinding, CachedRenderPipelineId, CompareFunction,
    DepthStencilState, FragmentState, MultisampleState, PipelineCache, PrimitiveState, RenderPipelineDescriptor,
    Sampler, SamplerBindingType, ShaderStages, SpecializedMeshPipeline as _, SpecializedMeshPipelineError,
    SpecializedRenderPipeline, SpecializedRenderPipelines, TextureSampleType, TextureView, VertexState,
};
use bevy::render::renderer::RenderDevice;
use bevy::render::sync_world::MainEntity;
use bevy::render::view::{ExtractedView, RetainedViewEntity};
use bevy::render::{Render, RenderStartup, RenderSystems};
use bevy::shader::{Shader, ShaderDefVal};
use sward_core::commands::DISTANCE_BUCKETS;
use sward_core::instanced::Technique;
use sward_core::wgsl::engine_bindings;
use sward_portable::GeneratedDraws;
#[cfg(feature = "vulkan")]
use sward_wgpu::DrawnBlades;

use super::cascades::{find_cascade_bands, CascadeBand, CascadeBands, Casting};
use super::extract::ExtractedGrass;
use super::portable::{GrassRoute, GrassSplats};
use crate::lighting::GrassLighting;

/// Bytes of one draw command (`sward_core::gpu::DrawCommand`).
const COMMAND_BYTES: u64 = 16;

/// The grass's phase items, pipelines and bind groups in the render world.
pub(crate) fn build(render_app: &mut SubApp) {
    render_app
        .init_resource::<SpecializedRenderPipelines<GrassPipeline>>()
        .init_resource::<GrassBindGroups>()
        .init_resource::<GrassItems>()
        .init_resource::<CascadeBands>()
        .add_render_command::<Opaque3d, DrawGrass<DrawBlades>>()
        .add_render_command::<Shadow, DrawGrassDepth<DrawBlades>>()
        .add_render_command::<Opaque3dPrepass, DrawGrassDepth<DrawBlades>>()
        .add_render_command::<Opaque3dDeferred, DrawGrassDepth<DrawBlades>>()
        .add_render_command::<Opaque3d, DrawGrass<DrawLevels>>()
        .add_render_command::<Shadow, DrawGrassDepth<DrawLevels>>()
        .add_render_command::<Opaque3dPrepass, DrawGrassDepth<DrawLevels>>()
        .add_render_command::<Opaque3dDeferred, DrawGrassDepth<DrawLevels>>()
        .add_render_command::<Opaque3d, DrawGrass<DrawBillboards>>()
        .add_render_command::<Shadow, DrawGrassDepth<DrawBillboards>>()
        .add_render_command::<Opaque3dPrepass, DrawBillboardsDepth>()
        .add_render_command::<Opaque3dDeferred, DrawBillboardsDepth>()
        .add_render_command::<Opaque3d, DrawGrass<DrawSplats>>()
        .add_render_command::<Shadow, DrawGrassDepth<DrawSplats>>()
        .add_render_command::<Opaque3dPrepass, DrawGrassDepth<DrawSplats>>()
        .add_render_command::<Opaque3dDeferred, DrawGrassDepth<DrawSplats>>()
        .add_systems(
            RenderStartup,
            init_grass_pipeline
                .after(MeshPipelineSystems)
                .after(bevy::pbr::init_prepass_pipeline),
        )
        // After the meshes: a deferred view's phase says whether the app renders deferred.
        .add_systems(
            Render,
            (
                queue_grass
                    .in_set(RenderSystems::Queue)
                    .after(RenderSystems::QueueMeshes),
                // After Bevy made the light views (`RenderSystems::CreateViews`).
                find_cascade_bands.in_set(RenderSystems::Queue),
            ),
        );
}

/// One of the grass's WESL modules, in the crate's text, importable at its path in the crate
/// (`sward_bevy::render_world::shaders::NAME`, which the modules' `super::NAME` imports reach).
/// Added to Bevy's shaders as it starts, not loaded by the asset server's tasks: the grass's
/// pipelines compile as soon as Bevy's do, however busy the machine.
macro_rules! grass_shader {
    ($name:literal) => {
        Shader::from_wesl(
            include_str!(concat!("shaders/", $name, ".wesl")),
            concat!("embedded://sward_bevy/render_world/shaders/", $name, ".wesl"),
        )
    };
}

/// Where the blades' vertex stages read the blades last drawn (beside `engine_bindings`, whose
/// frame and blades both routes bind where the library has them).
const PREVIOUS_BLADES: u32 = sward_core::declared::bindings::PREVIOUS_BLADES;
/// Where the Vulkan route's vertex stages read its drawn-blade records.
const DRAWN_BLADES: u32 = sward_core::declared::bindings::DRAWN_BLADES;
/// Where the splats' resolve reads the splat cells (as the core's resolve binds them).
const SPLAT_WORDS: u32 = sward_core::declared::bindings::SPLAT_WORDS;

/// The portable passes' WGSL as a Bevy shader library (`sward::portable`), its bindings at
/// group 2.
fn portable_library() -> Shader {
    // sward's own modules, composed by the WESL compiler Bevy composes with: an error is in
    // sward's text, not the game's (sward-core's and sward-portable's tests compose every module).
    let library = sward_core::wgsl::engine_library(2).unwrap_or_else(|e| panic!("{e}"));
    // WESL's import path of an embedded shader is its path: `sward::portable`.
    Shader::from_wesl(library, "embedded://sward/portable.wesl")
}

/// The blades' bind group: the Vulkan renderer's lists (the frame, the blades, the drawn
/// blades, the blades last drawn) or the portable passes' (`portable`).
fn blades_layout(portable: bool) -> BindGroupLayoutDescriptor {
    let storage = || storage_buffer_read_only_sized(false, None);
    let entries: Vec<_> = match portable {
        false => BindGroupLayoutEntries::with_indices(
            ShaderStages::VERTEX_FRAGMENT,
            (
                (engine_bindings::BLADES, storage()),
                (DRAWN_BLADES, storage()),
                (PREVIOUS_BLADES, storage()),
            ),
        )
        .iter()
        .cloned()
        .chain(frame_layout(ShaderStages::VERTEX_FRAGMENT))
        .collect(),
        // Read in the vertex stage alone (the fragment stage finds the colour from the frame),
        // so that Bevy's fragment stage keeps its storage buffers.
        true => BindGroupLayoutEntries::with_indices(
            ShaderStages::VERTEX,
            (
                (engine_bindings::BLADES, storage()),
                (engine_bindings::VISIBLE, storage()),
                (engine_bindings::COUNTERS, storage()),
                (engine_bindings::PAINT, storage()),
                (PREVIOUS_BLADES, storage()),
            ),
        )
        .iter()
        .cloned()
        .chain(frame_layout(ShaderStages::VERTEX_FRAGMENT))
        .collect(),
    };
    BindGroupLayoutDescriptor::new("sward: the blades", &entries)
}

/// The far grass's bind group (the portable passes'): the frame, the generated lists and the
/// paint in the vertex stage; for the billboards also the trample map, and the painted texture
/// and its sampler in the fragment stage.
fn far_layout(billboards: bool) -> BindGroupLayoutDescriptor {
    let storage = || storage_buffer_read_only_sized(false, None);
    let entries: Vec<_> = match billboards {
        false => BindGroupLayoutEntries::with_indices(
            ShaderStages::VERTEX,
            (
                (engine_bindings::LISTED, storage()),
                (engine_bindings::PAINT, storage()),
            ),
        )
        .to_vec(),
        true => BindGroupLayoutEntries::with_indices(
            ShaderStages::VERTEX,
            (
                (engine_bindings::LISTED, storage()),
                (engine_bindings::PAINT, storage()),
                (engine_bindings::TRAMPLE, storage()),
                (
                    engine_bindings::GRASS_TEXTURE,
                    texture_2d(TextureSampleType::Float { filterable: true }).visibility(ShaderStages::FRAGMENT),
                ),
                (
                    engine_bindings::GRASS_SAMPLER,
                    sampler(SamplerBindingType::Filtering).visibility(ShaderStages::FRAGMENT),
                ),
            ),
        )
        .to_vec(),
    };
    let entries: Vec<_> = entries
        .into_iter()
        .chain(frame_layout(ShaderStages::VERTEX_FRAGMENT))
        .collect();
    BindGroupLayoutDescriptor::new("sward: the far grass", &entries)
}

/// The splatted far field's bind group (the portable passes'): the frame, and the splat cells
/// in the fragment stage.
fn splats_layout() -> BindGroupLayoutDescriptor {
    let cells = storage_buffer_read_only_sized(false, None).visibility(ShaderStages::FRAGMENT);
    let entries: Vec<_> = BindGroupLayoutEntries::with_indices(ShaderStages::FRAGMENT, ((SPLAT_WORDS, cells),))
        .iter()
        .cloned()
        .chain(frame_layout(ShaderStages::VERTEX_FRAGMENT))
        .collect();
    BindGroupLayoutDescriptor::new("sward: the splatted far field", &entries)
}

/// The frame's uniform blocks in a bind group's layout (every block the library declares: a
/// pipeline's layout may hold bindings its shaders do not read), seen by `stages`.
fn frame_layout(stages: ShaderStages) -> impl Iterator<Item = BindGroupLayoutEntry> {
    let block = move |binding| uniform_buffer_sized(false, None).build(binding, stages);
    engine_bindings::FRAME_BLOCKS.into_iter().map(block)
}

/// The frame's uniform blocks bound: each its range of the frame's buffer `frame`.
fn frame_blocks(frame: &Buffer) -> impl Iterator<Item = BindGroupEntry<'_>> {
    sward_core::declared::frame_blocks().map(move |(binding, offset, size)| BindGroupEntry {
        binding,
        resource: BindingResource::Buffer(BufferBinding {
            buffer: frame,
            offset,
            size: std::num::NonZeroU64::new(size),
        }),
    })
}

/// A bind group's entries: `entries` and the frame's blocks of `frame`.
fn with_frame<'a>(entries: &[BindGroupEntry<'a>], frame: &'a Buffer) -> Vec<BindGroupEntry<'a>> {
    entries.iter().cloned().chain(frame_blocks(frame)).collect()
}

/// The pipelines, once Bevy's mesh and prepass pipelines exist (at render startup).
fn init_grass_pipeline(
    mut commands: Commands,
    mesh: Res<MeshPipeline>,
    prepass: Res<PrepassPipeline>,
    mut layouts: ResMut<MeshVertexBufferLayouts>,
    assets: Res<AssetServer>,
    route: Option<Res<GrassRoute>>,
    (device, splats): (Res<RenderDevice>, Option<Res<GrassSplats>>),
) {
    // No pipelines where there is no grass: their layouts may be beyond the device's limits.
    if route.is_none_or(|r| matches!(*r, GrassRoute::Unavailable(_))) {
        return;
    }
    commands.insert_resource(GrassPipeline {
        mesh: mesh.clone(),
        prepass: prepass.clone(),
        blades: [blades_layout(false), blades_layout(true)],
        far: [far_layout(false), far_layout(true)],
        splats: splats_layout(),
        narrow: splats
            .map_or(GrassSplats::default(), |s| *s)
            .cells_on(device.wgpu_device())
            == Some(true),
        shader: assets.add(grass_shader!("grass")),
        shadow_shader: assets.add(grass_shader!("grass_shadow")),
        prepass_shader: assets.add(grass_shader!("grass_prepass")),
        splat_shaders: [
            assets.add(grass_shader!("splat_resolve")),
            assets.add(grass_shader!("splat_prepass")),
        ],
        _libraries: [
            assets.add(grass_shader!("splat_cells")),
            assets.add(grass_shader!("blades")),
            assets.add(grass_shader!("blade_pbr")),
            assets.add(grass_shader!("portable_blades")),
            assets.add(grass_shader!("far_grass")),
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
    /// The Bezier blades': from the Vulkan renderer's lists, from the portable passes'.
    blades: [BindGroupLayoutDescriptor; 2],
    /// The far grass's: the generated levels', the billboards'.
    far: [BindGroupLayoutDescriptor; 2],
    /// The splatted far field's.
    splats: BindGroupLayoutDescriptor,
    /// Whether the portable passes splat into 32-bit cells on this device.
    narrow: bool,
    shader: Handle<Shader>,
    shadow_shader: Handle<Shader>,
    prepass_shader: Handle<Shader>,
    /// The splats' resolve in the main pass, and in the prepass and G-buffer.
    splat_shaders: [Handle<Shader>; 2],
    /// Held so that the grass shaders' imports stay loaded.
    _libraries: [Handle<Shader>; 6],
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

/// Which of the grass's parts a pipeline draws.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub(crate) enum GrassPart {
    /// The Bezier blades.
    Blades,
    /// The generated grass's four levels.
    Levels,
    /// The billboards.
    Billboards,
    /// The generated grass and billboards splatted beyond their splat distances, resolved by a
    /// screen-covering triangle (where the device splats: `PortableRenderer::for_engine`).
    Splats,
}

impl GrassPart {
    const ALL: [GrassPart; 4] = [
        GrassPart::Blades,
        GrassPart::Levels,
        GrassPart::Billboards,
        GrassPart::Splats,
    ];

    /// How the part's vertices make triangles: a strip up each blade, two triangles a
    /// billboard's quad, one covering the screen.
    fn topology(self) -> PrimitiveTopology {
        match self {
            GrassPart::Billboards | GrassPart::Splats => PrimitiveTopology::TriangleList,
            _ => PrimitiveTopology::TriangleStrip,
        }
    }

    /// Whether grass of `technique` has this part.
    fn of(self, technique: Technique) -> bool {
        match self {
            GrassPart::Blades => technique.draws_bezier(),
            GrassPart::Levels => technique.draws_instanced(),
            GrassPart::Billboards => technique.draws_billboards(),
            GrassPart::Splats => technique.draws_instanced() || technique.draws_billboards(),
        }
    }

    /// Whether the part is drawn in a pass of Bevy's: everything but the splats in every pass;
    /// the splats not into a shadow map (the far field casts no shadow beyond the grass's
    /// shadow distance, and splats lie beyond the drawn far grass).
    fn drawn_in(self, pass: GrassPass) -> bool {
        !(self == GrassPart::Splats && pass == GrassPass::Shadow)
    }
}

/// A grass pipeline: the view's mesh key, the pass, the part, whether the portable passes list
/// the grass, whether Bevy's shadows fall on it, and how far from the camera the far grass
/// casts (centimetres).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) struct GrassKey {
    mesh: MeshPipelineKey,
    pass: GrassPass,
    part: GrassPart,
    portable: bool,
    receives: bool,
    casting: u32,
    /// The splats in a cell a pixel under MSAA ([`GrassQuality::pixel_cells`](crate::GrassQuality)).
    pixel_cells: bool,
}

impl SpecializedRenderPipeline for GrassPipeline {
    type Key = GrassKey;

    fn specialize(&self, key: GrassKey) -> RenderPipelineDescriptor {
        let made = match key.pass {
            GrassPass::Shadow => return self.shadow_pipeline(key),
            GrassPass::Main => self.main_pipeline(key),
            GrassPass::Prepass | GrassPass::Deferred => self.prepass_pipeline(key),
        };
        made.unwrap_or_else(|e| {
            // Not for a layout of positions: Bevy's mesh pipeline takes every such layout.
            error!("sward's grass has no pipeline for a view: {e}");
            self.shadow_pipeline(key)
        })
    }
}

impl GrassPipeline {
    /// The shader definitions that say whose lists the blades come from, and which part of the
    /// grass is drawn.
    fn blade_defs(key: GrassKey) -> Vec<ShaderDefVal> {
        let (mut defs, part) = (Vec::new(), key.part);
        if key.portable {
            defs.push("SWARD_PORTABLE".into());
        }
        if matches!(part, GrassPart::Levels | GrassPart::Billboards) {
            defs.push("GRASS_FAR".into());
        }
        if part == GrassPart::Billboards {
            defs.push("GRASS_BILLBOARDS".into());
        }
        defs
    }

    /// The shader definitions of `key`'s part: the blades' (`blade_defs`), and where the
    /// splats are in 32-bit cells, `SPLAT_NARROW`.
    fn part_defs(&self, key: GrassKey) -> Vec<ShaderDefVal> {
        let mut defs = Self::blade_defs(key);
        if key.part == GrassPart::Splats && self.narrow {
            defs.push("SPLAT_NARROW".into());
        }
        defs
    }

    /// Group 1 of `part`'s prepass and G-buffer pipelines (`motion`: with motion vectors):
    /// Bevy's empty group, but for the billboards with motion vectors their own group again.
    /// Lavapipe crashed drawing the billboards with group 1 empty between a group 0 of two
    /// dynamic offsets (the view's and the last frame's) and a group 2 that holds a sampler,
    /// and with group 1 bound after a group 0 of one (a depth prepass, a shadow view); so it
    /// is bound twice only where group 0 has two.
    fn depth_group_one(&self, part: GrassPart, motion: bool) -> BindGroupLayoutDescriptor {
        match part == GrassPart::Billboards && motion {
            true => self.far[1].clone(),
            false => self.prepass.empty_layout.clone(),
        }
    }

    /// The bind group layout of the buffers of `key`'s part.
    fn layout_of(&self, key: GrassKey) -> BindGroupLayoutDescriptor {
        match key.part {
            GrassPart::Blades => self.blades[usize::from(key.portable)].clone(),
            GrassPart::Levels => self.far[0].clone(),
            GrassPart::Billboards => self.far[1].clone(),
            GrassPart::Splats => self.splats.clone(),
        }
    }

    /// The splats' fragment stage in a prepass on a target of `samples`: per sample where each
    /// sample has its cell (4×: `SplatTarget::set_samples`), else per pixel.
    fn splat_entry(samples: u32) -> &'static str {
        match samples {
            4 => "sample_fragment",
            _ => "fragment",
        }
    }

    /// The splats' stage in the main pass on a target of `samples`: under 4× MSAA a fragment a
    /// pixel lighting its sample cells' mean once, its alpha their share (alpha to coverage:
    /// its main pass 1.0 ms shorter than with a fragment a sample, on the H100 at 1920×1080 in
    /// the bench example's flight, docs/benchmarks-history.md), else per pixel.
    fn splat_resolve_entry(samples: u32) -> &'static str {
        match samples {
            4 => "pixel_fragment",
            _ => "fragment",
        }
    }

    /// The blades in a camera's opaque pass: Bevy's mesh pipeline for the view, its vertex
    /// input taken away, sward's blades bound at group 2, its shaders.
    fn main_pipeline(&self, key: GrassKey) -> Result<RenderPipelineDescriptor, SpecializedMeshPipelineError> {
        let mut desc = self.mesh.specialize(key.mesh, &self.mesh_layout)?;
        if key.receives {
            desc.vertex.shader_defs.push("GRASS_RECEIVES_SHADOWS".into());
        }
        desc.vertex.shader_defs.extend(self.part_defs(key));
        // A billboard's painted blades cover the samples their texture's alpha says (MSAA).
        if key.part == GrassPart::Billboards && desc.multisample.count > 1 {
            desc.multisample.alpha_to_coverage_enabled = true;
            desc.vertex.shader_defs.push("GRASS_COVERAGE".into());
        }
        desc.label = Some("sward: the blades".into());
        let splats = key.part == GrassPart::Splats;
        // The splats under MSAA: lit once a pixel, their cells' share covering its samples.
        let samples = match key.pixel_cells {
            true => 1,
            false => desc.multisample.count,
        };
        if splats && samples == 4 {
            desc.multisample.alpha_to_coverage_enabled = true;
        }
        let shader = if splats { &self.splat_shaders[0] } else { &self.shader };
        desc.vertex.shader = shader.clone();
        desc.vertex.buffers.clear();
        if let Some(fragment) = desc.fragment.as_mut() {
            fragment.shader = shader.clone();
            fragment.shader_defs = desc.vertex.shader_defs.clone();
            if splats {
                fragment.entry_point = Some(Self::splat_resolve_entry(samples).into());
            }
        }
        desc.layout.truncate(2);
        desc.layout.push(self.layout_of(key));
        desc.primitive.topology = key.part.topology();
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
        defs.extend(self.part_defs(key));
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
        let splats = key.part == GrassPart::Splats;
        // The shader holds a second fragment stage for a billboard's depth alone.
        let mut entry = Some(match (splats, key.pixel_cells) {
            (true, false) => Self::splat_entry(mesh.msaa_samples()).into(),
            _ => "fragment".into(),
        });
        if targets.iter().all(Option::is_none) {
            targets.clear();
            // Depth alone: a billboard's fragments still say where its painted blades are, the
            // splats' where their cells hold a blade.
            entry = match key.part {
                GrassPart::Billboards => Some("coverage_fragment".into()),
                GrassPart::Splats => Some("depth_fragment".into()),
                _ => None,
            };
        } else {
            defs.push("PREPASS_FRAGMENT".into());
        }
        let shader = if splats {
            &self.splat_shaders[1]
        } else {
            &self.prepass_shader
        };
        let view_layout = match motion {
            true => self.prepass.view_layout_motion_vectors.clone(),
            false => self.prepass.view_layout_no_motion_vectors.clone(),
        };
        Ok(RenderPipelineDescriptor {
            label: Some("sward: the blades' prepass".into()),
            layout: vec![view_layout, self.depth_group_one(key.part, motion), self.layout_of(key)],
            vertex: VertexState {
                shader: shader.clone(),
                shader_defs: defs.clone(),
                ..Default::default()
            },
            fragment: (!targets.is_empty() || entry.is_some()).then(|| FragmentState {
                shader: shader.clone(),
                shader_defs: defs,
                entry_point: entry,
                targets,
                ..Default::default()
            }),
            primitive: PrimitiveState {
                topology: key.part.topology(),
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

    /// The grass into a shadow map: depth only, as Bevy's prepass pipeline draws a mesh there
    /// (a billboard's fragments where its painted blades cover half of one).
    fn shadow_pipeline(&self, key: GrassKey) -> RenderPipelineDescriptor {
        let mut defs = Self::blade_defs(key);
        defs.push(ShaderDefVal::UInt("GRASS_SHADOW_CENTIMETRES".into(), key.casting));
        let billboards = key.part == GrassPart::Billboards;
        RenderPipelineDescriptor {
            label: Some("sward: the blades' shadows".into()),
            layout: vec![
                self.prepass.view_layout_no_motion_vectors.clone(),
                self.prepass.empty_layout.clone(),
                self.layout_of(key),
            ],
            vertex: VertexState {
                shader: self.shadow_shader.clone(),
                shader_defs: defs.clone(),
                ..Default::default()
            },
            fragment: billboards.then(|| FragmentState {
                shader: self.shadow_shader.clone(),
                shader_defs: defs,
                entry_point: Some("coverage_fragment".into()),
                targets: Vec::new(),
                ..Default::default()
            }),
            primitive: PrimitiveState {
                topology: key.part.topology(),
                cull_mode: None,
                // The sun's cascades keep what lies before their near plane.
                unclipped_depth: key.mesh.contains(MeshPipelineKey::UNCLIPPED_DEPTH_ORTHO)
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

/// sward's buffers bound for the grass's draws, each field's (by its main-world entity).
#[derive(Resource, Default)]
pub(crate) struct GrassBindGroups {
    fields: HashMap<Entity, FieldGroups>,
}

impl GrassBindGroups {
    /// Field `field`'s groups, made empty where it has none yet.
    pub(crate) fn field_mut(&mut self, field: Entity) -> &mut FieldGroups {
        self.fields.entry(field).or_default()
    }

    /// Nothing to draw of field `field` (it went, is hidden, or is drawn by sward's own pass).
    pub(crate) fn forget(&mut self, field: Entity) {
        self.fields.remove(&field);
    }

    /// Forget every field but those `keep` says to keep.
    pub(crate) fn retain(&mut self, mut keep: impl FnMut(Entity) -> bool) {
        self.fields.retain(|field, _| keep(*field));
    }

    /// The groups of the field item `item` is a part of.
    fn of_item(&self, items: &GrassItems, item: MainEntity) -> Option<&FieldGroups> {
        self.fields.get(items.field_of.get(&item)?)
    }
}

/// One field's buffers bound for its draws: per view that culls for itself, one bind group
/// per frame in flight and its draw commands; the frame being drawn; and which list each of
/// Bevy's views draws (a camera its own, its shadow cascades its list too).
#[derive(Default)]
pub(crate) struct FieldGroups {
    views: Vec<ViewGroups>,
    frame: usize,
    list_of: HashMap<Entity, usize>,
    /// The wgpu buffers the groups were made of, and per view which far parts it binds (made
    /// again when sward's change).
    made_of: Option<(Vec<wgpu::Buffer>, Vec<[bool; 2]>)>,
    /// Bytes into each view's draw commands where the distance buckets' begin.
    first_command: u64,
    /// How far the grass casts shadows: the far grass from the camera (`Grass::shadow_distance`),
    /// the Bezier blades, the tallest blade.
    casting: Casting,
}

/// The portable passes' buffers Bevy's draws read: the blades, the blades last drawn, the paint
/// maps, the trample map, and per view its frame's uniforms, visible list, counters and draw
/// commands, and its far grass where it listed any.
pub(crate) struct PortableBuffers {
    pub blades: wgpu::Buffer,
    pub previous: wgpu::Buffer,
    pub paint: wgpu::Buffer,
    pub trample: wgpu::Buffer,
    pub views: Vec<[wgpu::Buffer; 4]>,
    pub far: Vec<Option<FarBuffers>>,
    /// The first view's splat cells, where its frame splatted.
    pub splats: Option<wgpu::Buffer>,
}

/// A view's far grass as the portable passes listed it (`sward_portable::GeneratedDraws`).
pub(crate) struct FarBuffers {
    pub listed: wgpu::Buffer,
    pub draws: wgpu::Buffer,
    /// Whether it listed the generated levels.
    pub levels: bool,
    /// Where it listed billboards, their painted texture and its sampler.
    pub billboards: Option<(wgpu::TextureView, wgpu::Sampler)>,
    /// How far from the camera each level's blades begin, then the billboards.
    pub starts: [f32; GeneratedDraws::COMMANDS],
    /// The billboards' draw command (`GeneratedDraws::billboard_command`).
    pub billboard_command: u32,
}

/// One view's bind groups (one per frame in flight) and draw commands, and its far grass's.
struct ViewGroups {
    groups: Vec<BindGroup>,
    draws: Buffer,
    far: Option<FarGroups>,
    /// Its splat cells with its frame, where it splatted.
    splats: Option<BindGroup>,
}

/// A view's far grass: the levels' and the billboards' bind groups (where it listed them), and
/// their draw commands.
struct FarGroups {
    levels: Option<BindGroup>,
    billboards: Option<BindGroup>,
    draws: Buffer,
    starts: [f32; GeneratedDraws::COMMANDS],
    billboard_command: u32,
}

impl FieldGroups {
    /// Bind `drawn`'s buffers (every view's, every frame's uniforms), where they changed; this
    /// frame wrote `frame`'s uniforms, and Bevy's view `entity` draws list `list_of[entity]`.
    #[cfg(feature = "vulkan")]
    pub(crate) fn bind(
        &mut self,
        (drawn, frame): (&DrawnBlades, usize),
        list_of: HashMap<Entity, usize>,
        (device, cache, pipeline): (&RenderDevice, &PipelineCache, &GrassPipeline),
    ) {
        let made_of = (vec![drawn.blades.clone()], vec![[false; 2]; drawn.views.len()]);
        self.first_command = DrawnBlades::FIRST_BUCKET_COMMAND as u64 * COMMAND_BYTES;
        if self.made_of.as_ref() != Some(&made_of) {
            let layout = cache.get_bind_group_layout(&pipeline.blades[0]);
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
                            &with_frame(
                                &BindGroupEntries::with_indices((
                                    (engine_bindings::BLADES, blades.as_entire_binding()),
                                    (DRAWN_BLADES, listed.as_entire_binding()),
                                    (PREVIOUS_BLADES, before.as_entire_binding()),
                                )),
                                &uniforms,
                            ),
                        )
                    };
                    ViewGroups {
                        groups: view.uniforms.iter().map(group).collect(),
                        draws: Buffer::from(view.draws.clone()),
                        far: None,
                        splats: None,
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
        list_of: HashMap<Entity, usize>,
        (device, cache, pipeline): (&RenderDevice, &PipelineCache, &GrassPipeline),
    ) {
        let shared = [&buffers.blades, &buffers.previous, &buffers.paint, &buffers.trample];
        let far_buffers = buffers.far.iter().flatten().flat_map(|far| [&far.listed, &far.draws]);
        let made_of: Vec<wgpu::Buffer> = shared
            .into_iter()
            .chain(buffers.views.iter().flatten())
            .chain(far_buffers)
            .chain(&buffers.splats)
            .cloned()
            .collect();
        let parts = buffers.far.iter().map(|far| {
            far.as_ref()
                .map_or([false; 2], |far| [far.levels, far.billboards.is_some()])
        });
        let splats = buffers.splats.map(Buffer::from);
        let made_of = (made_of, parts.collect());
        self.first_command = 0;
        if self.made_of.as_ref() != Some(&made_of) {
            let layout = cache.get_bind_group_layout(&pipeline.blades[1]);
            let [blades, previous, paint, trample] = shared.map(|b| Buffer::from(b.clone()));
            self.views = buffers
                .views
                .iter()
                .zip(&buffers.far)
                .enumerate()
                .map(|(k, (view, far))| {
                    let [frame, visible, counters, draws] = view.clone().map(Buffer::from);
                    let entries = BindGroupEntries::with_indices((
                        (engine_bindings::BLADES, blades.as_entire_binding()),
                        (engine_bindings::VISIBLE, visible.as_entire_binding()),
                        (engine_bindings::COUNTERS, counters.as_entire_binding()),
                        (engine_bindings::PAINT, paint.as_entire_binding()),
                        (PREVIOUS_BLADES, previous.as_entire_binding()),
                    ));
                    let entries = with_frame(&entries, &frame);
                    let far = far
                        .as_ref()
                        .map(|far| far_groups(far, [&frame, &paint, &trample], (device, cache, pipeline)));
                    // Only the first view splats (the field's first camera).
                    let splats = match k {
                        0 => splats
                            .as_ref()
                            .map(|cells| splat_group(cells, &frame, (device, cache, pipeline))),
                        _ => None,
                    };
                    ViewGroups {
                        groups: vec![device.create_bind_group("sward: the portable blades", &layout, &entries)],
                        draws,
                        far,
                        splats,
                    }
                })
                .collect();
            self.made_of = Some(made_of);
        }
        self.frame = 0;
        self.list_of = list_of;
    }

    /// The view groups of the list Bevy's view `view` draws.
    fn view_of(&self, view: Entity) -> Option<&ViewGroups> {
        let list = self.list_of.get(&view).copied().unwrap_or(0);
        self.views.get(list)
    }

    /// The bind group and draw commands Bevy's view `view` draws with this frame.
    fn of(&self, view: Entity) -> Option<(&BindGroup, &Buffer, u64)> {
        let view = self.view_of(view)?;
        Some((view.groups.get(self.frame)?, &view.draws, self.first_command))
    }

    /// The bind group and draw commands of far part `part` (the levels, the billboards) Bevy's
    /// view `view` draws, where its list has the part, and which of the part's commands it
    /// draws: all of them, but in a shadow view (`shadow`) only those that begin within the
    /// shadow distance, and in a sun's cascade serving `band` only those whose blades can cast
    /// into it.
    fn far_of(
        &self,
        view: Entity,
        part: GrassPart,
        (shadow, band): (bool, Option<&CascadeBand>),
    ) -> Option<FarDraw<'_>> {
        let far = self.view_of(view)?.far.as_ref()?;
        let (group, commands) = match part {
            GrassPart::Levels => (far.levels.as_ref(), 0..GeneratedDraws::LEVEL_COMMANDS as usize),
            _ => (far.billboards.as_ref(), {
                let k = GeneratedDraws::BILLBOARD_COMMAND as usize;
                k..k + 1
            }),
        };
        // The billboards' start is the last; their command where the lists lay it. A level ends
        // where the next begins; the last, and the billboards, where the grid does.
        let ends = |k: usize| match k + 1 < GeneratedDraws::LEVEL_COMMANDS as usize {
            true => far.starts[k + 1],
            false => f32::INFINITY,
        };
        let into_band = |k: usize| band.is_none_or(|b| b.casts([far.starts[k], ends(k)], self.casting.tallest));
        let casts = |k: &usize| !shadow || (far.starts[*k] < self.casting.far && into_band(*k));
        let command = |k: usize| match k == GeneratedDraws::BILLBOARD_COMMAND as usize {
            true => far.billboard_command as usize,
            false => k,
        };
        Some(FarDraw {
            group: group?,
            draws: &far.draws,
            commands: commands.filter(casts).map(command).collect(),
        })
    }

    /// The splat cells' bind group Bevy's view `view` resolves, where its list splatted.
    fn splats_of(&self, view: Entity) -> Option<&BindGroup> {
        self.view_of(view)?.splats.as_ref()
    }

    /// Say how far the field's grass casts shadows.
    pub(crate) fn cast_as(&mut self, casting: Casting) {
        self.casting = casting;
    }
}

/// A far part's draws in a view: its bind group, the draw commands, and which of them it
/// draws.
struct FarDraw<'a> {
    group: &'a BindGroup,
    draws: &'a Buffer,
    commands: Vec<usize>,
}

/// A view's far grass bound: its levels and billboards (where it listed them) with the frame,
/// the paint and the trample map.
fn far_groups(
    far: &FarBuffers,
    [frame, paint, trample]: [&Buffer; 3],
    (device, cache, pipeline): (&RenderDevice, &PipelineCache, &GrassPipeline),
) -> FarGroups {
    let listed = Buffer::from(far.listed.clone());
    let levels = far.levels.then(|| {
        let entries = BindGroupEntries::with_indices((
            (engine_bindings::LISTED, listed.as_entire_binding()),
            (engine_bindings::PAINT, paint.as_entire_binding()),
        ));
        let entries = with_frame(&entries, frame);
        let layout = cache.get_bind_group_layout(&pipeline.far[0]);
        device.create_bind_group("sward: the generated levels", &layout, &entries)
    });
    let billboards = far.billboards.as_ref().map(|(view, sampled)| {
        let (texture, sampled) = (TextureView::from(view.clone()), Sampler::from(sampled.clone()));
        let entries = BindGroupEntries::with_indices((
            (engine_bindings::LISTED, listed.as_entire_binding()),
            (engine_bindings::PAINT, paint.as_entire_binding()),
            (engine_bindings::TRAMPLE, trample.as_entire_binding()),
            (engine_bindings::GRASS_TEXTURE, &texture),
            (engine_bindings::GRASS_SAMPLER, &sampled),
        ));
        let entries = with_frame(&entries, frame);
        let layout = cache.get_bind_group_layout(&pipeline.far[1]);
        device.create_bind_group("sward: the billboards", &layout, &entries)
    });
    FarGroups {
        levels,
        billboards,
        draws: Buffer::from(far.draws.clone()),
        starts: far.starts,
        billboard_command: far.billboard_command,
    }
}

/// A view's splat cells bound with its frame.
fn splat_group(
    cells: &Buffer,
    frame: &Buffer,
    (device, cache, pipeline): (&RenderDevice, &PipelineCache, &GrassPipeline),
) -> BindGroup {
    let entries = BindGroupEntries::with_indices(((SPLAT_WORDS, cells.as_entire_binding()),));
    let layout = cache.get_bind_group_layout(&pipeline.splats);
    device.create_bind_group("sward: the splatted far field", &layout, &with_frame(&entries, frame))
}

/// The render-world entities each field's phase items stand for, one a part, and the
/// main-world entity each is keyed by in Bevy's phases: the Bezier blades' the grass's own, the
/// far parts' their render entities (Bevy keys an item that is no mesh by it alone).
#[derive(Resource, Default)]
pub(crate) struct GrassItems {
    fields: HashMap<Entity, [(Entity, MainEntity); 4]>,
    /// The field each item's key stands for.
    field_of: HashMap<MainEntity, Entity>,
}

impl GrassItems {
    /// Field `field`'s items, made where it has none yet.
    fn of(&mut self, field: Entity, commands: &mut Commands) -> [(Entity, MainEntity); 4] {
        let field_of = &mut self.field_of;
        *self.fields.entry(field).or_insert_with(|| {
            let mut part = |main: Option<Entity>| {
                let render = commands.spawn_empty().id();
                let key = MainEntity::from(main.unwrap_or(render));
                field_of.insert(key, field);
                (render, key)
            };
            [part(Some(field)), part(None), part(None), part(None)]
        })
    }

    /// The items of fields no longer extracted, taken out of the maps (their render entities
    /// despawned).
    fn gone(&mut self, extracted: &ExtractedGrass, commands: &mut Commands) -> Vec<[(Entity, MainEntity); 4]> {
        let gone: Vec<Entity> = self
            .fields
            .keys()
            .filter(|f| extracted.field(**f).is_none())
            .copied()
            .collect();
        gone.into_iter()
            .filter_map(|field| self.fields.remove(&field))
            .inspect(|parts| {
                for (render, key) in parts {
                    self.field_of.remove(key);
                    commands.entity(*render).despawn();
                }
            })
            .collect()
    }
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

/// Each view's grass items, for each field drawn in Bevy's passes that the view sees: a
/// forward camera's opaque phase (and its prepass, where it has one), a deferred camera's
/// deferred phase and prepass, every shadow view's phase where the grass casts. The items of
/// fields that went are taken out of every view's phases.
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
    mut items: ResMut<GrassItems>,
) {
    let Some(pipeline) = pipeline else { return };
    let gone = items.gone(&extracted, &mut commands);
    let fields: Vec<_> = extracted
        .fields
        .iter()
        .map(|field| (field, items.of(field.entity, &mut commands)))
        .collect();
    let topology = MeshPipelineKey::from_primitive_topology_and_strip_index(PrimitiveTopology::TriangleStrip, None);
    let draws = [
        draw_ids::<DrawBlades>(&phases),
        draw_ids::<DrawLevels>(&phases),
        billboard_draw_ids(&phases),
        draw_ids::<DrawSplats>(&phases),
    ];
    for (view, layers, is_light) in &views {
        let entity = view.retained_view_entity;
        for at in gone.iter().flatten() {
            take_out(&mut phases, entity, *at);
        }
        let key = match is_light {
            false => keys.0.get(&entity).copied(),
            true => keys.1.get(&entity).map(|k| *k | MeshPipelineKey::DEPTH_PREPASS),
        };
        let Some(key) = key.map(|k| k | topology) else { continue };
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
        for &(field, parts) in &fields {
            let drawn = field.lighting == GrassLighting::Pbr && field.seen_on(layers);
            // The far grass's parts are the portable passes' (the Vulkan renderer lists the
            // Bezier blades alone for Bevy's passes).
            let portable = field.portable;
            let has = GrassPart::ALL
                .map(|part| drawn && part.of(field.technique()) && (part == GrassPart::Blades || portable));
            let casting = (field.shadow_distance * 100.0).round() as u32;
            for (k, part) in GrassPart::ALL.into_iter().enumerate() {
                let at = parts[k];
                let [opaque, shadow, early, gbuffer] = draws[k];
                let mut pipeline_for = |pass: GrassPass, wanted: bool| {
                    // A deferred camera's prepass draws no G-buffer (its deferred pass does).
                    let mesh = match pass {
                        GrassPass::Prepass => key - MeshPipelineKey::DEFERRED_PREPASS,
                        _ => key,
                    };
                    let key = GrassKey {
                        mesh,
                        pass,
                        part,
                        portable,
                        receives: field.shadows[1],
                        casting: if pass == GrassPass::Shadow { casting } else { 0 },
                        pixel_cells: part == GrassPart::Splats && field.pixel_cells,
                    };
                    (has[k] && wanted && part.drawn_in(pass)).then(|| pipelines.specialize(&cache, &pipeline, key))
                };
                if is_light {
                    // A shadow view sees the grass only where it casts.
                    let id = pipeline_for(GrassPass::Shadow, field.shadows[0]);
                    place_item(phases.shadows.get_mut(&entity), at, id.map(|id| (id, shadow)));
                    continue;
                }
                let main = pipeline_for(GrassPass::Main, !deferred);
                place_item(phases.opaque.get_mut(&entity), at, main.map(|id| (id, opaque)));
                let before = pipeline_for(GrassPass::Prepass, prepass && !deferred);
                place_item(phases.prepass.get_mut(&entity), at, before.map(|id| (id, early)));
                let into = pipeline_for(GrassPass::Deferred, deferred);
                place_item(phases.deferred.get_mut(&entity), at, into.map(|id| (id, gbuffer)));
            }
        }
    }
}

/// A gone field's item `at` taken out of view `view`'s phases.
fn take_out(phases: &mut GrassPhases, view: RetainedViewEntity, at: (Entity, MainEntity)) {
    place_item(phases.shadows.get_mut(&view), at, None);
    place_item(phases.opaque.get_mut(&view), at, None);
    place_item(phases.prepass.get_mut(&view), at, None);
    place_item(phases.deferred.get_mut(&view), at, None);
}

/// The billboards' draw functions, as [`draw_ids`]'s.
fn billboard_draw_ids(phases: &GrassPhases) -> [DrawFunctionId; 4] {
    [
        phases.opaque_draws.read().id::<DrawGrass<DrawBillboards>>(),
        phases.shadow_draws.read().id::<DrawGrassDepth<DrawBillboards>>(),
        phases.prepass_draws.read().id::<DrawBillboardsDepth>(),
        phases.deferred_draws.read().id::<DrawBillboardsDepth>(),
    ]
}

/// The draw functions of a part drawn by `D`: in the opaque phase, the shadow phase, the
/// prepass and the deferred G-buffer.
fn draw_ids<D: 'static>(phases: &GrassPhases) -> [DrawFunctionId; 4] {
    [
        phases.opaque_draws.read().id::<DrawGrass<D>>(),
        phases.shadow_draws.read().id::<DrawGrassDepth<D>>(),
        phases.prepass_draws.read().id::<DrawGrassDepth<D>>(),
        phases.deferred_draws.read().id::<DrawGrassDepth<D>>(),
    ]
}

/// The grass's item in a view's phase (`phase`, where the view has it): taken out, and put back
/// with `drawn`'s pipeline and draw function where the view draws it.
fn place_item<P: GrassPhaseItem>(
    phase: Option<&mut BinnedRenderPhase<P>>,
    at: (Entity, MainEntity),
    drawn: Option<(CachedRenderPipelineId, DrawFunctionId)>,
) {
    let Some(phase) = phase else { return };
    phase.remove(at.1);
    if let Some((pipeline, draw)) = drawn {
        let (batch, bin) = P::keys(pipeline, draw);
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
    AssetId::<Mesh>::default().untyped()
}

/// A part of the grass drawn by `D` in a camera's main opaque pass.
type DrawGrass<D> = (
    SetItemPipeline,
    SetMeshViewBindGroup<0>,
    SetMeshViewBindingArrayBindGroup<1>,
    D,
);

/// A part of the grass drawn by `D` in a shadow view, a camera's prepass or its deferred
/// G-buffer (Bevy's prepass view bindings).
type DrawGrassDepth<D> = (
    SetItemPipeline,
    SetPrepassViewBindGroup<0>,
    SetPrepassViewEmptyBindGroup<1>,
    D,
);

/// The billboards in a camera's prepass or its deferred G-buffer: with motion vectors their
/// group at 1 as well as at 2 (`GrassPipeline::depth_group_one`).
type DrawBillboardsDepth = (
    SetItemPipeline,
    SetPrepassViewBindGroup<0>,
    SetPrepassViewEmptyBindGroup<1>,
    SetBillboardGroupOne,
    DrawBillboards,
);

/// Bind the billboards' group at 1 too, where the view draws motion vectors.
struct SetBillboardGroupOne;

impl<P: PhaseItem> RenderCommand<P> for SetBillboardGroupOne {
    type Param = (SRes<GrassBindGroups>, SRes<GrassItems>);
    type ViewQuery = (Entity, Has<MotionVectorPrepass>);
    type ItemQuery = ();

    fn render<'w>(
        item: &P,
        (view, motion): ROQueryItem<'w, '_, Self::ViewQuery>,
        _: Option<ROQueryItem<'w, '_, Self::ItemQuery>>,
        (groups, items): SystemParamItem<'w, '_, Self::Param>,
        pass: &mut TrackedRenderPass<'w>,
    ) -> RenderCommandResult {
        if !motion {
            return RenderCommandResult::Success;
        }
        let groups = groups.into_inner().of_item(&items, item.main_entity());
        let Some(far) = groups.and_then(|g| g.far_of(view, GrassPart::Billboards, (false, None))) else {
            return RenderCommandResult::Skip;
        };
        pass.set_bind_group(1, far.group, &[]);
        RenderCommandResult::Success
    }
}

/// Bind sward's buffers and draw every distance bucket's command: each a strip per blade.
struct DrawBlades;

impl<P: PhaseItem> RenderCommand<P> for DrawBlades {
    type Param = (SRes<GrassBindGroups>, SRes<GrassItems>, SRes<CascadeBands>);
    type ViewQuery = Entity;
    type ItemQuery = ();

    fn render<'w>(
        item: &P,
        view: ROQueryItem<'w, '_, Self::ViewQuery>,
        _: Option<ROQueryItem<'w, '_, Self::ItemQuery>>,
        (groups, items, bands): SystemParamItem<'w, '_, Self::Param>,
        pass: &mut TrackedRenderPass<'w>,
    ) -> RenderCommandResult {
        let Some(groups) = groups.into_inner().of_item(&items, item.main_entity()) else {
            return RenderCommandResult::Skip;
        };
        // A sun's cascade beyond the Bezier blades' shadows draws none of them.
        if !groups.casting.bezier_into(bands.into_inner().of(view)) {
            return RenderCommandResult::Success;
        }
        let Some((group, draws, offset)) = groups.of(view) else {
            return RenderCommandResult::Skip;
        };
        pass.set_bind_group(2, group, &[]);
        // A draw per bucket: one multi-draw of the 64 commands drew nothing on lavapipe (through
        // wgpu, where sward's own multi-draw of them draws), the same commands one by one do.
        for bucket in 0..DISTANCE_BUCKETS as u64 {
            pass.draw_indirect(draws, offset + bucket * COMMAND_BYTES);
        }
        RenderCommandResult::Success
    }
}

/// Bind the splat cells of the view and draw the screen-covering triangle that resolves them,
/// where the view's list splatted this frame.
struct DrawSplats;

impl<P: PhaseItem> RenderCommand<P> for DrawSplats {
    type Param = (SRes<GrassBindGroups>, SRes<GrassItems>);
    type ViewQuery = Entity;
    type ItemQuery = ();

    fn render<'w>(
        item: &P,
        view: ROQueryItem<'w, '_, Self::ViewQuery>,
        _: Option<ROQueryItem<'w, '_, Self::ItemQuery>>,
        (groups, items): SystemParamItem<'w, '_, Self::Param>,
        pass: &mut TrackedRenderPass<'w>,
    ) -> RenderCommandResult {
        let groups = groups.into_inner().of_item(&items, item.main_entity());
        let Some(group) = groups.and_then(|g| g.splats_of(view)) else {
            // Nothing splatted for this view: nothing to resolve.
            return RenderCommandResult::Success;
        };
        pass.set_bind_group(2, group, &[]);
        pass.draw(0..3, 0..1);
        RenderCommandResult::Success
    }
}

/// Bind the far grass's buffers and draw a far part's commands: each generated level's (a
/// strip per blade), or (`BILLBOARDS`) the billboards' (18 vertices a billboard).
struct DrawFar<const BILLBOARDS: bool>;

/// The generated grass's levels.
type DrawLevels = DrawFar<false>;
/// The billboards.
type DrawBillboards = DrawFar<true>;

impl<P: PhaseItem, const BILLBOARDS: bool> RenderCommand<P> for DrawFar<BILLBOARDS> {
    type Param = (SRes<GrassBindGroups>, SRes<GrassItems>, SRes<CascadeBands>);
    type ViewQuery = (Entity, Has<LightEntity>);
    type ItemQuery = ();

    fn render<'w>(
        item: &P,
        (view, shadow): ROQueryItem<'w, '_, Self::ViewQuery>,
        _: Option<ROQueryItem<'w, '_, Self::ItemQuery>>,
        (groups, items, bands): SystemParamItem<'w, '_, Self::Param>,
        pass: &mut TrackedRenderPass<'w>,
    ) -> RenderCommandResult {
        let part = match BILLBOARDS {
            true => GrassPart::Billboards,
            false => GrassPart::Levels,
        };
        let Some(groups) = groups.into_inner().of_item(&items, item.main_entity()) else {
            return RenderCommandResult::Skip;
        };
        let band = bands.into_inner().of(view);
        draw_far(groups, (view, shadow, band), part, pass)
    }
}

/// Draw far part `part`'s commands in view `view` (a shadow view where `shadow`: those that
/// begin within the shadow distance and, in a sun's cascade serving `band`, cast into it), one
/// by one (as the Bezier blades' buckets).
fn draw_far<'w>(
    groups: &'w FieldGroups,
    (view, shadow, band): (Entity, bool, Option<&CascadeBand>),
    part: GrassPart,
    pass: &mut TrackedRenderPass<'w>,
) -> RenderCommandResult {
    let Some(far) = groups.far_of(view, part, (shadow, band)) else {
        return RenderCommandResult::Skip;
    };
    if far.commands.is_empty() {
        return RenderCommandResult::Success;
    }
    pass.set_bind_group(2, far.group, &[]);
    for k in far.commands {
        pass.draw_indirect(far.draws, k as u64 * GeneratedDraws::COMMAND_BYTES);
    }
    RenderCommandResult::Success
}
