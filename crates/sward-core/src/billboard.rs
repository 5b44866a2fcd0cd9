//! Billboard grass (SPEC §7 \[B\]): billboards of three textured quads crossing at 60°, placed on a grid
//! around the camera by the instanced grass's generator (jittered cells, clumped heights; see
//! [`BillboardParams::as_grid`]), and the grass texture sward paints for itself at start-up — a
//! billboard of curved, tapering blades in RGBA with alpha — with its mip chain. Billboards are drawn
//! with alpha-to-coverage, so each mip level keeps the coverage of the full-size image (averaging
//! alpha alone would thin distant billboards into nothing).

use serde::{Deserialize, Serialize};

use crate::instanced::{GridParams, InstancedParams};
use crate::rng::Pcg32;
use crate::validate::{Checks, Validate};

/// Billboards, as the scene file's `[billboard]` table holds them.
///
/// Its grid's keys sit in the same table (`GridParams`, flattened); a key the table leaves out
/// keeps the billboards' default, not the instanced grass's (`Deserialize` below).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(remote = "Self", default, deny_unknown_fields)]
pub struct BillboardParams {
    /// Where the billboards grow and how they vary (`density` in billboards per square unit, `radius` —
    /// fog hides the edge —, `inner_radius` — technique `landscape`: where the instanced grass
    /// gives way —, `height`, `width` — half-widths —, `clump_scale`, `sway`, `seed`).
    #[serde(flatten)]
    pub grid: GridParams,
    /// Technique `landscape`: width of the band past `inner_radius` over which billboards grow in
    /// while the instanced blades shrink away.
    pub fade: f32,
    /// Draw the billboards' depth first (their texture's coverage only), then shade only the billboard
    /// nearest the eye at each sample: the same picture, with each covered sample shaded once
    /// instead of once per overlapping quad (billboards near the eye overlap many deep).
    pub depth_prepass: bool,
    /// Distance beyond which a billboard is one quad turned to the eye instead of three crossed ones
    /// (its texture's coverage raised to match the three's overlap): a third of the vertices and
    /// of the fragments of far billboards, which cover a few pixels each.
    pub one_quad_distance: f32,
    /// Distance beyond which billboards are splatted by compute into the splat target (as the
    /// instanced grass's far blades) instead of rasterized: a few pixels each there, where
    /// the raster hardware spends most of its time on quads it barely covers.
    pub splat_distance: f32,
    /// Distance from which the listed billboards (up to `splat_distance`) are rasterized by compute
    /// into the splat target, sample by sample, instead of drawn by the raster hardware, which
    /// writes their alpha-to-coverage depth slowly where it has few raster units. Nearer billboards,
    /// and quads reaching behind the eye, are drawn. Default 0: every listed billboard, where the
    /// device has 64-bit atomics (else every one is drawn).
    pub raster_distance: f32,
}

impl Default for BillboardParams {
    fn default() -> Self {
        Self {
            grid: GridParams {
                density: 3.0,
                radius: 400.0,
                inner_radius: 0.0,
                height: [0.45, 0.95],
                width: [0.3, 0.5],
                clump_scale: 0.03,
                sway: 0.08,
                seed: 7,
            },
            fade: 12.0,
            depth_prepass: true,
            one_quad_distance: 30.0,
            splat_distance: 60.0,
            raster_distance: 0.0,
        }
    }
}

impl Serialize for BillboardParams {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        BillboardParams::serialize(self, s)
    }
}

impl<'de> Deserialize<'de> for BillboardParams {
    /// The table as written, over the billboards' defaults: a flattened grid would otherwise
    /// fill the keys left out from `GridParams::default`, the instanced grass's grid.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let written = toml::Table::deserialize(d)?;
        let mut table = match toml::Value::try_from(BillboardParams::default()) {
            Ok(toml::Value::Table(table)) => table,
            _ => return Err(D::Error::custom("the billboards' defaults are not a table")),
        };
        table.extend(written);
        BillboardParams::deserialize(toml::Value::Table(table)).map_err(D::Error::custom)
    }
}

