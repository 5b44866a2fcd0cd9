//! The grass on whatever device Bevy opened itself — Vulkan, Metal, DX12, GL, a browser's
//! WebGPU — and, on sward's Vulkan device, wherever Bevy's passes draw more than the Bezier
//! blades: sward's portable passes (`sward_portable`, WGSL through wgpu's safe API)
//! simulate the Bezier blades and cull them into each camera's lists, and generate the far
//! grass (the instanced grass's levels, the billboards) into them — splatting it beyond its
//! splat distances where the device has 64-bit atomic min and max
//! (`PortableRenderer::for_engine`) — before Bevy renders; Bevy's passes draw all of it and
//! resolve the splats (`phases.rs`, `shaders/portable_blades.wesl`, `shaders/far_grass.wesl`,
//! `shaders/splat_resolve.wesl`).
//! Where Bevy's own device cannot run the passes, one warning and [`GrassRoute`] say why, and
//! the app runs on without grass.

use bevy::ecs::prelude::*;
use bevy::ecs::query::QueryItem;
use bevy::log::{error, warn};
use bevy::platform::collections::HashMap;
use bevy::platform::time::Instant;
use bevy::render::diagnostic::{DiagnosticsRecorder, RecordDiagnostics};
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::{RenderAdapter, RenderDevice, RenderQueue};
use bevy::render::view::ExtractedView;
use sward_core::{Field, Scene};
use sward_portable::{
    engine_splat_cells, FieldView, PortableError, PortableField, PortablePasses, PortableRenderer,
    STORAGE_BUFFERS_PER_STAGE,
};

use super::cascades::Casting;
use super::extract::{ExtractedField, ExtractedGrass};
use super::frames::{
    cameras_seeing, frame_of, grow, lists_of, paint_texel, same_layout, splat_beyond_shadows, taking, ComputeView,
    Taking,
};
use super::phases::{FarBuffers, GrassBindGroups, GrassPipeline, PortableBuffers};
use crate::timings::{GrassFrameTimes, GrassTimings};

/// How the grass reaches the screen in this app, in both worlds once the plugin is finished.
#[derive(Resource, Clone, Debug, PartialEq, Eq)]
pub enum GrassRoute {
    /// sward's Vulkan renderer, on the device [`render_plugin`](crate::render_plugin) opened:
    /// every technique in sward's own pass, the Bezier blades in Bevy's; where Bevy's passes
    /// draw another technique, sward's portable passes list it on this device.
    Vulkan,
    /// sward's portable passes on the device Bevy opened (its backend and adapter named): every
    /// technique (the Bezier blades grown once or streamed, the generated grass and billboards
    /// to the horizon), drawn in Bevy's passes.
    Portable(String),
    /// No grass: why, in one sentence (an adapter without compute shaders, say).
    Unavailable(String),
}

/// How Bevy's passes get the far field of the portable passes — the generated grass and
/// billboards beyond their splat distances ([`SwardPlugin::splats`](crate::SwardPlugin)).
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GrassSplats {
    /// Splatted where the device can, and resolved in Bevy's passes: into 64-bit cells (each
    /// point's albedo, normal and height along its blade) where it has 64-bit atomic min and
    /// max (Vulkan, Metal, DX12), else into 32-bit cells (the albedo alone: WebGPU, GL).
    #[default]
    Auto,
    /// Into 32-bit cells on any device, as a device without 64-bit atomics splats (to see
    /// them where it has them).
    Narrow,
    /// Drawn as geometry to the horizon.
    Off,
}

impl GrassSplats {
    /// The cells the portable passes splat in on `device` (`sward_portable::engine_splat_cells`:
    /// `Some(true)` 32-bit, `Some(false)` 64-bit), or none.
    pub(crate) fn cells_on(self, device: &wgpu::Device) -> Option<bool> {
        match self {
            GrassSplats::Auto => engine_splat_cells(device, None),
            GrassSplats::Narrow => engine_splat_cells(device, Some(true)),
            GrassSplats::Off => None,
        }
    }
}

/// The portable passes and the fields they run, in the render world.
#[derive(Resource)]
pub(crate) struct PortableGrass {
    /// The passes whose pipelines every field's share (each field's are its `sibling`): on
    /// Bevy's device those made to learn whether it runs them, on sward's Vulkan device made
    /// when a field first needs them.
    template: Option<PortableRenderer>,
    /// Whether the passes could not be made on sward's Vulkan device, where they were tried
    /// (why is said once, when found).
    refused: bool,
    /// How the far field reaches Bevy's passes.
    splats: GrassSplats,
    /// Each grass entity's passes and field.
    fields: HashMap<Entity, FieldPasses>,
    timings: Option<GrassTimings>,
}

