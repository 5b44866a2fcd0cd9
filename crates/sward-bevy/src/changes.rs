//! What becomes of a change to a grass's scene while the app runs. Almost every value takes
//! effect: the field is grown again or repainted (`render_world::vulkan::taking`), or the next frame's
//! description carries it. A few are Bevy's to decide — the camera (Bevy's cameras see the
//! grass) and, unless the grass is lit by its scene, the sun, the overhead sky, ambient and fog
//! (Bevy's lights, exposure and fog; the horizon's colour is the fog's where Bevy has fog, else
//! the scene's), the shading model where Bevy's PBR lights the grass, and the generated grass's
//! own sizes where kinds of grass give them; a change to one of those is said once as a
//! warning, naming the keys and why. A change that leaves the scene invalid (a value out of its
//! range, set from an inspector or code) is said once and not applied: the grass keeps its last
//! valid scene ([`keep_valid`]).

use std::collections::HashSet;

use bevy::app::{App, PostUpdate};
use bevy::ecs::prelude::*;
use sward_core::Scene;

use crate::components::Grass;
use crate::lighting::GrassLighting;

/// The last valid scene of a grass entity, which a change that fails validation falls back to.
#[derive(Component, Clone, Debug)]
pub(crate) struct LastValid(Scene);

pub(crate) fn build(app: &mut App) {
    app.add_systems(
        PostUpdate,
        // After the scenes loaded this frame are taken, before anything reads the grass.
        keep_valid
            .in_set(crate::GrassSystems)
            .after(crate::assets::grow_from_sources)
            .before(crate::budget::share_budget),
    );
}

/// Each changed grass's scene checked as [`Grass::new`] checks one: valid, it is kept as the
/// grass's last valid scene; not, the sentence is said once and the grass's scene set back to
/// its last valid one (a grass that never had one is taken out: nothing of it is drawn).
pub(crate) fn keep_valid(
    mut grass: Query<(Entity, &mut Grass, Option<&mut LastValid>), Changed<Grass>>,
    mut commands: Commands,
    mut told: Local<HashSet<String>>,
) {
    for (entity, mut grass, last) in &mut grass {
        let why = match grass.scene.validate("Grass") {
            Ok(()) => {
                match last {
                    Some(mut last) if last.0 != grass.scene => last.0.clone_from(&grass.scene),
                    Some(_) => {}
                    None => {
                        commands.entity(entity).insert(LastValid(grass.scene.clone()));
                    }
                }
                continue;
            }
            Err(why) => why.to_string(),
        };
        let kept = match &last {
            Some(_) => "not applied: the grass keeps its last valid scene",
            None => "the Grass is taken out of its entity (build it with Grass::new, which says what is wrong)",
        };
        if told.insert(why.clone()) {
            bevy::log::warn!("{why}; {kept}");
        }
        match last {
            Some(last) => grass.scene.clone_from(&last.0),
            None => {
                commands.entity(entity).remove::<Grass>();
            }
        }
    }
}

