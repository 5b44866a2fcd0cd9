//! The GPU's block of collider spheres ([`MAX_COLLIDERS`], 128), which each field's own scene
//! colliders and bodies share with the app's [`GrassCollider`] and [`GrassOccluder`] entities:
//! how many each frame asks and how many did not fit ([`GrassSpheres`]), said once.

use bevy::app::{App, PostUpdate};
use bevy::camera::visibility::{ViewVisibility, VisibilitySystems};
use bevy::ecs::prelude::*;
use bevy::math::Vec4;
use bevy::prelude::ReflectDefault;
use sward_core::frame::{packed_counts, FrameColliders};
use sward_core::physics::MAX_COLLIDERS;

use crate::components::{Grass, GrassCollider};
use crate::occluders::GrassOccluder;

/// How the frame's collider spheres fit the GPU's block of 128: those that press the grass
/// (each field's scene colliders and bodies, and the [`GrassCollider`]s that do not cut), those
/// that mow it (cutting [`GrassCollider`]s and scene colliders), and those that only hide it from
/// the cull (seen [`GrassOccluder`]s), in that order of precedence; for the field that drops
/// most. Set by the plugin each frame; where any is dropped a warning says so once (until the
/// counts change), with what to change.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq, bevy::reflect::Reflect)]
#[reflect(Resource, Default)]
pub struct GrassSpheres {
    /// Spheres asked: pressing, cutting, hiding.
    pub asked: [u32; 3],
    /// Spheres left out of the block: pressing, cutting, hiding (they neither press, mow nor
    /// hide the grass).
    pub dropped: [u32; 3],
    /// Spheres that are not ones (a centre not finite, a radius below 0 or not a number), left
    /// out before the rest are counted.
    pub invalid: u32,
}

impl GrassSpheres {
    /// Whether every sphere asked fits.
    pub fn all_fit(&self) -> bool {
        self.dropped == [0; 3]
    }

    /// How `asked` pressing, cutting and hiding spheres fit the block.
    fn of(asked: [usize; 3]) -> GrassSpheres {
        let held = packed_counts(asked);
        GrassSpheres {
            asked: asked.map(|n| n as u32),
            dropped: [0, 1, 2].map(|k| (asked[k] - held[k]) as u32),
            invalid: 0,
        }
    }

    /// The warning where spheres were not ones.
    fn invalid_warning(&self) -> Option<String> {
        (self.invalid > 0).then(|| {
            format!(
                "{} of the grass's collider and occluder spheres are not spheres (a centre not finite, or a radius below 0 or not a number) and are left out: a GrassCollider's or GrassOccluder's spheres take a finite centre and a finite radius of 0 or more",
                self.invalid
            )
        })
    }

    /// The warning where spheres were dropped: the counts and what to change.
    fn warning(&self) -> Option<String> {
        if self.all_fit() {
            return None;
        }
        let [p, c, h] = self.asked;
        let [dp, dc, dh] = self.dropped;
        Some(format!(
            "the grass's collider spheres are {} ({p} pressing, {c} cutting, {h} hiding), over the GPU's {MAX_COLLIDERS}: {} left out ({dp} pressing, {dc} cutting, {dh} hiding), which do not touch the grass; pack bodies into fewer spheres (GrassFromCollider::spheres, GrassOccluder::packed, GrassCollider::from_mesh) or give fewer entities a GrassCollider or GrassOccluder (GrassSpheres counts them each frame)",
            p + c + h,
            dp + dc + dh,
        ))
    }
}

pub(crate) fn build(app: &mut App) {
    app.register_type::<GrassSpheres>()
        .init_resource::<GrassSpheres>()
        .add_systems(
            PostUpdate,
            // After visibility: an occluder hides grass only where a camera sees it.
            count_spheres
                .in_set(crate::GrassSystems)
                .after(VisibilitySystems::CheckVisibility),
        );
}

/// Whether `sphere` (centre and radius) is one: a finite centre and a finite radius of 0 or
/// more.
pub(crate) fn is_sphere(sphere: Vec4) -> bool {
    sphere.is_finite() && sphere.w >= 0.0
}

