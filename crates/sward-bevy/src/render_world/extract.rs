//! From Bevy's main world to its render world, each frame: the grass's scene where it changed,
//! where every collider's spheres are now, and the clock.

use std::time::Duration;

use bevy::app::SubApp;
use bevy::camera::visibility::{InheritedVisibility, RenderLayers, ViewVisibility};
use bevy::ecs::prelude::*;
use bevy::ecs::query::QueryItem;
use bevy::ecs::system::SystemParam;
use bevy::light::{DirectionalLight, GlobalAmbientLight, NotShadowCaster, NotShadowReceiver, PointLight, SpotLight};
use bevy::platform::collections::HashSet;
use bevy::platform::time::Instant;
use bevy::render::{Extract, ExtractSchedule};
use bevy::time::Time;
use bevy::transform::components::GlobalTransform;
use sward_core::frame::{FrameColliders, Sphere};
use sward_core::instanced::Technique;
use sward_core::look::Lamp;
use sward_core::placement::Placement;
use sward_core::Scene;

use super::portable::GrassRoute;
use crate::budget::GrassShare;
use crate::components::{Grass, GrassCollider};
use crate::lighting::{brightest_sun, point_lamp, spot_lamp, GrassLighting, Sun};
use crate::occluders::GrassOccluder;
use crate::quality::GrassQuality;

/// The main world's grass as the render world sees it this frame: each field, and what they
/// share — the lights, the colliders and the clock.
#[derive(Resource, Default)]
pub(crate) struct ExtractedGrass {
    /// Every [`Grass`] entity, in the order they were first seen.
    pub fields: Vec<ExtractedField>,
    /// Bevy's sun this frame (the brightest directional light), where there is one.
    pub sun: Option<Sun>,
    /// Bevy's ambient light for cameras without their own.
    pub ambient: Option<GlobalAmbientLight>,
    /// Bevy's visible point and spot lights, before exposure.
    pub lamps: Vec<Lamp>,
    /// The colliders' spheres and the visible occluders', in the world, where they are now.
    pub colliders: FrameColliders,
    /// Seconds since the app started (Bevy's virtual clock: pausing it pauses the grass).
    pub elapsed: f64,
    /// Which frame this is (a view of a frame already drawn skips the simulation).
    pub frame: u64,
    /// Host time this extract took.
    pub took: Duration,
}

/// One [`Grass`] entity as the render world sees it this frame.
pub(crate) struct ExtractedField {
    /// The main world's grass entity (the phase items Bevy draws it by stand for it).
    pub entity: Entity,
    /// Whether it is visible (its `Visibility` and its parents'): hidden grass is neither drawn
    /// nor simulated.
    pub visible: bool,
    /// The render layers it is on: a camera sees it where their layers meet.
    pub layers: RenderLayers,
    /// Where Bevy draws it: whether it casts into Bevy's shadow maps (no `NotShadowCaster`)
    /// and whether Bevy's shadows fall on it (no `NotShadowReceiver`).
    pub shadows: [bool; 2],
    /// Its scene as last changed (cloned only when the grass changes), with its share of the
    /// [`GrassBudget`] (`[field] blades`), and how many times either has changed: a render
    /// system that last took an older version takes this one, even where it skipped the frames
    /// between (grass hidden, or no camera, when it appeared).
    pub scene: Scene,
    pub scene_version: u64,
    /// How far from the camera its far grass casts shadows (world units; never negative).
    pub shadow_distance: f32,
    /// What lights it.
    pub lighting: GrassLighting,
    /// Whether sward's portable passes list it for Bevy's passes this frame: always on the
    /// device Bevy opened; on sward's Vulkan device where Bevy's passes draw grass of another
    /// technique than the Bezier blades alone (the Vulkan renderer lists those only for its own
    /// pass).
    pub portable: bool,
    /// Where its `GlobalTransform` puts it this frame and the last.
    pub placement: [Placement; 2],
    /// Whether its far field is splatted a cell a pixel under MSAA (the [`GrassQuality`] tier).
    pub pixel_cells: bool,
    /// Whether it was seen this frame (the entries of despawned grass go).
    seen: bool,
}

impl ExtractedField {
    /// Its scene's technique (which parts of the grass Bevy's passes draw).
    pub fn technique(&self) -> Technique {
        self.scene.technique
    }

    /// Whether a camera on `layers` sees it: it is visible and their layers meet.
    pub fn seen_on(&self, layers: Option<&RenderLayers>) -> bool {
        self.visible && layers.cloned().unwrap_or_default().intersects(&self.layers)
    }
}

