//! The viewer's paint brush: dabs of density, length or one kind of grass painted onto the
//! ground under the cursor. A drag is a stroke of the scene (`[[paint.stroke]]`, so regrowing
//! the field and saving the scene keep it) and is painted at once into the paint the renderer
//! holds, so every technique shows it the next frame. "Save maps" bakes the paint into PNG
//! files beside the saved scene and names them in it.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use sward_core::mesh::HeightGrid;
use sward_core::paint::{GroundPaint, PaintMap, Stroke};
use sward_core::Scene;

/// What the brush paints.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Painting {
    /// How much grass grows (0 bare, 1 all).
    Density,
    /// How tall it grows (a fraction of its height).
    Length,
    /// Only the species of this index grows.
    Species(usize),
}

/// The brush and the drag it is painting.
#[derive(Clone, Debug)]
pub struct Brush {
    /// Whether a left drag paints (instead of turning the camera).
    pub on: bool,
    pub painting: Painting,
    /// The density or length painted.
    pub value: f32,
    /// Units of ground it paints around the cursor.
    pub radius: f32,
    /// How far beyond its radius the brush fades out, as a share of the radius (a stroke's
    /// `softness` is this times the radius).
    pub falloff: f32,
    /// How far toward its value the brush paints, 0..1 (a stroke's `strength`): light strokes
    /// thin or shorten the grass a little at a time.
    pub strength: f32,
    /// The scene stroke the current drag extends, and the last point it painted.
    drag: Option<(usize, Vec2)>,
}

impl Default for Brush {
    fn default() -> Self {
        Brush {
            on: false,
            painting: Painting::Density,
            value: 0.0,
            radius: 1.5,
            falloff: 1.0 / 3.0,
            strength: 1.0,
            drag: None,
        }
    }
}

impl Brush {
    /// Paint at world ground point `xz`: the drag's stroke in `scene` gains the point, and the
    /// new stretch is painted into `paint` (made over `[paint] area` if the scene had none).
    /// Returns whether anything was painted (points closer than a fifth of the radius to the
    /// last are skipped).
    pub fn dab(&mut self, scene: &mut Scene, paint: &mut Option<GroundPaint>, xz: Vec2) -> bool {
        let from = match self.drag {
            Some((_, last)) if last.distance(xz) < 0.2 * self.radius => return false,
            Some((_, last)) => last,
            None => xz,
        };
        let species = match self.painting {
            Painting::Species(k) => Some(k),
            _ => None,
        };
        let stroke = self.stroke(vec![from.into(), xz.into()], scene);
        let map = paint
            .get_or_insert_with(GroundPaint::default)
            .map
            .get_or_insert_with(|| PaintMap::blank(&scene.paint, &scene.species));
        map.paint_stroke(&stroke, species);
        match self.drag {
            Some((k, _)) => scene.paint.strokes[k].points.push(xz.into()),
            None => {
                scene.paint.strokes.push(Stroke {
                    points: vec![xz.into()],
                    ..stroke
                });
            }
        }
        let k = self.drag.map_or(scene.paint.strokes.len() - 1, |(k, _)| k);
        self.drag = Some((k, xz));
        true
    }

    /// End the drag; whether it painted anything.
    pub fn lift(&mut self) -> bool {
        self.drag.take().is_some()
    }

    /// A stroke of this brush through `points`, in `scene` (whose species it names).
    fn stroke(&self, points: Vec<[f32; 2]>, scene: &Scene) -> Stroke {
        let (density, length) = match self.painting {
            Painting::Density => (Some(self.value), None),
            Painting::Length => (None, Some(self.value)),
            Painting::Species(_) => (None, None),
        };
        let species = match self.painting {
            Painting::Species(k) => scene.species.get(k).map(|s| s.name.clone()),
            _ => None,
        };
        Stroke {
            points,
            radius: self.radius,
            softness: self.radius * self.falloff,
            density,
            length,
            color: None,
            species,
            strength: self.strength,
        }
    }
}

/// Where the ray from `eye` along `ray` meets the ground: the height grid where there is one,
/// else the plane y = 0; `None` if it meets nothing within 2000 units.
pub fn ground_hit(eye: Vec3, ray: Vec3, grid: Option<&HeightGrid>) -> Option<Vec3> {
    let height = |p: Vec3| grid.map_or(Some(0.0), |g| g.height_at(p.x, p.z));
    let below = |t: f32| {
        let p = eye + ray * t;
        height(p).is_some_and(|h| p.y <= h)
    };
    // March in steps that grow with distance, then halve the last one down to a centimetre.
    let (mut t0, mut t) = (0.0f32, 0.05f32);
    while !below(t) {
        if t > 2000.0 {
            return None;
        }
        t0 = t;
        t += (0.02 * t).max(0.05);
    }
    while t - t0 > 0.01 {
        let mid = 0.5 * (t0 + t);
        if below(mid) {
            t = mid;
        } else {
            t0 = mid;
        }
    }
    Some(eye + ray * t)
}