/// The spheres the app's entities ask (pressing, cutting, hiding), as the render world takes
/// them, and how many are not spheres (left out).
fn app_spheres(
    colliders: &Query<&GrassCollider>,
    occluders: &Query<(&GrassOccluder, Option<&ViewVisibility>)>,
) -> ([usize; 3], usize) {
    let mut asked = [0; 3];
    let mut invalid = 0;
    let mut count = |spheres: &[Vec4], into: usize| {
        let valid = spheres.iter().filter(|s| is_sphere(**s)).count();
        asked[into] += valid;
        invalid += spheres.len() - valid;
    };
    for collider in colliders {
        count(&collider.spheres, usize::from(collider.cuts));
    }
    for (occluder, _) in occluders.iter().filter(|(_, v)| v.is_none_or(|v| v.get())) {
        count(&occluder.spheres, 2);
    }
    (asked, invalid)
}

/// This frame's [`GrassSpheres`]: for each field its scene's spheres with the app's, the one
/// that drops most kept (the app's alone where there is no field); the warning where it changed.
fn count_spheres(
    fields: Query<&Grass>,
    colliders: Query<&GrassCollider>,
    occluders: Query<(&GrassOccluder, Option<&ViewVisibility>)>,
    mut spheres: ResMut<GrassSpheres>,
    mut told: Local<[Option<String>; 2]>,
) {
    let (app, invalid) = app_spheres(&colliders, &occluders);
    let of_field = |grass: &Grass| {
        let own = FrameColliders::of_scene(&grass.scene, 0.0);
        GrassSpheres::of([app[0] + own.pushing.len(), app[1] + own.cutting.len(), app[2]])
    };
    let worst = fields
        .iter()
        .map(of_field)
        .max_by_key(|s| s.dropped.iter().sum::<u32>())
        .unwrap_or(GrassSpheres::of(app));
    let worst = GrassSpheres {
        invalid: invalid as u32,
        ..worst
    };
    spheres.set_if_neq(worst);
    // Each warning said once, again only when its sentence changes.
    let said = [worst.invalid_warning(), worst.warning()];
    for (sentence, before) in said.iter().zip(told.iter()) {
        if sentence.is_some() && sentence != before {
            bevy::log::warn!("{}", sentence.as_deref().unwrap_or_default());
        }
    }
    *told = said;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pressing_spheres_go_before_cutters_and_cutters_before_occluders() {
        let fits = GrassSpheres::of([100, 20, 8]);
        assert!(fits.all_fit() && fits.warning().is_none(), "{fits:?}");
        let over = GrassSpheres::of([120, 10, 30]);
        assert_eq!(over.dropped, [0, 2, 30]);
        let said = over.warning().expect("spheres dropped");
        assert!(
            said.contains("160 (120 pressing, 10 cutting, 30 hiding)") && said.contains("32 left out"),
            "{said}"
        );
        assert_eq!(GrassSpheres::of([200, 0, 0]).dropped, [72, 0, 0]);
    }

    /// Six Avian-sized bodies (24 spheres each) and a scene's own collider overfill the block:
    /// the resource counts what was left out, for the field that asks most.
    #[test]
    fn the_plugin_counts_the_spheres_left_out_each_frame() {
        let mut app = App::new();
        app.add_plugins(bevy::MinimalPlugins);
        app.init_resource::<GrassSpheres>()
            .add_systems(PostUpdate, count_spheres);
        let body = GrassCollider {
            spheres: vec![Vec4::new(0.0, 0.0, 0.0, 0.3); 24],
            cuts: false,
        };
        for _ in 0..6 {
            app.world_mut().spawn(body.clone());
        }
        app.update();
        assert_eq!(app.world().resource::<GrassSpheres>().dropped, [16, 0, 0]);
        let mut scene = sward_core::Scene::default();
        scene.colliders.push(sward_core::Collider {
            center: Default::default(),
            radius: 1.0,
            path: Vec::new(),
            speed: 1.0,
            cut: false,
            clear: false,
        });
        let field = Grass::new(scene).expect("a default scene with one collider is valid");
        app.world_mut().spawn(field);
        app.world_mut()
            .spawn(GrassOccluder::spheres(vec![Vec4::new(0.0, 0.0, 0.0, 2.0)]));
        app.update();
        let counted = *app.world().resource::<GrassSpheres>();
        assert_eq!((counted.asked, counted.dropped), ([145, 0, 1], [17, 0, 1]));
        // Spheres that are not ones are left out before the rest are counted.
        app.world_mut().spawn(GrassCollider {
            spheres: vec![
                Vec4::new(0.0, 0.0, 0.0, f32::NAN),
                Vec4::new(f32::INFINITY, 0.0, 0.0, 1.0),
            ],
            cuts: true,
        });
        app.update();
        let counted = *app.world().resource::<GrassSpheres>();
        assert_eq!((counted.asked, counted.invalid), ([145, 0, 1], 2));
    }
}