impl ExtractedGrass {
    /// The field of grass entity `entity`, where it is extracted.
    pub fn field(&self, entity: Entity) -> Option<&ExtractedField> {
        self.fields.iter().find(|f| f.entity == entity)
    }
}

pub(crate) fn build(render_app: &mut SubApp) {
    render_app
        .init_resource::<ExtractedGrass>()
        .add_systems(ExtractSchedule, extract_grass);
}

/// Bevy's lights in the main world.
#[derive(SystemParam)]
struct Lights<'w, 's> {
    suns: Extract<
        'w,
        's,
        Query<
            'static,
            'static,
            (
                &'static DirectionalLight,
                &'static GlobalTransform,
                Option<&'static ViewVisibility>,
            ),
        >,
    >,
    ambient: Extract<'w, 's, Option<Res<'static, GlobalAmbientLight>>>,
    points: Extract<
        'w,
        's,
        Query<
            'static,
            'static,
            (
                &'static PointLight,
                &'static GlobalTransform,
                Option<&'static ViewVisibility>,
            ),
        >,
    >,
    spots: Extract<
        'w,
        's,
        Query<
            'static,
            'static,
            (
                &'static SpotLight,
                &'static GlobalTransform,
                Option<&'static ViewVisibility>,
            ),
        >,
    >,
}

/// A grass entity as extracted: the grass, whether it is visible, its render layers, its
/// shadows, and where it stands.
type GrassEntity = (
    Entity,
    Ref<'static, Grass>,
    Option<&'static InheritedVisibility>,
    Option<&'static RenderLayers>,
    (Has<NotShadowCaster>, Has<NotShadowReceiver>),
    Option<&'static GlobalTransform>,
    Option<&'static GrassShare>,
);

/// The route the grass takes, and what the log was told: how the grass is drawn, that its
/// shadow distance is none, and the sentences on changes Bevy overrides.
type Told<'w, 's> = (
    Option<Res<'w, GrassRoute>>,
    Local<'s, bool>,
    Local<'s, bool>,
    Local<'s, HashSet<String>>,
    (Local<'s, bool>, Local<'s, bool>),
);

fn extract_grass(
    mut extracted: ResMut<ExtractedGrass>,
    grass: Extract<Query<GrassEntity>>,
    colliders: Extract<Query<(&GrassCollider, &GlobalTransform)>>,
    occluders: Extract<Query<(&GrassOccluder, &GlobalTransform, Option<&InheritedVisibility>)>>,
    // The clock, and the quality tier the grass is drawn at.
    (time, quality): (Extract<Res<Time>>, Extract<Option<Res<GrassQuality>>>),
    lights: Lights,
    // The route the grass takes, whether the log was told how it is drawn and of a shadow
    // distance that is none, the changes Bevy overrides that it was told of, of fields sward's
    // own pass leaves, and of a scale uneven along the axes (each once).
    (
        route,
        mut told_of_lighting,
        mut told_of_casting,
        mut told_of_overrides,
        (mut told_of_own_pass, mut told_of_scale),
    ): Told<'_, '_>,
) {
    let Lights {
        suns,
        ambient,
        points,
        spots,
    } = lights;
    let start = Instant::now();
    let on_bevy_s_device = route.is_some_and(|r| matches!(*r, GrassRoute::Portable(_)));
    let tier = quality.as_deref().copied().unwrap_or_default();
    let tier = (tier, quality.as_ref().is_some_and(|q| q.is_changed()));
    let mut told = Telling {
        lighting: &mut told_of_lighting,
        scale: &mut told_of_scale,
        casting: &mut told_of_casting,
        overrides: &mut told_of_overrides,
    };
    extracted.fields.iter_mut().for_each(|f| f.seen = false);
    for entity in &grass {
        let field = match extracted.fields.iter().position(|f| f.entity == entity.0) {
            Some(k) => &mut extracted.fields[k],
            None => {
                let new = new_field(&entity, tier.0);
                extracted.fields.push(new);
                extracted.fields.last_mut().expect("pushed")
            }
        };
        take_field(field, entity, (on_bevy_s_device, tier), &mut told);
    }
    extracted.fields.retain(|f| f.seen);
    if !on_bevy_s_device {
        one_field_for_sward_s_renderer(&mut extracted.fields, &mut told_of_own_pass);
    }
    let shining = suns.iter().filter(|(_, _, seen)| seen.is_none_or(|v| v.get()));
    extracted.sun = brightest_sun(shining.map(|(light, transform, _)| (light, transform)));
    extracted.ambient = ambient.as_deref().cloned();
    let seen = |v: Option<&ViewVisibility>| v.is_none_or(|v| v.get());
    extracted.lamps.clear();
    let points = points
        .iter()
        .filter(|(_, _, v)| seen(*v))
        .map(|(l, t, _)| point_lamp(l, t));
    let spots = spots
        .iter()
        .filter(|(_, _, v)| seen(*v))
        .map(|(l, t, _)| spot_lamp(l, t));
    extracted.lamps.extend(points.chain(spots));
    extracted.colliders = FrameColliders::default();
    for (collider, transform) in &colliders {
        let into = match collider.cuts {
            true => &mut extracted.colliders.cutting,
            false => &mut extracted.colliders.pushing,
        };
        into.extend(placed(&collider.spheres, transform));
    }
    for (occluder, transform, visible) in &occluders {
        if visible.is_none_or(|v| v.get()) {
            let hiding = placed(&occluder.spheres, transform);
            extracted.colliders.hiding.extend(hiding);
        }
    }
    extracted.elapsed = time.elapsed_secs_f64();
    extracted.frame += 1;
    extracted.took = start.elapsed();
}

