//! The scene description: everything a user may change, as one TOML file with one default per
//! value, and its validation. Bad input becomes one sentence that names the file, the key, the
//! problem and what is allowed.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};
use toml::Spanned;

use crate::camera::{Camera, CameraPath};
use crate::cull::{CullParams, LodParams};
pub use crate::field::Surface;
use crate::field::{Field, FieldDesc};
use crate::look::{BladeStyle, Shading};
use crate::mesh::MeshError;
use crate::physics::{Collider, SimParams, MAX_COLLIDERS};
use crate::validate::{Checks, Validate};
pub use crate::validate::{SceneError, MAX_BLADES, MAX_MAGNITUDE};
use crate::wind::Winds;

/// Everything a rendered scene is made of: the scene file, read and validated.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct Scene {
    /// The scene's name (window title, saved file names).
    pub name: String,
    /// Bezier blades with physics, the instanced grass, or both.
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
    /// The instanced grass (techniques `instanced`, `both` and `landscape`).
    pub instanced: crate::instanced::InstancedParams,
    /// Billboard grass (techniques `billboard` and `landscape`).
    pub billboard: crate::billboard::BillboardParams,
    /// How much the renderer spends per pixel and per blade (`high`: the reference picture).
    pub quality: crate::quality::Quality,
    /// The trample map: where colliders flattened the generated grass, fading as blades recover.
    pub trample: crate::trample::TrampleParams,
    /// Maps over the ground: where grass grows and how tall.
    pub paint: crate::paint::PaintParams,
    /// Kinds of grass, mixed by weight (none: one kind, from `[field]`, `[instanced]` and
    /// `[shading]`).
    pub species: Vec<crate::species::Species>,
    /// What the files the scene names hold, where given in memory instead of on disk (a game's
    /// asset server read them, or they were made in code): not part of the scene file.
    #[serde(skip)]
    #[cfg_attr(feature = "reflect", reflect(ignore))]
    pub contents: crate::content::Contents,
    /// The strokes painted over the paint while the scene runs (a game's edits), merged into
    /// the paint they change as they come: not part of the scene file.
    #[serde(skip)]
    #[cfg_attr(feature = "reflect", reflect(ignore))]
    pub edits: crate::paint_edits::PaintEdits,
}

impl Default for Scene {
    fn default() -> Self {
        Self {
            name: "default".into(),
            technique: Default::default(),
            instanced: Default::default(),
            billboard: Default::default(),
            trample: Default::default(),
            paint: Default::default(),
            species: Vec::new(),
            contents: Default::default(),
            edits: Default::default(),
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
        let message = crate::words::plain(&e.message().trim().replace('\n', "; "));
        let (line, column, mut message) = place_grid_mistake(text, (line, column), message);
        if message.starts_with("expected ") {
            let allowed = key_at_line(text, line).and_then(|key| allowed_at(&key).map(|a| (key, a)));
            if let Some((key, allowed)) = allowed {
                message = format!("{message}; {key} takes {allowed}");
            }
        }
        SceneError::Syntax {
            origin: origin.into(),
            line,
            column,
            message,
        }
    })?;
    let written: toml::Table = toml::from_str(text).expect("a scene that parsed is a TOML table");
    check_array_lengths(&written, &scene, origin)?;
    Ok(scene)
}

/// The dotted key written on line `line` of `text` (`field.blades` for `blades = …` under
/// `[field]`), where the line holds one; the element of a list of tables is left out (what a
/// key allows is the same in every element).
fn key_at_line(text: &str, line: usize) -> Option<String> {
    let lines: Vec<&str> = text.lines().collect();
    let written = lines.get(line.checked_sub(1)?)?;
    let (key, _) = written.split_once('=')?;
    let key = key.trim();
    let table = lines[..line - 1]
        .iter()
        .rev()
        .map(|l| l.trim())
        .find(|l| l.starts_with('['))
        .map(|header| header.trim_matches(|c| c == '[' || c == ']').trim().to_string());
    Some(match table {
        Some(table) => format!("{table}.{key}"),
        None => key.to_string(),
    })
}

