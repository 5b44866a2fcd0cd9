//! Edits of the grass in world space: a game sends a [`GrassEdit`] (a brush stroke over the
//! world's x and z: clear, mow, burn, regrow, a density, a kind of grass or a tint, over a
//! circle or along a path) and every field whose grass it reaches paints it in its own space,
//! wherever the field's transform puts it. What the edits painted is the scene's edits
//! (`Scene::edits`), merged into one map every `MERGE_AFTER` strokes, and carried over to its
//! scene when the scene file is loaded again.

use bevy::app::{App, PostUpdate, PreUpdate};
use bevy::ecs::message::{Message, MessageReader};
use bevy::ecs::prelude::*;
use bevy::log::warn;
use bevy::math::{Vec2, Vec3, Vec3Swizzles};
use bevy::transform::components::GlobalTransform;
use bevy::transform::TransformSystems;
use sward_core::paint::Stroke;
use sward_core::placement::Placement;
use sward_core::Scene;

use crate::components::Grass;

/// A brush stroke over the grass in world space, sent as a Bevy message: its points are the
/// world's x and z, its radius and softness world units. Every [`Grass`] whose ground it
/// reaches paints it from the frame it is read on, in the field's own space (moved, turned and
/// scaled by the field's transform), lasting until painted over.
///
/// ```no_run
/// use bevy::prelude::*;
/// use sward_bevy::prelude::Stroke;
/// use sward_bevy::GrassEdit;
///
/// fn mow_where_the_mower_is(mower: Single<&GlobalTransform, With<Name>>, mut edits: MessageWriter<GrassEdit>) {
///     let at = mower.translation();
///     edits.write(GrassEdit(Stroke::circle(Vec2::new(at.x, at.z), 0.8).mow(0.2)));
/// }
/// ```
#[derive(Message, Clone, Debug, PartialEq)]
pub struct GrassEdit(pub Stroke);

/// The main world's part: the edits read after this frame's transforms, before anything reads
/// the grass.
pub(crate) fn build(app: &mut App) {
    app.add_message::<GrassEdit>()
        .add_systems(PreUpdate, merge_edits)
        .add_systems(
            PostUpdate,
            paint_edits
                .in_set(crate::GrassSystems)
                .after(TransformSystems::Propagate)
                .after(crate::assets::grow_from_sources)
                .before(crate::changes::keep_valid),
        );
}

/// A field the edits may reach: its grass, where it stands.
type Edited = (&'static mut Grass, Option<&'static GlobalTransform>);

/// Paint each edit sent since the last frame into every field it reaches. An edit that is not a
/// stroke (no point, a radius below 0, a value out of its range) is said once and left out,
/// and so, once, is an edit that reaches no field.
pub(crate) fn paint_edits(
    mut edits: MessageReader<GrassEdit>,
    mut fields: Query<Edited>,
    (mut refused, mut unreached, mut overreached): (Local<bool>, Local<bool>, Local<bool>),
) {
    let edits: Vec<&Stroke> = edits
        .read()
        .map(|GrassEdit(stroke)| stroke)
        .filter(|stroke| {
            let wrong = refusal(stroke);
            if let (Some(wrong), false) = (&wrong, *refused) {
                warn!("a GrassEdit was left out: {wrong}");
                *refused = true;
            }
            wrong.is_none()
        })
        .collect();
    if edits.is_empty() {
        return;
    }
    let mut painted = vec![false; edits.len()];
    for (mut grass, transform) in &mut fields {
        let placed = crate::render_world::extract::placement_of(transform);
        let mut reached = Vec::new();
        for (stroke, painted) in edits.iter().zip(&mut painted) {
            let stroke = in_field(stroke, placed);
            if reaches(&grass.scene, &stroke) {
                if let (Some(past), false) = (past_the_area(&grass.scene, &stroke), *overreached) {
                    warn!("{past}");
                    *overreached = true;
                }
                reached.push(stroke);
                *painted = true;
            }
        }
        for stroke in reached {
            grass.paint(stroke);
        }
    }
    if let (Some(lost), false) = (painted.iter().position(|p| !p), *unreached) {
        let [x, z] = edits[lost].points[0];
        warn!(
            "a GrassEdit at x {x}, z {z} reached no field's paint area (each scene's [paint] area, \
             where its grass can be painted) that grows the kind of grass it names: nothing was painted"
        );
        *unreached = true;
    }
}

/// Merge each field's strokes into its paint where enough wait (however they came: edits or
/// `Grass::paint`), touching a field only then. At the frame's start: the strokes waiting were
/// all taken by the renderers and the sampler last frame, so they find the strokes they lack
/// still waiting, paint only those, and keep the field.
pub(crate) fn merge_edits(mut fields: Query<&mut Grass>) {
    for mut grass in &mut fields {
        if !grass.scene.edits.wants_merging() {
            continue;
        }
        if let Err(e) = grass.scene.merge_edits() {
            // Its paint's maps cannot be read: the field says so as it grows; the strokes wait.
            bevy::log::debug!("the grass's edits were not merged: {e}");
        }
    }
}

