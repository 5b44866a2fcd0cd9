//! Paint over the ground: maps laid over a rectangle of the ground that say, place by place, how
//! much grass grows there (density) and how tall it grows (length). Every technique reads them
//! through the rules here and their WGSL twins (`shading.wesl` `paint_map_at`, `twin.wesl`
//! `painted_height`): a blade grows where its own hash falls under the density, so a generated
//! blade, the Bezier blade it becomes and the billboard of its place all agree, and a path
//! painted black is bare at every distance with the same edge.

use crate::content::Contents;
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

use crate::instanced::simplex2;
use crate::mesh::MeshError;
use crate::rng::{hash_u32, hash_unit};
use crate::species::{Species, MAX_SPECIES};
use crate::validate::{Checks, Validate};

/// The scene's paint (`[paint]`): the maps and the ground they cover.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct PaintParams {
    /// The ground rectangle the maps cover: lowest x, lowest z, highest x, highest z. The
    /// image's first row lies along the lowest z, its first column along the lowest x; beyond
    /// the rectangle the map's edge carries on. Strokes paint within it, short of that edge.
    pub area: [f32; 4],
    /// A PNG read as grey: how much of the grass grows (black: none, white: all). None: all,
    /// everywhere.
    pub density: Option<String>,
    /// A PNG read as grey: how tall the grass grows, as a fraction of its height (black: not at
    /// all, white: full height). None: full height everywhere.
    pub length: Option<String>,
    /// A PNG read as RGB: the grass's colour there is multiplied by twice the map's (mid grey,
    /// 128, keeps the scene's colours; yellower for dry patches, darker for lush hollows).
    /// None: the scene's colours everywhere.
    pub color: Option<String>,
    /// Patches of grass and bare ground from noise, everywhere (times the density map where
    /// there is one).
    pub noise: Option<PaintNoise>,
    /// Patches of tinted grass from noise (dry patches, say), everywhere (times the colour
    /// map's tint where there is one).
    pub tint_noise: Option<TintNoise>,
    /// Texels per unit of ground of the map strokes are painted into where no map file is
    /// named (at most 2048 a side over `area`: coarser over a wider one).
    pub resolution: f32,
    /// Strokes painted over the maps, in order (paths, lawns, beds of one species).
    #[serde(rename = "stroke", skip_serializing_if = "Vec::is_empty")]
    pub strokes: Vec<Stroke>,
}

/// A stroke painted over the ground (`[[paint.stroke]]`): within `radius` of the line through
/// its points it sets what it names, blending into what was there over `softness` beyond.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct Stroke {
    /// The line's points: world x and z (one point: a disc).
    pub points: Vec<[f32; 2]>,
    /// How far from the line it paints fully, units.
    pub radius: f32,
    /// Over how many units beyond that it fades out.
    pub softness: f32,
    /// How much grass grows under it (0 bare, 1 all).
    pub density: Option<f32>,
    /// How tall the grass under it grows, as a fraction of its height.
    pub length: Option<f32>,
    /// What the grass's colour under it is multiplied by.
    pub color: Option<Vec3>,
    /// The one kind of grass that grows under it (a `[[species]]` name).
    pub species: Option<String>,
    /// How far it takes what was there toward what it names, 0 to 1 (0.5: half way; where
    /// it fades out, that much less).
    pub strength: f32,
}

impl Default for Stroke {
    fn default() -> Self {
        Self {
            points: Vec::new(),
            radius: 1.0,
            softness: 0.5,
            density: None,
            length: None,
            color: None,
            species: None,
            strength: 1.0,
        }
    }
}

/// What burnt grass's colour is multiplied by: near black, a little brown.
pub const BURNT: Vec3 = Vec3::new(0.22, 0.16, 0.1);
/// How tall burnt grass stands, as a fraction of its height: stubble.
pub const BURNT_LENGTH: f32 = 0.12;

/// Edits a game paints at run time: a stroke over a circle or along a path, then what it does
/// (`clear`, `mow`, `burn`, `regrow`, or a `density`, `species` or `tint` of its own), then
/// how (`softness`, `strength`). Each sets what it names and leaves the rest as it was.
impl Stroke {
    /// A stroke over the disc of `radius` around ground point `center` (world x, z), doing
    /// nothing until told what.
    pub fn circle(center: Vec2, radius: f32) -> Stroke {
        Stroke::path(&[center], radius)
    }

    /// A stroke `radius` wide either side of the line through ground points `points`.
    pub fn path(points: &[Vec2], radius: f32) -> Stroke {
        Stroke {
            points: points.iter().map(|p| p.to_array()).collect(),
            radius,
            softness: radius / 3.0,
            ..Stroke::default()
        }
    }

    /// Bare ground under it.
    pub fn clear(self) -> Stroke {
        self.density(0.0)
    }

    /// Grass under it cut to `length` of its height (0 to 1).
    pub fn mow(self, length: f32) -> Stroke {
        Stroke {
            length: Some(length),
            ..self
        }
    }

    /// Grass under it burnt: stubble, near black.
    pub fn burn(self) -> Stroke {
        self.mow(BURNT_LENGTH).tint(BURNT)
    }

    /// Grass under it grown back: all of it, full height, the scene's colours.
    pub fn regrow(self) -> Stroke {
        self.density(1.0).mow(1.0).tint(Vec3::ONE)
    }

    /// `density` of the grass grows under it (0 bare, 1 all).
    pub fn density(self, density: f32) -> Stroke {
        Stroke {
            density: Some(density),
            ..self
        }
    }