/// The tables whose keys are partly a flattened grid (`GridParams`): serde reports a mistake in
/// them at the table's header and without the keys the table takes, so the mistake is placed
/// here, from where the parser saw each key and value written — at the key it is about, with
/// the keys allowed (an unknown key), or at the value that does not fit (a wrong type).
fn place_grid_mistake(text: &str, (line, column): (usize, usize), message: String) -> (usize, usize, String) {
    let header = text.lines().nth(line.saturating_sub(1)).unwrap_or("").trim();
    let Some(table) = ["instanced", "billboard"]
        .into_iter()
        .find(|t| header == format!("[{t}]"))
    else {
        return (line, column, message);
    };
    let Ok(written) = toml::from_str::<GridTablesWritten>(text) else {
        return (line, column, message);
    };
    let (entries, keys, fits): (_, _, fn(toml::Table) -> bool) = match table {
        "instanced" => (
            written.instanced,
            default_keys(crate::instanced::InstancedParams::default()),
            |t| crate::instanced::InstancedParams::deserialize(toml::Value::Table(t)).is_ok(),
        ),
        _ => (
            written.billboard,
            default_keys(crate::billboard::BillboardParams::default()),
            |t| crate::billboard::BillboardParams::deserialize(toml::Value::Table(t)).is_ok(),
        ),
    };
    let unknown = message
        .strip_prefix("unknown field `")
        .and_then(|m| m.split('`').next());
    let placed = match unknown {
        Some(unknown) => entries.keys().find(|k| k.get_ref() == unknown).map(|key| {
            let allowed: Vec<String> = keys.iter().map(|k| format!("`{k}`")).collect();
            let said = format!("unknown field `{unknown}`, expected one of {}", allowed.join(", "));
            (key.span().start, said)
        }),
        // The first value, in the file's order, that does not fit its key alone.
        None => entries
            .iter()
            .filter(|(key, value)| {
                !fits(toml::Table::from_iter([(
                    key.get_ref().clone(),
                    value.get_ref().clone(),
                )]))
            })
            .map(|(_, value)| value.span().start)
            .min()
            .map(|at| (at, message.clone())),
    };
    match placed {
        Some((at, said)) => {
            let (line, column) = line_column(text, at);
            (line, column, said)
        }
        None => (line, column, message),
    }
}

/// The keys and values written in the grid tables, each with where the parser read it.
#[derive(Deserialize)]
struct GridTablesWritten {
    #[serde(default)]
    instanced: BTreeMap<Spanned<String>, Spanned<toml::Value>>,
    #[serde(default)]
    billboard: BTreeMap<Spanned<String>, Spanned<toml::Value>>,
}

/// The keys a table of `params` takes, in the order it writes them.
fn default_keys(params: impl Serialize) -> Vec<String> {
    match toml::Value::try_from(params) {
        Ok(toml::Value::Table(t)) => t.keys().cloned().collect(),
        _ => Vec::new(),
    }
}

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

/// The strokes of `new` after those of `old`, where `new` begins with them (empty where they are
/// the same); `None` where a stroke of `old` changed or went.
fn strokes_after<'a>(
    new: &'a [crate::paint::Stroke],
    old: &[crate::paint::Stroke],
) -> Option<&'a [crate::paint::Stroke]> {
    (new.get(..old.len())? == old).then(|| &new[old.len()..])
}

fn dotted(key: &str, child: &str) -> String {
    if key.is_empty() {
        child.to_string()
    } else {
        format!("{key}.{child}")
    }
}

impl Scene {
    /// The bench's `cis565` scene: `blades` blades on the default field under a steady analytic
    /// wind, seen from a metre up across the field, culled to 20 units (the scene the well-known
    /// Vulkan grass projects measure).
    pub fn cis565(blades: u32) -> Scene {
        let mut scene = Scene {
            name: "cis565".into(),
            field: crate::field::FieldDesc {
                blades,
                ..Default::default()
            },
            camera: crate::camera::Camera {
                position: glam::Vec3::new(0.0, 1.0, 10.0),
                target: glam::Vec3::new(0.0, 1.0, 0.0),
                fov_y_degrees: 45.0,
                near: 0.1,
                far: 100.0,
                ..Default::default()
            },
            ..Scene::default()
        };
        scene.wind[0].kind = crate::wind::WindKind::Analytic;
        scene.wind[0].direction = glam::Vec3::new(-1.0, 0.0, -1.0);
        scene.wind[0].strength = 2.5;
        scene.cull.distance_max = 20.0;
        scene.cull.distance_levels = 10;
        scene
    }

