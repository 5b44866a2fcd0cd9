//! The scene description: everything a user may change, as one TOML file with one default per
//! value, and its validation. Bad input becomes one sentence that names the file, the key, the
//! problem and what is allowed.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::camera::{Camera, CameraPath};
use crate::cull::{CullParams, LodParams};
pub use crate::field::Surface;
use crate::field::{Field, FieldDesc};
use crate::look::{BladeStyle, Shading};
use crate::mesh::MeshError;
use crate::physics::{Collider, SimParams, MAX_COLLIDERS};
use crate::wind::{Winds, MAX_WINDS};

/// The most blades one field may hold (2^26: 4 GiB of blades would be the next step).
pub const MAX_BLADES: u32 = 1 << 26;

/// Everything a rendered scene is made of: the scene file, read and validated.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Scene {
    /// The scene's name (window title, saved file names).
    pub name: String,
    /// Bezier blades with physics, the instanced field, or both.
    pub technique: crate::instanced::Technique,
    /// What the grass grows on.
    pub surface: Surface,
    /// How many blades grow and how they vary.
    pub field: FieldDesc,
    /// The camera the scene opens with.
    pub camera: Camera,
    /// Where the camera travels in animations (`sward render --animation`).
    pub camera_path: CameraPath,
    /// The simulation: fixed step, forces, gravity, collision decay.
    pub simulation: SimParams,
    /// Winds, summed (up to four).
    pub wind: Winds,
    /// Collider spheres, each standing or travelling a looped path.
    #[serde(rename = "collider")]
    pub colliders: Vec<Collider>,
    /// Mesh colliders, each approximated by a set of spheres.
    #[serde(rename = "body")]
    pub bodies: Vec<crate::bodies::Body>,
    /// Which culling tests run, and their thresholds.
    pub cull: CullParams,
    /// Level of detail and the compute route's hand-over distances.
    pub lod: LodParams,
    /// The blades' shape.
    pub blades: BladeStyle,
    /// Light, colours, shadows and fog.
    pub shading: Shading,
    /// The instanced field (techniques `instanced`, `both` and `landscape`).
    pub instanced: crate::instanced::InstancedParams,
    /// Billboard grass (techniques `billboard` and `landscape`).
    pub billboard: crate::billboard::BillboardParams,
    /// How much the renderer spends per pixel and per blade (`high`: the reference picture).
    pub quality: crate::quality::Quality,
    /// The trample map: where colliders flattened the generated grass, fading as blades recover.
    pub trample: crate::trample::TrampleParams,
}

impl Default for Scene {
    fn default() -> Self {
        Self {
            name: "default".into(),
            technique: Default::default(),
            instanced: Default::default(),
            billboard: Default::default(),
            trample: Default::default(),
            quality: Default::default(),
            surface: Surface::Plane,
            field: FieldDesc::default(),
            camera: Camera::default(),
            camera_path: CameraPath::default(),
            simulation: SimParams::default(),
            wind: Winds::default(),
            colliders: Vec::new(),
            bodies: Vec::new(),
            cull: CullParams::default(),
            lod: LodParams::default(),
            blades: BladeStyle::default(),
            shading: Shading::default(),
        }
    }
}

/// Parse scene text without validating it; `origin` names it in errors.
fn parse(text: &str, origin: &str) -> Result<Scene, SceneError> {
    let scene: Scene = toml::from_str(text).map_err(|e| {
        let (line, column) = e.span().map(|s| line_column(text, s.start)).unwrap_or((1, 1));
        SceneError::Syntax {
            origin: origin.into(),
            line,
            column,
            message: e.message().trim().replace('\n', "; "),
        }
    })?;
    let written: toml::Table = toml::from_str(text).expect("a scene that parsed is a TOML table");
    check_array_lengths(&written, &scene, origin)?;
    Ok(scene)
}

/// The largest number a scene may hold anywhere (units, seconds, strengths): beyond it, float
/// arithmetic on the GPU (a view matrix of a camera 1e30 units away) overflows to infinity.
pub const MAX_MAGNITUDE: f64 = 1e6;

/// The first number of the scene (dotted key, value) that is not finite or larger than
/// `MAX_MAGNITUDE`.
fn first_absurd_number(value: &toml::Value, key: &str) -> Option<(String, f64)> {
    match value {
        toml::Value::Float(f) if !f.is_finite() || f.abs() > MAX_MAGNITUDE => Some((key.to_string(), *f)),
        toml::Value::Table(t) => t.iter().find_map(|(k, v)| first_absurd_number(v, &dotted(key, k))),
        toml::Value::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(i, v)| first_absurd_number(v, &dotted(key, &i.to_string()))),
        _ => None,
    }
}

/// Every array the scene text wrote has as many values as the scene took from it: the parser
/// reads a fixed-size value (a position, a range) from the front of an array and would silently
/// drop what follows (`position = [1.0, 2.0, 3.0, 4.0]`).
fn check_array_lengths(written: &toml::Table, scene: &Scene, origin: &str) -> Result<(), SceneError> {
    let taken: toml::Table = toml::from_str(&scene.to_toml()).expect("a scene serialises to a TOML table");
    match first_longer_in_table(written, &taken, "") {
        Some((key, written, takes)) => Err(SceneError::TooManyValues {
            origin: origin.into(),
            key,
            written,
            takes,
        }),
        None => Ok(()),
    }
}