impl Validate for BillboardParams {
    fn validate(&self, c: &mut Checks) {
        self.grid
            .validate_as(c, "billboard", 1_000.0, "0 < density ≤ 1000 billboards per square unit");
        for (key, v) in [
            ("billboard.fade", self.fade),
            ("billboard.one_quad_distance", self.one_quad_distance),
            ("billboard.splat_distance", self.splat_distance),
            ("billboard.raster_distance", self.raster_distance),
        ] {
            c.non_negative(key, v);
        }
    }
}

impl BillboardParams {
    /// The billboards as an instanced-field grid: one billboard per cell, generated and culled by the
    /// same code (one level, nothing splatted, no bend).
    pub fn as_grid(&self) -> InstancedParams {
        InstancedParams {
            grid: self.grid,
            lod_distances: [f32::MAX; 3],
            splat_distance: f32::MAX,
            raster_distance: f32::MAX,
            bend: 0.0,
        }
    }
}

/// The billboard every billboard draws: 28 blades painted on 256² texels, painted once in a
/// process (every renderer, and every device, draws the same one).
pub fn shipped_grass_texture() -> GrassTexture {
    static SHIPPED: std::sync::OnceLock<GrassTexture> = std::sync::OnceLock::new();
    SHIPPED.get_or_init(|| paint_grass_texture(256, 28, 0x5eed)).clone()
}

/// Where the shipped billboard's painted blades lie in its quad, as (across, up) in [0, 1]²: the
/// corners bottom left, bottom right, top left, top right of a trapezoid (billboard_quads.wesl
/// `painted_outline`: near billboards are drawn as it). Roots crowd the middle and blades lean outward, and no tip reaches the top
/// 5 %: a fifth of the quad is clear.
pub const BILLBOARD_OUTLINE: [[f32; 2]; 4] = [[0.22, 0.0], [0.89, 0.0], [0.02, 0.95], [0.99, 0.95]];

/// The finest mip levels (0 to this) the billboards' draw draws within [`BILLBOARD_OUTLINE`] (billboards at
/// least 256 / 2^this pixels tall); coarser levels spread coverage wider.
pub const OUTLINE_LEVELS: usize = 2;

/// Alpha at or above which a texel counts as covered (alpha-to-coverage's midpoint).
pub const COVERAGE_ALPHA: f32 = 0.5;

/// An RGBA8 image and its mip chain, level 0 first (each half the size of the one before).
#[derive(Clone, Debug)]
pub struct GrassTexture {
    /// Side of level 0 in texels.
    pub size: u32,
    /// Row-major RGBA, straight (not premultiplied) alpha.
    pub levels: Vec<Vec<[u8; 4]>>,
}

impl GrassTexture {
    /// Side of mip level `level`.
    pub fn level_size(&self, level: usize) -> u32 {
        (self.size >> level).max(1)
    }

    /// Share of level `level`'s texels that alpha-to-coverage draws as grass.
    pub fn coverage(&self, level: usize) -> f32 {
        coverage(&self.levels[level], 1.0)
    }
}

/// One painted blade: a quadratic curve from its root on the bottom edge, tapering to its tip.
/// Roots crowd the middle of the edge and thin out toward its ends, and blades lean outward, so
/// a billboard is a clump: roots spread evenly along the edge once made a solid band of root colour
/// nearly as wide as the quad, whose straight sides showed, quad beside quad, as the flat dark
/// stair-stepped masses near the eye.
struct PaintedBlade {
    root: [f32; 2],
    guide: [f32; 2],
    tip: [f32; 2],
    width: f32,
    shade: f32,
    /// Where the blade can cover: its control points' box (the curve lies in their hull),
    /// grown by its widest half-width. A texel outside is not measured to its 32 segments.
    bounds: [f32; 4],
}

impl PaintedBlade {
    fn random(rng: &mut Pcg32) -> PaintedBlade {
        // Triangular about the middle: as many roots as before, fewest at the ends.
        let x = 0.5 + 0.4 * (rng.range(0.0, 1.0) + rng.range(0.0, 1.0) - 1.0);
        let height = rng.range(0.55, 0.97);
        let lean = ((x - 0.5) * 0.8 + rng.range(-0.15, 0.15)).clamp(0.05 - x, 0.95 - x);
        let width = rng.range(0.012, 0.03);
        let shade = rng.range(0.8, 1.15);
        PaintedBlade::new(
            [x, 0.0],
            [x + 0.3 * lean, 0.6 * height],
            [x + lean, height],
            width,
            shade,
        )
    }