    /// Only the kind of grass called `name` (a `[[species]]`) grows under it.
    pub fn species(self, name: impl Into<String>) -> Stroke {
        Stroke {
            species: Some(name.into()),
            ..self
        }
    }

    /// The grass's colour under it multiplied by `color` (each 0 to 2; 1 the scene's own).
    pub fn tint(self, color: Vec3) -> Stroke {
        Stroke {
            color: Some(color),
            ..self
        }
    }

    /// It fades out over `softness` units beyond its radius.
    pub fn softness(self, softness: f32) -> Stroke {
        Stroke { softness, ..self }
    }

    /// It takes what was there `strength` of the way (0 to 1) toward what it names.
    pub fn strength(self, strength: f32) -> Stroke {
        Stroke { strength, ..self }
    }
}

impl Stroke {
    /// How far ground point `xz` is from the stroke's line.
    fn distance(&self, xz: Vec2) -> f32 {
        // Read where it is painted, for every texel near it: no allocation here.
        match self.points.as_slice() {
            [] => f32::INFINITY,
            [p] => xz.distance(Vec2::from(*p)),
            points => points
                .windows(2)
                .map(|w| {
                    let (a, b) = (Vec2::from(w[0]), Vec2::from(w[1]));
                    let t = ((xz - a).dot(b - a) / (b - a).length_squared().max(1e-12)).clamp(0.0, 1.0);
                    xz.distance(a + (b - a) * t)
                })
                .fold(f32::INFINITY, f32::min),
        }
    }

    /// How much the stroke paints ground point `xz` (1 within its radius, fading to 0).
    fn amount(&self, xz: Vec2) -> f32 {
        let d = self.distance(xz);
        self.strength * (1.0 - smoothstep(self.radius, self.radius + self.softness, d))
    }
}

/// Patches of tinted grass from simplex noise (`[paint.tint_noise]`): where the noise's patches
/// are (`scale`, `cover`, `softness` as for `[paint.noise]`), the grass's colour is multiplied
/// by `color`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct TintNoise {
    /// Patches per unit of ground.
    pub scale: f32,
    /// About what share of the ground is tinted, 0 to 1.
    pub cover: f32,
    /// How gradually the tint fades at a patch's edge, in noise units.
    pub softness: f32,
    /// What the grass's colour is multiplied by in a patch (each 0 to 4).
    pub color: Vec3,
}

impl Default for TintNoise {
    fn default() -> Self {
        // Dry patches: yellower, a little paler.
        Self {
            scale: 0.04,
            cover: 0.35,
            softness: 0.2,
            color: Vec3::new(1.6, 1.25, 0.7),
        }
    }
}

impl TintNoise {
    /// What the grass's colour is multiplied by at world ground point `xz` (shading.wesl
    /// `painted_tint`).
    pub fn tint(&self, xz: Vec2) -> Vec3 {
        // Its own offset, so tinted patches do not line up with bare ones.
        let amount = noise_patch(xz, [self.scale, self.cover, self.softness], Vec2::new(-211.7, 93.1));
        Vec3::ONE.lerp(self.color, amount)
    }
}

/// Patches of grass and bare ground from simplex noise (`[paint.noise]`): the ground grows
/// grass where the noise is above a threshold set by `cover`, thinning over a band `softness`
/// wide on either side.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct PaintNoise {
    /// Patches per unit of ground (0.05: patches about 20 units across).
    pub scale: f32,
    /// About what share of the ground grows grass, 0 to 1.
    pub cover: f32,
    /// How gradually the grass thins at a patch's edge, in noise units (0: a sharp edge).
    pub softness: f32,
}

impl Default for PaintNoise {
    fn default() -> Self {
        Self {
            scale: 0.05,
            cover: 0.7,
            softness: 0.1,
        }
    }
}

impl PaintNoise {
    /// How much grass grows at world ground point `xz` (shading.wesl `painted_density`).
    pub fn density(&self, xz: Vec2) -> f32 {
        // Away from the origin, so the instanced grass's clump noise (at the same scale there)
        // does not line up with it.
        noise_patch(xz, [self.scale, self.cover, self.softness], Vec2::new(57.3, -131.9))
    }
}

/// How much of a noise patch (`[patches per unit, cover, softness]`) covers world ground point
/// `xz`, the noise shifted by `offset` (shading.wesl `noise_patch`).
fn noise_patch(xz: Vec2, [scale, cover, softness]: [f32; 3], offset: Vec2) -> f32 {
    let n = 0.5 + 0.5 * simplex2(xz * scale + offset);
    let threshold = 1.0 - cover;
    smoothstep(threshold - softness, threshold + softness, n)
}

impl Stroke {
    /// The lowest and highest ground point (x, z) the stroke paints; `None` for a stroke of no
    /// point.
    pub fn reach(&self) -> Option<(Vec2, Vec2)> {
        let reach = Vec2::splat(self.radius + self.softness);
        let points = self.points.iter().map(|&p| Vec2::from(p));
        let low = points.clone().reduce(Vec2::min)?;
        let high = points.reduce(Vec2::max)?;
        Some((low - reach, high + reach))
    }

