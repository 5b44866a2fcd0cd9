//! What both of sward's routes in Bevy share: which cameras see a field and which list each of
//! Bevy's views draws, what a changed scene asks of the field held, and a frame's description
//! from Bevy's world.

use bevy::camera::visibility::RenderLayers;
use bevy::core_pipeline::prepass::MotionVectorPrepass;
use bevy::ecs::prelude::*;
use bevy::ecs::query::QueryItem;
use bevy::pbr::ViewLightEntities;
use bevy::platform::collections::HashMap;
use bevy::render::camera::ExtractedCamera;
use bevy::render::view::{ExtractedView, Msaa};
use sward_core::camera::DepthDirection;
use sward_core::frame::VIEWS_PER_FRAME;
use sward_core::placement::Placement;
use sward_core::{Field, FrameDesc, Scene};

use super::extract::{ExtractedField, ExtractedGrass};

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
    /// frame, so they take the strokes without a new field, trails and all), or the Bezier
    /// blades stream (the tiles under the strokes are made anew from the paint, the others
    /// keep their blades' poses and trails: `repaint_under`).
    Repaint(&'a [sward_core::paint::Stroke]),
    /// Grow the field again: something it is grown from changed (`Scene::grows_as`: the files
    /// the scene names are among its contents). Where the blades grown are the blades held
    /// ([`same_layout`]), only the paint is put on the GPU again.
    Regrow,
}

/// What a renderer holding `old`'s field does to draw `scene`.
pub(crate) fn taking<'a>(old: Option<&Scene>, scene: &'a Scene) -> Taking<'a> {
    let Some(old) = old else {
        return Taking::Regrow;
    };
    let blades_read_the_paint = scene.bezier_blades() == 0 || scene.stream_window().is_some();
    if let Some(strokes) = scene.strokes_added_to(old).filter(|_| blades_read_the_paint) {
        return Taking::Repaint(strokes);
    }
    match old.grows_as(scene) {
        true => Taking::Nothing,
        false => Taking::Regrow,
    }
}

/// The side of a texel of the paint `field` holds (none where it has no map: a stroke makes one).
pub(crate) fn paint_texel(field: &Field) -> f32 {
    let map = field.paint.as_ref().and_then(|p| p.map.as_ref());
    map.map_or(0.0, |m| 1.0 / m.texels_per_unit().min_element())
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

/// Where the grass casts into Bevy's shadow maps, its far field splatted only beyond the
/// grass's shadow distance: a splat casts no shadow, so splats nearer than it would lose the
/// shade the far grass casts there when drawn. Beyond it the grass casts nothing either way;
/// the splats receive Bevy's shadows wherever they lie (their resolve is lit by Bevy's PBR).
pub(crate) fn splat_beyond_shadows(frame: &mut FrameDesc, field: &ExtractedField) {
    if !field.shadows[0] {
        return;
    }
    // The distances are the field's own; the shadow distance is the world's.
    let reach = field.shadow_distance / field.placement[0].scale;
    frame.instanced.splat_distance = frame.instanced.splat_distance.max(reach);
    frame.billboard.splat_distance = frame.billboard.splat_distance.max(reach);
    frame.billboard.raster_distance = frame.billboard.raster_distance.max(reach);
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
    let projection = sward_portable::sward_projection(view.clip_from_view, DepthDirection::Reverse);
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
    fn strokes_repaint_the_generated_and_streamed_grass_and_grow_fixed_bezier_blades_again() {
        let mut generated = park();
        generated.technique = Technique::Instanced;
        let mut stroked = generated.clone();
        stroked.paint.strokes.push(Stroke::circle(glam::Vec2::ZERO, 2.0).burn());
        assert!(matches!(taking(Some(&generated), &stroked), Taking::Repaint([_])));
        assert!(matches!(taking(None, &stroked), Taking::Regrow), "nothing held");
        let mut windy = generated.clone();
        windy.wind.0[0].strength += 1.0;
        assert!(matches!(taking(Some(&generated), &windy), Taking::Nothing));
        // The park's near field is Bezier blades, streamed: strokes (a game's edits too) make
        // only the tiles under them anew; blades grown once (not streamed) grow again.
        let mut bezier = generated.clone();
        bezier.technique = Technique::Landscape;
        assert!(bezier.stream_window().is_some() && bezier.bezier_blades() > 0);
        let mut edited = bezier.clone();
        edited.edits.paint(Stroke::circle(glam::Vec2::ZERO, 2.0).mow(0.3));
        assert!(matches!(taking(Some(&bezier), &edited), Taking::Repaint([_])));
        let mut fixed = bezier.clone();
        fixed.field.stream = false;
        let mut fixed_edited = fixed.clone();
        fixed_edited.edits = edited.edits.clone();
        assert!(matches!(taking(Some(&fixed), &fixed_edited), Taking::Regrow));
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