/// One grass entity's passes and the field they run.
struct FieldPasses {
    renderer: PortableRenderer,
    field: Option<PortableField>,
    /// The scene the field was grown from, and the version of the grass it was taken at.
    scene: Option<Scene>,
    version: u64,
    /// What the field was grown to (its size).
    grown: Option<Field>,
    steps: u64,
    /// The last error reported (each is said once, until a frame draws again).
    reported: Option<String>,
}

/// The portable passes on Bevy's device, or why this device cannot run them (said once, as a
/// warning).
pub(crate) fn finish(render_app: &mut bevy::app::SubApp, timings: Option<GrassTimings>) -> GrassRoute {
    let world = render_app.world();
    let adapter: &wgpu::Adapter = world.resource::<RenderAdapter>();
    let device = world.resource::<RenderDevice>().wgpu_device().clone();
    let info = adapter.get_info();
    let splats = world.get_resource::<GrassSplats>().copied().unwrap_or_default();
    let renderer = match passes_on(adapter, &device, splats) {
        Ok(renderer) => renderer,
        Err(e) => {
            let why = format!("sward draws no grass: {e}");
            warn!("{why}");
            return GrassRoute::Unavailable(why);
        }
    };
    build(render_app, Some(renderer), timings);
    GrassRoute::Portable(format!("{:?} ({})", info.backend, info.name))
}

/// The portable passes' resource and system in the render world: with `renderer` made, or to
/// be made when the grass first needs it (on sward's Vulkan device).
pub(crate) fn build(
    render_app: &mut bevy::app::SubApp,
    renderer: Option<PortableRenderer>,
    timings: Option<GrassTimings>,
) {
    if let Some(timings) = &timings {
        render_app.insert_resource(timings.clone());
    }
    let splats = render_app
        .world()
        .get_resource::<GrassSplats>()
        .copied()
        .unwrap_or_default();
    render_app.insert_resource(PortableGrass {
        template: renderer,
        refused: false,
        splats,
        fields: HashMap::default(),
        timings,
    });
    render_app.add_systems(
        bevy::render::Render,
        compute_grass.in_set(bevy::render::RenderSystems::PrepareBindGroups),
    );
}

/// The portable passes on `device`, where it can run them and Bevy's draws of their lists: made
/// for an engine (`PortableRenderer::for_engine`), so that where the device splats in the cells
/// `splats` asks for, the far field is splatted for Bevy's passes to light and resolve.
fn passes_on(
    adapter: &wgpu::Adapter,
    device: &wgpu::Device,
    splats: GrassSplats,
) -> Result<PortableRenderer, PortableError> {
    needs(adapter, device)?;
    match splats.cells_on(device) {
        Some(narrow) => PortableRenderer::for_engine(adapter, device, narrow),
        None => PortableRenderer::new(adapter, device),
    }
}

/// Storage buffers Bevy's draws of the blades bind in the vertex stage: the portable strips'
/// four (the blades, the visible list, the counters, the paint) and the blades last drawn, for
/// motion vectors.
const DRAW_STORAGE_BUFFERS: u32 = 5;

/// Whether the portable passes and Bevy's draws of the blades fit `device`.
fn needs(adapter: &wgpu::Adapter, device: &wgpu::Device) -> Result<(), PortableError> {
    let has = device.limits().max_storage_buffers_per_shader_stage;
    let needs = STORAGE_BUFFERS_PER_STAGE.max(DRAW_STORAGE_BUFFERS);
    if has < needs {
        let info = adapter.get_info();
        let adapter = format!("{:?} ({})", info.backend, info.name);
        return Err(PortableError::FewStorageBuffers { adapter, has, needs });
    }
    Ok(())
}

