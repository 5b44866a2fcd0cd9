//! From Bevy's main world to its render world, each frame: the grass's scene where it changed,
//! where every collider's spheres are now, and the clock.

use std::time::{Duration, Instant};

use bevy::app::SubApp;
use bevy::ecs::prelude::*;
use bevy::render::{Extract, ExtractSchedule};
use bevy::time::Time;
use bevy::transform::components::GlobalTransform;
use sward_core::frame::{FrameColliders, Sphere};
use sward_core::Scene;

use crate::components::{Grass, GrassCollider};

/// The main world's grass as the render world sees it this frame.
#[derive(Resource, Default)]
pub(crate) struct ExtractedGrass {
    /// Whether there is a [`Grass`] entity at all.
    pub present: bool,
    /// Its scene, where it appeared or changed this frame.
    pub changed: Option<Scene>,
    /// The colliders' spheres, in the world, where they are now.
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

fn extract_grass(
    mut extracted: ResMut<ExtractedGrass>,
    grass: Extract<Query<Ref<Grass>>>,
    colliders: Extract<Query<(&GrassCollider, &GlobalTransform)>>,
    time: Extract<Res<Time>>,
) {
    let start = Instant::now();
    let grass = grass.iter().next();
    extracted.present = grass.is_some();
    extracted.changed = grass.filter(|g| g.is_changed()).map(|g| g.scene.clone());
    extracted.colliders = FrameColliders::default();
    for (collider, transform) in &colliders {
        let (scale, _, _) = transform.to_scale_rotation_translation();
        let scale = scale.abs().max_element();
        let spheres = collider.spheres.iter().map(|s| Sphere {
            center: glam::Vec3::from_array(transform.transform_point(s.truncate()).to_array()),
            radius: s.w * scale,
        });
        let into = match collider.cuts {
            true => &mut extracted.colliders.cutting,
            false => &mut extracted.colliders.pushing,
        };
        into.extend(spheres);
    }
    extracted.elapsed = time.elapsed_secs_f64();
    extracted.frame += 1;
    extracted.took = start.elapsed();
}