    fn new(root: [f32; 2], guide: [f32; 2], tip: [f32; 2], width: f32, shade: f32) -> PaintedBlade {
        let (xs, ys) = ([root[0], guide[0], tip[0]], [root[1], guide[1], tip[1]]);
        let bounds = [
            xs.into_iter().fold(f32::MAX, f32::min) - width,
            ys.into_iter().fold(f32::MAX, f32::min) - width,
            xs.into_iter().fold(f32::MIN, f32::max) + width,
            ys.into_iter().fold(f32::MIN, f32::max) + width,
        ];
        PaintedBlade {
            root,
            guide,
            tip,
            width,
            shade,
            bounds,
        }
    }

    fn at(&self, t: f32) -> [f32; 2] {
        let mix = |a: f32, b: f32, c: f32| (1.0 - t) * (1.0 - t) * a + 2.0 * (1.0 - t) * t * b + t * t * c;
        [
            mix(self.root[0], self.guide[0], self.tip[0]),
            mix(self.root[1], self.guide[1], self.tip[1]),
        ]
    }

    /// Half-width at height `t`: tapering to the tip, and narrower at the root too (a third),
    /// where the billboard's blades stand crowded: full-width roots merged into one opaque band.
    fn half_width(&self, t: f32) -> f32 {
        self.width * (1.0 - t) * (0.35 + 0.65 * (t / 0.25).min(1.0))
    }

    /// Height along the blade (0 root, 1 tip) of the nearest point of the curve to `p`, if `p`
    /// lies within the blade's half-width there. The curve is walked as a chain of short segments
    /// and `p` measured to the nearest segment: measured to the chain's points alone, a thin
    /// blade was a string of discs, its outline beaded.
    fn cover(&self, p: [f32; 2]) -> Option<f32> {
        const STEPS: usize = 32;
        let [left, bottom, right, top] = self.bounds;
        if p[0] < left || p[0] > right || p[1] < bottom || p[1] > top {
            return None;
        }
        let mut best: Option<(f32, f32)> = None;
        let mut a = self.at(0.0);
        for i in 1..=STEPS {
            let (t0, t1) = ((i - 1) as f32 / STEPS as f32, i as f32 / STEPS as f32);
            let b = self.at(t1);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let along = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy).max(1e-12)).clamp(0.0, 1.0);
            let (ex, ey) = (p[0] - a[0] - along * dx, p[1] - a[1] - along * dy);
            let t = t0 + along * (t1 - t0);
            let reach = self.half_width(t);
            // The exact distance only near the blade: the square, with a margin far wider than
            // its rounding, rules out the rest alike.
            if ex * ex + ey * ey <= reach * reach * 1.001 {
                let d = ex.hypot(ey);
                if d <= reach && best.is_none_or(|(_, nearest)| d < nearest) {
                    best = Some((t, d));
                }
            }
            a = b;
        }
        best.map(|(t, _)| t)
    }
}

/// Paint `blades` blades into a `size`² texture (seeded), 2×2 supersampled, and build its mip
/// chain down to 1×1 with coverage kept level by level.
pub fn paint_grass_texture(size: u32, blades: u32, seed: u64) -> GrassTexture {
    let mut rng = Pcg32::new(seed, 7);
    let painted: Vec<PaintedBlade> = (0..blades).map(|_| PaintedBlade::random(&mut rng)).collect();
    let root = [0.16, 0.32, 0.07];
    let tip = [0.55, 0.78, 0.28];
    let mut base = Vec::with_capacity((size * size) as usize);
    for row in 0..size {
        for col in 0..size {
            let mut colour = [0.0f32; 3];
            let mut alpha = 0.0;
            for sub in 0..4 {
                let x = (col as f32 + 0.25 + 0.5 * (sub & 1) as f32) / size as f32;
                // Row 0 is the top of the image: the tips.
                let y = 1.0 - (row as f32 + 0.25 + 0.5 * (sub >> 1) as f32) / size as f32;
                // The last blade painted is in front.
                if let Some((t, blade)) = painted.iter().rev().find_map(|b| b.cover([x, y]).map(|t| (t, b))) {
                    for k in 0..3 {
                        colour[k] += (root[k] + (tip[k] - root[k]) * t) * blade.shade;
                    }
                    alpha += 1.0;
                }
            }
            let texel = if alpha > 0.0 {
                let c = colour.map(|c| to_srgb(c / alpha));
                [c[0], c[1], c[2], (alpha / 4.0 * 255.0).round() as u8]
            } else {
                [0, 0, 0, 0]
            };
            base.push(texel);
        }
    }
    let mut levels = vec![base];
    let target = coverage(&levels[0], 1.0);
    while levels.last().map_or(0, |l| l.len()) > 1 {
        let side = (levels.len() - 1) as u32;
        let next = downsample(levels.last().unwrap(), (size >> side).max(1));
        levels.push(keep_coverage(next, target));
    }
    GrassTexture { size, levels }
}

