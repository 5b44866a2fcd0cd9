//! sward's Vulkan renderer on the device `render_plugin` opened, and the pass in Bevy's `Core3d`
//! schedule that draws the grass — after the opaque meshes, before the transparent ones — into
//! the camera's colour and depth (its schedule, view components and render context).

use std::sync::Arc;
use std::time::Instant;

use bevy::app::SubApp;
use bevy::camera::visibility::RenderLayers;
use bevy::core_pipeline::core_3d::{main_opaque_pass_3d, main_transparent_pass_3d};
use bevy::core_pipeline::schedule::Core3d;
use bevy::core_pipeline::Core3dSystems;
use bevy::ecs::prelude::*;
use bevy::light::AmbientLight;
use bevy::log::error;
use bevy::pbr::DistanceFog;
use bevy::render::camera::ExtractedCamera;
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::{RenderAdapter, RenderContext, RenderDevice, RenderQueue, ViewQuery};
use bevy::render::view::{ExtractedView, Msaa, ViewDepthStencilTexture, ViewTarget};
use bevy::render::{Render, RenderSystems};
use sward_core::quality::{DrawRoute, QualityPreset};
use sward_core::{Field, Scene};
use sward_gpu::{Context, ContextDesc, DepthDirection};
use sward_wgpu::{BridgeError, FrameTarget, GrassRenderer, SwardDevice, TargetDesc, VIEWS_PER_FRAME};

use super::cascades::Casting;
use super::extract::{ExtractedField, ExtractedGrass};
use super::frames::{
    cameras_seeing, frame_of, grow, lists_of, paint_texel, same_layout, taking, world_frame_of, ComputeView, Taking,
};
use super::phases::{GrassBindGroups, GrassPipeline};
use super::portable::GrassRoute;
use crate::lighting::{exposed, GrassLighting, ViewLight};
use crate::timings::{GrassFrameTimes, GrassTimings};

/// sward's context on Bevy's render device, in the main world and the render world: its
/// device's name and draw routes, and, in tests, the validation layer's messages.
#[derive(Resource, Clone)]
pub struct SwardContext(pub Arc<Context>);

/// The grass on the GPU: the field grown from the scene, and the renderer for the target it
/// last drew into.
#[derive(Resource)]
struct GrassState {
    renderer: Option<(GrassRenderer, QualityPreset)>,
    /// The grass entity whose field it holds.
    held: Option<Entity>,
    /// The scene the field was grown from, and the version of the grass it was taken at.
    scene: Option<Scene>,
    version: u64,
    field: Option<Field>,
    uploaded: bool,
    /// Whether the renderer lists the blades for Bevy's passes to draw.
    listing: bool,
    /// Fixed steps simulated since the app started.
    steps: u64,
    /// The last frame a view drew grass in, and how many of its views did.
    drawn_frame: u64,
    frame_views: usize,
    /// The last error reported (each is reported once).
    reported: Option<String>,
    /// Where sward's measures of itself go, where the app asked for them.
    timings: Option<GrassTimings>,
    sward: SwardDevice,
}

/// Take Bevy's render device back with sward's renderer on it where [`crate::render_plugin`]
/// opened it, and schedule the grass pass; else run the portable passes on Bevy's own device
/// (`portable.rs`), or say why there will be no grass. Returns the route, and sward's context
/// where it is the Vulkan renderer's.
pub(crate) fn finish(
    render_app: &mut SubApp,
    context: &ContextDesc,
    timings: Option<GrassTimings>,
) -> (GrassRoute, Option<SwardContext>) {
    let world = render_app.world();
    let adapter: &wgpu::Adapter = world.resource::<RenderAdapter>();
    let device = world.resource::<RenderDevice>().wgpu_device().clone();
    let queue: wgpu::Queue = (**world.resource::<RenderQueue>()).clone();
    let sward = match sward_wgpu::adopt(adapter, device, queue, context) {
        Ok(sward) => sward,
        // Not the device render_plugin() opens: Bevy's own.
        Err(_) => return (super::portable::finish(render_app, timings), None),
    };
    let shared = SwardContext(sward.context.clone());
    render_app.insert_resource(shared.clone());
    if let Some(timings) = &timings {
        render_app.insert_resource(timings.clone());
    }
    let portable_timings = timings.clone();
    render_app.insert_resource(GrassState {
        renderer: None,
        held: None,
        scene: None,
        version: 0,
        field: None,
        uploaded: false,
        listing: false,
        steps: 0,
        drawn_frame: 0,
        frame_views: 0,
        reported: None,
        timings,
        sward,
    });
    render_app.add_systems(Render, compute_grass.in_set(RenderSystems::PrepareBindGroups));
    // Where Bevy's passes draw more than the Bezier blades, the portable passes list the grass
    // on this device (made when first needed).
    super::portable::build(render_app, None, portable_timings);
    render_app.add_systems(
        Core3d,
        draw_grass
            .in_set(Core3dSystems::MainPass)
            .after(main_opaque_pass_3d)
            .before(main_transparent_pass_3d),
    );
    (GrassRoute::Vulkan, Some(shared))
}

