//! sward's Vulkan renderer on the device `render_plugin` opened, and the pass in Bevy's `Core3d`
//! schedule that draws the grass — after the opaque meshes, before the transparent ones — into
//! the camera's colour and depth (its schedule, view components and render context).

use std::sync::Arc;
use std::time::Instant;

use bevy::app::SubApp;
use bevy::camera::visibility::RenderLayers;
use bevy::core_pipeline::core_3d::{main_opaque_pass_3d, main_transparent_pass_3d};
use bevy::core_pipeline::prepass::MotionVectorPrepass;
use bevy::core_pipeline::schedule::Core3d;
use bevy::core_pipeline::Core3dSystems;
use bevy::ecs::prelude::*;
use bevy::ecs::query::QueryItem;
use bevy::light::AmbientLight;
use bevy::log::error;
use bevy::pbr::{DistanceFog, ViewLightEntities};
use bevy::platform::collections::HashMap;
use bevy::render::camera::ExtractedCamera;
use bevy::render::render_resource::PipelineCache;
use bevy::render::renderer::{RenderAdapter, RenderContext, RenderDevice, RenderQueue, ViewQuery};
use bevy::render::view::{ExtractedView, Msaa, ViewDepthStencilTexture, ViewTarget};
use bevy::render::{Render, RenderSystems};
use sward_core::placement::Placement;
use sward_core::quality::{DrawRoute, QualityPreset};
use sward_core::{Field, FrameDesc, Scene};
use sward_gpu::{Context, ContextDesc, DepthDirection};
use sward_wgpu::{BridgeError, FrameTarget, GrassRenderer, SwardDevice, TargetDesc, VIEWS_PER_FRAME};

use super::extract::{ExtractedField, ExtractedGrass};
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
    /// How many times the files the scene names had been read again when it was taken.
    files: u32,
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
        files: 0,
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

/// A camera as the grass's compute passes read it where Bevy draws the blades: its view, its
/// shadow cascades' views, and whether it draws motion vectors.
pub(crate) type ComputeView<'a> = (
    Entity,
    &'a ExtractedView,
    &'a ExtractedCamera,
    &'a Msaa,
    Option<&'a RenderLayers>,
    Option<&'a ViewLightEntities>,
    Has<MotionVectorPrepass>,
);

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
            groups
                .field_mut(field.entity)
                .bind(drawn, list_of, (&device, &cache, &pipeline));
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
        let mut into = FrameTarget::new(target.sampled_main_texture_view().unwrap_or(main), depth.attachment.depth_stencil_views().attachment_view());
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
        let files_read_again = std::mem::replace(&mut self.files, extracted.files) != extracted.files;
        let old = self.scene.replace(scene.clone());
        match (taking(old.as_ref(), scene, files_read_again), self.field.as_mut()) {
            (Taking::Nothing, _) => return Ok(()),
            (Taking::Repaint(strokes), Some(field)) => scene.paint_strokes(&mut field.paint, strokes),
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
        let paint = self.field.as_ref().and_then(|f| f.paint.as_ref());
        if let Some((renderer, _)) = self.renderer.as_mut().filter(|_| self.uploaded) {
            renderer.wait_idle();
            renderer.renderer_mut().upload_paint(paint)?;
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

/// The 3D cameras that see the grass this frame (drawing into a target, on a render layer the
/// grass is on), in their order, the first `VIEWS_PER_FRAME` of them.
pub(crate) fn cameras_seeing<'a>(
    views: &'a Query<ComputeView<'static>>,
    grass_layers: &RenderLayers,
) -> Vec<QueryItem<'a, 'a, ComputeView<'static>>> {
    let mut cameras: Vec<_> = views
        .iter()
        .filter(|(_, _, camera, _, layers, ..)| {
            camera.target.is_some() && layers.cloned().unwrap_or_default().intersects(grass_layers)
        })
        .collect();
    cameras.sort_by_key(|(_, _, camera, ..)| camera.order);
    cameras.truncate(VIEWS_PER_FRAME);
    cameras
}

/// Which list each of Bevy's views draws: camera `k` of `cameras` its own, its shadow
/// cascades its list too (a point or spot light's views, shared by every camera, the first's).
pub(crate) fn lists_of(cameras: &[QueryItem<'_, '_, ComputeView<'static>>]) -> HashMap<Entity, usize> {
    let mut list_of = HashMap::default();
    for (k, &(entity, .., lights, _)) in cameras.iter().enumerate() {
        list_of.insert(entity, k);
        for &light in lights.map_or(&[][..], |l| &l.lights) {
            list_of.entry(light).or_insert(k);
        }
    }
    list_of
}

/// What a renderer holding the field of scene `old` does to draw `scene`.
pub(crate) enum Taking<'a> {
    /// Nothing: the field is the same.
    Nothing,
    /// Paint these strokes into the paint it holds: they are all that changed of the field,
    /// and no Bezier blade is drawn (the generated grass and the billboards read the paint each
    /// frame, so they take the strokes without a new field, trails and all).
    Repaint(&'a [sward_core::paint::Stroke]),
    /// Grow the field again: something it is grown from changed (`Scene::grows_as`), or the
    /// files the scene names were read again. Where the blades grown are the blades held
    /// ([`same_layout`]), only the paint is put on the GPU again.
    Regrow,
}

/// What a renderer holding `old`'s field does to draw `scene` (`files_read_again`: the files it
/// names were loaded again).
pub(crate) fn taking<'a>(old: Option<&Scene>, scene: &'a Scene, files_read_again: bool) -> Taking<'a> {
    let Some(old) = old.filter(|_| !files_read_again) else {
        return Taking::Regrow;
    };
    if let Some(strokes) = scene.strokes_added_to(old).filter(|_| scene.bezier_blades() == 0) {
        return Taking::Repaint(strokes);
    }
    match old.grows_as(scene) {
        true => Taking::Nothing,
        false => Taking::Regrow,
    }
}

