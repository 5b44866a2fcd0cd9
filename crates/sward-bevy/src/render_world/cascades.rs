//! Which of the grass each of the sun's shadow cascades draws. A cascade's shadow map is read
//! only by what the camera sees between its near and far bounds (its slice of the camera's
//! depth), so only blades within that slice, or near enough to it that their shadows fall into
//! it, need to be drawn into it: the near Bezier blades into the first cascades, the far grass
//! into the cascades its distance buckets reach. Every cascade used to draw all the grass that
//! casts, which made the grass's shadows cost Bevy's frame more than the rest of the grass.

use bevy::ecs::prelude::*;
use bevy::light::CascadeShadowConfig;
use bevy::math::{Mat4, Vec3};
use bevy::pbr::{ExtractedDirectionalLight, LightEntity, ViewLightEntities};
use bevy::platform::collections::HashMap;
use bevy::render::view::ExtractedView;

use super::extract::ExtractedField;

/// How far a blade's shadow reaches across the ground, per unit of its height, at most: the
/// sun at about 5.7° over the horizon. A lower sun's cascades draw every blade that casts.
const MOST_RUN_PER_HEIGHT: f32 = 10.0;

/// The part of the camera's view a shadow cascade serves: the distances from the eye its
/// receivers lie at, and how far a blade's shadow runs across the ground for each unit of its
/// height under its light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CascadeBand {
    /// The nearest and farthest distances from the eye (not depths: a receiver at the edge of
    /// the view lies farther than its depth) of what reads this cascade.
    pub seen: [f32; 2],
    /// A blade's shadow's length on flat ground per unit of its height.
    pub run: f32,
}

impl CascadeBand {
    /// The band of cascade `index` of `config`, for a camera whose projection is `clip_from_view`
    /// (none for an orthographic one, whose distances a depth does not bound) and a light
    /// shining along `towards` (none for a sun too low to bound its shadows).
    pub fn of(config: &CascadeShadowConfig, index: usize, clip_from_view: &Mat4, towards: Vec3) -> Option<CascadeBand> {
        let far = *config.bounds.get(index)?;
        let near = match index {
            0 => config.minimum_distance,
            // Bevy's cascades overlap the one before them by this share of its far bound.
            _ => config.bounds[index - 1] * (1.0 - config.overlap_proportion),
        };
        let widest = widest_distance_per_depth(clip_from_view)?;
        let run = shadow_run(towards)?;
        Some(CascadeBand {
            seen: [near, far * widest],
            run,
        })
    }

    /// Whether blades between `from` and `to` from the eye, none taller than `tallest`, can cast
    /// into this cascade: whether they lie within its band widened by their shadows' length.
    pub fn casts(&self, [from, to]: [f32; 2], tallest: f32) -> bool {
        // A blade's height more for its lean and the shadow filter's reach.
        let reach = tallest * (self.run + 1.0);
        from <= self.seen[1] + reach && to >= self.seen[0] - reach
    }
}

/// The greatest distance from the eye a point at depth 1 in the view can lie at: its corner's.
/// None for an orthographic projection.
fn widest_distance_per_depth(clip_from_view: &Mat4) -> Option<f32> {
    // A perspective projection puts -1 in the w row's z column; an orthographic one 1 in its w.
    if clip_from_view.w_axis.w != 0.0 {
        return None;
    }
    let [x, y] = [clip_from_view.x_axis.x, clip_from_view.y_axis.y];
    let (x, y) = (1.0 / x.abs().max(1e-6), 1.0 / y.abs().max(1e-6));
    Some((1.0 + x * x + y * y).sqrt())
}

/// How far a shadow runs across flat ground per unit of height under a light shining along
/// `towards`, or none where the light is under the horizon or too low to bound it.
fn shadow_run(towards: Vec3) -> Option<f32> {
    let down = -towards.normalize_or_zero().y;
    let across = (1.0 - down * down).max(0.0).sqrt();
    let run = across / down.max(1e-6);
    (down > 0.0 && run <= MOST_RUN_PER_HEIGHT).then_some(run)
}

/// How a field's grass reaches into the shadow maps, in world units: the far grass within
/// `far` of the camera (`Grass::shadow_distance`), the Bezier blades within `bezier` of it
/// (where the instanced grass takes over from them, or where nothing is drawn), none taller
/// than `tallest`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Casting {
    pub far: f32,
    pub bezier: f32,
    pub tallest: f32,
}

impl Default for Casting {
    /// Nothing known yet: no far grass casts, the Bezier blades into every cascade.
    fn default() -> Self {
        Casting {
            far: 0.0,
            bezier: f32::INFINITY,
            tallest: f32::INFINITY,
        }
    }
}

impl Casting {
    /// How `field`'s grass casts, as its scene and placement say.
    pub fn of(field: &ExtractedField) -> Casting {
        let scene = &field.scene;
        let scale = field.placement[0].scale;
        let species = sward_core::species::envelope(&scene.species).map_or(0.0, |e| e.height[1]);
        let tallest = [
            scene.field.height[1],
            scene.instanced.grid.height[1],
            scene.billboard.grid.height[1],
            species,
        ]
        .into_iter()
        .fold(0.0, f32::max);
        Casting {
            far: field.shadow_distance,
            bezier: scene.hand_over() * scale,
            tallest: tallest * scale,
        }
    }