    /// Check the stroke's values into `c`, under keys beginning `key` (`paint.stroke.3`).
    pub(crate) fn check(&self, c: &mut Checks, key: &str) {
        let s = self;
        let key = |name: &str| format!("{key}.{name}");
        c.check(
            !s.points.is_empty() && s.points.iter().flatten().all(|v| v.is_finite()),
            key("points"),
            &s.points,
            "at least one [x, z] point",
        );
        c.check(
            s.radius.is_finite() && s.radius >= 0.0 && s.softness.is_finite() && s.softness >= 0.0,
            key("radius"),
            (s.radius, s.softness),
            "a radius and softness ≥ 0",
        );
        for (name, v) in [("density", s.density), ("length", s.length)] {
            c.check(
                v.is_none_or(|v| (0.0..=1.0).contains(&v)),
                key(name),
                v.unwrap_or_default(),
                "0 to 1",
            );
        }
        c.check(
            s.color
                .is_none_or(|t| t.is_finite() && t.min_element() >= 0.0 && t.max_element() <= 2.0),
            key("color"),
            s.color.unwrap_or_default(),
            "three multipliers from 0 to 2",
        );
        c.check((0.0..=1.0).contains(&s.strength), key("strength"), s.strength, "0 to 1");
    }
}

/// GLSL's smoothstep (a step where the edges meet).
fn smoothstep(low: f32, high: f32, x: f32) -> f32 {
    if high <= low {
        return if x < low { 0.0 } else { 1.0 };
    }
    let t = ((x - low) / (high - low)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl Default for PaintParams {
    fn default() -> Self {
        Self {
            area: [-32.0, -32.0, 32.0, 32.0],
            density: None,
            length: None,
            color: None,
            noise: None,
            tint_noise: None,
            resolution: 4.0,
            strokes: Vec::new(),
        }
    }
}

impl PaintParams {
    /// Whether the ground is painted at all (maps or noise).
    pub fn paints(&self) -> bool {
        self.makes_a_map(&[]) || self.noise.is_some() || self.tint_noise.is_some()
    }

    /// Whether the paint, with the kinds of grass `species`, is a map over `area`: map files,
    /// strokes, or kinds weighted by a map or grown only where painted. The one rule
    /// [`PaintMap::load`], [`GroundPaint::load`] and a scene's stroke edits follow.
    pub fn makes_a_map(&self, species: &[Species]) -> bool {
        let files = [&self.density, &self.length, &self.color].iter().any(|m| m.is_some());
        let weighted = species.iter().any(|s| s.weight_map.is_some() || s.painted_only);
        files || weighted || !self.strokes.is_empty()
    }

    /// The maps' paths, relative ones made relative to directory `dir` (the scene file's).
    pub fn paths_mut(&mut self) -> impl Iterator<Item = &mut String> {
        self.density
            .iter_mut()
            .chain(self.length.iter_mut())
            .chain(self.color.iter_mut())
    }
}

impl Validate for PaintParams {
    fn validate(&self, c: &mut Checks) {
        let [x0, z0, x1, z1] = self.area;
        c.check(
            self.area.iter().all(|v| v.is_finite()) && x1 > x0 && z1 > z0,
            "paint.area",
            self.area,
            "[lowest x, lowest z, highest x, highest z], each highest above its lowest",
        );
        if let Some(n) = &self.noise {
            check_patches(c, "paint.noise", [n.scale, n.cover, n.softness]);
        }
        c.check(
            self.resolution.is_finite() && self.resolution > 0.0 && self.resolution <= 64.0,
            "paint.resolution",
            self.resolution,
            "0 < resolution ≤ 64 texels per unit",
        );
        for (k, s) in self.strokes.iter().enumerate() {
            s.check(c, &format!("paint.stroke.{k}"));
        }
        if let Some(t) = &self.tint_noise {
            check_patches(c, "paint.tint_noise", [t.scale, t.cover, t.softness]);
            c.check(
                t.color.is_finite() && t.color.min_element() >= 0.0 && t.color.max_element() <= 4.0,
                "paint.tint_noise.color",
                t.color,
                "three multipliers from 0 to 4",
            );
        }
    }
}

/// A noise's patches (`[scale, cover, softness]`) under `key`: each within what it allows.
fn check_patches(c: &mut Checks, key: &str, [scale, cover, softness]: [f32; 3]) {
    c.check(
        scale.is_finite() && scale > 0.0 && scale <= 100.0,
        format!("{key}.scale"),
        scale,
        "0 < scale ≤ 100 patches per unit",
    );
    c.check(
        cover.is_finite() && (0.0..=1.0).contains(&cover),
        format!("{key}.cover"),
        cover,
        "a share of the ground from 0 to 1",
    );
    c.check(
        softness.is_finite() && (0.0..=0.5).contains(&softness),
        format!("{key}.softness"),
        softness,
        "0 to 0.5 (noise units)",
    );
}

/// What the paint says at one place of the ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Paint {
    /// How much of the grass grows, 0 to 1.
    pub density: f32,
    /// How tall it grows, as a fraction of its height, 0 to 1.
    pub length: f32,
    /// What its colour is multiplied by (1: the scene's own colours).
    pub tint: Vec3,
    /// Each species' weight map there (1 where it has none).
    pub species: [f32; MAX_SPECIES],
}

impl Paint {
    /// Unpainted ground: all the grass, at full height, in the scene's colours.
    pub const FULL: Paint = Paint {
        density: 1.0,
        length: 1.0,
        tint: Vec3::ONE,
        species: [1.0; MAX_SPECIES],
    };
}

/// Mixed into a blade's hash for its density draw, so it is independent of the draws that
/// shape the blade.
pub const DENSITY_SALT: u32 = 0x2f6b_3a91;

/// The height the blade with hash `hash` and height `height` grows to where the ground is
/// painted `paint`: 0 (it does not grow) unless its draw falls under the density, else its
/// height scaled by the length.
pub fn painted_height(hash: u32, height: f32, paint: Paint) -> f32 {
    if hash_unit(hash ^ DENSITY_SALT) < paint.density {
        height * paint.length
    } else {
        0.0
    }
}

/// The hash a blade of a fixed (not generated) field draws its density with: from its root, so
/// it does not depend on the order blades were grown in.
pub fn root_hash(x: f32, z: f32) -> u32 {
    hash_u32(x.to_bits() ^ hash_u32(z.to_bits()))
}

/// The scene's maps, read and packed as the GPU holds them.
#[derive(Clone, Debug, PartialEq)]
pub struct PaintMap {
    /// The ground's lowest x and z the map covers.
    pub min: Vec2,
    /// Its highest x and z.
    pub max: Vec2,
    /// Texels along x and along z.
    pub size: [u32; 2],
    /// Texels row by row (z, then x), four words each: the density's byte lowest, then the
    /// length's; the tint's red, green and blue bytes (128: the scene's own colour); each
    /// species' weight map's byte (255 where it has none); nothing.
    pub texels: Vec<[u32; 4]>,
}

/// A paint map as the image files that make it (`PaintMap::images`).
pub struct PaintImages {
    /// How much grass grows.
    pub density: image::GrayImage,
    /// How tall it grows.
    pub length: image::GrayImage,
    /// What its colour is multiplied by (twice the pixel's).
    pub color: image::RgbImage,
    /// Each species' weight.
    pub species: Vec<image::GrayImage>,
}

/// A texel's tint word where the grass keeps the scene's colours.
const NEUTRAL_TINT: u32 = 0x0080_8080;

impl PaintMap {
    /// The maps `params` and the species' weight maps name, read; `None` where they name none
    /// (and no stroke or species needs a map). Fails with the file and what is allowed where a
    /// map cannot be read or the maps differ in size.
    pub fn load(params: &PaintParams, species: &[Species]) -> Result<Option<PaintMap>, MeshError> {
        PaintMap::load_from(&Contents::default(), params, species)
    }

    /// [`PaintMap::load`], each map the image given under its name in `contents` where given.
    pub fn load_from(
        contents: &Contents,
        params: &PaintParams,
        species: &[Species],
    ) -> Result<Option<PaintMap>, MeshError> {
        let weight_maps: Vec<Option<String>> = species.iter().map(|s| s.weight_map.clone()).collect();
        let grey = |path: &Option<String>| path.as_deref().map(|p| read_map(contents, p, 1)).transpose();
        let (density, length) = (grey(&params.density)?, grey(&params.length)?);
        let color = params.color.as_deref().map(|p| read_map(contents, p, 3)).transpose()?;
        let weights = weight_maps.iter().map(grey).collect::<Result<Vec<_>, _>>()?;
        // Where a species has no map of its own: everywhere, or (painted only) nowhere.
        let unpainted = |k: usize| species.get(k).map_or(255, |s| if s.painted_only { 0 } else { 255 });
        let mut named = vec![
            (&density, &params.density),
            (&length, &params.length),
            (&color, &params.color),
        ];
        named.extend(weights.iter().zip(&weight_maps));
        let mut read = named
            .iter()
            .filter_map(|(m, path)| Some((m.as_ref()?, path.as_deref()?)));
        let Some((first, first_path)) = read.next() else {
            // Strokes, or species grown only where painted: a blank map over the area.
            return Ok(params.makes_a_map(species).then(|| PaintMap::blank(params, species)));
        };
        if let Some((other, path)) = read.find(|(m, _)| m.size != first.size) {
            return Err(MeshError::Map {
                path: path.to_string(),
                reason: format!(
                    "it is {}×{} pixels but {first_path} is {}×{}; a scene's paint maps share one size",
                    other.size[0], other.size[1], first.size[0], first.size[1]
                ),
            });
        }
        let size = first.size;
        let byte = |map: &Option<ReadMap>, i: usize| u32::from(map.as_ref().map_or(255, |m| m.bytes[i]));
        let texels = (0..(size[0] * size[1]) as usize)
            .map(|i| {
                let tint = color.as_ref().map_or(NEUTRAL_TINT, |m| {
                    let rgb = &m.bytes[3 * i..3 * i + 3];
                    u32::from(rgb[0]) | u32::from(rgb[1]) << 8 | u32::from(rgb[2]) << 16
                });
                let species = (0..MAX_SPECIES).fold(0, |word, k| {
                    let weight = match weights.get(k) {
                        Some(Some(m)) => u32::from(m.bytes[i]),
                        _ => unpainted(k),
                    };
                    word | weight << (8 * k)
                });
                [byte(&density, i) | byte(&length, i) << 8, tint, species, 0]
            })
            .collect();
        let [x0, z0, x1, z1] = params.area;
        Ok(Some(PaintMap {
            min: Vec2::new(x0, z0),
            max: Vec2::new(x1, z1),
            size,
            texels,
        }))
    }

    /// A map over `params.area` at `params.resolution` (at most `MAX_MAP_SIDE` a side) where
    /// nothing is painted yet: every species grows there but those grown only where painted.
    pub fn blank(params: &PaintParams, species: &[Species]) -> PaintMap {
        let [x0, z0, x1, z1] = params.area;
        let (min, max) = (Vec2::new(x0, z0), Vec2::new(x1, z1));
        let size = ((max - min) * params.resolution)
            .ceil()
            .clamp(Vec2::splat(2.0), Vec2::splat(MAX_MAP_SIDE as f32));
        let mut unpainted = Paint::FULL;
        for (k, s) in species.iter().take(MAX_SPECIES).enumerate() {
            unpainted.species[k] = if s.painted_only { 0.0 } else { 1.0 };
        }
        PaintMap::from_paint(min, max, [size.x as u32, size.y as u32], |_, _| unpainted)
    }

    /// Paint `stroke` into the texels; `species` is the index of the one kind it grows.
    pub fn paint_stroke(&mut self, stroke: &Stroke, species: Option<usize>) {
        self.paint_stroke_marking(stroke, species, |_| {});
    }

    /// [`PaintMap::paint_stroke`], saying the index of each texel it changes to `changed`.
    pub(crate) fn paint_stroke_marking(
        &mut self,
        stroke: &Stroke,
        species: Option<usize>,
        mut changed: impl FnMut(usize),
    ) {
        let per_unit = self.texels_per_unit();
        // Only the texels within its reach.
        let reach = stroke.radius + stroke.softness + 1.0 / per_unit.min_element();
        let (low, high) = stroke.points.iter().fold((Vec2::MAX, Vec2::MIN), |(lo, hi), &p| {
            (lo.min(Vec2::from(p)), hi.max(Vec2::from(p)))
        });
        let texel = |p: Vec2| ((p - self.min) * per_unit).floor();
        let [inner_first, inner_last] = self.paintable();
        let first = texel(low - reach).clamp(inner_first, inner_last);
        let last = texel(high + reach).clamp(inner_first, inner_last);
        for z in first.y as u32..=last.y as u32 {
            for x in first.x as u32..=last.x as u32 {
                let centre = self.min + (Vec2::new(x as f32, z as f32) + 0.5) / per_unit;
                let amount = stroke.amount(centre);
                if amount <= 0.0 {
                    continue;
                }
                let index = (z * self.size[0] + x) as usize;
                changed(index);
                let texel = &mut self.texels[index];
                let mut paint = unpack_texel(*texel);
                let mix = |old: f32, new: Option<f32>| new.map_or(old, |v| old + (v - old) * amount);
                paint.density = mix(paint.density, stroke.density);
                paint.length = mix(paint.length, stroke.length);
                paint.tint = stroke.color.map_or(paint.tint, |c| paint.tint.lerp(c, amount));
                if let Some(only) = species {
                    for (k, w) in paint.species.iter_mut().enumerate() {
                        *w = mix(*w, Some(if k == only { 1.0 } else { 0.0 }));
                    }
                }
                *texel = pack_texel(&paint);
            }
        }
    }

    /// The first and the last texel (x, z) that strokes and clearings may paint: all but the
    /// outermost ring where the map is three texels or more across. The ring's paint carries on
    /// beyond the area ([`PaintMap::at`], shading.wesl `paint_map_at`): painted, a stroke
    /// reaching the area's edge would paint every point past it in line with it, to the horizon.
    fn paintable(&self) -> [Vec2; 2] {
        let size = Vec2::new(self.size[0] as f32, self.size[1] as f32);
        let ring = Vec2::select(size.cmpge(Vec2::splat(3.0)), Vec2::ONE, Vec2::ZERO);
        [ring, size - Vec2::ONE - ring]
    }

    /// The maps as images, in the files' own terms: density, length (grey), colour (RGB, 128
    /// the scene's own), and the first `species` species' weights (grey).
    pub fn images(&self, species: usize) -> PaintImages {
        let [w, h] = self.size;
        let byte = |i: usize, word: usize, k: u32| (self.texels[i][word] >> (8 * k) & 0xff) as u8;
        let index = |x: u32, z: u32| (z * w + x) as usize;
        PaintImages {
            density: image::GrayImage::from_fn(w, h, |x, z| image::Luma([byte(index(x, z), 0, 0)])),
            length: image::GrayImage::from_fn(w, h, |x, z| image::Luma([byte(index(x, z), 0, 1)])),
            color: image::RgbImage::from_fn(w, h, |x, z| {
                let i = index(x, z);
                image::Rgb([byte(i, 1, 0), byte(i, 1, 1), byte(i, 1, 2)])
            }),
            species: (0..species.min(MAX_SPECIES) as u32)
                .map(|k| image::GrayImage::from_fn(w, h, |x, z| image::Luma([byte(index(x, z), 2, k)])))
                .collect(),
        }
    }

    /// A map over `min`..`max` of `size` texels from each texel's paint (row by row).
    pub fn from_paint(min: Vec2, max: Vec2, size: [u32; 2], paint: impl Fn(u32, u32) -> Paint) -> PaintMap {
        let texels = (0..size[1])
            .flat_map(|z| (0..size[0]).map(move |x| (x, z)))
            .map(|(x, z)| pack_texel(&paint(x, z)))
            .collect();
        PaintMap { min, max, size, texels }
    }

    /// Texels per unit of ground along x and z.
    pub fn texels_per_unit(&self) -> Vec2 {
        Vec2::new(self.size[0] as f32, self.size[1] as f32) / (self.max - self.min)
    }

    /// The paint at world ground point `xz`: the four nearest texels blended, the edge carrying
    /// on beyond the area (as shading.wesl `paint_map_at` samples it).
    pub fn at(&self, xz: Vec2) -> Paint {
        let at = (xz - self.min) * self.texels_per_unit() - 0.5;
        let limit = Vec2::new(self.size[0] as f32 - 1.0, self.size[1] as f32 - 1.0);
        let at = at.clamp(Vec2::ZERO, limit);
        let low = at.floor();
        let f = at - low;
        let (x0, z0) = (low.x as u32, low.y as u32);
        let (x1, z1) = ((x0 + 1).min(self.size[0] - 1), (z0 + 1).min(self.size[1] - 1));
        let texel = |x: u32, z: u32| unpack_texel(self.texels[(z * self.size[0] + x) as usize]);
        let blend = |a: Paint, b: Paint, t: f32| Paint {
            density: a.density + (b.density - a.density) * t,
            length: a.length + (b.length - a.length) * t,
            tint: a.tint.lerp(b.tint, t),
            species: [0, 1, 2, 3].map(|k| a.species[k] + (b.species[k] - a.species[k]) * t),
        };
        let near = blend(texel(x0, z0), texel(x1, z0), f.x);
        let far = blend(texel(x0, z1), texel(x1, z1), f.x);
        blend(near, far, f.y)
    }
}

/// A texel of paint `p` (`unpack_texel`'s inverse, to a byte).
fn pack_texel(p: &Paint) -> [u32; 4] {
    let byte = |v: f32, most: f32| (v.clamp(0.0, 1.0) * most).round().min(255.0) as u32;
    let t = p.tint / 2.0;
    let tint = byte(t.x, 256.0) | byte(t.y, 256.0) << 8 | byte(t.z, 256.0) << 16;
    let species = (0..MAX_SPECIES).fold(0, |word, k| word | byte(p.species[k], 255.0) << (8 * k));
    [byte(p.density, 255.0) | byte(p.length, 255.0) << 8, tint, species, 0]
}

/// A texel's paint (shading.wesl `paint_texel`).
fn unpack_texel([amounts, tint, species, _]: [u32; 4]) -> Paint {
    let byte = |word: u32, k: u32| (word >> (8 * k) & 0xff) as f32;
    Paint {
        density: byte(amounts, 0) / 255.0,
        length: byte(amounts, 1) / 255.0,
        tint: Vec3::new(byte(tint, 0), byte(tint, 1), byte(tint, 2)) / 128.0,
        species: [0, 1, 2, 3].map(|k| byte(species, k) / 255.0),
    }
}

/// All the scene paints on the ground: its maps and its noise.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GroundPaint {
    /// The maps, where the scene names any.
    pub map: Option<PaintMap>,
    /// The noise, where the scene asks for it.
    pub noise: Option<PaintNoise>,
    /// The tint's noise, where the scene asks for it.
    pub tint_noise: Option<TintNoise>,
}