/// A view as the grass pass reads it: Bevy's view and targets, and what lights it.
type GrassView<'a> = (
    &'a ExtractedView,
    &'a ViewTarget,
    &'a ViewDepthStencilTexture,
    &'a Msaa,
    Option<&'a ExtractedCamera>,
    Option<&'a AmbientLight>,
    Option<&'a DistanceFog>,
    Option<&'a RenderLayers>,
);

/// The grass of this frame into the view's colour and depth: the first view of a frame that
/// sees the grass (visible, on a render layer of the camera's) simulates, culls and draws;
/// each later view of the same frame culls and draws it for its own camera (up to
/// `VIEWS_PER_FRAME` views; more draw nothing).
fn draw_grass(
    view: ViewQuery<GrassView<'static>>,
    extracted: Res<ExtractedGrass>,
    mut state: ResMut<GrassState>,
    mut ctx: RenderContext,
    mut told_of_viewports: Local<bool>,
) {
    let index = match extracted.frame == state.drawn_frame {
        true => state.frame_views,
        false => 0,
    };
    let Some(field) = vulkan_field(&extracted).filter(|f| f.lighting != GrassLighting::Pbr) else {
        return;
    };
    if index >= VIEWS_PER_FRAME {
        return;
    }
    let start = Instant::now();
    let (view, target, depth, msaa, camera, ambient, fog, layers) = view.into_inner();
    // A camera sees the grass where their render layers meet (both default to layer 0).
    if !field.seen_on(layers) {
        return;
    }
    // sward's own pass draws into the whole target (said once: the other cameras draw on).
    if camera.is_some_and(|c| c.viewport.is_some()) {
        if !std::mem::replace(&mut *told_of_viewports, true) {
            error!("sward's own pass draws no grass in a camera with a viewport (a split screen): it draws into a camera's whole target; give the grass GrassLighting::Pbr, which Bevy draws in each camera's viewport");
        }
        return;
    }
    // Bevy's exposure (its default where the camera has none).
    let exposure = camera.map_or(bevy::camera::Exposure::default().exposure(), |c| c.exposure);
    let light = ViewLight::of(extracted.sun, extracted.ambient.as_ref(), ambient, exposure, fog);
    let drawn = state.draw((&extracted, field), (view, target, depth, msaa), light, index);
    match drawn {
        Ok(buffers) => {
            state.drawn_frame = extracted.frame;
            state.frame_views = index + 1;
            state.reported = None;
            for buffer in buffers {
                ctx.add_command_buffer(buffer);
            }
            if index == 0 {
                state.measured(&extracted, start);
            }
        }
        Err(e) => state.report(e.to_string()),
    }
}

/// Where Bevy draws the grass in its own passes ([`GrassLighting::Pbr`]): sward's compute
/// passes for each 3D camera that sees the grass (the first steps it; each culls and lists it
/// for itself, up to `VIEWS_PER_FRAME`; cameras past those draw the first's list), submitted
/// before Bevy renders the frame, and sward's buffers bound for the draws.
#[allow(clippy::too_many_arguments)]
fn compute_grass(
    extracted: Res<ExtractedGrass>,
    mut state: ResMut<GrassState>,
    views: Query<ComputeView<'static>>,
    queue: Res<RenderQueue>,
    device: Res<RenderDevice>,
    cache: Res<PipelineCache>,
    pipeline: Option<Res<GrassPipeline>>,
    mut groups: ResMut<GrassBindGroups>,
) {
    let Some(field) = vulkan_field(&extracted) else {
        // The portable passes list every field (portable.rs): the Vulkan renderer's goes.
        state.renderer = None;
        return;
    };
    let shown = field.visible && field.lighting == GrassLighting::Pbr;
    let cameras = cameras_seeing(&views, &field.layers);
    let (Some(pipeline), false, true) = (pipeline, cameras.is_empty(), shown) else {
        groups.forget(field.entity);
        return;
    };
    let start = Instant::now();
    let motion = cameras.iter().any(|&(.., draws_motion_vectors)| draws_motion_vectors);
    let mut computed = Vec::new();
    for (k, &(_, view, camera, msaa, ..)) in cameras.iter().enumerate() {
        match state.compute((&extracted, field), (view, camera, msaa), (k, cameras.len(), motion)) {
            Ok(buffer) => computed.push(buffer),
            Err(e) => {
                groups.forget(field.entity);
                state.report(e.to_string());
                return;
            }
        }
    }
    let list_of = lists_of(&cameras);
    queue.submit(computed);
    let (renderer, _) = state.renderer.as_mut().expect("made by compute");
    match renderer.drawn_blades() {
        Ok(Some(drawn)) => {
            let groups = groups.field_mut(field.entity);
            groups.bind(drawn, list_of, (&device, &cache, &pipeline));
            groups.cast_as(Casting::of(field));
            state.drawn_frame = extracted.frame;
            state.reported = None;
            state.measured(&extracted, start);
        }
        Ok(None) => groups.forget(field.entity),
        Err(e) => {
            groups.forget(field.entity);
            state.report(e.to_string());
        }
    }
}