/// Why `stroke` cannot be painted, in the words of a scene's checks (`None`: it can). The kind
/// of grass it names is each field's to know ([`reaches`]).
fn refusal(stroke: &Stroke) -> Option<String> {
    let mut scene = Scene::default();
    scene.paint.strokes.push(Stroke {
        species: None,
        ..stroke.clone()
    });
    scene.validate("GrassEdit").err().map(|e| e.to_string())
}

/// `stroke`, whose points are the world's x and z, in the field's own space where `placed` puts
/// it: each point carried onto the field's ground plane, the radius and softness by its scale.
fn in_field(stroke: &Stroke, placed: Placement) -> Stroke {
    let origin_height = placed.point_to_world(Vec3::ZERO).y;
    let points = stroke
        .points
        .iter()
        .map(|&[x, z]| placed.point_to_field(Vec3::new(x, origin_height, z)).xz().to_array())
        .collect();
    Stroke {
        points,
        radius: stroke.radius / placed.scale,
        softness: stroke.softness / placed.scale,
        ..stroke.clone()
    }
}

/// Whether `stroke` (in the field's space) reaches ground where `scene` can paint it: its paint's
/// area (beyond which a stroke would paint only the map's edge, which carries on outward), in a
/// field that grows the kind of grass it names, if it names one.
fn reaches(scene: &Scene, stroke: &Stroke) -> bool {
    let named = stroke.species.as_ref();
    if named.is_some_and(|name| !scene.species.iter().any(|s| &s.name == name)) {
        return false;
    }
    let [x0, z0, x1, z1] = scene.paint.area;
    let reach = stroke.radius + stroke.softness;
    stroke.points.iter().any(|&[x, z]| {
        let p = Vec2::new(x, z);
        let nearest = p.clamp(Vec2::new(x0, z0), Vec2::new(x1, z1));
        p.distance(nearest) <= reach
    })
}

/// Where `stroke` (in the field's space) reaches past `scene`'s paint area, the sentence that
/// says so: it paints only within the area (its edge carries the paint beneath on beyond it).
fn past_the_area(scene: &Scene, stroke: &Stroke) -> Option<String> {
    let (low, high) = stroke.reach()?;
    let [x0, z0, x1, z1] = scene.paint.area;
    let inside = low.cmpge(Vec2::new(x0, z0)).all() && high.cmple(Vec2::new(x1, z1)).all();
    let [x, z] = stroke.points[0];
    (!inside).then(|| {
        format!(
            "a GrassEdit at x {x}, z {z} (the field's own) reaches past its field's paint area \
             ([paint] area = [{x0}, {z0}, {x1}, {z1}]): it paints only within it; a wider area \
             lets edits reach further (said once)"
        )
    })
}