impl GroundPaint {
    /// What `params` paints and `species`' weight maps weigh, the maps read; `None` where
    /// nothing is painted. Fails with the file and what is allowed where a map cannot be used.
    /// Maps given in `contents` under their names are not read from disk.
    pub fn load(
        params: &PaintParams,
        species: &[Species],
        contents: &Contents,
    ) -> Result<Option<GroundPaint>, MeshError> {
        if !params.makes_a_map(species) && params.noise.is_none() && params.tint_noise.is_none() {
            return Ok(None);
        }
        Ok(Some(GroundPaint {
            map: PaintMap::load_from(contents, params, species)?,
            noise: params.noise,
            tint_noise: params.tint_noise,
        }))
    }

    /// Bare ground in every disc of `discs` (xy the centre's world x and z, z the radius),
    /// thinning to full over the texel beyond it. Without maps, a map of 0.25-unit texels
    /// around the discs is made for them; with maps they are stamped at the maps' texels (and
    /// only within their area).
    pub fn clear(&mut self, discs: &[Vec3]) {
        if discs.is_empty() {
            return;
        }
        let map = self.map.get_or_insert_with(|| clearing_map(discs));
        let per_unit = map.texels_per_unit();
        // Texels a little beyond the disc too, so that blended between texels the whole disc
        // is bare (its four nearest texels lie within 0.71 texels of any point).
        let beyond = 0.75 / per_unit.min_element();
        let [first, last] = map.paintable();
        for z in first.y as u32..=last.y as u32 {
            for x in first.x as u32..=last.x as u32 {
                let centre = map.min + (Vec2::new(x as f32, z as f32) + 0.5) / per_unit;
                if discs.iter().any(|d| centre.distance(d.truncate()) < d.z + beyond) {
                    map.texels[(z * map.size[0] + x) as usize][0] &= !0xff;
                }
            }
        }
    }