/// The portable passes for each field they list, for each 3D camera that sees it (the first
/// steps it; each culls it into its own lists, up to `VIEWS_PER_FRAME`; cameras past those draw
/// the first's), submitted before Bevy renders the frame, and their buffers bound for Bevy's
/// draws. Every field a camera sees is culled in one submission against one depth pyramid
/// holding all their occluders (`PortableRenderer::record_fields_view`): one field's grass and
/// ground hide another's, and the pyramid is built once a camera, not once a field.
#[allow(clippy::too_many_arguments)]
fn compute_grass(
    extracted: Res<ExtractedGrass>,
    mut grass: ResMut<PortableGrass>,
    views: Query<ComputeView<'static>>,
    queue: Res<RenderQueue>,
    (adapter, render_device): (Res<RenderAdapter>, Res<RenderDevice>),
    cache: Res<PipelineCache>,
    pipeline: Option<Res<GrassPipeline>>,
    mut groups: ResMut<GrassBindGroups>,
    recorder: Option<Res<DiagnosticsRecorder>>,
) {
    let start = Instant::now();
    let listed = |f: &&ExtractedField| f.portable;
    // sward's Vulkan renderer draws the other fields (vulkan.rs), or they went: their passes go.
    grass
        .fields
        .retain(|entity, _| extracted.field(*entity).is_some_and(|f| f.portable));
    groups.retain(|entity| extracted.field(entity).is_some());
    let device = render_device.wgpu_device();
    // The fields drawn this frame, each with the cameras that see it.
    let mut drawn = Vec::new();
    for field in extracted.fields.iter().filter(listed) {
        let cameras = cameras_seeing(&views, &field.layers);
        let (Some(_), false, true) = (pipeline.as_deref(), cameras.is_empty(), field.visible) else {
            groups.forget(field.entity);
            continue;
        };
        let Some(passes) = grass.passes_for(field, &adapter, device) else {
            groups.forget(field.entity);
            continue;
        };
        if let Err(e) = passes.prepare(field, device) {
            groups.forget(field.entity);
            passes.report(e);
            continue;
        }
        drawn.push((field, cameras));
    }
    let Some(pipeline) = pipeline.as_deref() else { return };
    let submitted = grass.record_cameras((device, &queue, recorder.as_deref()), &extracted, &drawn);
    for (field, cameras) in &drawn {
        let passes = grass.fields.get_mut(&field.entity).expect("made above");
        let Some(buffers) = passes.buffers(cameras.len()) else {
            groups.forget(field.entity);
            continue;
        };
        let groups = groups.field_mut(field.entity);
        groups.bind_portable(buffers, lists_of(cameras), (&render_device, &cache, pipeline));
        groups.cast_as(Casting::of(field));
        passes.reported = None;
    }
    if !drawn.is_empty() {
        grass.measured(&extracted, start, submitted);
    }
}