/// The first array (dotted key, its length, the length taken) in `written` longer than the
/// same array in `taken`.
fn first_longer_array(written: &toml::Value, taken: &toml::Value, key: &str) -> Option<(String, usize, usize)> {
    match (written, taken) {
        (toml::Value::Table(w), toml::Value::Table(t)) => first_longer_in_table(w, t, key),
        (toml::Value::Array(w), toml::Value::Array(t)) if w.len() > t.len() => {
            Some((key.to_string(), w.len(), t.len()))
        }
        (toml::Value::Array(w), toml::Value::Array(t)) => w
            .iter()
            .zip(t)
            .enumerate()
            .find_map(|(i, (wv, tv))| first_longer_array(wv, tv, &dotted(key, &i.to_string()))),
        _ => None,
    }
}

/// [`first_longer_array`] over the keys of table `written` (at dotted key `key`).
fn first_longer_in_table(written: &toml::Table, taken: &toml::Table, key: &str) -> Option<(String, usize, usize)> {
    written
        .iter()
        .find_map(|(k, v)| taken.get(k).and_then(|t| first_longer_array(v, t, &dotted(key, k))))
}

fn dotted(key: &str, child: &str) -> String {
    if key.is_empty() {
        child.to_string()
    } else {
        format!("{key}.{child}")
    }
}

/// What is wrong with a scene file.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("cannot read scene file {path}: {reason}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// The text is not a scene file: bad TOML, an unknown key, a value of the wrong type.
    #[error("{origin}: line {line}, column {column}: {message}")]
    Syntax {
        /// Where the text came from (a file name).
        origin: String,
        /// Line of the mistake, from 1.
        line: usize,
        /// Column of the mistake, from 1.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A `--set` key the scene file does not have.
    #[error(
        "--set {key}: the scene file has no such key; keys look like wind.strength, field.blades or collider.0.radius"
    )]
    UnknownKey {
        /// The key given.
        key: String,
    },
    /// A `--set` value that does not fit its key.
    #[error("--set {key}={value}: {message}")]
    BadOverride {
        /// The key.
        key: String,
        /// The value given.
        value: String,
        /// What is wrong.
        message: String,
    },
    /// An array longer than its key takes.
    #[error("{origin}: {key} has {written} values; it takes {takes}")]
    TooManyValues {
        /// Where the scene came from.
        origin: String,
        /// The key.
        key: String,
        /// Values written.
        written: usize,
        /// Values it takes.
        takes: usize,
    },
    /// A number that is not finite or of absurd size.
    #[error("{origin}: {key} = {value} is not allowed: every number in a scene is finite and within ±{MAX_MAGNITUDE}")]
    Absurd {
        /// Where the scene came from.
        origin: String,
        /// The key.
        key: String,
        /// The value written.
        value: String,
    },
    /// A value outside what its key allows.
    #[error("{origin}: {key} = {value} is not allowed: {allowed}")]
    Invalid {
        /// Where the scene came from.
        origin: String,
        /// The key.
        key: &'static str,
        /// The value written.
        value: String,
        /// What is allowed.
        allowed: &'static str,
    },
}