    /// The paint at world ground point `xz`: the map's, its density times the noise's, its
    /// tint times the tint noise's.
    pub fn at(&self, xz: Vec2) -> Paint {
        let mut paint = self.map.as_ref().map_or(Paint::FULL, |m| m.at(xz));
        if let Some(noise) = &self.noise {
            paint.density *= noise.density(xz);
        }
        if let Some(noise) = &self.tint_noise {
            paint.tint *= noise.tint(xz);
        }
        paint
    }
}

/// A full map of 0.25-unit texels over `discs` and a unit around them (at most
/// `MAX_MAP_SIDE` texels a side: coarser over a wider spread).
fn clearing_map(discs: &[Vec3]) -> PaintMap {
    let low = discs.iter().map(|d| d.truncate() - d.z).fold(Vec2::MAX, Vec2::min) - 1.0;
    let high = discs.iter().map(|d| d.truncate() + d.z).fold(Vec2::MIN, Vec2::max) + 1.0;
    let texel = ((high - low).max_element() / MAX_MAP_SIDE as f32).max(0.25);
    let size = ((high - low) / texel).ceil().as_uvec2().max(glam::UVec2::splat(2));
    let high = low + size.as_vec2() * texel;
    PaintMap::from_paint(low, high, size.into(), |_, _| Paint::FULL)
}