/// Whether field `new` has the blades of field `held` where they are: the same blades, tiles
/// and ground, not streamed (a streamed window's tiles are made on the GPU from the paint).
/// A change of the paint's tint or of a kind's colours grows such a field: its blades, their
/// poses and trails stay on the GPU.
pub(crate) fn same_layout(held: &Field, new: &Field) -> bool {
    let fixed = held.stream.is_none() && new.stream.is_none();
    fixed && held.blades == new.blades && held.tiles == new.tiles && held.ground == new.ground && held.size == new.size
}

/// The field `scene` grows, or why not in one sentence.
pub(crate) fn grow(scene: &Scene) -> Result<Field, String> {
    scene
        .grow_field()
        .map_err(|e| format!("the grass's field could not be grown: {e}"))
}

/// The field sward's Vulkan renderer holds: the first the portable passes do not list.
fn vulkan_field(extracted: &ExtractedGrass) -> Option<&ExtractedField> {
    extracted.fields.iter().find(|f| !f.portable)
}

/// This frame's description of a field placed as `placed` says ([`world_frame_of`], carried
/// into the field's space: `FrameDesc::placed`).
pub(crate) fn frame_of(
    scene: &Scene,
    field_size: glam::Vec2,
    (extracted, placed): (&ExtractedGrass, &ExtractedField),
    at: (&ExtractedView, [u32; 2]),
    steps: &mut u64,
) -> FrameDesc {
    let [now, last] = placed.placement;
    world_frame_of(scene, field_size, extracted, now, at, steps).placed(now, last)
}

/// This frame's description in Bevy's world: the scene's settings, Bevy's camera (`view`,
/// drawn at `viewport` pixels), the fixed steps due since the last frame (`steps`: those
/// simulated so far), and the colliders — the scene's own where `placement` puts its field,
/// and the app's.
pub(crate) fn world_frame_of(
    scene: &Scene,
    field_size: glam::Vec2,
    extracted: &ExtractedGrass,
    placement: Placement,
    (view, viewport): (&ExtractedView, [u32; 2]),
    steps: &mut u64,
) -> FrameDesc {
    let step = scene.simulation.step as f64;
    let due = (extracted.elapsed / step) as u64;
    // A long stall is not caught up: at most the scene's sub-steps per frame, the last ones
    // before now (the grass's clock skips the rest).
    let now = due
        .saturating_sub(*steps)
        .min(scene.simulation.max_substeps.max(1) as u64);
    let time = ((due - now) as f64 * step) as f32;
    *steps = (*steps).max(due);
    let world_from_view = view.world_from_view.to_matrix();
    let projection = sward_wgpu::sward_projection(view.clip_from_view, DepthDirection::Reverse);
    let mut frame = FrameDesc::of_scene(scene, field_size, (time, now as u32), viewport)
        .with_view_projection(world_from_view.inverse(), projection);
    frame.colliders = placement.colliders_to_world(&frame.colliders);
    frame.colliders.extend_from(&extracted.colliders);
    frame
}

#[cfg(test)]
mod tests {
    use super::*;
    use sward_core::instanced::Technique;
    use sward_core::paint::Stroke;

    fn park() -> Scene {
        Scene::from_toml(include_str!("../../../../scenes/park.toml"), "park.toml").unwrap()
    }

    #[test]
    fn strokes_repaint_the_generated_grass_and_grow_the_bezier_blades_again() {
        let mut generated = park();
        generated.technique = Technique::Instanced;
        let mut stroked = generated.clone();
        stroked.paint.strokes.push(Stroke::circle(glam::Vec2::ZERO, 2.0).burn());
        assert!(matches!(
            taking(Some(&generated), &stroked, false),
            Taking::Repaint([_])
        ));
        assert!(
            matches!(taking(Some(&generated), &stroked, true), Taking::Regrow),
            "files read again"
        );
        assert!(matches!(taking(None, &stroked, false), Taking::Regrow), "nothing held");
        let mut windy = generated.clone();
        windy.wind.0[0].strength += 1.0;
        assert!(matches!(taking(Some(&generated), &windy, false), Taking::Nothing));
        // The park's near field is Bezier blades (streamed): strokes grow it again.
        let mut bezier = stroked.clone();
        bezier.technique = Technique::Landscape;
        let mut unstroked = bezier.clone();
        unstroked.paint.strokes.pop();
        assert!(matches!(taking(Some(&unstroked), &bezier, false), Taking::Regrow));
    }

    #[test]
    fn a_field_whose_blades_did_not_change_keeps_its_blades_on_the_gpu() {
        // Unpainted: the tint is its first paint.
        let mut meadow = Scene::default();
        meadow.field.blades = 2000;
        let field = meadow.grow_field().unwrap();
        // A tint over the ground grows the field again: the same blades.
        let mut tinted = meadow.clone();
        tinted.paint.tint_noise = Some(Default::default());
        assert!(!tinted.grows_as(&meadow));
        assert!(same_layout(&field, &tinted.grow_field().unwrap()));
        // Fewer blades, or a streamed window: other blades.
        let mut fewer = meadow.clone();
        fewer.field.blades -= 1;
        assert!(!same_layout(&field, &fewer.grow_field().unwrap()));
        let park = park().grow_field().unwrap();
        assert!(
            !same_layout(&park, &park.clone()),
            "a streamed window's tiles are made from the paint"
        );
    }
}
