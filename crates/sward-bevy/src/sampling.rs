//! Asking the grass from game code: [`GrassSampling`] beside a [`Grass`] answers, on the CPU,
//! how dense, how tall, which kind, what tint and how pressed the grass is at a point
//! (footsteps, stealth, grazing), kept in step with the grass's scene and its colliders each
//! frame; the [`GrassSampler`] system parameter asks every sampled field at once, in world
//! space. Only a grass that has a `GrassSampling` pays for it.

use bevy::app::{App, PostUpdate};
use bevy::camera::visibility::InheritedVisibility;
use bevy::ecs::prelude::*;
use bevy::ecs::system::SystemParam;
use bevy::log::warn;
use bevy::math::{Vec3, Vec3Swizzles};
use bevy::prelude::ReflectDefault;
use bevy::time::Time;
use bevy::transform::components::GlobalTransform;
use bevy::transform::TransformSystems;
use sward_core::frame::Sphere;
use sward_core::placement::Placement;
use sward_core::sample::{GrassSample, GrassSampler as FieldSampler};
use sward_core::{Collider, Scene};

use crate::components::{Grass, GrassCollider};

/// What a [`Grass`] is asked ([`GrassSampling::at`]), on every `Grass` (a required component;
/// the [`GrassSampler`] system parameter asks them all in world space). It follows the grass's
/// scene (its paint and the strokes a game paints at run time, its kinds of grass, its ground)
/// and the [`GrassCollider`]s' presses and cuts, by the rules the blades are grown and pressed
/// by, so what it says is what is drawn (within the spread of the blades near the point).
#[derive(Component, Default, bevy::reflect::Reflect)]
#[reflect(Component, Default)]
pub struct GrassSampling {
    #[reflect(ignore)]
    sampler: Option<FieldSampler>,
    /// The scene the sampler answers for.
    #[reflect(ignore)]
    scene: Option<Scene>,
    /// Where the grass's `GlobalTransform` puts its field.
    #[reflect(ignore)]
    placement: Placement,
}

impl GrassSampling {
    /// The grass at world point `point` (its ground point below or above it, in the field's
    /// own space where its `Transform` placed it); `None` until the grass's scene has been
    /// taken (the frame after both are spawned), or where its files could not be read (said
    /// once as a warning). Heights are the world's (the field's scale applied).
    pub fn at(&self, point: Vec3) -> Option<GrassSample> {
        let placed = self.placement;
        let local = placed.point_to_field(point);
        let mut sample = self.sampler.as_ref()?.at(local.xz());
        sample.height *= placed.scale;
        sample.ground = sample
            .ground
            .map(|g| placed.point_to_world(Vec3::new(local.x, g, local.z)).y);
        Some(sample)
    }

    /// Take `scene` where it changed: what it says beside its field is taken as it is, strokes
    /// added are painted into the paint held, and a scene of another field is sampled anew,
    /// keeping the presses.
    fn take(&mut self, scene: &Scene) {
        if self.scene.as_ref() == Some(scene) {
            return;
        }
        let old = self.scene.replace(scene.clone());
        if let (Some(old), Some(sampler)) = (old, self.sampler.as_mut()) {
            if old.grows_as(scene) {
                sampler.tune(scene);
                return;
            }
            if let Some(strokes) = scene.strokes_added_to(&old) {
                sampler.tune(scene);
                sampler.paint(scene, strokes);
                return;
            }
        }
        match FieldSampler::new(scene) {
            Ok(mut sampler) => {
                if let Some(old) = self.sampler.take() {
                    sampler.keep_presses_of(old);
                }
                self.sampler = Some(sampler);
            }
            Err(e) => warn!("the grass cannot be sampled: {e}"),
        }
    }
}

/// Every grass at once, in world space: a system parameter that asks each visible [`Grass`]
/// (through its [`GrassSampling`]) about a point and answers with the field whose grass
/// grows densest there. What it says is as of the last `PostUpdate` (each field's transform
/// and scene, the colliders' presses and cuts, all on the CPU: it never waits on the GPU); a
/// system in `PostUpdate` after [`GrassSystems`](crate::GrassSystems) sees this frame's.
///
/// ```no_run
/// use bevy::prelude::*;
/// use sward_bevy::GrassSampler;
///
/// fn footsteps(grass: GrassSampler, walkers: Query<&GlobalTransform, With<Name>>) {
///     for at in &walkers {
///         if grass.at(at.translation()).is_some_and(|g| g.density > 0.5 && g.pressed < 0.2) {
///             // Rustling through standing grass.
///         }
///     }
/// }
/// ```
#[derive(SystemParam)]
pub struct GrassSampler<'w, 's> {
    fields: Query<'w, 's, (&'static GrassSampling, Option<&'static InheritedVisibility>)>,
}