/// On sward's Vulkan device, its renderer holds one field: the first it would list. Any other
/// drawn in Bevy's passes is listed by the portable passes instead; any other drawn by sward's
/// own pass is not drawn, said once.
fn one_field_for_sward_s_renderer(fields: &mut [ExtractedField], told: &mut bool) {
    let mut held = false;
    let mut left = 0;
    for field in fields.iter_mut().filter(|f| !f.portable) {
        match (held, field.lighting) {
            (false, _) => held = true,
            (true, GrassLighting::Pbr) => field.portable = true,
            (true, _) => {
                field.visible = false;
                left += 1;
            }
        }
    }
    if left > 0 && !std::mem::replace(told, true) {
        bevy::log::warn!(
            "sward's own pass (GrassLighting::Bevy or Scene) draws one field, the first: {left} more are not drawn; give them GrassLighting::Pbr, which Bevy's passes draw any number of"
        );
    }
}

/// What the log was told once: how the grass is drawn, that a shadow distance is none, and
/// the sentences on changes Bevy overrides.
struct Telling<'a> {
    lighting: &'a mut bool,
    scale: &'a mut bool,
    casting: &'a mut bool,
    overrides: &'a mut HashSet<String>,
}

/// A grass entity's field as first seen.
fn new_field(entity: &QueryItem<'_, '_, GrassEntity>, tier: GrassQuality) -> ExtractedField {
    ExtractedField {
        entity: entity.0,
        visible: true,
        layers: RenderLayers::default(),
        shadows: [true; 2],
        scene: at_tier(tier, &entity.1.scene, None),
        scene_version: 1,
        shadow_distance: 0.0,
        lighting: GrassLighting::default(),
        portable: true,
        placement: [placement_of(entity.5); 2],
        pixel_cells: tier.pixel_cells(),
        seen: true,
    }
}

/// `scene` at quality `tier`, or as authored where that fails its checks (said once where
/// `told` keeps what was said).
fn at_tier(tier: GrassQuality, scene: &Scene, told: Option<&mut HashSet<String>>) -> Scene {
    tier.applied(scene).unwrap_or_else(|why| {
        let sentence = format!("{why}; the grass is drawn as its scene is authored");
        if told.is_some_and(|told| told.insert(sentence.clone())) {
            bevy::log::warn!("{sentence}");
        }
        scene.clone()
    })
}

/// Where a `GlobalTransform` puts a field (none: where its scene does).
pub(crate) fn placement_of(transform: Option<&GlobalTransform>) -> Placement {
    transform.map_or(Placement::IDENTITY, |t| {
        let (scale, rotation, translation) = t.to_scale_rotation_translation();
        Placement::from_scale_rotation_translation(scale, rotation, translation)
    })
}