    /// Read, parse and validate a scene file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let io = |reason: String| SceneError::Io {
            path: path.display().to_string(),
            reason,
        };
        let bytes = crate::files::read(path).map_err(io)?;
        let text = String::from_utf8(bytes).map_err(|_| io("it is not UTF-8 text".into()))?;
        Scene::from_toml_in(&text, &path.display().to_string(), path.parent())
    }

    /// Parse and validate scene text; `origin` names it in errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Scene, SceneError> {
        Scene::from_toml_in(text, origin, None)
    }

    /// Parse and validate the text of a scene file that lies in `folder` (where known): the
    /// relative paths it names (meshes, height and paint maps, species' weight maps) are
    /// relative to that folder.
    pub fn from_toml_in(text: &str, origin: &str, folder: Option<&Path>) -> Result<Scene, SceneError> {
        Scene::from_toml_given(text, origin, folder, crate::content::Contents::default())
    }

    /// [`Scene::from_toml_in`] with what the files it names hold given in `contents` (under
    /// their names as resolved in `folder`: [`Scene::files_named_in`]), so that nothing is read
    /// from disk to validate it or to grow its field.
    pub fn from_toml_given(
        text: &str,
        origin: &str,
        folder: Option<&Path>,
        contents: crate::content::Contents,
    ) -> Result<Scene, SceneError> {
        let mut scene: Scene = parse(text, origin)?;
        if let Some(folder) = folder {
            scene.resolve_paths(folder);
        }
        scene.contents = contents;
        scene.validate(origin)?;
        Ok(scene)
    }

    /// The files scene text lying in `folder` names, relative to that folder (what
    /// [`Scene::from_toml_given`] looks for in its contents). Fails only where the text does not
    /// parse; its values are not validated yet.
    pub fn files_named_in(text: &str, origin: &str, folder: &Path) -> Result<Vec<String>, SceneError> {
        let mut scene: Scene = parse(text, origin)?;
        scene.resolve_paths(folder);
        Ok(scene.named_files())
    }

    /// Make the relative paths the scene names relative to `folder`.
    fn resolve_paths(&mut self, folder: &Path) {
        for named in self.named_files_mut() {
            if Path::new(named.as_str()).is_relative() {
                *named = folder.join(named.as_str()).display().to_string();
            }
        }
    }

    /// Every file the scene names: its ground's mesh or height map, its bodies' meshes, its
    /// paint maps and its kinds' weight maps (as written, or as resolved where they were).
    pub fn named_files(&self) -> Vec<String> {
        self.clone().named_files_mut().map(|p| p.clone()).collect()
    }

    /// The paths of every file the scene names, to change.
    fn named_files_mut(&mut self) -> impl Iterator<Item = &mut String> {
        let surface = match &mut self.surface {
            Surface::Mesh { path, .. } | Surface::Heightmap { path, .. } => Some(path),
            _ => None,
        };
        let bodies = self.bodies.iter_mut().filter_map(|b| match &mut b.shape {
            crate::bodies::BodyShape::Mesh { path, .. } => Some(path),
            _ => None,
        });
        let weight_maps = self.species.iter_mut().filter_map(|s| s.weight_map.as_mut());
        surface
            .into_iter()
            .chain(bodies)
            .chain(self.paint.paths_mut())
            .chain(weight_maps)
    }

    /// How many Bezier blades the scene grows: its field's, or none when it draws only the
    /// instanced grass.
    pub fn bezier_blades(&self) -> u32 {
        match self.stream_window() {
            Some(window) => window.blades(),
            None if self.technique.draws_bezier() => self.field.blades,
            None => 0,
        }
    }

    /// The fewest blades (`field.blades`) a streamed field's window takes: a window of tiles
    /// that reaches past the hand-over on every side; none where the field does not stream.
    pub fn least_streaming_blades(&self) -> Option<u32> {
        let window = self.stream_window()?;
        let tiles = 2.0 * (self.hand_over() / window.tile_size() + 0.5);
        Some((tiles.ceil() as u32).max(2).pow(2) * crate::tiles::TILE_BLADES)
    }

    /// The window of tiles the Bezier field streams in around the eye, where it streams
    /// (`field.stream`, and the scene draws Bezier blades).
    pub fn stream_window(&self) -> Option<crate::stream::StreamWindow> {
        (self.field.stream && self.technique.draws_bezier())
            .then(|| crate::stream::StreamWindow::for_budget(self.field.blades, &self.instanced))
    }

    /// How far from the eye a streamed field's Bezier blades are drawn: where the instanced grass
    /// takes over (`instanced.inner_radius`), or the distance cut-off where nothing does.
    pub fn hand_over(&self) -> f32 {
        if self.technique.draws_instanced() {
            self.instanced.grid.inner_radius
        } else {
            self.cull.distance_max
        }
    }

    /// Whether the trample map runs: asked for, where generated grass (which keeps no state of
    /// its own) is drawn or a cutter mows (the map keeps the cut, for every blade).
    pub fn tramples(&self) -> bool {
        let generated = self.technique.draws_instanced() || self.technique.draws_billboards();
        self.trample.enabled && (generated || self.colliders.iter().any(|c| c.cut))
    }

    /// Whether `other` grows the field this scene grows: everything [`Scene::grow_field`] reads
    /// is the same (the field, its surface, its paint and species, how many Bezier blades the
    /// technique draws, the streamed window, the ground the colliders and bodies keep bare). A
    /// renderer holding one's field grows the other's again where not; the rest of a scene
    /// (wind, physics, look, level of detail) is read each frame.
    pub fn grows_as(&self, other: &Scene) -> bool {
        self.field == other.field
            && self.surface == other.surface
            && self.paint == other.paint
            && self.species == other.species
            && self.bezier_blades() == other.bezier_blades()
            && self.stream_window() == other.stream_window()
            && self.clearings() == other.clearings()
            && self.contents == other.contents
            && self.edits == other.edits
    }

    /// The strokes this scene paints over `old`'s where that is all that differs (it grows
    /// the field `old` grows but for strokes added after `old`'s own: its file's strokes or its
    /// edits'): painted into the paint a renderer holds
    /// ([`PaintMap::paint_stroke`](crate::paint::PaintMap::paint_stroke)), they need no new
    /// field where no Bezier blade is drawn, as the viewer's brush and a game's edits paint.
    /// `None` where anything else of the field changed (or nothing did).
    pub fn strokes_added_to<'a>(&'a self, old: &Scene) -> Option<&'a [crate::paint::Stroke]> {
        let added = match self.edits.added_since(&old.edits) {
            Some([]) => strokes_after(&self.paint.strokes, &old.paint.strokes)?,
            Some(added) if self.paint.strokes == old.paint.strokes => added,
            _ => return None,
        };
        if added.is_empty() {
            return None;
        }
        // Ground cleared with no map to paint into is cleared at texels of its own: the map
        // the strokes need is made over the whole area, so the field grows again.
        let cleared_only = !old.makes_a_paint_map() && !old.clearings().is_empty();
        let mut unpainted = self.clone();
        unpainted.paint.strokes.clone_from(&old.paint.strokes);
        unpainted.edits = old.edits.clone();
        (unpainted.grows_as(old) && !cleared_only).then_some(added)
    }

    /// Whether the scene's paint is a map over `[paint] area`: its files', its strokes', its
    /// kinds of grass's or its edits'.
    fn makes_a_paint_map(&self) -> bool {
        self.paint.makes_a_map(&self.species) || !self.edits.is_empty()
    }

    /// Paint `strokes` (of this scene's) into `paint`, where the grass grows by a map (made over
    /// `[paint] area` at its resolution where the scene had none).
    pub fn paint_strokes(&self, paint: &mut Option<crate::paint::GroundPaint>, strokes: &[crate::paint::Stroke]) {
        let map = paint
            .get_or_insert_with(Default::default)
            .map
            .get_or_insert_with(|| crate::paint::PaintMap::blank(&self.paint, &self.species));
        for stroke in strokes {
            map.paint_stroke(stroke, self.species_named(stroke.species.as_deref()));
        }
        // Ground the colliders keep bare stays bare (as `paint_map` clears after the strokes).
        let clearings = self.clearings();
        if let (Some(paint), false) = (paint.as_mut(), clearings.is_empty()) {
            paint.clear(&clearings);
        }
    }

    /// The index of the kind of grass called `name`, where the scene lists one.
    fn species_named(&self, name: Option<&str>) -> Option<usize> {
        name.and_then(|n| self.species.iter().position(|s| s.name == n))
    }

    /// The field the scene describes, on its surface, where its paint lets grass grow, cut
    /// into tiles; no blades where the scene draws only generated grass. Fails only if a mesh
    /// file or paint map cannot be used.
    pub fn grow_field(&self) -> Result<Field, MeshError> {
        let paint = self.paint_map()?;
        if let Some(window) = self.stream_window() {
            let mut field = Field::streamed(&self.surface, &self.contents, window)?;
            field.paint = paint;
            return Ok(field);
        }
        let desc = FieldDesc {
            blades: self.bezier_blades(),
            ..self.field
        };
        let mut field = Field::grow_painted(&self.surface, &self.contents, &desc, paint.as_ref(), &self.species)?;
        // Generated grass obeys the paint too, where the scene draws no Bezier blades.
        field.paint = paint;
        Ok(field)
    }

    /// The scene's paint, its maps read (`None`: nothing painted). Fails with the file and what is
    /// allowed where a map cannot be used.
    pub fn paint_map(&self) -> Result<Option<crate::paint::GroundPaint>, MeshError> {
        let clearings = self.clearings();
        let mut paint = crate::paint::GroundPaint::load(&self.paint, &self.species, &self.contents)?;
        if !self.edits.is_empty() {
            let paint = paint.get_or_insert_with(Default::default);
            paint
                .map
                .get_or_insert_with(|| crate::paint::PaintMap::blank(&self.paint, &self.species));
        }
        if let Some(map) = paint.as_mut().and_then(|p| p.map.as_mut()) {
            self.paint_file_strokes(map);
            self.edits.overlay_onto(map);
            for stroke in self.edits.pending() {
                map.paint_stroke(stroke, self.species_named(stroke.species.as_deref()));
            }
        }
        if !clearings.is_empty() {
            paint.get_or_insert_with(Default::default).clear(&clearings);
        }
        Ok(paint)
    }

    /// Paint the scene file's strokes into `map`.
    fn paint_file_strokes(&self, map: &mut crate::paint::PaintMap) {
        for stroke in &self.paint.strokes {
            map.paint_stroke(stroke, self.species_named(stroke.species.as_deref()));
        }
    }

    /// Merge the edits' strokes waiting into the map of the earlier ones
    /// ([`PaintEdits`](crate::paint_edits::PaintEdits)): the scene paints what it painted,
    /// held in one map however many strokes came. Fails where the paint's maps cannot be read.
    pub fn merge_edits(&mut self) -> Result<(), MeshError> {
        let beneath = crate::paint_edits::Beneath {
            paint: self.paint.clone(),
            species: self.species.clone(),
            contents: self.contents.clone(),
        };
        let mut edits = std::mem::take(&mut self.edits);
        let merged = edits.merge(
            beneath,
            || self.paint_beneath_edits(),
            |stroke| self.species_named(stroke.species.as_deref()),
        );
        self.edits = edits;
        merged
    }

    /// The paint the edits are painted over: the maps and the file's strokes, not yet cleared.
    fn paint_beneath_edits(&self) -> Result<crate::paint::PaintMap, MeshError> {
        let loaded = crate::paint::GroundPaint::load(&self.paint, &self.species, &self.contents)?;
        let mut map = loaded
            .and_then(|p| p.map)
            .unwrap_or_else(|| crate::paint::PaintMap::blank(&self.paint, &self.species));
        self.paint_file_strokes(&mut map);
        Ok(map)
    }

    /// The discs of ground the standing colliders and bodies that clear it keep bare: xy the
    /// world x and z of a sphere's centre, z its radius.
    fn clearings(&self) -> Vec<glam::Vec3> {
        let spheres = self
            .colliders
            .iter()
            .filter(|c| c.clear && c.path.len() < 2)
            .map(|c| c.center.extend(c.radius));
        let bodies = self
            .bodies
            .iter()
            .filter(|b| b.clear && b.path.len() < 2)
            .flat_map(|b| b.spheres_at(0.0, &self.contents));
        spheres.chain(bodies).map(|s| glam::Vec3::new(s.x, s.z, s.w)).collect()
    }

    /// Every collider sphere at time `t`: the scene's spheres where their paths take them, then
    /// the spheres of each body.
    pub fn colliders_at(&self, t: f32) -> Vec<Collider> {
        let spheres = self.colliders.iter().map(|c| c.at(t));
        spheres
            .chain(self.bodies.iter().flat_map(|b| b.colliders_at(t, &self.contents)))
            .collect()
    }

    /// This scene with `key = value` overrides applied (dotted keys as in the scene file, values
    /// in TOML syntax; a bare word is taken as a string), validated like a scene file.
    pub fn with_overrides(&self, sets: &[(String, String)]) -> Result<Scene, SceneError> {
        let mut table: toml::Table = toml::from_str(&self.to_toml()).expect("a scene serialises to a TOML table");
        // The keys as the scene has them, for the nearest one to a mistyped key.
        let self_table = table.clone();
        let mut added = Vec::new();
        for (key, value) in sets {
            let parsed = toml::from_str::<toml::Table>(&format!("v = {value}"))
                .ok()
                .and_then(|mut t| t.remove("v"))
                .unwrap_or_else(|| toml::Value::String(value.clone()));
            // A key the scene leaves out (an optional table, say) is added to its table; an unknown
            // one is refused when the scene is read back (with the keys that table allows).
            match lookup(&mut table, key) {
                Some(slot) => *slot = parsed,
                None => {
                    let (parent, leaf) = key.rsplit_once('.').map_or((None, key.as_str()), |(p, l)| (Some(p), l));
                    let parent = match parent {
                        Some(p) => lookup(&mut table, p).and_then(toml::Value::as_table_mut),
                        None => Some(&mut table),
                    };
                    let parent = parent.ok_or_else(|| unknown_key(&self_table, key))?;
                    parent.insert(leaf.to_string(), parsed);
                    added.push((key.clone(), leaf.to_string()));
                }
            }
        }
        let text = toml::to_string(&table).unwrap_or_default();
        let scene: Scene = toml::from_str(&text).map_err(|e| {
            let unknown = added
                .iter()
                .find(|(_, leaf)| e.message().contains(&format!("unknown field `{leaf}`")));
            if let Some((key, _)) = unknown {
                return unknown_key(&self_table, key);
            }
            let (key, value) = sets.last().cloned().unwrap_or_default();
            let mut message = crate::words::plain(&e.message().trim().replace('\n', "; "));
            if let Some(allowed) = allowed_at(&key) {
                message = format!("{message}; {key} takes {allowed}");
            }
            SceneError::BadOverride { key, value, message }
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
        let mut c = Checks::new(origin);
        self.validate_into(&mut c);
        c.finish()
    }

    /// Every check of the scene's values, into `c`.
    pub(crate) fn validate_into(&self, c: &mut Checks) {
        self.surface.validate(c);
        self.field.validate(c);
        self.simulation.validate(c);
        self.check_simulation_across(c);
        self.wind.validate(c);
        self.check_collider_count(c);
        self.bodies.iter().for_each(|b| b.validate(c));
        self.check_body_meshes(c);
        self.camera_path.validate(c);
        self.colliders.iter().for_each(|k| k.validate(c));
        self.cull.validate(c);
        self.lod.validate(c);
        self.camera.validate(c);
        self.shading.validate(c);
        self.blades.validate(c);
        self.instanced.validate(c);
        self.billboard.validate(c);
        self.trample.validate(c);
        self.paint.validate(c);
        for (k, stroke) in self.edits.pending().iter().enumerate() {
            stroke.check(c, &format!("edit.{k}"));
        }
        self.check_species(c);
        self.check_stream(c);
    }

    /// Each body's mesh packs into spheres: loading it, only once everything else is right.
    fn check_body_meshes(&self, c: &mut Checks) {
        for body in &self.bodies {
            if c.passed() {
                if let Err(e) = body.packing(&self.contents) {
                    c.check(false, "body.shape", e.to_string(), "a closed mesh that loads");
                }
            }
        }
    }

    /// The step against the stiffest blade: explicit integration diverges past it.
    fn check_simulation_across(&self, c: &mut Checks) {
        let stiffest = self
            .species
            .iter()
            .map(|s| s.stiffness[1])
            .fold(self.field.stiffness[1], f32::max);
        c.check(
            stiffest * self.simulation.step < 1.0,
            "simulation.step",
            self.simulation.step,
            format!(
                "a step small enough that stiffness × step < 1 for the stiffest blades ({stiffest}; explicit integration of stiff blades diverges)"
            ),
        );
    }

    /// A streamed field grows on ground with a height over x and z, and its budget fills a
    /// window that reaches past the hand-over on every side.
    fn check_stream(&self, c: &mut Checks) {
        let Some(window) = self.stream_window() else {
            return;
        };
        c.check(
            matches!(
                self.surface,
                Surface::Plane | Surface::Terrain { .. } | Surface::Heightmap { .. }
            ),
            "field.stream",
            true,
            "streaming on a plane, terrain or height map only; a sphere or mesh ground keeps the fixed field (stream = false)",
        );
        let reach = self.hand_over();
        c.check(
            reach > 0.0,
            "instanced.inner_radius",
            reach,
            "a positive hand-over radius where the field streams (the Bezier blades are drawn inside it, the instanced grass beyond)",
        );
        let needed = self.least_streaming_blades().unwrap_or(0);
        c.check(
            window.tiles >= 2 && window.reach() >= reach,
            "field.blades",
            self.field.blades,
            format!(
                "a streaming budget of at least {needed} blades (a window of tiles of {} blades that reaches past the hand-over at {reach} units on every side)",
                crate::tiles::TILE_BLADES
            ),
        );
        let most = crate::stream::MAX_TILES.isqrt().pow(2) * crate::tiles::TILE_BLADES;
        c.check(
            window.tiles * window.tiles <= crate::stream::MAX_TILES,
            "field.blades",
            self.field.blades,
            format!(
                "a streaming budget of at most {most} blades (a window of at most {} tiles)",
                crate::stream::MAX_TILES
            ),
        );
    }

    /// At most four species, each named once and valid.
    fn check_species(&self, c: &mut Checks) {
        let species = &self.species;
        c.check(
            species.len() <= crate::species::MAX_SPECIES,
            "species",
            species.len(),
            "at most 4 [[species]] tables",
        );
        for (k, s) in species.iter().enumerate() {
            c.check(
                !s.name.is_empty() && species[..k].iter().all(|o| o.name != s.name),
                "species.name",
                &s.name,
                "a name of its own for each species",
            );
            s.validate(c);
        }
        let names: Vec<&str> = species.iter().map(|s| s.name.as_str()).collect();
        for (k, stroke) in self.paint.strokes.iter().enumerate() {
            if let Some(name) = &stroke.species {
                c.check(
                    names.contains(&name.as_str()),
                    format!("paint.stroke.{k}.species"),
                    name,
                    format!("the name of one of the scene's [[species]]: {}", names.join(", ")),
                );
            }
        }
    }

    /// Every collider sphere, the bodies' too, fits the GPU's block.
    fn check_collider_count(&self, c: &mut Checks) {
        let body_spheres: u32 = self.bodies.iter().map(|b| b.spheres).sum();
        c.check(
            self.colliders.len() + body_spheres as usize <= MAX_COLLIDERS,
            "collider",
            self.colliders.len() + body_spheres as usize,
            "at most 128 collider spheres, counting the spheres of every body",
        );
    }
}

/// What `key` allows, as the scene's checks say it (a range, a count), where a default scene
/// checks that key: for the plain words of a `--set` value of the wrong type.
fn allowed_at(key: &str) -> Option<std::borrow::Cow<'static, str>> {
    let mut checks = Checks::recording("--set");
    Scene::default().validate_into(&mut checks);
    checks.allowed(key)
}

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