impl GrassState {
    /// This frame's compute passes for Bevy's passes to draw the blades of, for its view
    /// `index` of `views`: simulated (view 0), culled for `view` and listed (the strip route's
    /// buckets); the blades last drawn kept where a view draws `motion` vectors.
    fn compute(
        &mut self,
        (extracted, placed): (&ExtractedGrass, &ExtractedField),
        (view, camera, msaa): (&ExtractedView, &ExtractedCamera, &Msaa),
        (index, views, motion): (usize, usize, bool),
    ) -> Result<wgpu::CommandBuffer, BridgeError> {
        self.take_scene(placed)?;
        let (Some(scene), Some(field)) = (&self.scene, &self.field) else {
            return Err(BridgeError::Target("the grass has no field yet".into()));
        };
        // Grass of another technique never comes here: the portable passes list it.
        let (scene, size) = (scene.clone(), field.size);
        // One renderer lists for every camera: the first's target makes it (only its compute
        // passes run, which draw into no target).
        if index == 0 || self.renderer.is_none() {
            let desc = TargetDesc {
                samples: msaa.samples(),
                depth_direction: DepthDirection::Reverse,
                ..TargetDesc::new(view.target_format, bevy::core_pipeline::core_3d::CORE_3D_DEPTH_FORMAT)
            };
            self.renderer_for(&desc, scene.quality.preset)?;
        }
        let (renderer, _) = self.renderer.as_mut().expect("made above");
        if !self.listing {
            renderer.set_drawn_blades(true)?;
            self.listing = true;
        }
        if index == 0 {
            renderer.reserve_views(views)?;
        }
        renderer.set_previous_blades(motion);
        let viewport = camera
            .physical_viewport_size
            .map_or([1, 1], |s| [s.x.max(1), s.y.max(1)]);
        let mut frame = frame_of(&scene, size, (extracted, placed), (view, viewport), &mut self.steps);
        frame.route = DrawRoute::Strips;
        let (renderer, _) = self.renderer.as_mut().expect("made above");
        renderer.encode_compute(&frame, index)
    }

    /// The command buffers of this frame's grass in the view, its `index`th of the frame.
    fn draw(
        &mut self,
        (extracted, placed): (&ExtractedGrass, &ExtractedField),
        (view, target, depth, msaa): (&ExtractedView, &ViewTarget, &ViewDepthStencilTexture, &Msaa),
        light: ViewLight,
        index: usize,
    ) -> Result<[wgpu::CommandBuffer; 2], BridgeError> {
        self.take_scene(placed)?;
        let (Some(scene), Some(field)) = (&self.scene, &self.field) else {
            return Err(BridgeError::Target("the grass has no field yet".into()));
        };
        let (scene, size) = (scene.clone(), field.size);
        let desc = TargetDesc {
            samples: msaa.samples(),
            depth_direction: DepthDirection::Reverse,
            ..TargetDesc::new(target.main_texture_format(), depth.texture().format())
        };
        match &self.renderer {
            // The first view's renderer holds the grass it stepped: a later view must fit it.
            Some((renderer, _)) if index > 0 && renderer.target() != &desc => {
                return Err(BridgeError::Target(format!(
                    "the cameras that see the grass drawn by sward's own pass share the first camera's colour format and samples ({:?}, {}), and camera {index} of the frame has {:?}, {}: give it the same Msaa and Hdr, or use GrassLighting::Pbr",
                    renderer.target().color,
                    renderer.target().samples,
                    desc.color,
                    desc.samples
                )));
            }
            _ => self.renderer_for(&desc, scene.quality.preset)?,
        }
        let texture = target.main_texture().size();
        let viewport = [texture.width, texture.height];
        let mut frame = world_frame_of(
            &scene,
            size,
            extracted,
            placed.placement[0],
            (view, viewport),
            &mut self.steps,
        );
        if placed.lighting == GrassLighting::Bevy {
            light.light(&mut frame.shading);
            frame.lamps = exposed(&extracted.lamps, light.exposure);
        }
        let [now, last] = placed.placement;
        let frame = frame.placed(now, last);
        let main = target.main_texture_view();
        let mut into = FrameTarget::new(
            target.sampled_main_texture_view().unwrap_or(main),
            depth.attachment.depth_stencil_views().attachment_view(),
        );
        if target.sampled_main_texture_view().is_some() {
            // Bevy resolves at the end of its passes that draw; the grass may be the last.
            into = into.resolving_into(main);
        }
        let (renderer, _) = self.renderer.as_mut().expect("made above");
        renderer.encode_view(&frame, &into, index)
    }