/// Write `paint`'s maps as PNG files named after `scene` into `dir` and name them in the scene
/// (its strokes, baked into them, are dropped): the density, length and colour maps, and each
/// species' weight map. Returns the files written.
pub fn save_maps(scene: &mut Scene, paint: &GroundPaint, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let Some(map) = &paint.map else {
        anyhow::bail!("nothing is painted yet: paint with the brush first");
    };
    std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("cannot make {}: {e}", dir.display()))?;
    let images = map.images(scene.species.len());
    let mut written = Vec::new();
    let mut save = |name: &str, image: image::DynamicImage| -> anyhow::Result<String> {
        let path = dir.join(format!("{}-{name}.png", scene.name));
        image
            .save(&path)
            .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))?;
        written.push(path.clone());
        Ok(path.display().to_string())
    };
    scene.paint.density = Some(save("density", images.density.into())?);
    scene.paint.length = Some(save("length", images.length.into())?);
    scene.paint.color = Some(save("color", images.color.into())?);
    for (k, weights) in images.species.into_iter().enumerate() {
        let name = format!("species-{}", scene.species[k].name);
        scene.species[k].weight_map = Some(save(&name, weights.into())?);
    }
    scene.paint.strokes.clear();
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn park() -> Scene {
        Scene::from_toml(include_str!("../../../../scenes/park.toml"), "park").unwrap()
    }

    #[test]
    fn a_drag_paints_one_stroke_that_regrowing_replays() {
        let mut scene = park();
        let strokes = scene.paint.strokes.len();
        let mut paint = scene.paint_map().unwrap();
        let mut brush = Brush {
            on: true,
            ..Brush::default()
        };
        // A bare line from (20, 0) to (30, 0), dabbed every half unit.
        for i in 0..=20 {
            brush.dab(&mut scene, &mut paint, Vec2::new(20.0 + 0.5 * i as f32, 0.0));
        }
        assert!(brush.lift());
        assert_eq!(scene.paint.strokes.len(), strokes + 1);
        let at = |p: &Option<GroundPaint>, x: f32| p.as_ref().unwrap().at(Vec2::new(x, 0.0)).density;
        assert_eq!(at(&paint, 25.0), 0.0);
        assert_eq!(at(&paint, 25.0 + 0.0), at(&scene.paint_map().unwrap(), 25.0));
        // Beside the line the meadow is untouched.
        assert_eq!(at(&paint, 40.0), 1.0);
    }

    /// A half-strength brush thins the grass halfway to its value, and a brush with no falloff
    /// leaves the grass just beyond its radius as it was, where the default one fades.
    #[test]
    fn the_brush_s_strength_and_falloff_reach_the_paint() {
        let density_after = |brush: Brush, x: f32| {
            let mut scene = park();
            let mut paint = scene.paint_map().unwrap();
            let mut brush = Brush { on: true, ..brush };
            brush.dab(&mut scene, &mut paint, Vec2::new(30.0, 0.0));
            brush.lift();
            assert_eq!(scene.paint.strokes.last().unwrap().strength, brush.strength);
            paint.unwrap().at(Vec2::new(x, 0.0)).density
        };
        let full = density_after(Brush::default(), 30.0);
        let half = density_after(
            Brush {
                strength: 0.5,
                ..Brush::default()
            },
            30.0,
        );
        assert_eq!(full, 0.0);
        assert!((half - 0.5).abs() < 0.02, "a half-strength stroke left {half}");
        // Halfway through the default fade beyond the radius: half thinned, and untouched
        // without a falloff.
        let beyond = 30.0 + 1.5 + 0.25;
        let soft = density_after(Brush::default(), beyond);
        let hard = density_after(
            Brush {
                falloff: 0.0,
                ..Brush::default()
            },
            beyond,
        );
        assert!(
            (0.2..0.8).contains(&soft) && hard > 0.98,
            "beyond the radius: {soft} soft, {hard} hard"
        );
    }

    #[test]
    fn saved_maps_load_back_as_the_paint_they_bake() {
        let mut scene = park();
        let mut paint = scene.paint_map().unwrap();
        let mut brush = Brush {
            on: true,
            painting: Painting::Length,
            value: 0.25,
            ..Brush::default()
        };
        brush.dab(&mut scene, &mut paint, Vec2::new(-30.0, 5.0));
        brush.lift();
        let dir = std::env::temp_dir().join(format!("sward-brush-{}", std::process::id()));
        let painted = paint.clone().unwrap();
        let written = save_maps(&mut scene, &painted, &dir).unwrap();
        assert_eq!(written.len(), 3 + scene.species.len());
        assert!(scene.paint.strokes.is_empty());
        let reloaded = scene.paint_map().unwrap().unwrap();
        for p in [
            Vec2::new(-30.0, 5.0),
            Vec2::new(0.0, -20.0),
            Vec2::new(4.0, -20.0),
            Vec2::new(60.0, 60.0),
        ] {
            let (a, b) = (painted.at(p), reloaded.at(p));
            assert!((a.density - b.density).abs() < 0.01, "{p}: {a:?} {b:?}");
            assert!((a.length - b.length).abs() < 0.01, "{p}: {a:?} {b:?}");
            assert!((a.tint - b.tint).abs().max_element() < 0.02, "{p}: {a:?} {b:?}");
            let kinds = scene.species.len();
            assert_eq!(a.species[..kinds], b.species[..kinds], "{p}");
        }
        assert!((reloaded.at(Vec2::new(-30.0, 5.0)).length - 0.25).abs() < 0.01);
    }

    #[test]
    fn the_cursor_finds_the_ground_on_a_plane_and_misses_the_sky() {
        let eye = Vec3::new(0.0, 2.0, 0.0);
        let hit = ground_hit(eye, Vec3::new(0.0, -1.0, 1.0).normalize(), None).unwrap();
        assert!(hit.distance(Vec3::new(0.0, 0.0, 2.0)) < 0.02, "{hit}");
        assert!(ground_hit(eye, Vec3::new(0.0, 0.2, 1.0).normalize(), None).is_none());
    }
}