/// `key` refused, with the key of `table` nearest to it: each part of the dotted key that the
/// table lacks replaced by the nearest one at its place (by edit distance, where it is near).
fn unknown_key(table: &toml::Table, key: &str) -> SceneError {
    let hint = nearest_key(table, key).map_or_else(
        || "keys look like wind.strength, field.blades or collider.0.radius".to_string(),
        |near| format!("did you mean {near}?"),
    );
    SceneError::UnknownKey {
        key: key.to_string(),
        hint,
    }
}

/// The key of `table` nearest to `key`, part by part; `None` where a part has nothing near.
fn nearest_key(table: &toml::Table, key: &str) -> Option<String> {
    let mut level = toml::Value::Table(table.clone());
    let mut found = Vec::new();
    for part in key.split('.') {
        let next = match (&level, part.parse::<usize>()) {
            (toml::Value::Array(list), Ok(index)) => list.get(index).map(|v| (part.to_string(), v.clone())),
            (toml::Value::Table(t), _) => t.get(part).map(|v| (part.to_string(), v.clone())).or_else(|| {
                let near = crate::words::nearest(part, t.keys().map(String::as_str))?;
                t.get(near).map(|v| (near.to_string(), v.clone()))
            }),
            _ => None,
        };
        let (name, value) = next?;
        found.push(name);
        level = value;
    }
    let near = found.join(".");
    (near != key).then_some(near)
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

    /// A change to what the field is grown from grows it again; a change to what is read each
    /// frame does not.
    #[test]
    fn a_scene_grows_another_field_only_where_what_the_field_is_grown_from_changed() {
        let meadow = Scene::from_toml(include_str!("../../../scenes/meadow.toml"), "meadow").unwrap();
        let changed = |change: fn(&mut Scene)| {
            let mut scene = meadow.clone();
            change(&mut scene);
            assert_ne!(scene, meadow, "the change changed nothing");
            scene.grows_as(&meadow)
        };
        let regrown: [fn(&mut Scene); 6] = [
            |s| s.field.blades += 1,
            |s| {
                s.paint.strokes.push(crate::paint::Stroke {
                    points: vec![[0.0, 0.0]],
                    density: Some(0.0),
                    ..Default::default()
                })
            },
            |s| s.species.push(s.species.first().cloned().unwrap_or_default()),
            |s| s.technique = crate::instanced::Technique::Instanced,
            |s| s.field.stream = true,
            |s| {
                s.colliders.push(Collider {
                    clear: true,
                    ..Collider::sphere(Vec3::new(1.0, 0.3, 1.0), 0.5)
                })
            },
        ];
        for (k, change) in regrown.into_iter().enumerate() {
            assert!(!changed(change), "change {k} kept the field");
        }
        let kept: [fn(&mut Scene); 3] = [
            |s| s.shading.root_color = Vec3::new(0.9, 0.1, 0.1),
            |s| s.technique = crate::instanced::Technique::Both,
            |s| s.instanced.grid.radius += 10.0,
        ];
        for (k, change) in kept.into_iter().enumerate() {
            assert!(changed(change), "change {k} grew the field again");
        }
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
            assert_eq!(frame.packed_counts(), [5, 1, 0]);
            let placed: Vec<Vec4> = frame
                .pushing
                .iter()
                .chain(&frame.cutting)
                .map(|s| s.center.extend(s.radius))
                .collect();
            assert_eq!(placed, expected, "at {t} s");
            // More spheres than the GPU holds: the pushing ones first, then the cutters, then
            // the hiding ones, as many as fit.
            let crowd = crate::frame::FrameColliders {
                pushing: vec![frame.pushing[0]; MAX_COLLIDERS - 2],
                cutting: frame.cutting.clone(),
                hiding: frame.cutting.repeat(3),
            };
            assert_eq!(crowd.packed_counts(), [MAX_COLLIDERS as u32 - 2, 1, 1]);
        }
    }

    #[test]
    fn a_mistake_in_a_grid_table_names_its_line_and_what_is_allowed() {
        let unknown = err("name = \"x\"\n\n[instanced]\ndensity = 40.0\ndensty = 2.0\n");
        assert!(unknown.contains("line 5, column 1:"), "{unknown}");
        assert!(
            unknown.contains("unknown field `densty`, expected one of `bend`"),
            "{unknown}"
        );
        assert!(
            unknown.contains("`density`") && unknown.contains("`radius`"),
            "{unknown}"
        );
        let misfit = err("[billboard]\nfade = 3.0\nheight = \"tall\"\n");
        assert!(misfit.contains("line 3, column 10"), "{misfit}");
        assert!(misfit.contains("expected a list of 2 numbers in brackets"), "{misfit}");
        assert!(misfit.contains("found the word \"tall\""), "{misfit}");
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
    fn a_mistyped_set_key_is_answered_with_the_nearest_key() {
        let sets = |k: &str| vec![(k.to_string(), "1".to_string())];
        let said = |k: &str| Scene::default().with_overrides(&sets(k)).unwrap_err().to_string();
        assert_eq!(
            said("wind.strenght"),
            "--set wind.strenght: the scene file has no such key; did you mean wind.strength?"
        );
        assert!(said("wnd.strength").ends_with("did you mean wind.strength?"));
        assert!(said("feild.blades").ends_with("did you mean field.blades?"));
        assert!(said("nothing.like.it").ends_with("keys look like wind.strength, field.blades or collider.0.radius"));
        assert_eq!(crate::words::edit_distance("kitten", "sitting"), 3);
    }

    #[test]
    fn a_scene_file_s_value_of_the_wrong_type_names_what_its_key_takes() {
        let e = err("[field]\nblades = \"lots\"\n");
        assert!(e.contains("line 2"), "{e}");
        assert!(
            e.ends_with("expected a whole number from 0 up, found the word \"lots\"; field.blades takes a whole number from 1 to 67108864 (2^26)"),
            "{e}"
        );
        assert_eq!(
            key_at_line("name = \"x\"\n[wind]\nstrength = 2\n", 3).as_deref(),
            Some("wind.strength")
        );
        assert_eq!(key_at_line("technique = 3\n", 1).as_deref(), Some("technique"));
    }

    #[test]
    fn a_value_of_the_wrong_type_is_answered_in_plain_words() {
        let said = |k: &str, v: &str| {
            let sets = [(k.to_string(), v.to_string())];
            Scene::default().with_overrides(&sets).unwrap_err().to_string()
        };
        assert_eq!(
            said("field.blades", "lots"),
            "--set field.blades=lots: expected a whole number from 0 up, found the word \"lots\"; field.blades takes a whole number from 1 to 67108864 (2^26)"
        );
        let wind = said("wind.type", "whril");
        assert!(wind.contains("unknown variant `whril`"), "{wind}");
        assert!(wind.ends_with("did you mean `whirl`?"), "{wind}");
        let flag = said("cull.occlusion", "0.5");
        assert!(flag.contains("expected true or false, found the number 0.5"), "{flag}");
        assert!(!flag.contains("boolean"), "{flag}");
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
            .with_overrides(&sets(&[("wind.strenght", "3")]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("wind.strenght") && e.contains("no such key"), "{e}");
        // A table the scene leaves out is added.
        let painted = base
            .with_overrides(&sets(&[(
                "paint.noise",
                "{ scale = 0.1, cover = 0.5, softness = 0.0 }",
            )]))
            .unwrap();
        assert_eq!(painted.paint.noise.map(|n| n.cover), Some(0.5));
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
        assert!(e.contains("line 4") && e.contains("expected true or false"), "{e}");
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

    #[test]
    fn a_collider_that_clears_leaves_no_blade_under_it() {
        let scene = Scene::from_toml(
            "[field]\nblades = 4000\nsize = [10.0, 10.0]\n[[collider]]\ncenter = [2.0, 0.5, 1.0]\nradius = 1.5\nclear = true\n",
            "clearing",
        )
        .unwrap();
        let field = scene.grow_field().unwrap();
        let from_centre = |b: &crate::Blade| glam::Vec2::new(b.v0.x - 2.0, b.v0.z - 1.0).length();
        assert!(field.blades.iter().all(|b| from_centre(b) > 1.4));
        let around = field
            .blades
            .iter()
            .filter(|b| (1.75..2.5).contains(&from_centre(b)))
            .count();
        // The ring 1.75 to 2.5 units out keeps its share of 40 blades a square unit.
        assert!(around > 300, "{around} blades around the clearing");
        assert!(field.blades.len() > 3600, "{}", field.blades.len());
    }

    #[test]
    fn strokes_added_to_a_scene_are_painted_into_the_paint_a_renderer_holds() {
        let park = Scene::from_toml(include_str!("../../../scenes/park.toml"), "park.toml").unwrap();
        let strokes = [
            crate::paint::Stroke::circle(glam::Vec2::new(14.0, -6.0), 4.0).regrow(),
            crate::paint::Stroke::path(&[glam::Vec2::ZERO, glam::Vec2::new(5.0, 5.0)], 1.0)
                .species("dry")
                .strength(0.5),
        ];
        let mut edited = park.clone();
        edited.paint.strokes.extend(strokes.iter().cloned());
        let added = edited.strokes_added_to(&park).expect("only strokes added");
        assert_eq!(added, &strokes[..]);
        // Painted into the park's paint, they give the paint the edited scene grows with — the
        // boulder's ground still bare under the stroke that regrows it.
        let mut held = park.paint_map().unwrap();
        edited.paint_strokes(&mut held, added);
        assert_eq!(held, edited.paint_map().unwrap());
        assert_eq!(
            crate::paint::paint_at(held.as_ref(), glam::Vec2::new(14.0, -6.0)).density,
            0.0
        );
        // Anything else changed, or a stroke changed or taken away: the field grows again.
        let mut moved = edited.clone();
        moved.paint.strokes[4].radius = 2.0;
        assert_eq!(moved.strokes_added_to(&park).map(<[_]>::len), Some(2));
        assert!(moved.strokes_added_to(&edited).is_none(), "a stroke changed");
        assert!(park.strokes_added_to(&edited).is_none(), "strokes taken away");
        assert!(park.strokes_added_to(&park).is_none(), "nothing added");
        let mut taller = edited.clone();
        taller.species[0].height[1] += 0.1;
        assert!(taller.strokes_added_to(&park).is_none(), "a kind of grass changed");
        // A stroke's strength is checked.
        let mut strong = edited;
        strong.paint.strokes[5].strength = 1.5;
        let error = strong.validate("park").unwrap_err().to_string();
        assert!(
            error.contains("paint.stroke.5.strength") && error.contains("0 to 1"),
            "{error}"
        );
    }
}