impl Scene {
    /// Read, parse and validate a scene file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|e| SceneError::Io {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
        let origin = path.display().to_string();
        let mut scene: Scene = parse(&text, &origin)?;
        // Mesh paths in a scene file are relative to that file.
        let surface = match &mut scene.surface {
            Surface::Mesh { path, .. } | Surface::Heightmap { path, .. } => Some(path),
            _ => None,
        };
        let bodies = scene.bodies.iter_mut().filter_map(|b| match &mut b.shape {
            crate::bodies::BodyShape::Mesh { path, .. } => Some(path),
            _ => None,
        });
        for mesh in surface.into_iter().chain(bodies) {
            if let (true, Some(dir)) = (Path::new(mesh.as_str()).is_relative(), path.parent()) {
                *mesh = dir.join(mesh.as_str()).display().to_string();
            }
        }
        scene.validate(&origin)?;
        Ok(scene)
    }

    /// Parse and validate scene text; `origin` names it in errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Scene, SceneError> {
        let scene = parse(text, origin)?;
        scene.validate(origin)?;
        Ok(scene)
    }

    /// How many Bezier blades the scene grows: its field's, or none when it draws only the
    /// instanced field.
    pub fn bezier_blades(&self) -> u32 {
        if self.technique.draws_bezier() {
            self.field.blades
        } else {
            0
        }
    }

    /// Whether the trample map runs: asked for, where generated grass (which keeps no state of
    /// its own) is drawn or a cutter mows (the map keeps the cut, for every blade).
    pub fn tramples(&self) -> bool {
        let generated = self.technique.draws_instanced() || self.technique.draws_billboards();
        self.trample.enabled && (generated || self.colliders.iter().any(|c| c.cut))
    }

    /// The field the scene describes, on its surface, cut into tiles; no blades where the scene
    /// draws only generated grass. Fails only if a mesh file cannot be used.
    pub fn grow_field(&self) -> Result<Field, MeshError> {
        let desc = FieldDesc {
            blades: self.bezier_blades(),
            ..self.field
        };
        Field::grow(&self.surface, &desc)
    }

    /// Every collider sphere at time `t`: the scene's spheres where their paths take them, then
    /// the spheres of each body.
    pub fn colliders_at(&self, t: f32) -> Vec<Collider> {
        let spheres = self.colliders.iter().map(|c| c.at(t));
        spheres
            .chain(self.bodies.iter().flat_map(|b| b.colliders_at(t)))
            .collect()
    }

    /// This scene with `key = value` overrides applied (dotted keys as in the scene file, values
    /// in TOML syntax; a bare word is taken as a string), validated like a scene file.
    pub fn with_overrides(&self, sets: &[(String, String)]) -> Result<Scene, SceneError> {
        let mut table: toml::Table = toml::from_str(&self.to_toml()).expect("a scene serialises to a TOML table");
        for (key, value) in sets {
            let parsed = toml::from_str::<toml::Table>(&format!("v = {value}"))
                .ok()
                .and_then(|mut t| t.remove("v"))
                .unwrap_or_else(|| toml::Value::String(value.clone()));
            let slot = lookup(&mut table, key).ok_or_else(|| SceneError::UnknownKey { key: key.clone() })?;
            *slot = parsed;
        }
        let text = toml::to_string(&table).unwrap_or_default();
        let scene: Scene = toml::from_str(&text).map_err(|e| {
            let (key, value) = sets.last().cloned().unwrap_or_default();
            SceneError::BadOverride {
                key,
                value,
                message: e.message().trim().replace('\n', "; "),
            }
        })?;
        check_array_lengths(&table, &scene, "--set")?;
        scene.validate("--set")?;
        Ok(scene)
    }

    /// The scene as TOML text (what the viewer's "save" writes).
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).unwrap_or_default()
    }

    /// Check every value against what the model and the renderer can handle.
    pub fn validate(&self, origin: &str) -> Result<(), SceneError> {
        let numbers: toml::Value = toml::from_str(&self.to_toml()).expect("a scene serialises to a TOML table");
        if let Some((key, value)) = first_absurd_number(&numbers, "") {
            return Err(SceneError::Absurd {
                origin: origin.into(),
                key,
                value: value.to_string(),
            });
        }
        let mut checks = Checks { origin, error: None };
        self.check_field(&mut checks);
        self.check_simulation(&mut checks);
        self.check_culling(&mut checks);
        self.check_look(&mut checks);
        self.check_instanced(&mut checks);
        self.check_billboard(&mut checks);
        self.check_trample(&mut checks);
        match checks.error {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    fn check_field(&self, c: &mut Checks) {
        match &self.surface {
            Surface::Sphere { center, radius } => c.check(
                *radius > 0.0 && radius.is_finite() && center.is_finite(),
                "surface.radius",
                radius,
                "a positive radius and a finite centre",
            ),
            Surface::Terrain {
                size,
                height,
                resolution,
                ..
            } => {
                c.check_relief(*size, *height);
                c.check(
                    (2..=2048).contains(resolution),
                    "surface.resolution",
                    resolution,
                    "2 to 2048 cells per side",
                );
            }
            Surface::Heightmap { size, height, .. } => {
                c.check_relief(*size, *height);
            }
            Surface::Mesh { scale, .. } => c.check(
                *scale > 0.0 && scale.is_finite(),
                "surface.scale",
                scale,
                "a positive scale",
            ),
            Surface::Plane => {}
        }
        let f = &self.field;
        c.check(
            f.blades >= 1 && f.blades <= MAX_BLADES,
            "field.blades",
            f.blades,
            "a whole number from 1 to 67108864 (2^26)",
        );
        c.check(
            f.size.x > 0.0 && f.size.y > 0.0 && f.size.is_finite(),
            "field.size",
            f.size,
            "two positive extents [x, z]",
        );
        c.check(
            range_ok(f.height),
            "field.height",
            fmt_range(f.height),
            "a range [min, max] with 0 < min ≤ max",
        );
        c.check(
            range_ok(f.width),
            "field.width",
            fmt_range(f.width),
            "a range [min, max] with 0 < min ≤ max",
        );
        c.check(
            f.width[1] <= f.height[0],
            "field.width",
            fmt_range(f.width),
            "widths no larger than the smallest height (field.height[0]); a blade wider than tall is not grass",
        );
        c.check(
            range_ok(f.stiffness),
            "field.stiffness",
            fmt_range(f.stiffness),
            "a range [min, max] with 0 < min ≤ max",
        );
    }

    fn check_simulation(&self, c: &mut Checks) {
        let s = &self.simulation;
        c.check(
            s.step > 0.0 && s.step <= 0.05,
            "simulation.step",
            s.step,
            "a step in seconds in (0, 0.05]",
        );
        c.check(
            self.field.stiffness[1] * s.step < 1.0,
            "simulation.step",
            s.step,
            "a step small enough that stiffness × step < 1 (explicit integration of stiff blades diverges)",
        );
        c.check(
            (1..=64).contains(&s.max_substeps),
            "simulation.max_substeps",
            s.max_substeps,
            "1 to 64",
        );
        c.check(
            finite_non_negative(s.gravity_strength),
            "simulation.gravity_strength",
            s.gravity_strength,
            "a finite value ≥ 0",
        );
        c.check(
            s.gravity_direction.length() > 1e-6 && s.gravity_direction.is_finite(),
            "simulation.gravity_direction",
            s.gravity_direction,
            "a non-zero direction",
        );
        c.check(
            (0.0..=1.0).contains(&s.point_gravity_blend),
            "simulation.point_gravity_blend",
            s.point_gravity_blend,
            "a blend in [0, 1]",
        );
        c.check(
            finite_non_negative(s.point_gravity_strength),
            "simulation.point_gravity_strength",
            s.point_gravity_strength,
            "a finite value ≥ 0",
        );
        c.check(
            finite_non_negative(s.eta_decay),
            "simulation.eta_decay",
            s.eta_decay,
            "a finite rate ≥ 0",
        );
        c.check(
            (1..=MAX_WINDS).contains(&self.wind.len()),
            "wind",
            self.wind.len(),
            "one to four wind fields ([wind] or [[wind]] tables; type = \"none\" for calm)",
        );
        for w in self.wind.iter() {
            c.check(
                finite_non_negative(w.strength),
                "wind.strength",
                w.strength,
                "a finite value ≥ 0",
            );
            c.check(
                (0.0..=1.0).contains(&w.gust),
                "wind.gust",
                w.gust,
                "an amplitude in [0, 1]",
            );
            c.check(
                w.scale > 0.0 && w.scale.is_finite(),
                "wind.scale",
                w.scale,
                "a positive spatial frequency",
            );
            c.check(
                w.direction.is_finite() && w.center.is_finite() && w.speed.is_finite(),
                "wind",
                "…",
                "finite direction, centre and speed",
            );
        }
        let body_spheres: u32 = self.bodies.iter().map(|b| b.spheres).sum();
        c.check(
            self.colliders.len() + body_spheres as usize <= MAX_COLLIDERS,
            "collider",
            self.colliders.len() + body_spheres as usize,
            "at most 128 collider spheres, counting the spheres of every body",
        );
        self.check_bodies(c);
        let path = &self.camera_path;
        c.check(
            path.points.iter().all(|p| p.is_finite()) && path.speed.is_finite() && path.speed >= 0.0,
            "camera_path.points",
            path.points.len(),
            "finite points and a finite speed ≥ 0",
        );
        for collider in &self.colliders {
            c.check(
                collider.radius > 0.0 && collider.center.is_finite(),
                "collider.radius",
                collider.radius,
                "a positive radius and a finite centre",
            );
            c.check(
                collider.path.iter().all(|p| p.is_finite()) && collider.speed.is_finite() && collider.speed >= 0.0,
                "collider.path",
                collider.path.len(),
                "finite path points and a finite speed ≥ 0",
            );
        }
    }

    fn check_trample(&self, c: &mut Checks) {
        let t = &self.trample;
        c.check(
            (16..=crate::trample::TrampleParams::MAX_RESOLUTION).contains(&t.resolution),
            "trample.resolution",
            t.resolution,
            "16 to 4096 texels along a side",
        );
        c.check(
            t.extent > 0.0 && t.extent <= 100_000.0,
            "trample.extent",
            t.extent,
            "0 < extent ≤ 100000 units of ground",
        );
        c.check(
            t.regrow.is_finite() && (0.0..=100.0).contains(&t.regrow),
            "trample.regrow",
            t.regrow,
            "0 ≤ regrow ≤ 100 units of height per second",
        );
    }

    fn check_billboard(&self, c: &mut Checks) {
        let p = &self.billboard;
        c.check(
            p.density > 0.0 && p.density <= 1_000.0,
            "billboard.density",
            p.density,
            "0 < density ≤ 1000 tufts per square unit",
        );
        c.check(
            p.radius > 0.0 && p.radius.is_finite() && (0.0..p.radius).contains(&p.inner_radius),
            "billboard.radius",
            p.radius,
            "a positive cut-off radius above inner_radius ≥ 0",
        );
        c.check(
            range_ok(p.height),
            "billboard.height",
            fmt_range(p.height),
            "a range [min, max] with 0 < min ≤ max",
        );
        c.check(
            range_ok(p.width),
            "billboard.width",
            fmt_range(p.width),
            "a range [min, max] with 0 < min ≤ max",
        );
        for (key, v) in [
            ("billboard.sway", p.sway),
            ("billboard.fade", p.fade),
            ("billboard.clump_scale", p.clump_scale),
            ("billboard.one_quad_distance", p.one_quad_distance),
            ("billboard.splat_distance", p.splat_distance),
            ("billboard.raster_distance", p.raster_distance),
        ] {
            c.check(finite_non_negative(v), key, v, "a finite value ≥ 0");
        }
    }

    fn check_instanced(&self, c: &mut Checks) {
        let p = &self.instanced;
        c.check(
            p.density > 0.0 && p.density <= 10_000.0,
            "instanced.density",
            p.density,
            "0 < density ≤ 10000 blades per square unit",
        );
        c.check(
            p.radius > 0.0 && p.radius.is_finite() && (0.0..p.radius).contains(&p.inner_radius),
            "instanced.radius",
            p.radius,
            "a positive cut-off radius above inner_radius ≥ 0",
        );
        let [d0, d1, d2] = p.lod_distances;
        c.check(
            0.0 < d0 && d0 < d1 && d1 < d2 && d2 < p.radius,
            "instanced.lod_distances",
            format!("{:?}", p.lod_distances),
            "three distances with 0 < first < second < third < radius",
        );
        c.check(
            p.splat_distance > 0.0 && !p.splat_distance.is_nan(),
            "instanced.splat_distance",
            p.splat_distance,
            "a positive distance (at radius or beyond: nothing is splatted)",
        );
        c.check(
            range_ok(p.height),
            "instanced.height",
            fmt_range(p.height),
            "a range [min, max] with 0 < min ≤ max",
        );
        c.check(
            range_ok(p.width),
            "instanced.width",
            fmt_range(p.width),
            "a range [min, max] with 0 < min ≤ max",
        );
        for (key, v) in [
            ("instanced.bend", p.bend),
            ("instanced.sway", p.sway),
            ("instanced.clump_scale", p.clump_scale),
            ("instanced.raster_distance", p.raster_distance),
        ] {
            c.check(finite_non_negative(v), key, v, "a finite value ≥ 0");
        }
    }

    fn check_bodies(&self, c: &mut Checks) {
        use crate::bodies::BodyShape;
        for body in &self.bodies {
            let size = match &body.shape {
                BodyShape::Boulder { radius, .. } => *radius,
                BodyShape::Mesh { scale, .. } => *scale,
            };
            c.check(
                size >= 0.01 && size.is_finite(),
                "body.shape",
                size,
                "a boulder radius or mesh scale of at least 0.01",
            );
            c.check(
                (1..=64).contains(&body.spheres),
                "body.spheres",
                body.spheres,
                "1 to 64 spheres per body",
            );
            c.check(
                body.center.is_finite() && body.path.iter().all(|p| p.is_finite()) && body.speed >= 0.0,
                "body.path",
                body.path.len(),
                "a finite centre and path and a finite speed ≥ 0",
            );
            if c.error.is_none() {
                if let Err(e) = body.packing() {
                    c.check(false, "body.shape", e.to_string(), "a closed mesh that loads");
                }
            }
        }
    }

    fn check_culling(&self, c: &mut Checks) {
        let k = &self.cull;
        c.check(
            k.orientation_threshold > 0.0 && k.orientation_threshold <= 1.0,
            "cull.orientation_threshold",
            k.orientation_threshold,
            "a value in (0, 1]",
        );
        c.check(
            finite_non_negative(k.frustum_tolerance),
            "cull.frustum_tolerance",
            k.frustum_tolerance,
            "a finite value ≥ 0",
        );
        c.check(
            (1..=1000).contains(&k.distance_levels),
            "cull.distance_levels",
            k.distance_levels,
            "1 to 1000 buckets",
        );
        c.check(
            k.distance_max > 0.0 && k.distance_max.is_finite(),
            "cull.distance_max",
            k.distance_max,
            "a positive distance",
        );
        c.check(
            finite_non_negative(k.tile_margin),
            "cull.tile_margin",
            k.tile_margin,
            "a finite distance ≥ 0",
        );
        c.check(
            finite_non_negative(k.occlusion_tolerance),
            "cull.occlusion_tolerance",
            k.occlusion_tolerance,
            "a finite depth ≥ 0",
        );
        c.check(
            k.blade_occluders.resolve(0.0) <= MAX_BLADES,
            "cull.blade_occluders",
            k.blade_occluders,
            "\"auto\", or 0 (only the ground and colliders occlude) to as many blades as a field may hold",
        );
        let l = &self.lod;
        c.check(
            l.min_level >= 1.0 && l.min_level <= l.max_level && l.max_level <= 64.0,
            "lod",
            fmt_range([l.min_level, l.max_level]),
            "levels with 1 ≤ min_level ≤ max_level ≤ 64",
        );
        c.check(
            l.near >= 0.0 && l.near < l.far,
            "lod",
            fmt_range([l.near, l.far]),
            "distances with 0 ≤ near < far",
        );
        c.check(
            l.splat_distance >= 0.0,
            "lod.splat_distance",
            l.splat_distance,
            "a distance of 0 (splat every blade on the compute route) or more",
        );
        c.check(
            l.strip_distance >= 0.0,
            "lod.strip_distance",
            l.strip_distance,
            "a distance of 0 (rasterize every near blade by compute on the compute route) or more",
        );
        let cam = &self.camera;
        c.check(
            cam.fov_y_degrees > 1.0 && cam.fov_y_degrees < 179.0,
            "camera.fov_y_degrees",
            cam.fov_y_degrees,
            "an angle in (1, 179) degrees",
        );
        c.check(
            cam.near >= 1e-3 && cam.near < cam.far,
            "camera.near",
            cam.near,
            "0.001 ≤ near < far",
        );
        c.check(
            cam.position.distance(cam.target) > 1e-4 && cam.position.is_finite() && cam.target.is_finite(),
            "camera.target",
            cam.target,
            "a finite point other than camera.position",
        );
        let forward = (cam.target - cam.position).normalize_or_zero();
        c.check(
            cam.up.length() > 1e-6 && cam.up.normalize_or_zero().cross(forward).length() > 1e-3,
            "camera.up",
            cam.up,
            "a non-zero direction not along the line of sight",
        );
    }

    fn check_look(&self, c: &mut Checks) {
        let s = &self.shading;
        for (key, value) in [
            ("shading.specular", s.specular),
            ("shading.translucency", s.translucency),
        ] {
            c.check(finite_non_negative(value), key, value, "a finite value ≥ 0");
        }
        for (key, value) in [
            ("shading.ambient_occlusion", s.ambient_occlusion),
            ("shading.clump_variation", s.clump_variation),
        ] {
            c.check((0.0..=1.0).contains(&value), key, value, "a value in [0, 1]");
        }
        c.check(
            s.shininess >= 1.0 && s.shininess.is_finite(),
            "shading.shininess",
            s.shininess,
            "an exponent ≥ 1",
        );
        c.check(
            s.clump_scale > 0.0 && s.clump_scale.is_finite(),
            "shading.clump_scale",
            s.clump_scale,
            "a positive spatial frequency",
        );
        let b = &self.blades;
        c.check(
            (0.0..1.0).contains(&b.tip_threshold),
            "blades.tip_threshold",
            b.tip_threshold,
            "a value in [0, 1)",
        );
        c.check(
            (0.0..=16.0).contains(&b.min_width_pixels),
            "blades.min_width_pixels",
            b.min_width_pixels,
            "0 (off) to 16 pixels",
        );
        let s = &self.shading;
        c.check(
            s.light_direction.length() > 1e-6,
            "shading.light_direction",
            s.light_direction,
            "a non-zero direction",
        );
        c.check(
            (0.0..=1.0).contains(&s.ambient),
            "shading.ambient",
            s.ambient,
            "a share in [0, 1]",
        );
        c.check(
            (0.0..=1.0).contains(&s.color_jitter),
            "shading.color_jitter",
            s.color_jitter,
            "a share in [0, 1]",
        );
        c.check(
            finite_non_negative(s.fog_density),
            "shading.fog_density",
            s.fog_density,
            "a finite density ≥ 0",
        );
        c.check(
            finite_non_negative(s.blade_shadow_distance) && s.blade_shadow_distance <= 1000.0,
            "shading.blade_shadow_distance",
            s.blade_shadow_distance,
            "a distance in [0, 1000] units (0: blades cast no shadows)",
        );
        let colors = [
            s.light_color,
            s.root_color,
            s.tip_color,
            s.ground_color,
            s.sky_zenith,
            s.sky_horizon,
        ];
        c.check(
            colors.iter().all(|v| v.is_finite() && v.min_element() >= 0.0),
            "shading",
            "colour",
            "colours with finite components ≥ 0",
        );
    }
}

/// Collects the first failed check.
struct Checks<'a> {
    origin: &'a str,
    error: Option<SceneError>,
}

