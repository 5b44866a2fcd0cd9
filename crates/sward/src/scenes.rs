//! Scenes that ship inside the binary, and resolving `--scene` (a shipped name or a path).

use std::path::Path;

use anyhow::bail;
use sward_core::Scene;

/// (name, TOML text) of every scene in `scenes/`.
pub const SHIPPED: &[(&str, &str)] = &[
    ("meadow", include_str!("../../../scenes/meadow.toml")),
    ("planet", include_str!("../../../scenes/planet.toml")),
    ("hills", include_str!("../../../scenes/hills.toml")),
    ("trample", include_str!("../../../scenes/trample.toml")),
    ("landscape", include_str!("../../../scenes/landscape.toml")),
    ("prairie", include_str!("../../../scenes/prairie.toml")),
    ("trail", include_str!("../../../scenes/trail.toml")),
    ("openworld", include_str!("../../../scenes/openworld.toml")),
    ("park", include_str!("../../../scenes/park.toml")),
];

/// Load `--scene` and apply the `--set` overrides.
pub fn load_with(arg: &str, sets: &[(String, String)]) -> anyhow::Result<Scene> {
    let scene = load(arg)?;
    if sets.is_empty() {
        return Ok(scene);
    }
    Ok(scene.with_overrides(sets)?)
}

/// Load `--scene`: a path if one exists (or it looks like one), else a shipped scene's name.
pub fn load(arg: &str) -> anyhow::Result<Scene> {
    let path = Path::new(arg);
    if path.exists() || arg.ends_with(".toml") || arg.contains('/') {
        return Ok(Scene::load(path)?);
    }
    match SHIPPED.iter().find(|(name, _)| *name == arg) {
        Some((name, text)) => Ok(Scene::from_toml(text, &format!("shipped scene {name}"))?),
        None => {
            let names: Vec<&str> = SHIPPED.iter().map(|(n, _)| *n).collect();
            let hint = sward_core::words::nearest(arg, names.iter().copied())
                .map_or_else(String::new, |near| format!("did you mean {near}? "));
            bail!(
                "no scene named '{arg}'; {hint}shipped scenes are {}, or give a path to a .toml file",
                names.join(", ")
            )
        }
    }
}

/// `sward scene`: every key of a scene file, as a commented scene file or (`markdown`) as the
/// reference page `docs/scene-reference.md`.
pub fn print_reference(markdown: bool) -> anyhow::Result<()> {
    let keys = sward_core::reference::reference().map_err(anyhow::Error::msg)?;
    match markdown {
        true => print!("{}", sward_core::reference::markdown(&keys)),
        false => print!("{}", sward_core::reference::commented_scene(&keys)),
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mistyped_scene_name_is_answered_with_the_nearest() {
        let said = load("prarie").unwrap_err().to_string();
        assert!(
            said.contains("no scene named 'prarie'; did you mean prairie?"),
            "{said}"
        );
        let far = load("zzzzzzzz").unwrap_err().to_string();
        assert!(!far.contains("did you mean"), "{far}");
    }

    #[test]
    fn every_shipped_scene_loads() {
        for (name, _) in SHIPPED {
            let scene = load(name).unwrap_or_else(|e| panic!("{name}: {e:#}"));
            assert_eq!(&scene.name, name);
        }
        let trample = load("trample").unwrap();
        assert_eq!(trample.colliders.len(), 64);
        assert!(trample.colliders.iter().all(|c| c.path.len() == 8));
        // The spheres travel: where they are differs from frame to frame.
        let (a, b) = (trample.colliders[0].at(0.0), trample.colliders[0].at(1.0));
        assert!(a.center.distance(b.center) > 0.5);
        // The boulder adds its packed spheres, and they move too.
        assert_eq!(trample.colliders_at(0.0).len(), 64 + 16);
        let boulder = |t| trample.colliders_at(t)[64].center;
        assert!(boulder(0.0).distance(boulder(1.0)) > 0.5);
    }

    /// The scale preset: 2^24 blades with physics, at least 16 moving spheres resting on the
    /// rolling terrain (half sunk, as in the trample scene), and a camera at a person's eye height.
    #[test]
    fn prairie_is_the_scale_preset_on_its_terrain() {
        let prairie = load("prairie").unwrap();
        assert!(prairie.field.blades >= 1 << 24);
        assert!(prairie.colliders.len() >= 16);
        let sward_core::scene::Surface::Terrain {
            size,
            height,
            resolution,
            seed,
        } = prairie.surface
        else {
            panic!("the prairie grows on terrain");
        };
        let grid = sward_core::mesh::Mesh::terrain(size, height, resolution, seed)
            .height_grid()
            .unwrap();
        let ground = |p: glam::Vec3| grid.height_at(p.x, p.z).expect("on the terrain");
        let eye = prairie.camera.position;
        let above = eye.y - ground(eye);
        assert!((1.4..2.1).contains(&above), "the eye is {above:.2} above the ground");
        for c in &prairie.colliders {
            assert!(c.path.len() >= 4 && c.speed > 0.0);
            for p in &c.path {
                let rest = p.y - ground(*p);
                assert!(
                    (rest - 0.5 * c.radius).abs() < 0.1 * c.radius,
                    "a sphere of radius {} at {p} sits {rest:.2} above the ground",
                    c.radius
                );
            }
        }
    }

    /// The park paints what it shows: bare paths, lawns only along them, three kinds of grass,
    /// and its boulder rests half sunk on the terrain with the ground bare under it.
    #[test]
    fn the_park_paints_paths_lawns_and_kinds_of_grass() {
        let park = load("park").unwrap();
        assert_eq!(park.species.len(), 3);
        let paint = park.paint_map().unwrap().expect("the park is painted");
        let at = |x: f32, z: f32| paint.at(glam::Vec2::new(x, z));
        // On the path, beside it on the lawn, and out in the meadow.
        assert_eq!(at(0.0, -20.0).density, 0.0);
        assert_eq!(at(4.0, -20.0).density, 1.0);
        assert_eq!(at(4.0, -20.0).species[2], 1.0);
        assert_eq!(at(4.0, -20.0).species[0], 0.0);
        assert_eq!(at(40.0, -20.0).species, [1.0, 1.0, 0.0, 1.0]);
        let sward_core::scene::Surface::Terrain {
            size,
            height,
            resolution,
            seed,
        } = park.surface
        else {
            panic!("the park lies on terrain");
        };
        let grid = sward_core::mesh::Mesh::terrain(size, height, resolution, seed)
            .height_grid()
            .unwrap();
        let boulder = &park.bodies[0];
        let ground = grid.height_at(boulder.center.x, boulder.center.z).unwrap();
        eprintln!("the ground under the boulder is at {ground}");
        assert!(
            (boulder.center.y - ground - 0.5).abs() < 0.2,
            "the boulder's centre is {} above the ground",
            boulder.center.y - ground
        );
        assert_eq!(at(boulder.center.x, boulder.center.z).density, 0.0);
        // The still camera stands at a person's eye height over the path, looking along it.
        let eye = park.camera.position;
        let above = eye.y - grid.height_at(eye.x, eye.z).unwrap();
        let target = park.camera.target;
        eprintln!(
            "eye {above} above; target ground {}",
            grid.height_at(target.x, target.z).unwrap()
        );
        assert!((1.4..2.1).contains(&above), "the eye is {above:.2} above the ground");
        assert_eq!(at(eye.x, eye.z).density, 0.0, "the eye stands on the path");
    }
}