/// A field's scene loaded anew (hot reload) keeps what the edits painted: `held`'s edits
/// carried over to the file's scene.
pub(crate) fn repainted(scene: &Scene, held: Option<&Grass>) -> Scene {
    let mut scene = scene.clone();
    if let Some(grass) = held {
        scene.edits = grass.scene.edits.clone();
    }
    scene
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::transform::components::Transform;

    /// An app with the edits' system, its transforms propagated.
    fn app() -> App {
        let mut app = App::new();
        app.add_plugins((bevy::MinimalPlugins, bevy::transform::TransformPlugin))
            .add_message::<GrassEdit>()
            .add_systems(PostUpdate, paint_edits.after(TransformSystems::Propagate));
        app
    }

    fn strokes(app: &App, field: Entity) -> Vec<Stroke> {
        let scene = &app.world().get::<Grass>(field).unwrap().scene;
        assert!(scene.paint.strokes.is_empty(), "edits are not the file's strokes");
        scene.edits.pending().to_vec()
    }

    /// One edit in world space reaches both fields it covers, each in its own space (moved,
    /// turned, scaled), and not a field far from it; the fields hold what it painted.
    #[test]
    fn an_edit_paints_every_field_it_reaches_in_the_field_s_space() {
        let mut app = app();
        let here = app.world_mut().spawn(Grass::default()).id();
        let turned = Transform::from_xyz(10.0, 2.0, 0.0)
            .with_rotation(bevy::math::Quat::from_rotation_y(std::f32::consts::FRAC_PI_2))
            .with_scale(Vec3::splat(2.0));
        let beside = app.world_mut().spawn((Grass::default(), turned)).id();
        let far = app
            .world_mut()
            .spawn((Grass::default(), Transform::from_xyz(500.0, 0.0, 0.0)))
            .id();
        app.update();
        app.world_mut()
            .write_message(GrassEdit(Stroke::circle(Vec2::new(6.0, 0.0), 2.0).burn()));
        app.update();
        let [mine] = &strokes(&app, here)[..] else {
            panic!("one stroke here: {:?}", strokes(&app, here))
        };
        assert_eq!(mine.points, [[6.0, 0.0]]);
        assert_eq!(mine.radius, 2.0);
        let [theirs] = &strokes(&app, beside)[..] else {
            panic!("one stroke beside")
        };
        // World (6, 0) is 4 units toward -x of the turned field's origin: in its space, scaled
        // by 2, 2 units toward its own -z (a quarter turn about y takes its z to the world's x).
        let [x, z] = theirs.points[0];
        assert!(x.abs() < 1e-5 && (z + 2.0).abs() < 1e-5, "{:?}", theirs.points);
        assert_eq!(theirs.radius, 1.0);
        assert!(strokes(&app, far).is_empty(), "a field 500 units away was painted");
    }

    /// An edit that is no stroke paints nothing and leaves every field's scene valid; one naming a
    /// kind of grass paints only the fields that grow it.
    #[test]
    fn an_edit_that_is_no_stroke_is_left_out() {
        let mut app = app();
        let mut grass = Grass::default();
        grass.scene.species.push(sward_core::species::Species {
            name: "clover".into(),
            ..Default::default()
        });
        let field = app.world_mut().spawn(grass).id();
        app.update();
        let mut wrong = Stroke::circle(Vec2::ZERO, 2.0).mow(0.5);
        wrong.radius = f32::NAN;
        assert!(
            refusal(&wrong).is_some_and(|w| w.contains("radius")),
            "{:?}",
            refusal(&wrong)
        );
        app.world_mut().write_message(GrassEdit(wrong));
        app.world_mut()
            .write_message(GrassEdit(Stroke::circle(Vec2::ZERO, 2.0).mow(1.5)));
        app.world_mut()
            .write_message(GrassEdit(Stroke::circle(Vec2::ZERO, 2.0).species("no such grass")));
        app.update();
        assert!(strokes(&app, field).is_empty(), "{:?}", strokes(&app, field));
        let grass = app.world().get::<Grass>(field).unwrap();
        assert!(grass.scene.validate("Grass").is_ok());
        let kind = grass.scene.species[0].name.clone();
        app.world_mut()
            .write_message(GrassEdit(Stroke::circle(Vec2::ZERO, 2.0).species(kind.clone())));
        app.update();
        let [sown] = &strokes(&app, field)[..] else {
            panic!("{:?}", strokes(&app, field))
        };
        assert_eq!(sown.species.as_ref(), Some(&kind));
    }

    /// An edit reaching past a field's paint area is said (it paints within the area only);
    /// one within it is not.
    #[test]
    fn an_edit_past_the_paint_area_is_said() {
        let scene = Scene::default();
        let [x0, _, x1, _] = scene.paint.area;
        let within = Stroke::circle(Vec2::new(0.5 * (x0 + x1), 0.0), 2.0).mow(0.2);
        assert_eq!(past_the_area(&scene, &within), None);
        let across = Stroke::circle(Vec2::new(x1 - 0.5, 0.0), 2.0).mow(0.2);
        let said = past_the_area(&scene, &across).expect("a stroke across the edge is said");
        assert!(
            said.contains("[paint] area") && said.contains(&format!("{x1}")),
            "{said}"
        );
    }

    /// A field's edits are carried over to its scene loaded anew.
    #[test]
    fn edits_are_carried_over_to_a_reloaded_scene() {
        let mut grass = Grass::default();
        grass.paint(Stroke::circle(Vec2::ONE, 1.0).clear());
        let file = Scene::default();
        let again = repainted(&file, Some(&grass));
        assert_eq!(again.edits, grass.scene.edits);
        assert_eq!(again.edits.count(), 1);
        assert_eq!(repainted(&file, None), file);
    }

    /// A thousand edits leave a field's scene no bigger than a few do: merged at each frame's
    /// start into its paint once `MERGE_AFTER` wait, the field's scene holding at most a frame's
    /// strokes and those before the merge; and what it paints is what the thousand strokes
    /// painted one by one paint.
    #[test]
    fn a_thousand_edits_are_merged_into_the_paint() {
        let mut app = app();
        app.add_systems(PreUpdate, merge_edits);
        let field = app.world_mut().spawn(Grass::default()).id();
        app.update();
        let mut one_by_one = Scene::default();
        let mut most_waiting = 0;
        for k in 0..1000 {
            let at = Vec2::new((k % 40) as f32 * 0.3 - 6.0, (k / 40) as f32 * 0.5 - 6.0);
            let stroke = Stroke::circle(at, 0.6).mow(0.2 + (k % 5) as f32 * 0.1);
            one_by_one.paint.strokes.push(stroke.clone());
            app.world_mut().write_message(GrassEdit(stroke));
            app.update();
            let edits = &app.world().get::<Grass>(field).unwrap().scene.edits;
            most_waiting = most_waiting.max(edits.pending().len());
            assert_eq!(edits.count(), k + 1);
        }
        assert!(
            most_waiting <= sward_core::paint_edits::MERGE_AFTER + 1,
            "{most_waiting} strokes waited"
        );
        let scene = &app.world().get::<Grass>(field).unwrap().scene;
        let [merged, painted] = [scene, &one_by_one].map(|s| s.paint_map().unwrap().unwrap().map.unwrap());
        assert!(
            merged == painted,
            "the merged edits paint what the strokes painted one by one do"
        );
    }
}