impl GrassSampler<'_, '_> {
    /// The grass at world point `point` over every visible sampled field: where fields overlap,
    /// the one that grows densest there; `None` where no field has been sampled yet.
    pub fn at(&self, point: Vec3) -> Option<GrassSample> {
        self.fields
            .iter()
            .filter(|(_, visible)| visible.is_none_or(|v| v.get()))
            .filter_map(|(sampling, _)| sampling.at(point))
            .reduce(|densest, other| match other.density > densest.density {
                true => other,
                false => densest,
            })
    }
}

/// The main world's part: every sampled grass kept in step before the game's next systems,
/// where this frame's transforms put it.
pub(crate) fn build(app: &mut App) {
    app.add_systems(
        PostUpdate,
        keep_in_step
            .in_set(crate::GrassSystems)
            .after(TransformSystems::Propagate),
    );
}

/// A sampled grass: its scene, its sampler, the files its scene read, and where it stands.
type SampledGrass = (
    &'static Grass,
    &'static mut GrassSampling,
    Option<&'static GlobalTransform>,
);

/// Each sampled grass takes its scene and this frame's colliders (in its field's own space).
pub(crate) fn keep_in_step(
    mut grass: Query<SampledGrass>,
    colliders: Query<(&GrassCollider, &GlobalTransform)>,
    time: Res<Time>,
) {
    if grass.is_empty() {
        return;
    }
    let now: Vec<(Sphere, bool)> = colliders
        .iter()
        .flat_map(|(collider, transform)| {
            crate::render_world::extract::placed(&collider.spheres, transform).map(|s| (s, collider.cuts))
        })
        .collect();
    for (grass, mut sampling, transform) in &mut grass {
        let sampling = sampling.bypass_change_detection();
        sampling.placement = crate::render_world::extract::placement_of(transform);
        let placed = sampling.placement;
        // The colliders as the field's own space has them.
        let now: Vec<Collider> = now
            .iter()
            .map(|&(s, cut)| {
                let s = placed.sphere_to_field(s);
                Collider {
                    cut,
                    ..Collider::sphere(s.center, s.radius)
                }
            })
            .collect();
        sampling.take(&grass.scene);
        if let Some(sampler) = sampling.sampler.as_mut() {
            sampler.step(&now, time.delta_secs());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::transform::components::Transform;

    /// Two fields fifty units apart, each sampled: the sampler answers each point from the field
    /// that grows there, nothing between them, and a hidden field is not asked.
    #[test]
    fn the_sampler_answers_in_world_space_over_every_field() {
        let mut app = App::new();
        app.add_plugins((bevy::MinimalPlugins, bevy::transform::TransformPlugin))
            .add_systems(PostUpdate, keep_in_step.after(TransformSystems::Propagate));
        let tall = |height: f32| {
            let mut grass = Grass::default();
            grass.scene.field.height = [height, height];
            grass.scene.species.clear();
            grass
        };
        // Without Bevy's visibility systems here, each field is made visible by hand.
        let shown = InheritedVisibility::VISIBLE;
        app.world_mut().spawn((tall(1.0), GrassSampling::default(), shown));
        let far = app
            .world_mut()
            .spawn((
                tall(2.0),
                GrassSampling::default(),
                shown,
                Transform::from_xyz(50.0, 0.0, 0.0),
            ))
            .id();
        app.update();
        app.update();
        let mut all = app.world_mut().query::<&GrassSampling>();
        let held: Vec<bool> = all.iter(app.world()).map(|s| s.sampler.is_some()).collect();
        assert_eq!(held, [true, true], "each field holds a sampler");
        let ask = |app: &mut App, at: Vec3| {
            let mut state = bevy::ecs::system::SystemState::<GrassSampler>::new(app.world_mut());
            let sampler = state.get(app.world()).expect("the sampler's query");
            sampler.at(at).expect("the fields are sampled")
        };
        let near = ask(&mut app, Vec3::ZERO);
        let between = ask(&mut app, Vec3::new(25.0, 0.0, 0.0));
        let there = ask(&mut app, Vec3::new(50.0, 0.0, 0.0));
        assert!(near.density > 0.0 && there.density > 0.0, "{near:?} {there:?}");
        assert_eq!(between.density, 0.0, "{between:?}");
        assert!(
            there.height > near.height,
            "the far field's grass is taller: {near:?} {there:?}"
        );
        app.world_mut().entity_mut(far).insert(InheritedVisibility::HIDDEN);
        let hidden = ask(&mut app, Vec3::new(50.0, 0.0, 0.0));
        assert_eq!(hidden.density, 0.0, "a hidden field answered: {hidden:?}");
    }
}
