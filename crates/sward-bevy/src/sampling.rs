//! Asking the grass from game code: [`GrassSampling`] beside a [`Grass`] answers, on the CPU,
//! how dense, how tall, which kind, what tint and how pressed the grass is at a point
//! (footsteps, stealth, grazing), kept in step with the grass's scene and its colliders each
//! frame. Only a grass that has one pays for it.

use bevy::app::{App, PostUpdate};
use bevy::ecs::prelude::*;
use bevy::log::warn;
use bevy::math::{Vec3, Vec3Swizzles};
use bevy::prelude::ReflectDefault;
use bevy::time::Time;
use bevy::transform::components::GlobalTransform;
use sward_core::frame::Sphere;
use sward_core::placement::Placement;
use sward_core::sample::{GrassSample, GrassSampler};
use sward_core::{Collider, Scene};

use crate::assets::GrassFiles;
use crate::components::{Grass, GrassCollider};

/// Put beside a [`Grass`] to ask it questions: [`GrassSampling::at`]. It follows the grass's
/// scene (its paint and the strokes a game paints at run time, its kinds of grass, its ground)
/// and the [`GrassCollider`]s' presses and cuts, by the rules the blades are grown and pressed
/// by, so what it says is what is drawn (within the spread of the blades near the point).
#[derive(Component, Default, bevy::reflect::Reflect)]
#[reflect(Component, Default)]
pub struct GrassSampling {
    #[reflect(ignore)]
    sampler: Option<GrassSampler>,
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
        match GrassSampler::new(scene) {
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

/// The main world's part: every sampled grass kept in step before the game's next systems.
pub(crate) fn build(app: &mut App) {
    app.add_systems(PostUpdate, keep_in_step.in_set(crate::GrassSystems));
}

/// A sampled grass: its scene, its sampler, the files its scene read, and where it stands.
type SampledGrass = (
    &'static Grass,
    &'static mut GrassSampling,
    Option<Ref<'static, GrassFiles>>,
    Option<&'static GlobalTransform>,
);

/// Each sampled grass takes its scene and this frame's colliders (in its field's own space).
fn keep_in_step(mut grass: Query<SampledGrass>, colliders: Query<(&GrassCollider, &GlobalTransform)>, time: Res<Time>) {
    if grass.is_empty() {
        return;
    }
    let now: Vec<(Sphere, bool)> = colliders
        .iter()
        .flat_map(|(collider, transform)| {
            crate::render_world::extract::placed(&collider.spheres, transform).map(|s| (s, collider.cuts))
        })
        .collect();
    for (grass, mut sampling, files, transform) in &mut grass {
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
        if files.is_some_and(|f| f.is_changed()) {
            // The maps it read were changed: read them again.
            sampling.scene = None;
        }
        sampling.take(&grass.scene);
        if let Some(sampler) = sampling.sampler.as_mut() {
            sampler.step(&now, time.delta_secs());
        }
    }
}
