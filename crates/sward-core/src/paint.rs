//! Paint over the ground: maps laid over a rectangle of the ground that say, place by place, how
//! much grass grows there (density) and how tall it grows (length). Every technique reads them
//! through the rules here and their GLSL twins (`common.glsl` `paint_at`, `instanced.glsl`
//! `painted_height`): a blade grows where its own hash falls under the density, so a generated
//! blade, the Bezier blade it becomes and the billboard tuft of its place all agree, and a path
//! painted black is bare at every distance with the same edge.

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

use crate::instanced::simplex2;
use crate::mesh::MeshError;
use crate::rng::{hash_u32, hash_unit};
use crate::validate::{Checks, Validate};

/// The scene's paint (`[paint]`): the maps and the ground they cover.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PaintParams {
    /// The ground rectangle the maps cover: lowest x, lowest z, highest x, highest z. The
    /// image's first row lies along the lowest z, its first column along the lowest x; beyond
    /// the rectangle the map's edge carries on.
    pub area: [f32; 4],
    /// A PNG read as grey: how much of the grass grows (black: none, white: all). None: all,
    /// everywhere.
    pub density: Option<String>,
    /// A PNG read as grey: how tall the grass grows, as a fraction of its height (black: not at
    /// all, white: full height). None: full height everywhere.
    pub length: Option<String>,
    /// Patches of grass and bare ground from noise, everywhere (times the density map where
    /// there is one).
    pub noise: Option<PaintNoise>,
}

/// Patches of grass and bare ground from simplex noise (`[paint.noise]`): the ground grows
/// grass where the noise is above a threshold set by `cover`, thinning over a band `softness`
/// wide on either side.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
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
    /// How much grass grows at world ground point `xz` (`common.glsl` `noise_density`).
    pub fn density(&self, xz: Vec2) -> f32 {
        // Away from the origin, so the instanced grass's clump noise (at the same scale there)
        // does not line up with it.
        let n = 0.5 + 0.5 * simplex2(xz * self.scale + Vec2::new(57.3, -131.9));
        let threshold = 1.0 - self.cover;
        smoothstep(threshold - self.softness, threshold + self.softness, n)
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
            noise: None,
        }
    }
}

impl PaintParams {
    /// Whether any map is painted.
    pub fn painted(&self) -> bool {
        self.density.is_some() || self.length.is_some()
    }

    /// Whether the ground is painted at all (maps or noise).
    pub fn paints(&self) -> bool {
        self.painted() || self.noise.is_some()
    }

    /// The maps' paths, relative ones made relative to directory `dir` (the scene file's).
    pub fn paths_mut(&mut self) -> impl Iterator<Item = &mut String> {
        self.density.iter_mut().chain(self.length.iter_mut())
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
            c.check(
                n.scale.is_finite() && n.scale > 0.0 && n.scale <= 100.0,
                "paint.noise.scale",
                n.scale,
                "0 < scale ≤ 100 patches per unit",
            );
            c.check(
                n.cover.is_finite() && (0.0..=1.0).contains(&n.cover),
                "paint.noise.cover",
                n.cover,
                "a share of the ground from 0 to 1",
            );
            c.check(
                n.softness.is_finite() && (0.0..=0.5).contains(&n.softness),
                "paint.noise.softness",
                n.softness,
                "0 to 0.5 (noise units)",
            );
        }
    }
}

/// What the paint says at one place of the ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Paint {
    /// How much of the grass grows, 0 to 1.
    pub density: f32,
    /// How tall it grows, as a fraction of its height, 0 to 1.
    pub length: f32,
}