fn to_srgb(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// Share of texels whose alpha, scaled by `scale`, reaches `COVERAGE_ALPHA`.
fn coverage(texels: &[[u8; 4]], scale: f32) -> f32 {
    let covered = texels
        .iter()
        .filter(|t| t[3] as f32 / 255.0 * scale >= COVERAGE_ALPHA)
        .count();
    covered as f32 / texels.len() as f32
}

/// Halve a `side`² level: colour averaged over covered texels (weighted by alpha, so empty texels
/// do not darken edges), alpha averaged.
fn downsample(level: &[[u8; 4]], side: u32) -> Vec<[u8; 4]> {
    let side = side as usize;
    let next = (side / 2).max(1);
    let mut out = Vec::with_capacity(next * next);
    for row in 0..next {
        for col in 0..next {
            let mut colour = [0.0f32; 3];
            let mut alpha = 0.0;
            for (dr, dc) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let t = level[(2 * row + dr).min(side - 1) * side + (2 * col + dc).min(side - 1)];
                let a = t[3] as f32;
                for k in 0..3 {
                    colour[k] += t[k] as f32 * a;
                }
                alpha += a;
            }
            let c = if alpha > 0.0 {
                colour.map(|c| (c / alpha).round() as u8)
            } else {
                [0, 0, 0]
            };
            out.push([c[0], c[1], c[2], (alpha / 4.0).round() as u8]);
        }
    }
    out
}