/// Take this frame's state of grass entity `entity` into its `field`.
fn take_field(
    field: &mut ExtractedField,
    (_, grass, visible, layers, (caster, receiver), transform, share): QueryItem<'_, '_, GrassEntity>,
    (on_bevy_s_device, (tier, tier_changed)): (bool, (GrassQuality, bool)),
    told: &mut Telling,
) {
    field.seen = true;
    field.visible = visible.is_none_or(|v| v.get());
    field.layers = layers.cloned().unwrap_or_default();
    field.shadows = [!caster, !receiver];
    let changed = grass.is_changed() && !grass.is_added();
    if changed || tier_changed {
        let overridden = crate::changes::overridden(&field.scene, &grass.scene, grass.lighting);
        if let Some(sentence) = crate::changes::warning(&overridden).filter(|s| told.overrides.insert(s.clone())) {
            bevy::log::warn!("{sentence}");
        }
        field.scene = at_tier(tier, &grass.scene, Some(told.overrides));
        field.scene_version += 1;
    }
    field.pixel_cells = tier.pixel_cells();
    // Its share of the budget: a changed share grows it again.
    let blades = share.map_or(grass.scene.field.blades, |s| s.blades);
    if field.scene.field.blades != blades {
        field.scene.field.blades = blades;
        field.scene_version += 1;
    }
    field.shadow_distance = match casting_distance(grass.shadow_distance) {
        Ok(distance) => {
            *told.casting = false;
            tier.shadow_distance(distance)
        }
        Err(why) => {
            if !std::mem::replace(told.casting, true) {
                bevy::log::warn!("{why}");
            }
            0.0
        }
    };
    field.lighting = match on_bevy_s_device {
        true => drawn_portably(&grass, told.lighting),
        false => grass.lighting,
    };
    field.portable =
        on_bevy_s_device || (field.lighting == GrassLighting::Pbr && field.technique() != Technique::Bezier);
    field.placement = [placement_of(transform), field.placement[0]];
    if let Some(scale) = transform.map(|t| t.to_scale_rotation_translation().0) {
        let uneven = scale.abs().max_element() - scale.abs().min_element() > 1e-4 * scale.abs().max_element();
        if uneven && !std::mem::replace(told.scale, true) {
            bevy::log::warn!(
                "a Grass entity's Transform scales it by {scale}, and a field is scaled the same along every axis: by its largest scale, {} (to change its width and depth, change its scene's [field] size)",
                scale.abs().max_element()
            );
        }
    }
}

/// Spheres of an entity's space (centre and radius) where its transform puts them in the
/// world, scaled by its largest scale.
pub(crate) fn placed<'a>(
    spheres: &'a [bevy::math::Vec4],
    transform: &'a GlobalTransform,
) -> impl Iterator<Item = Sphere> + 'a {
    let (scale, _, _) = transform.to_scale_rotation_translation();
    let scale = scale.abs().max_element();
    // A sphere that is not one (counted and said in the main world: `GrassSpheres`) is left out.
    spheres
        .iter()
        .filter(|s| crate::spheres::is_sphere(**s))
        .map(move |s| Sphere {
            center: transform.transform_point(s.truncate()),
            radius: s.w * scale,
        })
}

/// The far grass's shadow distance as [`Grass::shadow_distance`] asks it (at most a hundred
/// kilometres), or why the value is none, in one sentence.
fn casting_distance(asked: f32) -> Result<f32, String> {
    match asked >= 0.0 {
        true => Ok(asked.min(1e5)),
        false => Err(format!(
            "Grass::shadow_distance is {asked}, and it takes a distance from the camera in world units, 0 or more (0: the far grass casts no shadow): the far grass casts none"
        )),
    }
}

/// How `grass` is drawn on a device Bevy opened: in Bevy's passes, whatever it asks (sward's
/// own pass needs the Vulkan device of `render_plugin`: said once).
fn drawn_portably(grass: &Grass, told: &mut bool) -> GrassLighting {
    if grass.lighting != GrassLighting::Pbr && !std::mem::replace(told, true) {
        bevy::log::warn!(
            "sward's own pass (GrassLighting::{:?}) needs the Vulkan device of DefaultPlugins.set(sward_bevy::render_plugin()?); on the device Bevy opened the grass is drawn in Bevy's passes (GrassLighting::Pbr)",
            grass.lighting
        );
    }
    GrassLighting::Pbr
}

#[cfg(test)]
mod tests {
    use super::casting_distance;

    #[test]
    fn a_shadow_distance_is_a_distance_or_refused_in_one_sentence() {
        assert_eq!(casting_distance(40.0), Ok(40.0));
        assert_eq!(casting_distance(0.0), Ok(0.0));
        assert_eq!(casting_distance(f32::INFINITY), Ok(1e5));
        for bad in [-1.0, f32::NAN, f32::NEG_INFINITY] {
            let why = casting_distance(bad).expect_err("not a distance");
            assert!(
                why.contains("Grass::shadow_distance") && why.contains("0 or more"),
                "{why}"
            );
            assert_eq!(why.matches(". ").count(), 0, "one sentence: {why}");
        }
    }
}