impl Paint {
    /// Unpainted ground: all the grass, at full height.
    pub const FULL: Paint = Paint {
        density: 1.0,
        length: 1.0,
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
    /// Texels row by row (z, then x): the density's byte lowest, then the length's.
    pub texels: Vec<u32>,
}

impl PaintMap {
    /// The maps `params` names, read; `None` where it names none. Fails with the file and what
    /// is allowed where a map cannot be read or the two differ in size.
    pub fn load(params: &PaintParams) -> Result<Option<PaintMap>, MeshError> {
        if !params.painted() {
            return Ok(None);
        }
        let density = params.density.as_deref().map(read_grey).transpose()?;
        let length = params.length.as_deref().map(read_grey).transpose()?;
        let size = match (&density, &length) {
            (Some(d), Some(l)) if d.0 != l.0 => {
                return Err(MeshError::Map {
                    path: params.length.clone().unwrap_or_default(),
                    reason: format!(
                        "it is {}×{} pixels but the density map is {}×{}; a scene's paint maps share one size",
                        l.0[0], l.0[1], d.0[0], d.0[1]
                    ),
                })
            }
            (Some(d), _) => d.0,
            (None, Some(l)) => l.0,
            (None, None) => unreachable!("painted() said a map is named"),
        };
        let texels = (0..(size[0] * size[1]) as usize)
            .map(|i| {
                let d = density.as_ref().map_or(255, |m| m.1[i]);
                let l = length.as_ref().map_or(255, |m| m.1[i]);
                u32::from(d) | u32::from(l) << 8
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

    /// A map over `min`..`max` of `size` texels from each texel's paint (row by row).
    pub fn from_paint(min: Vec2, max: Vec2, size: [u32; 2], paint: impl Fn(u32, u32) -> Paint) -> PaintMap {
        let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u32;
        let texels = (0..size[1])
            .flat_map(|z| (0..size[0]).map(move |x| (x, z)))
            .map(|(x, z)| {
                let p = paint(x, z);
                byte(p.density) | byte(p.length) << 8
            })
            .collect();
        PaintMap { min, max, size, texels }
    }

    /// Texels per unit of ground along x and z.
    pub fn texels_per_unit(&self) -> Vec2 {
        Vec2::new(self.size[0] as f32, self.size[1] as f32) / (self.max - self.min)
    }

    /// The paint at world ground point `xz`: the four nearest texels blended, the edge carrying
    /// on beyond the area (as `common.glsl` `paint_at` samples it).
    pub fn at(&self, xz: Vec2) -> Paint {
        let at = (xz - self.min) * self.texels_per_unit() - 0.5;
        let limit = Vec2::new(self.size[0] as f32 - 1.0, self.size[1] as f32 - 1.0);
        let at = at.clamp(Vec2::ZERO, limit);
        let low = at.floor();
        let f = at - low;
        let (x0, z0) = (low.x as u32, low.y as u32);
        let (x1, z1) = ((x0 + 1).min(self.size[0] - 1), (z0 + 1).min(self.size[1] - 1));
        let texel = |x: u32, z: u32| {
            let t = self.texels[(z * self.size[0] + x) as usize];
            Vec2::new((t & 0xff) as f32, (t >> 8 & 0xff) as f32) / 255.0
        };
        let near = texel(x0, z0).lerp(texel(x1, z0), f.x);
        let far = texel(x0, z1).lerp(texel(x1, z1), f.x);
        let v = near.lerp(far, f.y);
        Paint {
            density: v.x,
            length: v.y,
        }
    }
}

/// All the scene paints on the ground: its maps and its noise.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundPaint {
    /// The maps, where the scene names any.
    pub map: Option<PaintMap>,
    /// The noise, where the scene asks for it.
    pub noise: Option<PaintNoise>,
}

impl GroundPaint {
    /// What `params` paints, its maps read; `None` where it paints nothing. Fails with the
    /// file and what is allowed where a map cannot be used.
    pub fn load(params: &PaintParams) -> Result<Option<GroundPaint>, MeshError> {
        if !params.paints() {
            return Ok(None);
        }
        Ok(Some(GroundPaint {
            map: PaintMap::load(params)?,
            noise: params.noise,
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
        for z in 0..map.size[1] {
            for x in 0..map.size[0] {
                let centre = map.min + (Vec2::new(x as f32, z as f32) + 0.5) / per_unit;
                if discs.iter().any(|d| centre.distance(d.truncate()) < d.z + beyond) {
                    map.texels[(z * map.size[0] + x) as usize] &= !0xff;
                }
            }
        }
    }

    /// The paint at world ground point `xz`: the map's, its density times the noise's.
    pub fn at(&self, xz: Vec2) -> Paint {
        let mut paint = self.map.as_ref().map_or(Paint::FULL, |m| m.at(xz));
        if let Some(noise) = &self.noise {
            paint.density *= noise.density(xz);
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

/// A PNG read as 8-bit grey: its size and its pixels row by row.
fn read_grey(path: &str) -> Result<([u32; 2], Vec<u8>), MeshError> {
    let fail = |reason: String| MeshError::Map {
        path: path.to_string(),
        reason,
    };
    let image = image::open(path).map_err(|e| fail(e.to_string()))?.into_luma8();
    let (w, h) = image.dimensions();
    if w < 2 || h < 2 || w > MAX_MAP_SIDE || h > MAX_MAP_SIDE {
        return Err(fail(format!(
            "it is {w}×{h} pixels; a paint map has 2 to {MAX_MAP_SIDE} pixels a side"
        )));
    }
    Ok(([w, h], image.into_raw()))
}

/// The most texels along a paint map's side (a 4096² map is 64 MiB on the GPU).
pub const MAX_MAP_SIDE: u32 = 4096;

#[cfg(test)]
mod tests {
    use super::*;

    fn stripe() -> PaintMap {
        // Bare where 4 ≤ x < 6 (texels 4 and 5 of 10 over x in 0..10), half height where z ≥ 5.
        PaintMap::from_paint(Vec2::ZERO, Vec2::splat(10.0), [10, 10], |x, z| Paint {
            density: if (4..6).contains(&x) { 0.0 } else { 1.0 },
            length: if z >= 5 { 0.5 } else { 1.0 },
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
    }

    #[test]
    fn density_keeps_its_share_of_blades_and_length_scales_them() {
        let half = Paint {
            density: 0.5,
            length: 0.25,
        };
        let heights: Vec<f32> = (0..20_000u32).map(|i| painted_height(hash_u32(i), 0.8, half)).collect();
        let grown = heights.iter().filter(|&&h| h > 0.0).count() as f32 / heights.len() as f32;
        assert!((grown - 0.5).abs() < 0.02, "{grown}");
        assert!(heights.iter().all(|&h| h == 0.0 || h == 0.2));
        assert!((0..1000u32).all(|i| painted_height(i, 1.0, Paint::FULL) == 1.0));
        let bare = Paint {
            density: 0.0,
            length: 1.0,
        };
        assert!((0..1000u32).all(|i| painted_height(i, 1.0, bare) == 0.0));
    }

    #[test]
    fn noise_grows_grass_on_about_its_cover_of_the_ground() {
        for cover in [0.3, 0.7] {
            let paint = GroundPaint {
                map: None,
                noise: Some(PaintNoise {
                    scale: 0.05,
                    cover,
                    softness: 0.0,
                }),
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
        let mut paint = GroundPaint { map: None, noise: None };
        paint.clear(&[Vec3::new(3.0, -2.0, 1.5)]);
        assert_eq!(paint.at(Vec2::new(3.0, -2.0)).density, 0.0);
        assert_eq!(paint.at(Vec2::new(3.0, -0.8)).density, 0.0);
        assert_eq!(paint.at(Vec2::new(3.0, -0.5)).density, 0.0);
        assert_eq!(paint.at(Vec2::new(3.0, 0.0)).density, 1.0);
        assert_eq!(paint.at(Vec2::new(40.0, 9.0)).density, 1.0);
        let mut painted = GroundPaint {
            map: Some(stripe()),
            noise: None,
        };
        painted.clear(&[Vec3::new(8.0, 8.0, 1.0)]);
        assert_eq!(painted.at(Vec2::new(8.0, 8.0)).density, 0.0);
        assert_eq!(painted.at(Vec2::new(8.0, 8.0)).length, 128.0 / 255.0);
        assert_eq!(painted.at(Vec2::new(1.0, 2.0)).density, 1.0);
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
        let e = PaintMap::load(&missing).unwrap_err().to_string();
        assert!(e.contains("none.png") && e.contains("PNG"), "{e}");
        let mixed = PaintParams {
            density: Some(small.display().to_string()),
            length: Some(big.display().to_string()),
            ..PaintParams::default()
        };
        let e = PaintMap::load(&mixed).unwrap_err().to_string();
        assert!(e.contains("big.png") && e.contains("share one size"), "{e}");
        let one = PaintParams {
            density: Some(small.display().to_string()),
            ..PaintParams::default()
        };
        let map = PaintMap::load(&one).unwrap().unwrap();
        assert_eq!(map.size, [4, 4]);
        assert_eq!(
            map.at(Vec2::ZERO),
            Paint {
                density: 0.0,
                length: 1.0
            }
        );
    }
}