    /// Take the grass's scene where it changed since this last took it ([`taking`]): paint the
    /// strokes added, or grow the field again, keeping the blades on the GPU where they are
    /// the same ([`same_layout`]).
    fn take_scene(&mut self, extracted: &ExtractedField) -> Result<(), BridgeError> {
        if self.held != Some(extracted.entity) {
            // Another grass entity's field: grown anew.
            self.held = Some(extracted.entity);
            (self.scene, self.field, self.version, self.uploaded) = (None, None, 0, false);
        }
        if self.version == extracted.scene_version {
            return Ok(());
        }
        let scene = &extracted.scene;
        self.version = extracted.scene_version;
        let old = self.scene.replace(scene.clone());
        let mut repainted: &[sward_core::paint::Stroke] = &[];
        match (taking(old.as_ref(), scene), self.field.as_mut()) {
            (Taking::Nothing, _) => return Ok(()),
            (Taking::Repaint(strokes), Some(field)) => {
                scene.paint_strokes(&mut field.paint, strokes);
                repainted = strokes;
            }
            (_, held) => {
                let grown = grow(scene).map_err(BridgeError::Target)?;
                let kept = held.is_some_and(|held| same_layout(held, &grown));
                self.field = Some(grown);
                if !kept {
                    self.uploaded = false;
                    return Ok(());
                }
            }
        }
        // The blades on the GPU stay, their poses and trails with them: only the paint is new
        // (put on the GPU from the field that holds it, not copied: a map can be 64 MiB).
        let field = self.field.as_ref().expect("held or grown above");
        if let Some((renderer, _)) = self.renderer.as_mut().filter(|_| self.uploaded) {
            renderer.wait_idle();
            renderer.renderer_mut().upload_paint(field.paint.as_ref())?;
            renderer.renderer_mut().repaint_under(repainted, paint_texel(field));
        }
        Ok(())
    }

    /// A renderer for `target` at `quality`, holding the field.
    fn renderer_for(&mut self, target: &TargetDesc, quality: QualityPreset) -> Result<(), BridgeError> {
        let fits = matches!(&self.renderer, Some((r, q)) if r.target() == target && *q == quality);
        if !fits {
            // The old one first: its buffers go before the new one's are made.
            self.renderer = None;
            let mut renderer = GrassRenderer::new(&self.sward, target, quality)?;
            renderer.set_timing(self.timings.is_some());
            self.renderer = Some((renderer, quality));
            self.uploaded = false;
            self.listing = false;
        }
        if !self.uploaded {
            let (renderer, _) = self.renderer.as_mut().expect("made above");
            renderer.upload(self.field.as_ref().expect("grown with the scene"))?;
            self.uploaded = true;
        }
        Ok(())
    }

    /// Keep this frame's measures, where the app asked for them: the grass pass began at `start`.
    fn measured(&self, extracted: &ExtractedGrass, start: Instant) {
        let Some(timings) = &self.timings else { return };
        let renderer = self.renderer.as_ref().map(|(r, _)| r);
        timings.push(GrassFrameTimes {
            frame: extracted.frame,
            gpu: renderer.and_then(|r| r.pass_times().copied()),
            extract: extracted.took,
            draw: start.elapsed(),
            gpu_wait: renderer.map_or(std::time::Duration::ZERO, |r| r.gpu_wait()),
        });
    }

    /// Say `error` once (until a frame draws again).
    fn report(&mut self, error: String) {
        if self.reported.as_ref() != Some(&error) {
            error!("sward draws no grass this frame: {error}");
            self.reported = Some(error);
        }
    }
}

/// The field sward's Vulkan renderer holds: the first the portable passes do not list.
fn vulkan_field(extracted: &ExtractedGrass) -> Option<&ExtractedField> {
    extracted.fields.iter().find(|f| !f.portable)
}