/// The paint at `xz` where there is any, else full.
pub fn paint_at(paint: Option<&GroundPaint>, xz: Vec2) -> Paint {
    paint.map_or(Paint::FULL, |p| p.at(xz))
}

/// A map as read: its size and its pixels' bytes row by row.
struct ReadMap {
    size: [u32; 2],
    bytes: Vec<u8>,
}

/// A PNG (or the image given under its name) read as 8-bit grey (`channels` 1) or RGB (3).
fn read_map(contents: &Contents, path: &str, channels: u32) -> Result<ReadMap, MeshError> {
    let fail = |reason: String| MeshError::Map {
        path: path.to_string(),
        reason,
    };
    let image = contents.read_image(std::path::Path::new(path)).map_err(fail)?;
    let (w, h) = (image.width(), image.height());
    if w < 2 || h < 2 || w > MAX_MAP_SIDE || h > MAX_MAP_SIDE {
        return Err(fail(format!(
            "it is {w}×{h} pixels; a paint map has 2 to {MAX_MAP_SIDE} pixels a side"
        )));
    }
    let bytes = match channels {
        1 => image.into_luma8().into_raw(),
        _ => image.into_rgb8().into_raw(),
    };
    Ok(ReadMap { size: [w, h], bytes })
}

/// The most texels along a paint map's side (a 2048² map is 64 MiB on the GPU).
pub const MAX_MAP_SIDE: u32 = 2048;