    /// Whether the Bezier blades cast into a cascade serving `band` (every cascade where `band`
    /// is none).
    pub fn bezier_into(&self, band: Option<&CascadeBand>) -> bool {
        band.is_none_or(|band| band.casts([0.0, self.bezier], self.tallest))
    }
}

/// Each shadow view of a sun's cascade this frame, and the band of the camera's view it serves
/// (none for views whose band is not bounded: they draw all the grass that casts).
#[derive(Resource, Default)]
pub(crate) struct CascadeBands(HashMap<Entity, CascadeBand>);

impl CascadeBands {
    /// The band shadow view `view` serves, where it is a sun's cascade with one.
    pub fn of(&self, view: Entity) -> Option<&CascadeBand> {
        self.0.get(&view)
    }
}

/// Find the band each camera's sun cascades serve (after Bevy made the light views).
pub(crate) fn find_cascade_bands(
    cameras: Query<(&ExtractedView, &ViewLightEntities)>,
    light_views: Query<&LightEntity>,
    lights: Query<&ExtractedDirectionalLight>,
    mut bands: ResMut<CascadeBands>,
) {
    bands.0.clear();
    for (camera, light_views_of) in &cameras {
        for &view in &light_views_of.lights {
            let Ok(&LightEntity::Directional {
                light_entity,
                cascade_index,
            }) = light_views.get(view)
            else {
                continue;
            };
            let Ok(light) = lights.get(light_entity) else { continue };
            let towards = light.transform.forward().as_vec3();
            let band = CascadeBand::of(
                &light.cascade_shadow_config,
                cascade_index,
                &camera.clip_from_view,
                towards,
            );
            if let Some(band) = band {
                bands.0.insert(view, band);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::camera::{CameraProjection, OrthographicProjection, PerspectiveProjection};

    /// Four cascades to 150 m, the first to 10 m, as the open world's sun has them.
    fn open_world_cascades() -> CascadeShadowConfig {
        bevy::light::CascadeShadowConfigBuilder {
            maximum_distance: 150.0,
            first_cascade_far_bound: 10.0,
            ..Default::default()
        }
        .build()
    }

    /// Bevy's projection of a 55° camera on a 16:9 target.
    fn camera() -> Mat4 {
        PerspectiveProjection {
            fov: 55f32.to_radians(),
            aspect_ratio: 16.0 / 9.0,
            near: 0.05,
            ..Default::default()
        }
        .get_clip_from_view()
    }

    #[test]
    fn a_cascade_serves_its_slice_of_depth_out_to_the_corners_of_the_view() {
        let config = open_world_cascades();
        let sun = Vec3::new(1.0, -1.1, -0.6);
        let first = CascadeBand::of(&config, 0, &camera(), sun).expect("a perspective camera under a high sun");
        let second = CascadeBand::of(&config, 1, &camera(), sun).expect("the second cascade");
        assert_eq!(first.seen[0], config.minimum_distance);
        // The corner of a 55° 16:9 view lies about 1.46 times as far as its depth.
        assert!((first.seen[1] / 10.0 - 1.46).abs() < 0.02, "{first:?}");
        assert!(second.seen[0] < 10.0 && second.seen[0] > 5.0, "{second:?}");
        assert!(
            CascadeBand::of(&config, 4, &camera(), sun).is_none(),
            "there are four cascades"
        );
    }

    #[test]
    fn blades_cast_into_the_cascades_their_shadows_reach_and_no_other() {
        let config = open_world_cascades();
        let sun = Vec3::new(1.0, -1.1, -0.6);
        let bands: Vec<CascadeBand> = (0..4)
            .map(|k| CascadeBand::of(&config, k, &camera(), sun).unwrap())
            .collect();
        // The Bezier blades within 12 m, a metre tall: the first two cascades.
        let near = [0.0, 12.0];
        assert_eq!(
            bands.iter().map(|b| b.casts(near, 1.0)).collect::<Vec<_>>(),
            [true, true, false, false]
        );
        // The far grass's level from 28 to 45 m: not the first cascade, nor the last.
        let level = [28.0, 45.0];
        assert_eq!(
            bands.iter().map(|b| b.casts(level, 1.0)).collect::<Vec<_>>(),
            [false, true, true, false]
        );
        // A blade just short of a cascade's band casts into it where its shadow reaches it.
        let short = bands[2].seen[0] - 2.0;
        assert!(bands[2].casts([0.0, short], 1.2));
        assert!(!bands[2].casts([0.0, short], 0.5));
    }

    #[test]
    fn a_low_sun_or_an_orthographic_camera_bounds_no_band() {
        let config = open_world_cascades();
        let low = Vec3::new(1.0, -0.05, 0.0);
        assert!(CascadeBand::of(&config, 0, &camera(), low).is_none());
        let below = Vec3::new(0.0, 1.0, 0.0);
        assert!(CascadeBand::of(&config, 0, &camera(), below).is_none());
        let ortho = OrthographicProjection::default_3d().get_clip_from_view();
        assert!(CascadeBand::of(&config, 0, &ortho, Vec3::new(0.0, -1.0, 0.0)).is_none());
    }
}