/// Scale a level's alpha so that its coverage matches `target` (bisection on the scale).
fn keep_coverage(mut level: Vec<[u8; 4]>, target: f32) -> Vec<[u8; 4]> {
    let (mut lo, mut hi) = (0.0f32, 8.0f32);
    for _ in 0..24 {
        let mid = 0.5 * (lo + hi);
        if coverage(&level, mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    for t in &mut level {
        t[3] = (t[3] as f32 * hi).min(255.0).round() as u8;
    }
    level
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A blade's cover measured to all 32 segments everywhere, as painted before its bounds.
    fn measured_everywhere(blade: &PaintedBlade, p: [f32; 2]) -> Option<f32> {
        let mut best: Option<(f32, f32)> = None;
        let mut a = blade.at(0.0);
        for i in 1..=32 {
            let (t0, t1) = ((i - 1) as f32 / 32.0, i as f32 / 32.0);
            let b = blade.at(t1);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let along = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy).max(1e-12)).clamp(0.0, 1.0);
            let d = (p[0] - a[0] - along * dx).hypot(p[1] - a[1] - along * dy);
            let t = t0 + along * (t1 - t0);
            if d <= blade.half_width(t) && best.is_none_or(|(_, nearest)| d < nearest) {
                best = Some((t, d));
            }
            a = b;
        }
        best.map(|(t, _)| t)
    }

    #[test]
    fn a_blade_painted_within_its_bounds_covers_exactly_what_it_covered_measured_everywhere() {
        let mut rng = Pcg32::new(0x5eed, 7);
        let mut covered = 0;
        for blade in (0..28).map(|_| PaintedBlade::random(&mut rng)) {
            for (row, col) in (0..160).flat_map(|r| (0..160).map(move |c| (r, c))) {
                let p = [(col as f32 + 0.25) / 160.0, (row as f32 + 0.75) / 160.0];
                let cover = blade.cover(p);
                assert_eq!(cover, measured_everywhere(&blade, p), "at {p:?}");
                covered += cover.is_some() as u32;
            }
        }
        assert!(covered > 1000, "the blades cover {covered} points");
    }

    #[test]
    fn a_billboard_table_keeps_the_billboards_defaults_for_the_keys_it_leaves_out() {
        let scene = crate::Scene::from_toml("[billboard]\ndensity = 2.0\nfade = 3.0\n", "t").unwrap();
        let defaults = BillboardParams::default();
        let b = scene.billboard;
        assert_eq!((b.grid.density, b.fade), (2.0, 3.0));
        let grid = GridParams {
            density: 2.0,
            ..defaults.grid
        };
        assert_eq!(b.grid, grid, "not the instanced grass's grid defaults");
        assert_eq!(b.splat_distance, defaults.splat_distance);
        // The instanced grass's table likewise keeps its own.
        let scene = crate::Scene::from_toml("[instanced]\nradius = 80.0\n", "t").unwrap();
        assert_eq!(scene.instanced.grid.height, GridParams::default().height);
        // Keys neither table has are refused, naming the key.
        let err = crate::Scene::from_toml("[billboard]\ndensty = 2.0\n", "t").unwrap_err();
        assert!(err.to_string().contains("densty"), "{err}");
        // And a scene written out reads back the same.
        let round = crate::Scene::from_toml(&scene.to_toml(), "t").unwrap();
        assert_eq!(round.billboard, scene.billboard);
    }

    #[test]
    fn the_painted_billboard_is_green_grass_on_transparency() {
        let tex = paint_grass_texture(64, 24, 3);
        let base = &tex.levels[0];
        let covered = tex.coverage(0);
        assert!((0.08..0.6).contains(&covered), "coverage {covered}");
        // Green dominates every covered texel; the top corners are sky (transparent).
        for t in base.iter().filter(|t| t[3] > 128) {
            assert!(t[1] > t[0] && t[1] > t[2], "not green: {t:?}");
        }
        assert_eq!(base[0][3], 0);
        assert_eq!(base[63][3], 0);
        // The bottom rows, where the roots are, cover more than the top rows.
        let rows = |r: std::ops::Range<usize>| {
            r.flat_map(|r| &base[r * 64..(r + 1) * 64])
                .filter(|t| t[3] > 128)
                .count()
        };
        assert!(rows(56..64) > 2 * rows(0..8));
    }

    /// The cause of the flat, dark, stair-stepped masses the billboards showed near the eye:
    /// roots spread evenly along the bottom edge made a solid band of root colour as wide as the
    /// quad, whose straight sides and edges lined up quad beside quad. Now the roots crowd the
    /// middle: over the bottom tenth, the outer fifths on either side are nearly transparent
    /// (mean alpha 0.06; 0.38 before) while the middle still holds the clump (0.55).
    #[test]
    fn a_billboard_is_a_clump_not_a_band_across_the_quad() {
        let size = 256;
        let tex = paint_grass_texture(size as u32, 28, 0x5eed);
        let alpha = |x: usize, y: usize| tex.levels[0][y * size + x][3] as f32 / 255.0;
        let (mut outer, mut middle) = ((0.0, 0.0), (0.0, 0.0));
        for y in size * 9 / 10..size {
            for x in 0..size {
                let sum = if x < size / 5 || x >= size * 4 / 5 {
                    &mut outer
                } else {
                    &mut middle
                };
                sum.0 += alpha(x, y);
                sum.1 += 1.0;
            }
        }
        let (outer, middle) = (outer.0 / outer.1, middle.0 / middle.1);
        assert!(outer < 0.15, "the bottom's outer fifths: mean alpha {outer}");
        assert!(middle > 0.4, "the clump's middle: mean alpha {middle}");
    }

    /// The cause of the beaded outlines of thin painted blades: a texel counted as blade when it
    /// lay within the half-width of one of the curve's sample points, so a thin blade was a
    /// string of discs, narrower between them. Measured to the curve's segments, a point just
    /// inside the edge (0.9 of the half-width out from a straight blade's midline) is covered at
    /// every height; the string of 49 discs left it out between discs.
    #[test]
    fn a_thin_painted_blade_has_a_smooth_outline() {
        let blade = PaintedBlade::new([0.5, 0.0], [0.5, 0.45], [0.5, 0.9], 0.012, 1.0);
        for i in 5..=90 {
            let t = i as f32 / 100.0;
            let p = [0.5 + 0.9 * blade.half_width(t), 0.9 * t];
            assert!(
                blade.cover(p).is_some(),
                "just inside the edge at height {t}: uncovered"
            );
        }
        assert!(blade.cover([0.5 + 1.1 * blade.half_width(0.5), 0.45]).is_none());
    }

    #[test]
    fn every_mip_level_keeps_the_coverage_of_the_full_image() {
        let tex = paint_grass_texture(128, 24, 5);
        assert_eq!(tex.levels.len(), 8, "128 → 1 is eight levels");
        for (level, texels) in tex.levels.iter().enumerate() {
            assert_eq!(texels.len() as u32, tex.level_size(level).pow(2));
        }
        let full = tex.coverage(0);
        for level in 1..5 {
            let c = tex.coverage(level);
            assert!(
                (c - full).abs() < 0.06,
                "level {level} covers {c}, the full image {full}"
            );
        }
        // Plain alpha averaging (what the rescale corrects) would have lost coverage.
        let plain = downsample(&downsample(&tex.levels[0], 128), 64);
        assert!(coverage(&plain, 1.0) < full - 0.02 || coverage(&plain, 1.0) > full + 0.02);
    }

    /// Every texel of the shipped billboard's finest levels that alpha-to-coverage may draw (alpha
    /// above 1/20: four samples start at 1/8) lies within the outline near billboards are drawn as,
    /// with the half texel bilinear filtering reaches around it; and the billboards' draw
    /// (billboard_quads.wesl) draws this outline. (The outline is the smallest such trapezoid to 0.01; holding level 4 too, it
    /// would be 92 % of the quad.)
    #[test]
    fn the_billboard_outline_holds_every_painted_blade() {
        let tex = shipped_grass_texture();
        let [bl, br, tl, tr] = BILLBOARD_OUTLINE;
        let edge = |a: [f32; 2], b: [f32; 2], up: f32| a[0] + (b[0] - a[0]) * up / b[1];
        for level in 0..=OUTLINE_LEVELS {
            let side = tex.level_size(level) as usize;
            let texel = 1.0 / side as f32;
            for (i, t) in tex.levels[level].iter().enumerate().filter(|(_, t)| t[3] > 12) {
                let (x, row) = ((i % side) as f32, (i / side) as f32);
                let (left, right) = (((x - 0.5) * texel).max(0.0), ((x + 1.5) * texel).min(1.0));
                // Up from the quad's bottom (texture row 0 holds the tips).
                let (low, high) = ((1.0 - (row + 1.5) * texel).max(0.0), 1.0 - (row - 0.5) * texel);
                let inside = high <= tl[1] + 1e-3
                    && [low, high]
                        .iter()
                        .all(|&up| edge(bl, tl, up) <= left + 1e-3 && right <= edge(br, tr, up) + 1e-3);
                assert!(
                    inside,
                    "level {level} texel ({x}, {row}) alpha {} outside the outline",
                    t[3]
                );
            }
        }
        // billboard_quads.wesl `painted_outline`: across by side and row, up by row.
        let shader = include_str!("../shaders/billboard_quads.wesl");
        assert_eq!((bl[1], tl[1]), (br[1], tr[1]), "each row of the outline level");
        let across = format!(
            "select(select({:?}, {:?}, right), select({:?}, {:?}, right), top)",
            bl[0], br[0], tl[0], tr[0]
        );
        let up = format!("select({:?}, {:?}, top)", bl[1], tl[1]);
        assert!(
            shader.contains(&across) && shader.contains(&up),
            "billboard_quads.wesl's painted_outline is not {across} and {up}"
        );
    }

    #[test]
    fn painting_is_deterministic_per_seed() {
        let a = paint_grass_texture(32, 12, 9);
        let b = paint_grass_texture(32, 12, 9);
        let c = paint_grass_texture(32, 12, 10);
        assert_eq!(a.levels, b.levels);
        assert_ne!(a.levels[0], c.levels[0]);
    }
}
