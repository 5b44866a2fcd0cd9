//! From Bevy's main world to its render world, each frame: the grass's scene where it changed,
//! where every collider's spheres are now, and the clock.

use std::time::{Duration, Instant};

use bevy::app::SubApp;
use bevy::camera::visibility::{InheritedVisibility, RenderLayers, ViewVisibility};
use bevy::ecs::prelude::*;
use bevy::ecs::system::SystemParam;
use bevy::light::{DirectionalLight, GlobalAmbientLight, NotShadowCaster, NotShadowReceiver, PointLight, SpotLight};
use bevy::render::{Extract, ExtractSchedule};
use bevy::time::Time;
use bevy::transform::components::GlobalTransform;
use sward_core::frame::{FrameColliders, Sphere};
use sward_core::instanced::Technique;
use sward_core::look::Lamp;
use sward_core::Scene;

use crate::components::{Grass, GrassCollider};
use crate::lighting::{brightest_sun, point_lamp, spot_lamp, GrassLighting, Sun};
use crate::occluders::GrassOccluder;

/// The main world's grass as the render world sees it this frame.
#[derive(Resource, Default)]
pub(crate) struct ExtractedGrass {
    /// Whether there is a [`Grass`] entity at all.
    pub present: bool,
    /// The main world's grass entity (the phase items Bevy draws it by stand for it).
    pub entity: Option<Entity>,
    /// Whether it is visible (its `Visibility` and its parents'): hidden grass is neither drawn
    /// nor simulated.
    pub visible: bool,
    /// The render layers it is on: a camera sees it where their layers meet.
    pub layers: RenderLayers,
    /// Where Bevy draws it: whether it casts into Bevy's shadow maps (no `NotShadowCaster`)
    /// and whether Bevy's shadows fall on it (no `NotShadowReceiver`).
    pub shadows: [bool; 2],
    /// Its scene, where it appeared or changed this frame.
    pub changed: Option<Scene>,
    /// Its scene's technique (which parts of the grass Bevy's passes draw).
    pub technique: Technique,
    /// How far from the camera its far grass casts shadows (world units; never negative).
    pub shadow_distance: f32,
    /// What lights it.
    pub lighting: GrassLighting,
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

/// The grass entity as extracted: the grass, whether it is visible, and its render layers.
type GrassEntity = (
    Entity,
    Ref<'static, Grass>,
    Option<&'static InheritedVisibility>,
    Option<&'static RenderLayers>,
    (Has<NotShadowCaster>, Has<NotShadowReceiver>),
);

fn extract_grass(
    mut extracted: ResMut<ExtractedGrass>,
    grass: Extract<Query<GrassEntity>>,
    colliders: Extract<Query<(&GrassCollider, &GlobalTransform)>>,
    occluders: Extract<Query<(&GrassOccluder, &GlobalTransform, Option<&InheritedVisibility>)>>,
    time: Extract<Res<Time>>,
    lights: Lights,
    // Whether the grass runs on the portable passes, and whether the log was told how it is
    // drawn.
    (portable, mut told_of_technique): (Option<Res<crate::portable::PortableGrass>>, Local<bool>),
) {
    let Lights {
        suns,
        ambient,
        points,
        spots,
    } = lights;
    let start = Instant::now();
    let grass = grass.iter().next();
    extracted.present = grass.is_some();
    extracted.entity = grass.as_ref().map(|(entity, ..)| *entity);
    extracted.visible = grass.is_some_and(|(_, _, visible, ..)| visible.is_none_or(|v| v.get()));
    extracted.layers = grass
        .and_then(|(_, _, _, layers, _)| layers.cloned())
        .unwrap_or_default();
    extracted.shadows = grass.map_or([true; 2], |(.., (caster, receiver))| [!caster, !receiver]);
    let grass = grass.map(|(_, grass, ..)| grass);
    extracted.changed = grass.as_ref().filter(|g| g.is_changed()).map(|g| g.scene.clone());
    extracted.technique = grass.as_ref().map_or(Technique::default(), |g| g.scene.technique);
    let casting = grass.as_ref().map_or(0.0, |g| g.shadow_distance);
    // Not a number, or below nothing: no far shadows; at most a hundred kilometres.
    extracted.shadow_distance = if casting > 0.0 { casting.min(1e5) } else { 0.0 };
    extracted.lighting = grass.map_or(GrassLighting::default(), |g| match portable {
        Some(_) => drawn_portably(&g, &mut told_of_technique),
        None => drawn_as(&g, &mut told_of_technique),
    });
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

/// Spheres of an entity's space (centre and radius) where its transform puts them in the
/// world, scaled by its largest scale.
fn placed<'a>(spheres: &'a [bevy::math::Vec4], transform: &'a GlobalTransform) -> impl Iterator<Item = Sphere> + 'a {
    let (scale, _, _) = transform.to_scale_rotation_translation();
    let scale = scale.abs().max_element();
    spheres.iter().map(move |s| Sphere {
        center: glam::Vec3::from_array(transform.transform_point(s.truncate()).to_array()),
        radius: s.w * scale,
    })
}

/// How `grass` is drawn on sward's Vulkan device: as it asks, except that grass of another
/// technique than the Bezier blades, whose far grass the Vulkan renderer draws (or splats)
/// itself, is drawn by sward's own pass (said once).
fn drawn_as(grass: &Grass, told: &mut bool) -> GrassLighting {
    if grass.lighting != GrassLighting::Pbr || grass.scene.technique == Technique::Bezier {
        return grass.lighting;
    }
    if !std::mem::replace(told, true) {
        bevy::log::warn!(
            "on sward's Vulkan device Bevy's passes draw the Bezier technique only, and this grass's scene asks for {}: sward's own pass draws it, lit by Bevy's lights (GrassLighting::Bevy), without Bevy's shadows, prepass or G-buffer (on the device Bevy opens itself, Bevy's passes draw every technique)",
            format!("{:?}", grass.scene.technique).to_lowercase()
        );
    }
    GrassLighting::Bevy
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