#[cfg(test)]
mod tests {
    use super::*;

    fn stripe() -> PaintMap {
        // Bare where 4 ≤ x < 6 (texels 4 and 5 of 10 over x in 0..10), half height where z ≥ 5.
        PaintMap::from_paint(Vec2::ZERO, Vec2::splat(10.0), [10, 10], |x, z| Paint {
            density: if (4..6).contains(&x) { 0.0 } else { 1.0 },
            length: if z >= 5 { 0.5 } else { 1.0 },
            tint: if x < 2 { Vec3::new(1.5, 1.0, 0.5) } else { Vec3::ONE },
            species: [1.0, if z < 5 { 0.0 } else { 1.0 }, 1.0, 1.0],
        })
    }

    #[test]
    fn a_painted_path_is_bare_and_its_surroundings_full() {
        let map = stripe();
        assert_eq!(map.at(Vec2::new(5.0, 2.0)).density, 0.0);
        assert_eq!(map.at(Vec2::new(1.0, 2.0)).density, 1.0);
        // Half-way across the path's edge texels, half the grass.
        assert!((map.at(Vec2::new(4.0, 2.0)).density - 0.5).abs() < 1e-6);
        // The edge carries on beyond the area.
        assert_eq!(map.at(Vec2::new(5.0, -40.0)).density, 0.0);
        assert_eq!(map.at(Vec2::new(5.0, 40.0)).length, 128.0 / 255.0);
        // The tint: as painted, blended across the edge of its texels, neutral elsewhere.
        assert_eq!(map.at(Vec2::new(0.5, 2.0)).tint, Vec3::new(1.5, 1.0, 0.5));
        assert_eq!(map.at(Vec2::new(2.0, 2.0)).tint, Vec3::new(1.25, 1.0, 0.75));
        assert_eq!(map.at(Vec2::new(7.0, 2.0)).tint, Vec3::ONE);
        assert_eq!(map.at(Vec2::new(7.0, 2.0)).species, [1.0, 0.0, 1.0, 1.0]);
        assert_eq!(map.at(Vec2::new(7.0, 5.0)).species, [1.0, 0.5, 1.0, 1.0]);
    }

    #[test]
    fn density_keeps_its_share_of_blades_and_length_scales_them() {
        let half = Paint {
            density: 0.5,
            length: 0.25,
            ..Paint::FULL
        };
        let heights: Vec<f32> = (0..20_000u32).map(|i| painted_height(hash_u32(i), 0.8, half)).collect();
        let grown = heights.iter().filter(|&&h| h > 0.0).count() as f32 / heights.len() as f32;
        assert!((grown - 0.5).abs() < 0.02, "{grown}");
        assert!(heights.iter().all(|&h| h == 0.0 || h == 0.2));
        assert!((0..1000u32).all(|i| painted_height(i, 1.0, Paint::FULL) == 1.0));
        let bare = Paint {
            density: 0.0,
            ..Paint::FULL
        };
        assert!((0..1000u32).all(|i| painted_height(i, 1.0, bare) == 0.0));
    }

    #[test]
    fn noise_grows_grass_on_about_its_cover_of_the_ground() {
        for cover in [0.3, 0.7] {
            let paint = GroundPaint {
                noise: Some(PaintNoise {
                    scale: 0.05,
                    cover,
                    softness: 0.0,
                }),
                ..GroundPaint::default()
            };
            let samples = 200 * 200;
            let grown = (0..samples)
                .filter(|i| paint.at(Vec2::new((i % 200) as f32, (i / 200) as f32) * 2.0).density > 0.5)
                .count() as f32
                / samples as f32;
            assert!((grown - cover).abs() < 0.15, "cover {cover}: grass on {grown}");
        }
    }