impl Checks<'_> {
    /// A terrain's footprint and hill height.
    fn check_relief(&mut self, size: glam::Vec2, height: f32) {
        self.check(
            size.min_element() > 0.0 && size.is_finite(),
            "surface.size",
            size,
            "two positive extents [x, z]",
        );
        self.check(
            height.is_finite() && height >= 0.0,
            "surface.height",
            height,
            "a finite height ≥ 0",
        );
    }

    fn check(&mut self, ok: bool, key: &'static str, value: impl std::fmt::Debug, allowed: &'static str) {
        if !ok && self.error.is_none() {
            let value = format!("{value:?}").trim_matches('"').to_string();
            self.error = Some(SceneError::Invalid {
                origin: self.origin.into(),
                key,
                value,
                allowed,
            });
        }
    }
}

/// The value at a dotted key, if the table has it.
/// The value at dotted `key`; a number picks an element of a list of tables (`wind.1.strength`,
/// `body.0.speed`).
fn lookup<'a>(table: &'a mut toml::Table, key: &str) -> Option<&'a mut toml::Value> {
    let mut parts = key.split('.');
    let mut value = table.get_mut(parts.next()?)?;
    for part in parts {
        value = match (value, part.parse::<usize>()) {
            (toml::Value::Array(list), Ok(index)) => list.get_mut(index)?,
            (value, _) => value.as_table_mut()?.get_mut(part)?,
        };
    }
    Some(value)
}