/// The keys whose change in `new` from `old` Bevy overrides for grass lit by `lighting`, each
/// with why.
pub(crate) fn overridden(old: &Scene, new: &Scene, lighting: GrassLighting) -> Vec<(&'static str, &'static str)> {
    const CAMERA: &str = "Bevy's cameras see the grass";
    const NAME: &str = "the app names its own windows and files";
    const PBR: &str = "Bevy's PBR lights the grass drawn in Bevy's passes, as a rough two-sided surface (GrassLighting::Bevy or Scene draw it with the scene's model)";
    const KINDS: &str = "its kinds of grass ([[species]]) give the generated grass its heights, widths and lean";
    const LIGHT: &str = "Bevy's lights, exposure and fog light the grass (GrassLighting::Scene lights it by its scene)";
    let (a, b) = (&old.shading, &new.shading);
    let by_bevy = lighting != GrassLighting::Scene;
    let kinds = !new.species.is_empty();
    let pbr = lighting == GrassLighting::Pbr;
    [
        ("name", old.name != new.name, NAME),
        ("camera", old.camera != new.camera, CAMERA),
        ("camera_path", old.camera_path != new.camera_path, CAMERA),
        (
            "shading.light_direction",
            by_bevy && a.light_direction != b.light_direction,
            LIGHT,
        ),
        ("shading.light_color", by_bevy && a.light_color != b.light_color, LIGHT),
        ("shading.ambient", by_bevy && a.ambient != b.ambient, LIGHT),
        ("shading.sky_zenith", by_bevy && a.sky_zenith != b.sky_zenith, LIGHT),
        ("shading.fog_density", by_bevy && a.fog_density != b.fog_density, LIGHT),
        ("shading.model", pbr && a.model != b.model, PBR),
        ("shading.specular", pbr && a.specular != b.specular, PBR),
        ("shading.shininess", pbr && a.shininess != b.shininess, PBR),
        (
            "instanced.height",
            kinds && old.instanced.grid.height != new.instanced.grid.height,
            KINDS,
        ),
        (
            "instanced.width",
            kinds && old.instanced.grid.width != new.instanced.grid.width,
            KINDS,
        ),
        (
            "instanced.bend",
            kinds && old.instanced.bend != new.instanced.bend,
            KINDS,
        ),
    ]
    .into_iter()
    .filter(|(_, changed, _)| *changed)
    .map(|(key, _, why)| (key, why))
    .collect()
}