impl PortableGrass {
    /// Each camera's passes over the `drawn` fields it sees, in the cameras' order (a field's
    /// first camera steps it), one submission a camera: a view's uniforms are written once per
    /// submission. Each is a span of Bevy's render diagnostics where the app has them
    /// (`RenderDiagnosticsPlugin`): "sward/grass" for the first camera, "sward/grass camera K"
    /// for a later one. Returns the time the submissions took (where the GPU is the floor, the
    /// frame's wait for it may fall there).
    fn record_cameras(
        &mut self,
        (device, queue, recorder): (&wgpu::Device, &wgpu::Queue, Option<&DiagnosticsRecorder>),
        extracted: &ExtractedGrass,
        drawn: &[(&ExtractedField, Vec<QueryItem<'_, '_, ComputeView<'static>>>)],
    ) -> std::time::Duration {
        // Each field's cameras are in this order too (by `Camera::order`, then as queried).
        let mut cameras: Vec<_> = drawn.iter().flat_map(|(_, c)| c.iter()).collect();
        cameras.sort_by_key(|(_, _, camera, ..)| camera.order);
        let mut listed = bevy::platform::collections::HashSet::new();
        cameras.retain(|(entity, ..)| listed.insert(*entity));
        let mut submitted = std::time::Duration::ZERO;
        for &&(camera, view, extracted_camera, msaa, ..) in &cameras {
            let viewport = extracted_camera
                .physical_viewport_size
                .map_or([1, 1], |s| [s.x.max(1), s.y.max(1)]);
            // The fields this camera sees, with its place among each one's cameras.
            let seeing: Vec<(&ExtractedField, usize, bool)> = drawn
                .iter()
                .filter_map(|(field, cameras)| {
                    let k = cameras.iter().position(|c| c.0 == camera)?;
                    let motion = cameras.iter().any(|&(.., draws_motion_vectors)| draws_motion_vectors);
                    Some((*field, k, motion))
                })
                .collect();
            let mut encoder = device.create_command_encoder(&Default::default());
            let name = match cameras.iter().position(|c| c.0 == camera) {
                Some(0) => "sward/grass".to_string(),
                k => format!("sward/grass camera {}", k.unwrap_or_default()),
            };
            let span = recorder.time_span(&mut encoder, name);
            self.record_camera(
                device,
                queue,
                &mut encoder,
                (extracted, &seeing),
                (view, viewport, msaa.samples()),
            );
            span.end(&mut encoder);
            let commands = encoder.finish();
            let submitting = Instant::now();
            queue.submit([commands]);
            submitted += submitting.elapsed();
        }
        submitted
    }

    /// One camera's passes over the fields it sees (`seeing`: each field, the camera's place
    /// among its cameras, whether any of them draws motion vectors), culled together.
    fn record_camera(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        (extracted, seeing): (&ExtractedGrass, &[(&ExtractedField, usize, bool)]),
        (view, viewport, samples): (&ExtractedView, [u32; 2], u32),
    ) {
        let mut passes: Vec<_> = self
            .fields
            .iter_mut()
            .filter_map(|(entity, passes)| {
                let &(field, k, motion) = seeing.iter().find(|(f, ..)| f.entity == *entity)?;
                if k == 0 {
                    // The field's first camera splats, a cell a sample of its target on a 4× one
                    // (a cell a pixel at the quality tiers that ask it).
                    passes
                        .renderer
                        .set_splat_samples(if field.pixel_cells { 1 } else { samples });
                }
                let (desc, run) = passes.view_of(device, (extracted, field), (view, viewport), (k, motion))?;
                Some((passes, desc, run, k))
            })
            .collect();
        let mut fields: Vec<FieldView> = passes
            .iter_mut()
            .filter_map(|(passes, desc, run, k)| {
                let FieldPasses { renderer, field, .. } = &mut **passes;
                Some(FieldView {
                    renderer,
                    field: field.as_mut()?,
                    desc,
                    passes: *run,
                    view: *k,
                })
            })
            .collect();
        PortableRenderer::record_fields_view(device, queue, encoder, &mut fields);
    }

    /// The passes of `field`: its own, else a sibling of the template (made now where there is
    /// none yet: tried once on sward's Vulkan device, which is not asked again each frame where
    /// it cannot run them, and says why once, as an error); or none where they cannot be made.
    fn passes_for(
        &mut self,
        field: &ExtractedField,
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
    ) -> Option<&mut FieldPasses> {
        if self.refused {
            return None;
        }
        if !self.fields.contains_key(&field.entity) {
            if self.template.is_none() {
                match passes_on(adapter, device, self.splats) {
                    Ok(made) => self.template = Some(made),
                    Err(e) => {
                        error!("sward draws no grass: Bevy's passes draw grass of the {} technique through sward's portable passes, and this device cannot run them: {e}", field.technique().name());
                        self.refused = true;
                        return None;
                    }
                }
            }
            // The pipelines of the passes made first: a field spawned costs no compiling.
            let template = self.template.as_ref().expect("made above");
            self.fields
                .insert(field.entity, FieldPasses::new(template.sibling(device)));
        }
        self.fields.get_mut(&field.entity)
    }

    /// Keep this frame's measures, where the app asked for them: the passes began at `start`
    /// (the portable passes take no timestamps).
    fn measured(&self, extracted: &ExtractedGrass, start: Instant, submitting: std::time::Duration) {
        let Some(timings) = &self.timings else { return };
        timings.push(GrassFrameTimes {
            frame: extracted.frame,
            gpu: None,
            extract: extracted.took,
            draw: start.elapsed(),
            gpu_wait: submitting,
        });
    }
}

impl FieldPasses {
    fn new(renderer: PortableRenderer) -> FieldPasses {
        FieldPasses {
            renderer,
            field: None,
            scene: None,
            version: 0,
            grown: None,
            steps: 0,
            reported: None,
        }
    }

    /// Take the grass's scene where it changed since this last took it (or where the field
    /// went), as `frames::taking` says: paint the strokes added, or grow the field again and
    /// put it (where its blades are not the ones held: `frames::same_layout`), its ground mesh
    /// and its paint on the GPU; or say why the portable passes cannot draw it.
    fn prepare(&mut self, extracted: &ExtractedField, device: &wgpu::Device) -> Result<(), String> {
        if self.version == extracted.scene_version && self.field.is_some() {
            return Ok(());
        }
        let scene = &extracted.scene;
        self.version = extracted.scene_version;
        let old = self.scene.replace(scene.clone());
        let taken = match self.field {
            Some(_) => taking(old.as_ref(), scene),
            None => Taking::Regrow,
        };
        let renderer = &mut self.renderer;
        match (taken, self.grown.as_mut()) {
            (Taking::Nothing, _) => {}
            (Taking::Repaint(strokes), Some(grown)) => {
                scene.paint_strokes(&mut grown.paint, strokes);
                renderer.upload_paint(device, grown.paint.as_ref());
                if let Some(field) = self.field.as_mut() {
                    field.repaint_under(strokes, paint_texel(grown));
                }
            }
            (_, held) => {
                let grown = grow(scene)?;
                if held.is_none_or(|held| !same_layout(held, &grown)) || self.field.is_none() {
                    self.field = None;
                    let field = match grown.stream {
                        Some(window) => PortableField::streamed(device, window),
                        None => PortableField::with_tiles(device, &grown.blades, grown.tiles.clone()),
                    }
                    .map_err(|e| e.to_string())?;
                    renderer.upload_ground(device, grown.ground.as_ref());
                    self.field = Some(field);
                }
                // Where the blades are the same, they stay on the GPU with their poses and trails.
                renderer.upload_paint(device, grown.paint.as_ref());
                self.grown = Some(grown);
            }
        }
        Ok(())
    }

    /// This frame's description of the field seen as camera `k` of its cameras (the first's
    /// steps the field too) and the passes it runs, keeping the blades' last pose where a
    /// camera draws `motion` vectors; none where the field is not grown.
    fn view_of(
        &mut self,
        device: &wgpu::Device,
        (extracted, placed): (&ExtractedGrass, &ExtractedField),
        (view, viewport): (&ExtractedView, [u32; 2]),
        (k, motion): (usize, bool),
    ) -> Option<(sward_core::FrameDesc, PortablePasses)> {
        let (Some(scene), Some(grown), Some(field)) = (&self.scene, &self.grown, self.field.as_mut()) else {
            return None;
        };
        if motion {
            // The blades as they stood before this frame stepped them: the motion vectors' start.
            field.keep_previous(device);
        }
        let mut steps = self.steps;
        let mut frame = frame_of(scene, grown.size, (extracted, placed), (view, viewport), &mut steps);
        splat_beyond_shadows(&mut frame, placed);
        Some(match k {
            0 => {
                self.steps = steps;
                (frame, PortablePasses::ALL)
            }
            // A later view culls the pose the first stepped to (no steps of its own).
            _ => (sward_core::FrameDesc { steps: 0, ..frame }, PortablePasses::CULL),
        })
    }

    /// The buffers of `views` views' draws, where there is a field.
    fn buffers(&self, views: usize) -> Option<PortableBuffers> {
        let (field, renderer) = (self.field.as_ref()?, &self.renderer);
        let lists = (0..views)
            .map(|k| {
                let lists = field.lists(k)?;
                let frame = renderer.frame_uniforms(k)?;
                Some([frame, lists.visible(), lists.counters(), lists.draws()].map(Clone::clone))
            })
            .collect::<Option<Vec<_>>>()?;
        let far = (0..views).map(|k| self.far_buffers(k)).collect();
        Some(PortableBuffers {
            blades: field.blades().clone(),
            // Bound, and read only where a camera draws motion vectors.
            previous: field.previous_blades().unwrap_or(field.blades()).clone(),
            paint: renderer.paint_texels().clone(),
            trample: renderer.trample_texels().clone(),
            views: lists,
            far,
            splats: renderer.splat_cells(0).cloned(),
        })
    }

    /// View `k`'s far grass, where its last frame generated any.
    fn far_buffers(&self, k: usize) -> Option<FarBuffers> {
        let far = self.renderer.generated_draws(k)?;
        Some(FarBuffers {
            listed: far.listed.clone(),
            draws: far.draws.clone(),
            levels: far.instanced,
            billboards: far.billboards.map(|(view, sampler)| (view.clone(), sampler.clone())),
            starts: far.starts,
            billboard_command: far.billboard_command,
        })
    }

    /// Say `error` once (until a frame draws again).
    fn report(&mut self, error: String) {
        if self.reported.as_ref() != Some(&error) {
            error!("sward draws no grass this frame: {error}");
            self.reported = Some(error);
        }
    }
}