fn range_ok(r: [f32; 2]) -> bool {
    r[0] > 0.0 && r[0] <= r[1] && r[1].is_finite()
}

fn finite_non_negative(x: f32) -> bool {
    x.is_finite() && x >= 0.0
}

fn fmt_range(r: [f32; 2]) -> String {
    format!("[{}, {}]", r[0], r[1])
}

fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    (line, column)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec3, Vec4};

    fn err(text: &str) -> String {
        Scene::from_toml(text, "test.toml").unwrap_err().to_string()
    }

    #[test]
    fn empty_file_is_the_default_scene() {
        assert_eq!(Scene::from_toml("", "x").unwrap(), Scene::default());
    }

    #[test]
    fn each_frame_places_the_colliders_pushing_ones_first_then_the_cutters() {
        let text = "[[collider]]\ncenter = [0.0, 0.5, 0.0]\nradius = 0.5\ncut = true\n\
                    [[collider]]\ncenter = [1.0, 0.3, 0.0]\nradius = 0.3\nspeed = 2.0\n\
                    path = [[1.0, 0.3, 0.0], [4.0, 0.3, 0.0], [4.0, 0.3, 3.0]]\n\
                    [[body]]\nshape = { type = \"boulder\", radius = 0.6, seed = 3 }\nspheres = 4\n\
                    center = [-3.0, 0.5, 0.0]\npath = [[-3.0, 0.5, 0.0], [-3.0, 0.5, 5.0]]\nroll = true\n";
        let scene = Scene::from_toml(text, "t").unwrap();
        for t in [0.0, 0.7, 3.1] {
            let all = scene.colliders_at(t);
            let sphere = |c: &Collider| c.center.extend(c.radius);
            let expected: Vec<Vec4> = all
                .iter()
                .filter(|c| !c.cut)
                .chain(all.iter().filter(|c| c.cut))
                .map(sphere)
                .collect();
            let frame = crate::frame::FrameColliders::of_scene(&scene, t);
            assert_eq!(frame.packed_counts(), (5, 1));
            let placed: Vec<Vec4> = frame
                .pushing
                .iter()
                .chain(&frame.cutting)
                .map(|s| s.center.extend(s.radius))
                .collect();
            assert_eq!(placed, expected, "at {t} s");
            // More spheres than the GPU holds: the pushing ones first, as many as fit.
            let crowd = crate::frame::FrameColliders {
                pushing: vec![frame.pushing[0]; MAX_COLLIDERS - 1],
                cutting: frame.cutting.repeat(3),
            };
            assert_eq!(crowd.packed_counts(), (MAX_COLLIDERS as u32 - 1, 1));
        }
    }

    #[test]
    fn round_trips_through_toml() {
        let mut scene = Scene::default();
        scene.colliders.push(Collider::sphere(Vec3::new(1.0, 0.5, 2.0), 0.7));
        scene.wind[0].kind = crate::wind::WindKind::Noise;
        assert_eq!(Scene::from_toml(&scene.to_toml(), "x").unwrap(), scene);
    }

    #[test]
    fn a_camera_path_is_read_saved_and_checked() {
        let text = "[camera_path]\npoints = [[0.0, 2.0, -8.0], [6.0, 2.0, -8.0]]\nspeed = 1.5\ndolly = true\n";
        let scene = Scene::from_toml(text, "path.toml").unwrap();
        assert_eq!(scene.camera_path.points.len(), 2);
        assert!(scene.camera_path.dolly && !scene.camera_path.is_still());
        assert_eq!(Scene::from_toml(&scene.to_toml(), "x").unwrap(), scene);
        // Every scene has the table, so `--set camera_path.speed=…` works on any of them.
        let set = [("camera_path.speed".to_string(), "3.5".to_string())];
        assert_eq!(Scene::default().with_overrides(&set).unwrap().camera_path.speed, 3.5);
        let bad = Scene::from_toml("[camera_path]\npoints = [[0.0, 2.0, -8.0]]\nspeed = -1.0\n", "bad.toml");
        let message = bad.unwrap_err().to_string();
        assert!(
            message.contains("bad.toml") && message.contains("camera_path"),
            "{message}"
        );
    }

    #[test]
    fn wind_fields_combine_as_a_list_of_tables() {
        let text = "[[wind]]\ntype = \"waves\"\nstrength = 2.0\n[[wind]]\ntype = \"whirl\"\ncenter = [1.0, 0.0, 2.0]\n";
        let scene = Scene::from_toml(text, "t").unwrap();
        let kinds: Vec<_> = scene.wind.iter().map(|w| w.kind).collect();
        assert_eq!(kinds, [crate::wind::WindKind::Waves, crate::wind::WindKind::Whirl]);
        assert_eq!(Scene::from_toml(&scene.to_toml(), "t").unwrap(), scene);
        // The sum is what a blade feels.
        let p = glam::Vec3::new(3.0, 0.0, -1.0);
        assert_eq!(
            scene.wind.at(p, 0.5),
            scene.wind[0].at(p, 0.5) + scene.wind[1].at(p, 0.5)
        );
        let five = "[[wind]]\n".repeat(5);
        let e = Scene::from_toml(&five, "t").unwrap_err().to_string();
        assert!(e.contains("one to four wind fields"), "{e}");
        let e = Scene::from_toml("[[wind]]\ntype = \"tornado\"\n", "t")
            .unwrap_err()
            .to_string();
        assert!(e.contains("tornado") && e.contains("whirl"), "{e}");
    }

    #[test]
    fn arrays_longer_than_their_value_are_refused_not_cut_short() {
        for (text, said) in [
            (
                "[camera]\nposition = [1.0, 2.0, 3.0, 4.0, 5.0]\n",
                "camera.position has 5 values; it takes 3",
            ),
            (
                "[field]\nheight = [0.4, 0.9, 1.0]\n",
                "field.height has 3 values; it takes 2",
            ),
            (
                "[[collider]]\ncenter = [0.0, 1.0, 0.0]\nradius = 1.0\npath = [[0.0, 1.0, 0.0, 9.0]]\n",
                "collider.0.path.0 has 4 values; it takes 3",
            ),
        ] {
            let error = Scene::from_toml(text, "s.toml").unwrap_err().to_string();
            assert_eq!(error, format!("s.toml: {said}"));
        }
        let sets = [("camera.position".to_string(), "[1.0, 2.0, 3.0, 4.0]".to_string())];
        let error = Scene::default().with_overrides(&sets).unwrap_err().to_string();
        assert_eq!(error, "--set: camera.position has 4 values; it takes 3");
        // Lists of any length keep every value.
        let path = "[[collider]]\ncenter = [0.0, 1.0, 0.0]\nradius = 1.0\npath = [[0.0, 1.0, 0.0], [1.0, 1.0, 0.0], [2.0, 1.0, 0.0]]\n";
        assert_eq!(Scene::from_toml(path, "s.toml").unwrap().colliders[0].path.len(), 3);
    }

    #[test]
    fn overrides_change_one_value_and_are_validated() {
        let base = Scene::default();
        let sets = |pairs: &[(&str, &str)]| {
            pairs
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect::<Vec<_>>()
        };
        let s = base
            .with_overrides(&sets(&[
                ("wind.strength", "3.5"),
                ("wind.type", "noise"),
                ("field.blades", "100"),
            ]))
            .unwrap();
        assert_eq!(s.wind[0].strength, 3.5);
        assert_eq!(s.wind[0].kind, crate::wind::WindKind::Noise);
        assert_eq!(s.field.blades, 100);
        // A collider becomes a mower from the command line: its `cut` key is always there.
        let mut with_ball = base.clone();
        with_ball.colliders.push(crate::Collider::sphere(glam::Vec3::Y, 1.0));
        let mower = with_ball.with_overrides(&sets(&[("collider.0.cut", "true")])).unwrap();
        assert!(mower.colliders[0].cut);
        assert_eq!(
            Scene {
                wind: base.wind.clone(),
                field: base.field,
                ..s.clone()
            },
            base
        );
        // A number picks one table of a list.
        let two = Scene::from_toml("[[wind]]\n[[wind]]\ntype = \"whirl\"\n", "t").unwrap();
        let s2 = two.with_overrides(&sets(&[("wind.1.strength", "9.5")])).unwrap();
        assert_eq!((s2.wind[0].strength, s2.wind[1].strength), (two.wind[0].strength, 9.5));
        let e = two
            .with_overrides(&sets(&[("wind.2.strength", "1")]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("no such key"), "{e}");
        let e = base
            .with_overrides(&sets(&[("wnd.strength", "3")]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("wnd.strength") && e.contains("no such key"), "{e}");
        let e = base
            .with_overrides(&sets(&[("field.blades", "0")]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("field.blades") && e.contains("1 to"), "{e}");
        let e = base
            .with_overrides(&sets(&[("field.blades", "many")]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("--set field.blades=many"), "{e}");
    }

    #[test]
    fn bad_values_name_the_key_and_what_is_allowed() {
        let e = err("[trample]\nresolution = 5\n");
        assert!(e.contains("trample.resolution") && e.contains("16 to 4096"), "{e}");
        let e = err("[trample]\nextent = -1.0\n");
        assert!(e.contains("trample.extent") && e.contains("0 < extent"), "{e}");
        let e = err("[trample]\nregrow = -0.5\n");
        assert!(e.contains("trample.regrow") && e.contains("0 ≤ regrow"), "{e}");
        for key in ["one_quad_distance", "splat_distance", "raster_distance"] {
            let e = err(&format!("[billboard]\n{key} = -3.0\n"));
            assert!(e.contains(&format!("billboard.{key}")) && e.contains("≥ 0"), "{e}");
        }
        let e = err("[instanced]\nraster_distance = -1.0\n");
        assert!(e.contains("instanced.raster_distance") && e.contains("≥ 0"), "{e}");
        let e = err("[[collider]]\ncenter = [0.0, 1.0, 0.0]\nradius = 1.0\ncut = \"yes\"\n");
        assert!(e.contains("line 4") && e.contains("boolean"), "{e}");
        let e = err("[field]\nheight = [-1.0, 2.0]\n");
        assert!(e.contains("field.height") && e.contains("0 < min"), "{e}");
        let e = err("[field]\nblades = 0\n");
        assert!(e.contains("field.blades") && e.contains("1 to"), "{e}");
        let e = err("[field]\nwidth = [0.5, 3.0]\nheight = [1.0, 2.0]\n");
        assert!(e.contains("field.width") && e.contains("wider than tall"), "{e}");
        let e = err("[wind]\ntype = \"tornado\"\n");
        assert!(
            e.contains("line 2") && e.contains("tornado") && e.contains("waves"),
            "{e}"
        );
        let e = err("[field]\nblades = \"many\"\n");
        assert!(e.contains("line 2"), "{e}");
        let e = err("[feild]\nblades = 3\n");
        assert!(e.contains("feild") && e.contains("line 1"), "{e}");
        assert!(!e.contains('\n'), "one line: {e}");
    }
}