/// The one sentence that says `keys` (with why) changed to no effect; `None` where none did.
pub(crate) fn warning(keys: &[(&'static str, &'static str)]) -> Option<String> {
    let (_, why) = keys.first()?;
    let named: Vec<&str> = keys.iter().map(|(k, _)| *k).collect();
    let more: Vec<&str> = keys.iter().map(|(_, w)| *w).filter(|w| w != why).collect();
    let mut sentence = format!(
        "the grass's scene changed {}, which sward does not use in Bevy: {why}",
        named.join(", ")
    );
    if let Some(other) = more.first() {
        sentence.push_str(&format!("; {other}"));
    }
    Some(sentence)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A value out of its range set on a grass (as an inspector sets one) is not applied: the
    /// grass's scene goes back to its last valid one; a grass spawned with an invalid scene is
    /// taken out; `Grass::default()` is valid.
    #[test]
    fn an_invalid_change_is_not_applied() {
        let mut app = App::new();
        app.add_plugins(bevy::MinimalPlugins)
            .add_systems(PostUpdate, keep_valid);
        let valid = Grass::default();
        assert!(valid.scene.validate("Grass").is_ok());
        let field = app.world_mut().spawn(valid.clone()).id();
        app.update();
        let mut changed = app.world_mut().get_mut::<Grass>(field).expect("a grass");
        changed.scene.shading.fog_density = -1.0;
        app.update();
        let kept = app.world().get::<Grass>(field).expect("still a grass");
        assert_eq!(kept.scene.shading.fog_density, valid.scene.shading.fog_density);
        let mut changed = app.world_mut().get_mut::<Grass>(field).expect("a grass");
        changed.scene.shading.fog_density = 0.02;
        app.update();
        let density = app.world().get::<Grass>(field).map(|g| g.scene.shading.fog_density);
        assert_eq!(density, Some(0.02));
        let mut invalid = Grass::default();
        invalid.scene.shading.fog_density = f32::NAN;
        let spawned = app.world_mut().spawn(invalid).id();
        app.update();
        assert!(app.world().get::<Grass>(spawned).is_none());
    }
    use crate::render_world::frames::{taking, Taking};
    use sward_core::FrameDesc;

    /// The frame sward draws of `scene` in Bevy lit by `lighting`: Bevy's camera, and (unless
    /// lit by the scene) Bevy's sun, sky and fog.
    fn frame(scene: &Scene, lighting: GrassLighting) -> FrameDesc {
        let bevy_camera = sward_core::Camera::default();
        // Over a second in: where the colliders' paths have taken them, at their speeds.
        let mut frame = FrameDesc::of_scene(scene, glam::Vec2::splat(100.0), (1.3, 1), [640, 480])
            .with_view_projection(bevy_camera.view(), bevy_camera.projection(640.0 / 480.0));
        if lighting != GrassLighting::Scene {
            let sun = crate::lighting::Sun {
                toward: glam::Vec3::new(0.3, 1.0, 0.2),
                lux: glam::Vec3::splat(10_000.0),
            };
            crate::lighting::ViewLight::of(Some(sun), None, None, 1.0, None).light(&mut frame.shading);
        }
        frame
    }

    /// The words of the scene's choices (techniques, shapes, presets, routes, models, winds).
    const WORDS: &[&str] = &[
        "instanced",
        "both",
        "landscape",
        "billboard",
        "linear",
        "triangle",
        "low",
        "medium",
        "ultra",
        "tessellation",
        "compute",
        "mesh",
        "lambert",
        "off",
        "all",
        "noise",
        "gusts",
        "64",
        "rock",
    ];

    /// Values `v` could be changed to, nearest first.
    fn nudged(v: &toml::Value) -> Vec<toml::Value> {
        use toml::Value;
        match v {
            Value::Integer(i) => vec![Value::Integer(i + 1), Value::Integer(i - 1), Value::Integer(i * 2)],
            Value::Float(f) => [f * 1.25 + 0.05, f * 0.8, f - 0.05, f + 1.0].map(Value::Float).to_vec(),
            Value::Boolean(b) => vec![Value::Boolean(!b)],
            // A word: one of the words the scene's choices take (those that do not fit its key
            // fail to read), or another file or name.
            Value::String(w) => WORDS
                .iter()
                .filter(|&&o| o != w)
                .map(|o| Value::String(o.to_string()))
                .chain([Value::String(format!("other-{w}"))])
                .collect(),
            Value::Array(a) if !a.is_empty() => nudged(&a[0])
                .into_iter()
                .map(|first| {
                    let mut a = a.clone();
                    a[0] = first;
                    Value::Array(a)
                })
                .collect(),
            _ => Vec::new(),
        }
    }

    /// Every number and switch of every table of a scene with every table filled in (the scene
    /// reference's), changed one at a time: where would `change` have an effect.
    fn every_change(mut change: impl FnMut(&str, &Scene, &Scene)) -> usize {
        let example = sward_core::reference::example_scene();
        let table: toml::Table = toml::from_str(&example.to_toml()).unwrap();
        let mut changed = 0;
        let mut leaves = Vec::new();
        collect(&toml::Value::Table(table.clone()), String::new(), &mut leaves);
        let leaves_seen = leaves.len();
        for (path, value) in leaves {
            for new in nudged(&value) {
                let mut edited = toml::Value::Table(table.clone());
                set(&mut edited, &path, new);
                let Ok(scene) = toml::to_string(&edited).map_err(|e| e.to_string()).and_then(|t| {
                    let scene = Scene::from_toml(&t, "changed").map_err(|e| e.to_string())?;
                    Ok(scene)
                }) else {
                    continue;
                };
                if scene != example {
                    change(&path, &example, &scene);
                    changed += 1;
                    break;
                }
            }
        }
        eprintln!("{changed} of {leaves_seen} values changed");
        changed
    }

    /// Every leaf of `v` under `at` (a list's first item only), with its path.
    fn collect(v: &toml::Value, at: String, into: &mut Vec<(String, toml::Value)>) {
        let join = |k: &str| {
            if at.is_empty() {
                k.to_string()
            } else {
                format!("{at}.{k}")
            }
        };
        match v {
            toml::Value::Table(t) => t.iter().for_each(|(k, v)| collect(v, join(k), into)),
            toml::Value::Array(a) if a.first().is_some_and(|f| f.is_table()) => {
                collect(&a[0], format!("{at}[0]"), into)
            }
            _ => into.push((at, v.clone())),
        }
    }

    /// Set the leaf at `path` of `v` (`[0]`: a list's first item).
    fn set(v: &mut toml::Value, path: &str, to: toml::Value) {
        let mut here = v;
        for part in path.split('.') {
            let (key, first) = match part.strip_suffix("[0]") {
                Some(k) => (k, true),
                None => (part, false),
            };
            here = here.get_mut(key).expect("a key of the scene");
            if first {
                here = here.get_mut(0).expect("a listed table");
            }
        }
        *here = to;
    }

    #[test]
    fn every_value_a_game_changes_takes_effect_or_is_warned() {
        for lighting in [GrassLighting::Pbr, GrassLighting::Scene] {
            let mut ignored = Vec::new();
            let mut warned = 0;
            let changed = every_change(|key, old, new| {
                let grown = !matches!(taking(Some(old), new), Taking::Nothing);
                let drawn = frame(old, lighting) != frame(new, lighting);
                let said = overridden(old, new, lighting);
                warned += !said.is_empty() as usize;
                // A travelling collider's centre and clearing: placed by its path (below).
                let placed_by_path = [
                    "collider[0].center",
                    "collider[0].clear",
                    "body[0].center",
                    "body[0].clear",
                ];
                if !grown && !drawn && said.is_empty() && !placed_by_path.contains(&key) {
                    ignored.push(key.to_string());
                }
                // A key Bevy overrides is warned, not also grown or (but for the shading model,
                // which the frame carries for sward's own pass) drawn.
                let model = ["shading.model", "shading.specular", "shading.shininess"].contains(&key);
                if !said.is_empty() {
                    assert!(
                        (!drawn || model) && !grown,
                        "{key} is warned of with {lighting:?} but takes effect"
                    );
                }
            });
            eprintln!("{lighting:?}: {changed} values changed, {warned} warned of");
            assert!(changed >= 155, "only {changed} values of the scene were changed");
            assert!(warned >= 2, "the camera's changes are warned of");
            assert!(
                ignored.is_empty(),
                "{lighting:?}: changed with no effect and no warning: {ignored:?}"
            );
        }
    }

    /// Where and whether a collider (or body) clears the ground is read where it stands; one
    /// that travels a path is placed by it (its `center` and `clear` unused, as the scene file
    /// says): standing, a change to either takes effect.
    #[test]
    fn a_standing_collider_s_place_and_clearing_take_effect() {
        let mut standing = sward_core::reference::example_scene();
        standing.colliders[0].path.clear();
        standing.bodies[0].path.clear();
        let changes: [fn(&mut Scene); 4] = [
            |s| s.colliders[0].center.x += 1.0,
            |s| s.colliders[0].clear = !s.colliders[0].clear,
            |s| s.bodies[0].center.x += 1.0,
            |s| s.bodies[0].clear = !s.bodies[0].clear,
        ];
        for change in changes {
            let mut changed = standing.clone();
            change(&mut changed);
            let grown = !matches!(taking(Some(&standing), &changed), Taking::Nothing);
            let drawn = frame(&standing, GrassLighting::Pbr) != frame(&changed, GrassLighting::Pbr);
            assert!(grown || drawn, "a standing collider's change has no effect");
        }
    }

    #[test]
    fn a_change_bevy_overrides_is_said_in_one_sentence() {
        let old = Scene::default();
        let mut new = old.clone();
        new.camera.position.x += 1.0;
        new.shading.fog_density += 0.01;
        let keys = overridden(&old, &new, GrassLighting::Pbr);
        let sentence = warning(&keys).unwrap();
        assert!(
            sentence.contains("camera, shading.fog_density")
                && sentence.contains("Bevy's cameras")
                && sentence.contains("GrassLighting::Scene"),
            "{sentence}"
        );
        assert_eq!(
            overridden(&old, &new, GrassLighting::Scene).len(),
            1,
            "lit by its scene, only the camera"
        );
        assert!(warning(&[]).is_none());
    }
}