    #[test]
    fn a_clearing_leaves_its_disc_bare_and_the_rest_as_painted() {
        let mut paint = GroundPaint::default();
        paint.clear(&[Vec3::new(3.0, -2.0, 1.5)]);
        assert_eq!(paint.at(Vec2::new(3.0, -2.0)).density, 0.0);
        assert_eq!(paint.at(Vec2::new(3.0, -0.8)).density, 0.0);
        assert_eq!(paint.at(Vec2::new(3.0, -0.5)).density, 0.0);
        assert_eq!(paint.at(Vec2::new(3.0, 0.0)).density, 1.0);
        assert_eq!(paint.at(Vec2::new(40.0, 9.0)).density, 1.0);
        let mut painted = GroundPaint {
            map: Some(stripe()),
            ..GroundPaint::default()
        };
        painted.clear(&[Vec3::new(8.0, 8.0, 1.0)]);
        assert_eq!(painted.at(Vec2::new(8.0, 8.0)).density, 0.0);
        assert_eq!(painted.at(Vec2::new(8.0, 8.0)).length, 128.0 / 255.0);
        assert_eq!(painted.at(Vec2::new(1.0, 2.0)).density, 1.0);
    }

    #[test]
    fn a_stroke_paints_along_its_line_and_fades_at_its_edge() {
        let params = PaintParams {
            area: [0.0, 0.0, 20.0, 10.0],
            strokes: vec![Stroke {
                points: vec![[2.0, 5.0], [18.0, 5.0]],
                radius: 1.0,
                softness: 1.0,
                density: Some(0.0),
                species: Some("lawn".into()),
                ..Stroke::default()
            }],
            ..PaintParams::default()
        };
        let mut map = PaintMap::load(&params, &[]).unwrap().unwrap();
        assert_eq!(map.size, [80, 40]);
        map.paint_stroke(&params.strokes[0], Some(1));
        let at = |x: f32, z: f32| map.at(Vec2::new(x, z));
        assert_eq!(at(10.0, 5.0).density, 0.0);
        assert!(at(10.0, 5.9).density < 0.01);
        assert!((0.2..0.8).contains(&at(10.0, 6.5).density), "{:?}", at(10.0, 6.5));
        assert_eq!(at(10.0, 8.0).density, 1.0);
        assert_eq!(at(10.0, 5.0).species, [0.0, 1.0, 0.0, 0.0]);
        assert_eq!(at(10.0, 8.0).species, [1.0; 4]);
        // Past its ends it fades as a round cap.
        assert!((0.3..0.7).contains(&at(0.5, 5.0).density));
    }

    /// A stroke across the area's edge paints within the area only: beyond it the paint is
    /// what lies beneath the stroke (before, the edge texels it reached carried its paint on to
    /// the horizon: a mown band leaving the area went on for ever). A collider's clearing
    /// likewise.
    #[test]
    fn a_stroke_across_the_area_s_edge_paints_nothing_beyond_it() {
        let params = PaintParams {
            area: [0.0, 0.0, 20.0, 10.0],
            ..PaintParams::default()
        };
        let mut map = PaintMap::blank(&params, &[]);
        let across = Stroke::path(&[Vec2::new(10.0, 5.0), Vec2::new(25.0, 5.0)], 1.0).mow(0.2);
        map.paint_stroke(&across, None);
        let at = |map: &PaintMap, x: f32, z: f32| map.at(Vec2::new(x, z));
        assert!(
            (at(&map, 15.0, 5.0).length - 0.2).abs() < 0.01,
            "{:?}",
            at(&map, 15.0, 5.0)
        );
        assert!(at(&map, 19.5, 5.0).length < 0.3, "{:?}", at(&map, 19.5, 5.0));
        for x in [20.5, 30.0, 1000.0] {
            assert_eq!(at(&map, x, 5.0).length, 1.0, "at x {x}, beyond the area");
        }
        let mut paint = GroundPaint {
            map: Some(map),
            ..GroundPaint::default()
        };
        paint.clear(&[Vec3::new(5.0, 0.0, 1.0)]);
        let map = paint.map.as_ref().unwrap();
        assert_eq!(at(map, 5.0, 0.5).density, 0.0);
        assert_eq!(
            at(map, 5.0, -50.0).density,
            1.0,
            "a clearing at the edge reaches past it"
        );
    }

    #[test]
    fn a_missing_or_mismatched_map_is_one_sentence_naming_the_file() {
        let dir = std::env::temp_dir().join(format!("sward-paint-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let small = dir.join("small.png");
        image::GrayImage::new(4, 4).save(&small).unwrap();
        let big = dir.join("big.png");
        image::GrayImage::new(8, 8).save(&big).unwrap();
        let missing = PaintParams {
            density: Some(dir.join("none.png").display().to_string()),
            ..PaintParams::default()
        };
        let e = PaintMap::load(&missing, &[]).unwrap_err().to_string();
        assert!(e.contains("none.png") && e.contains("PNG"), "{e}");
        let mixed = PaintParams {
            density: Some(small.display().to_string()),
            length: Some(big.display().to_string()),
            ..PaintParams::default()
        };
        let e = PaintMap::load(&mixed, &[]).unwrap_err().to_string();
        assert!(e.contains("big.png") && e.contains("share one size"), "{e}");
        let coloured = PaintParams {
            density: Some(small.display().to_string()),
            color: Some(big.display().to_string()),
            ..PaintParams::default()
        };
        let e = PaintMap::load(&coloured, &[]).unwrap_err().to_string();
        assert!(e.contains("big.png") && e.contains("small.png"), "{e}");
        let one = PaintParams {
            density: Some(small.display().to_string()),
            ..PaintParams::default()
        };
        let map = PaintMap::load(&one, &[]).unwrap().unwrap();
        assert_eq!(map.size, [4, 4]);
        assert_eq!(
            map.at(Vec2::ZERO),
            Paint {
                density: 0.0,
                ..Paint::FULL
            }
        );
    }
}
