//! The instanced grass (SPEC §7 \[F\]): blades with no stored state, generated each frame on the GPU
//! from a hash of their grid cell around the camera, culled (bounding sphere against the frustum,
//! distance cut-off) and sorted into levels of detail, then drawn as triangle strips. This module
//! holds its parameters and the CPU reference of generation and culling that `generate_grid.wesl`
//! mirrors; the tests compare the two.

use glam::{IVec2, Mat4, Vec2, Vec3, Vec4};
use serde::{Deserialize, Serialize};

use crate::mesh::HeightGrid;
use crate::rng::{hash_u32, hash_unit};
use crate::tiles::frustum_planes;
use crate::validate::{Checks, Validate};

/// Grid cells per side of a patch: the unit of generation (one row of workgroups).
pub const PATCH_CELLS: i32 = 32;
/// Blades in one patch.
pub const PATCH_BLADES: u32 = (PATCH_CELLS * PATCH_CELLS) as u32;
/// Strip segments per level of detail, finest first; each level halves the one before, so the
/// vertices of a coarser strip are every other vertex of the finer one (the morph targets).
pub const LOD_SEGMENTS: [u32; 4] = [8, 4, 2, 1];
/// Levels of detail of the instanced grass.
pub const LODS: usize = LOD_SEGMENTS.len();
/// The level of blades drawn by compute instead of by the raster hardware — splatted (beyond
/// `splat_distance`) or rasterized (from `raster_distance` on): counted like the others, never
/// in a draw command.
pub const SPLAT_LEVEL: usize = LODS;
/// Splat cells (samples of a 4× target) a rasterized blade may span at most: a workgroup
/// rasterizes a blade, a pixel row per invocation, so one blade much bigger than the rest would
/// hold its workgroup long after the others are done, and the nearest blades are what the
/// raster hardware draws well (`raster_from`).
pub const RASTER_MAX_CELLS: f32 = 1024.0;
/// The share of `splat_distance` over which drawn blades dissolve into splatted ones.
pub const SPLAT_BAND: f32 = 0.1;

/// Which blades a scene draws.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(rename_all = "snake_case")]
pub enum Technique {
    /// Bezier blades with physics (the paper's technique).
    #[default]
    Bezier,
    /// The instanced grass only.
    Instanced,
    /// Bezier blades near the camera, instanced blades beyond `instanced.inner_radius`.
    Both,
    /// Billboard grass only: three crossed textured quads per billboard.
    Billboard,
    /// The whole chain: Bezier blades near the camera, instanced blades beyond
    /// `instanced.inner_radius`, billboards from `billboard.inner_radius` (cross-faded with the
    /// instanced grass's edge), and the ground tinted with grass colour up to the horizon.
    Landscape,
}

impl Technique {
    /// Every technique, from the paper's alone to the whole chain.
    pub const ALL: [Technique; 5] = [
        Technique::Bezier,
        Technique::Instanced,
        Technique::Both,
        Technique::Billboard,
        Technique::Landscape,
    ];

    /// Whether Bezier blades with physics are grown and drawn.
    pub fn draws_bezier(self) -> bool {
        matches!(self, Technique::Bezier | Technique::Both | Technique::Landscape)
    }

    /// Whether the instanced grass is generated and drawn.
    pub fn draws_instanced(self) -> bool {
        matches!(self, Technique::Instanced | Technique::Both | Technique::Landscape)
    }

    /// Whether billboards are generated and drawn.
    pub fn draws_billboards(self) -> bool {
        matches!(self, Technique::Billboard | Technique::Landscape)
    }

    /// The technique's name as the scene file and the command line spell it.
    pub fn name(self) -> &'static str {
        match self {
            Technique::Bezier => "bezier",
            Technique::Instanced => "instanced",
            Technique::Both => "both",
            Technique::Billboard => "billboard",
            Technique::Landscape => "landscape",
        }
    }

    /// The value `FrameUniforms::instanced_meta.y` carries (`flags::TECHNIQUE_*`).
    pub fn index(self) -> u32 {
        use crate::flags::*;
        match self {
            Technique::Bezier => TECHNIQUE_BEZIER,
            Technique::Instanced => TECHNIQUE_INSTANCED,
            Technique::Both => TECHNIQUE_BOTH,
            Technique::Billboard => TECHNIQUE_BILLBOARD,
            Technique::Landscape => TECHNIQUE_LANDSCAPE,
        }
    }
}

/// The most items a generated grid holds within its cut-off radius (a larger one would list
/// more patches than a frame can walk).
pub const MAX_GRID_ITEMS: u32 = 1 << 28;

/// A grid of generated grass around the eye — the instanced grass's blades, the billboards'
/// billboards: how dense it grows, how far it reaches, how its items vary. Both tables of the scene
/// file hold these keys (flattened: `[instanced] density = …`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default)]
pub struct GridParams {
    /// Items (blades, billboards) per square unit.
    pub density: f32,
    /// Distance beyond which nothing of the grid is drawn.
    pub radius: f32,
    /// Nothing of the grid nearer than this (it is left to the technique nearer the eye).
    pub inner_radius: f32,
    /// Height range [min, max]; clumps of simplex noise pick within it.
    pub height: [f32; 2],
    /// Half-width range [min, max].
    pub width: [f32; 2],
    /// Spatial frequency of the height and width clumps, 1/units.
    pub clump_scale: f32,
    /// Wind sway of the top, as a share of the height: the billboards'. The generated blades
    /// need none: they settle in the wind itself, as the Bezier blades do (`InstancedParams::bend`).
    pub sway: f32,
    /// Seed of the grid's hash (placement, shape, variation).
    pub seed: u32,
}

impl Default for GridParams {
    /// The instanced grass's grid.
    fn default() -> Self {
        Self {
            density: 60.0,
            radius: 120.0,
            inner_radius: 0.0,
            height: [0.35, 0.9],
            width: [0.02, 0.04],
            clump_scale: 0.07,
            sway: 0.12,
            seed: 1,
        }
    }
}

impl GridParams {
    /// Distance between neighbouring grid cells.
    pub fn spacing(&self) -> f32 {
        1.0 / self.density.max(1e-6).sqrt()
    }

    /// The grid's items (blades, billboards) within its cut-off radius.
    pub fn candidates(&self) -> f64 {
        std::f64::consts::PI * (self.radius as f64).powi(2) * self.density as f64
    }

    /// Check the grid's keys under scene table `table`, whose density may reach `max_density`
    /// (`density_allowed` says so in words).
    pub(crate) fn validate_as(&self, c: &mut Checks, table: &str, max_density: f32, density_allowed: &'static str) {
        let key = |name: &str| format!("{table}.{name}");
        c.check(
            self.density > 0.0 && self.density <= max_density,
            key("density"),
            self.density,
            density_allowed,
        );
        c.check(
            self.radius > 0.0 && self.radius.is_finite() && (0.0..self.radius).contains(&self.inner_radius),
            key("radius"),
            self.radius,
            "a positive cut-off radius above inner_radius ≥ 0",
        );
        c.check(
            self.candidates() <= MAX_GRID_ITEMS as f64,
            key("radius"),
            self.radius,
            format!(
                "a cut-off radius within which the grid holds at most {MAX_GRID_ITEMS} (2^28) items \
                 (density × π × radius², here {:.3e}): lower {table}.radius or {table}.density",
                self.candidates()
            ),
        );
        c.range(key("height"), self.height);
        c.range(key("width"), self.width);
        c.non_negative(key("sway"), self.sway);
        c.non_negative(key("clump_scale"), self.clump_scale);
    }
}

/// The instanced grass, as the scene file's `[instanced]` table holds it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct InstancedParams {
    /// Where the blades grow and how they vary (`density`, `radius`, `inner_radius`, `height`,
    /// `width` — half-widths —, `clump_scale`, `sway`, `seed`; inner radius: blades nearer are
    /// left to the Bezier field).
    #[serde(flatten)]
    pub grid: GridParams,
    /// Distances where the level of detail drops from 0 to 1, 1 to 2 and 2 to 3 (one triangle).
    pub lod_distances: [f32; 3],
    /// Beyond this distance blades are not drawn as triangles but splatted into the frame by the
    /// compute pass (walked from root to tip a pixel at a time; no MSAA), which is far cheaper on
    /// GPUs with few raster units. A band of `SPLAT_BAND` before it dissolves blade by blade
    /// from one to the other. At `radius` or beyond, nothing is splatted.
    pub splat_distance: f32,
    /// From this distance up to the splat distance blades are rasterized by compute into the
    /// splat target (`instanced_raster.wesl`) as the strips the raster hardware would draw —
    /// the same triangles, shaded once per pixel as the hardware shades them — instead of
    /// drawn; nearer they are drawn. Never nearer than where the tallest blade spans
    /// `RASTER_MAX_CELLS` on screen (`raster_from`). Needs 64-bit atomics (as splats do); at
    /// the splat distance or beyond (the default) nothing is rasterized: on the H100 it is
    /// faster than the hardware at quality `low` only (docs/benchmarks-history.md).
    pub raster_distance: f32,
    /// A lean at rest toward the blade's face, as a share of its height, that the Bezier blades
    /// do not have: each generated blade stands as a Bezier blade of its height and stiffness
    /// settles in the frame's gravity and wind (twin.wesl `settle`), and `bend` tips its
    /// rest over before it settles (0: as the Bezier blades).
    pub bend: f32,
}

impl Default for InstancedParams {
    fn default() -> Self {
        Self {
            grid: GridParams::default(),
            lod_distances: [10.0, 30.0, 60.0],
            splat_distance: 15.0,
            raster_distance: 1.0e6,
            bend: 0.0,
        }
    }
}

impl Validate for InstancedParams {
    fn validate(&self, c: &mut Checks) {
        let g = &self.grid;
        g.validate_as(c, "instanced", 10_000.0, "0 < density ≤ 10000 blades per square unit");
        let [d0, d1, d2] = self.lod_distances;
        c.check(
            0.0 < d0 && d0 < d1 && d1 < d2 && d2 < g.radius,
            "instanced.lod_distances",
            format!("{:?}", self.lod_distances),
            "three distances with 0 < first < second < third < radius",
        );
        c.check(
            self.splat_distance > 0.0 && !self.splat_distance.is_nan(),
            "instanced.splat_distance",
            self.splat_distance,
            "a positive distance (at radius or beyond: nothing is splatted)",
        );
        c.non_negative("instanced.bend", self.bend);
        c.non_negative("instanced.raster_distance", self.raster_distance);
    }
}

/// One generated blade, as the cull pass writes it (packed into 32 bytes on the GPU).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InstancedBlade {
    /// Where the blade stands.
    pub root: Vec3,
    /// Face rotation about +y, radians.
    pub facing: f32,
    /// Height.
    pub height: f32,
    /// Half-width at the root.
    pub width: f32,
    /// Its lean at rest toward its face, a share of its height (`InstancedParams::bend`).
    pub bend: f32,
    /// The cell's hash (per-blade colour, the splat dissolve).
    pub hash: u32,
}

impl InstancedParams {
    /// Distance between neighbouring grid cells.
    pub fn spacing(&self) -> f32 {
        self.grid.spacing()
    }
}

/// The hash of grid cell `cell` for a field seeded `seed` (shared with `generate_grid.wesl`).
pub fn cell_hash(cell: IVec2, seed: u32) -> u32 {
    hash_u32((cell.x as u32).wrapping_mul(73_856_093) ^ hash_u32((cell.y as u32) ^ seed.wrapping_mul(19_349_663)))
}

/// The blade of grid cell `cell`: jittered position, clumped height and width, facing, pitch,
/// bend and wind phase, all from the cell's hash and simplex noise of its position. On a
/// `ground` height grid the root sits on its triangles; off the grid the blade has no height
/// (and is culled).
pub fn blade_at(cell: IVec2, p: &InstancedParams, ground: Option<&HeightGrid>) -> InstancedBlade {
    let h = cell_hash(cell, p.grid.seed);
    let (h1, h2, h3) = (hash_u32(h), hash_u32(h ^ 0x68e3_1da4), hash_u32(h ^ 0xb529_7a4d));
    let (h4, h5) = (hash_u32(h ^ 0x1b56_c4e9), hash_u32(h ^ 0x7f4a_7c15));
    let spacing = p.spacing();
    let xz = (cell.as_vec2() + Vec2::new(hash_unit(h1), hash_unit(h2))) * spacing;
    let y = ground.map_or(Some(0.0), |g| g.height_at(xz.x, xz.y));
    let clump = 0.5 + 0.5 * simplex2(xz * p.grid.clump_scale);
    let tall = (clump + 0.25 * (hash_unit(h3) - 0.5)).clamp(0.0, 1.0);
    InstancedBlade {
        root: Vec3::new(xz.x, y.unwrap_or(0.0), xz.y),
        facing: hash_unit(h4) * std::f32::consts::TAU,
        height: if y.is_some() {
            p.grid.height[0] + (p.grid.height[1] - p.grid.height[0]) * tall
        } else {
            0.0
        },
        width: p.grid.width[0] + (p.grid.width[1] - p.grid.width[0]) * (0.5 * tall + 0.5 * hash_unit(h5)),
        bend: p.bend * (0.5 + hash_unit(h5)),
        hash: h,
    }
}

/// The level of detail of a blade seen from `eye` within the frustum `planes` (`SPLAT_LEVEL` when
/// splatted), or `None` when it is culled: outside the frustum (bounding sphere), beyond the
/// cut-off or inside the inner radius.
pub fn lod_of(blade: &InstancedBlade, eye: Vec3, planes: &[Vec4; 6], p: &InstancedParams) -> Option<usize> {
    if blade.height <= 0.0 {
        return None;
    }
    let center = blade.root + Vec3::Y * (0.5 * blade.height);
    let radius = bounding_radius(blade);
    if planes.iter().any(|pl| pl.truncate().dot(center) + pl.w < -radius) {
        return None;
    }
    let dist = (blade.root - eye).length();
    if dist >= p.grid.radius || dist < p.grid.inner_radius {
        return None;
    }
    if splatted(dist, blade.hash, p.splat_distance) || dist >= p.raster_distance {
        return Some(SPLAT_LEVEL);
    }
    Some(lod_at(dist, p))
}

/// The level of detail of a blade drawn as a strip (or rasterized as one) at `dist`.
pub fn lod_at(dist: f32, p: &InstancedParams) -> usize {
    p.lod_distances.iter().filter(|&&d| dist >= d).count()
}

/// Where the compute rasterizer takes the blades of `p` over from the raster hardware: at
/// `p.raster_distance`, but never nearer than where the grid's biggest blade — standing bent
/// and swaying, or trampled flat — spans `RASTER_MAX_CELLS` splat cells, with `focal` the
/// projection's pixels per unit at unit depth (`generate_grid.wesl` reads the result from the
/// uniforms, so every pass agrees).
pub fn raster_from(p: &InstancedParams, focal: f32) -> f32 {
    let extent = p.grid.height[1] * (1.0 + p.bend + p.grid.sway).max(1.15) + p.grid.width[1];
    let cells_per_unit = 2.0 * focal; // two cells per pixel side on a 4× target
    p.raster_distance
        .max(extent + extent * cells_per_unit / RASTER_MAX_CELLS)
}

/// The radius about its middle (half its height above its root) that holds every shape blade
/// `blade` takes: settled in gravity and wind or laid down by the trample map, it lies anywhere
/// its length reaches above the ground, at most √1.25 of its height from its middle
/// (`generate_grid.wesl` `lod_of`).
pub fn bounding_radius(blade: &InstancedBlade) -> f32 {
    1.15 * blade.height + blade.width
}

/// Whether a blade with `hash` at `dist` is splatted: always beyond `splat_distance`, never
/// before its dissolve band, and within the band by a per-blade threshold rising with distance.
pub fn splatted(dist: f32, hash: u32, splat_distance: f32) -> bool {
    let band = SPLAT_BAND * splat_distance;
    dist >= splat_distance
        || (dist > splat_distance - band
            && hash_unit(hash_u32(hash ^ 0x2545_f491)) * band < dist - (splat_distance - band))
}

/// A patch's side in world units on grid `p`.
pub fn patch_size(p: &InstancedParams) -> f32 {
    PATCH_CELLS as f32 * p.spacing()
}

/// How many patches each way from the eye's the cut-off radius of grid `p` may reach.
pub fn patch_reach(p: &InstancedParams) -> i32 {
    (p.grid.radius / patch_size(p)).ceil() as i32 + 1
}

/// The patches a grid may generate in a frame: `(2 reach + 1)²` around the eye's.
pub fn patch_candidates(p: &InstancedParams) -> u32 {
    (2 * patch_reach(p) + 1).pow(2) as u32
}

/// How high above the ground a blade of grid `p` may reach, bent and swaying.
pub fn patch_top(p: &InstancedParams) -> f32 {
    p.grid.height[1] * (1.0 + p.bend + p.grid.sway)
}

/// Every offset from the eye's patch within `reach` each way, nearest ring first (by squared
/// length, then row, then column): the order patch lists are built in, on the GPU
/// (`patch_cull.wesl`) and in [`patches`], so the generated grass is drawn roughly front to back
/// and the list is the same every run.
pub fn patch_order(reach: i32) -> Vec<IVec2> {
    let mut order: Vec<IVec2> = (-reach..=reach)
        .flat_map(|z| (-reach..=reach).map(move |x| IVec2::new(x, z)))
        .collect();
    order.sort_by_key(|o| (o.length_squared(), o.y, o.x));
    order
}

/// The patches (in units of `PATCH_CELLS` cells) within the cut-off radius of `eye` whose box
/// (patch square × up to the tallest blade) meets the view frustum, in [`patch_order`]: the ones
/// generated this frame. `patch_cull.wesl` builds the same list on the GPU (and also leaves out
/// the patches its depth pyramid hides).
pub fn patches(view_proj: &Mat4, eye: Vec3, p: &InstancedParams, ground: Option<&HeightGrid>) -> Vec<IVec2> {
    let [low, high] = ground.map_or([0.0, 0.0], |g| g.span);
    let planes = frustum_planes(view_proj);
    let size = patch_size(p);
    let center = IVec2::new((eye.x / size).floor() as i32, (eye.z / size).floor() as i32);
    let top = patch_top(p);
    let kept = |patch: IVec2| {
        let lo = Vec3::new(patch.x as f32 * size, low, patch.y as f32 * size) - Vec3::splat(top);
        let hi = Vec3::new((patch.x + 1) as f32 * size, high + top, (patch.y + 1) as f32 * size) + Vec3::splat(top);
        let nearest = eye.clamp(lo, hi);
        // The corner farthest from the eye, height included (as `patch_cull.wesl`).
        let farthest = Vec3::select((eye - lo).cmpgt(hi - eye), lo, hi);
        if nearest.distance(eye) > p.grid.radius || farthest.distance(eye) < p.grid.inner_radius {
            return false;
        }
        !planes.iter().any(|pl| {
            let corner = Vec3::select(pl.truncate().cmpge(Vec3::ZERO), hi, lo);
            pl.truncate().dot(corner) + pl.w < 0.0
        })
    };
    patch_order(patch_reach(p))
        .into_iter()
        .map(|offset| center + offset)
        .filter(|&patch| kept(patch))
        .collect()
}

/// Upper bounds on how many blades each level can hold this frame: blades within each level's
/// outer distance (plus a patch of slack) and, where the camera sees only a sector of the
/// ground, within that sector; never more than the patches generated.
pub fn lod_capacities(p: &InstancedParams, patch_count: usize, seen: Option<&SeenSector>) -> [u32; LODS] {
    // Splatted blades need no list; rasterized ones have their own (`raster_capacity`).
    let outer = [
        p.lod_distances[0],
        p.lod_distances[1],
        p.lod_distances[2],
        p.grid.radius,
    ]
    .map(|d| d.min(p.splat_distance).min(p.raster_distance));
    outer.map(|d| disk_capacity(p, d, patch_count, seen))
}

/// An upper bound on how many blades the list of blades rasterized by compute can hold this
/// frame: those within the splat distance, where any are rasterized.
pub fn raster_capacity(p: &InstancedParams, patch_count: usize, seen: Option<&SeenSector>) -> u32 {
    let outer = p.splat_distance.min(p.grid.radius);
    match p.raster_distance < outer {
        true => disk_capacity(p, outer, patch_count, seen),
        false => 0,
    }
}

/// Upper bound on the cells of grid `p` within `distance` of the eye (plus a patch of slack) —
/// within the sector the camera sees, widened by what a kept patch may reach beyond it, where
/// `seen` says — and never more than the `patch_count` patches generated hold.
pub fn disk_capacity(p: &InstancedParams, distance: f32, patch_count: usize, seen: Option<&SeenSector>) -> u32 {
    let generated = patch_count as f64 * PATCH_BLADES as f64;
    let slack = PATCH_CELLS as f64 * p.spacing() as f64 * 1.5;
    let radius = distance as f64 + slack;
    let disk = std::f64::consts::PI * radius.powi(2);
    // A kept patch's box (its square widened by the tallest blade) meets the frustum, so its
    // cells lie within its diagonal and that widening of the sector.
    let reach = std::f64::consts::SQRT_2 * (patch_size(p) + patch_top(p)) as f64;
    let area = seen.map_or(disk, |s| s.area(radius, reach).min(disk));
    (area * p.grid.density as f64 * 1.1).min(generated).ceil() as u32
}

/// The directions over the ground in which a perspective camera sees anything: every point of
/// its frustum lies, seen from above, within `half_angle` of `toward` from the eye (the frustum
/// is the cone of its four corner rays, and a cone seen from above is the cone of their
/// directions over the ground). What the generated grass's lists need hold: the blades of the
/// patches in it, not of the whole disk around the eye.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeenSector {
    /// The sector's middle, a unit direction over the ground (x, z).
    pub toward: Vec2,
    /// Its half-angle, radians (less than a right angle).
    pub half_angle: f32,
}

impl SeenSector {
    /// The sector `camera` sees, or None where it sees every direction (an orthographic camera,
    /// one looking steeply up or down, or a view wider than a half-turn).
    pub fn of(camera: &crate::frame::FrameCamera) -> Option<SeenSector> {
        let projection = camera.projection;
        // A perspective projection's w is −z in view space.
        if projection.x_axis.w != 0.0 || projection.y_axis.w != 0.0 || projection.z_axis.w != -1.0 {
            return None;
        }
        let (sx, sy) = (projection.x_axis.x, projection.y_axis.y);
        if sx == 0.0 || sy == 0.0 {
            return None;
        }
        let to_world = camera.view.inverse();
        let corners = [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)].map(|(x, y): (f32, f32)| {
            // The view-space ray through clip corner (x, y) at depth 1 (looking down −z).
            let ray = Vec3::new((x + projection.z_axis.x) / sx, (y + projection.z_axis.y) / sy, -1.0);
            let world = to_world.transform_vector3(ray);
            Vec2::new(world.x, world.z).normalize_or_zero()
        });
        if corners.contains(&Vec2::ZERO) {
            return None;
        }
        let toward = corners.iter().sum::<Vec2>().normalize_or_zero();
        if toward == Vec2::ZERO {
            return None;
        }
        let half_angle = corners.iter().map(|c| toward.angle_to(*c).abs()).fold(0.0, f32::max);
        (half_angle < std::f32::consts::FRAC_PI_2 * 0.95).then_some(SeenSector { toward, half_angle })
    }

    /// The area within `radius` of the eye in the sector, widened by `margin` on every side.
    pub fn area(&self, radius: f64, margin: f64) -> f64 {
        let angle = self.half_angle as f64;
        // A convex sector grown by a disk: its area, its perimeter times the margin, the disk.
        let perimeter = 2.0 * radius + 2.0 * angle * radius;
        angle * radius * radius + perimeter * margin + std::f64::consts::PI * margin * margin
    }

    /// Whether ground point `point` (x, z) lies in the sector from `eye` (x, z), widened by
    /// `margin`: within `margin` of a point of it.
    pub fn holds(&self, eye: Vec2, point: Vec2, margin: f32) -> bool {
        let offset = point - eye;
        if offset.length() <= margin {
            return true;
        }
        let angle = self.toward.angle_to(offset).abs();
        if angle <= self.half_angle {
            return true;
        }
        // Outside the angle: its distance to the nearer edge ray.
        let edge = Vec2::from_angle(self.half_angle * self.toward.angle_to(offset).signum()).rotate(self.toward);
        let along = offset.dot(edge).max(0.0);
        (offset - edge * along).length() <= margin
    }
}

/// 2D simplex noise in [-1, 1] (Gustavson's formulation with a hashed gradient), mirrored in
/// the core's noise.wesl.
pub fn simplex2(v: Vec2) -> f32 {
    const F2: f32 = 0.366_025_42; // (√3 − 1) / 2
    const G2: f32 = 0.211_324_87; // (3 − √3) / 6
    let i = (v + Vec2::splat((v.x + v.y) * F2)).floor();
    let x0 = v - i + Vec2::splat((i.x + i.y) * G2);
    let step = if x0.x > x0.y { Vec2::X } else { Vec2::Y };
    let x1 = x0 - step + Vec2::splat(G2);
    let x2 = x0 - Vec2::ONE + Vec2::splat(2.0 * G2);
    let corner = |c: Vec2, x: Vec2| {
        let t = 0.5 - x.length_squared();
        if t <= 0.0 {
            return 0.0;
        }
        let h = hash_u32((c.x as i32 as u32).wrapping_add(hash_u32(c.y as i32 as u32)));
        let angle = hash_unit(h) * std::f32::consts::TAU;
        let g = Vec2::new(angle.cos(), angle.sin());
        t * t * t * t * g.dot(x)
    };
    70.0 * (corner(i, x0) + corner(i + step, x1) + corner(i + Vec2::ONE, x2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_technique_s_name_is_how_the_scene_file_spells_it() {
        for t in [
            Technique::Bezier,
            Technique::Instanced,
            Technique::Both,
            Technique::Billboard,
            Technique::Landscape,
        ] {
            assert_eq!(toml::Value::try_from(t).unwrap().as_str(), Some(t.name()));
        }
    }
    use crate::camera::Camera;

    #[test]
    fn blades_are_deterministic_and_within_their_ranges() {
        let p = InstancedParams::default();
        for k in 0..2000 {
            let cell = IVec2::new(k % 50 - 25, k / 50 - 20);
            let b = blade_at(cell, &p, None);
            assert_eq!(b, blade_at(cell, &p, None));
            assert!((p.grid.height[0]..=p.grid.height[1]).contains(&b.height));
            assert!((p.grid.width[0]..=p.grid.width[1]).contains(&b.width));
            // Inside its own cell.
            let local = Vec2::new(b.root.x, b.root.z) / p.spacing() - cell.as_vec2();
            assert!(local.cmpge(Vec2::ZERO).all() && local.cmple(Vec2::ONE).all(), "{local}");
        }
    }

    #[test]
    fn simplex_noise_is_bounded_smooth_and_not_flat() {
        let values: Vec<f32> = (0..4000)
            .map(|k| simplex2(Vec2::new(k as f32 * 0.037, k as f32 * 0.021)))
            .collect();
        assert!(values.iter().all(|v| v.abs() <= 1.0));
        assert!(values.iter().cloned().fold(f32::MIN, f32::max) > 0.4);
        assert!(values.iter().cloned().fold(f32::MAX, f32::min) < -0.4);
        let a = simplex2(Vec2::new(3.2, 7.7));
        let b = simplex2(Vec2::new(3.2001, 7.7));
        assert!((a - b).abs() < 1e-2);
    }

    #[test]
    fn patches_cover_the_view_only() {
        let p = InstancedParams::default();
        let camera = Camera {
            position: Vec3::new(0.0, 1.7, 0.0),
            target: Vec3::new(0.0, 1.0, -10.0),
            ..Camera::default()
        };
        let vp = camera.view_projection(16.0 / 9.0);
        let list = patches(&vp, camera.position, &p, None);
        let size = PATCH_CELLS as f32 * p.spacing();
        assert!(!list.is_empty());
        // Nothing far behind the camera; something far ahead.
        assert!(list.iter().all(|c| (c.y as f32) * size < 3.0 * size));
        assert!(list.iter().any(|c| (c.y as f32) * size < -0.8 * p.grid.radius));
        // Fewer than the whole disk: the frustum keeps a fraction.
        let disk = std::f32::consts::PI * (p.grid.radius / size).powi(2);
        assert!((list.len() as f32) < 0.5 * disk, "{} of {disk}", list.len());
    }

    /// An eye higher above the ground than the inner radius (a top-down camera) is farther than
    /// it from every blade: the patches under it are generated, as the blades' own test keeps
    /// them; an eye at a walker's height leaves out those wholly within it.
    #[test]
    fn an_eye_above_the_inner_radius_keeps_the_patches_under_it() {
        let p = InstancedParams {
            grid: GridParams {
                inner_radius: 12.0,
                ..GridParams::default()
            },
            ..InstancedParams::default()
        };
        let size = PATCH_CELLS as f32 * p.spacing();
        let under = |height: f32| {
            let camera = Camera {
                position: Vec3::new(0.1, height, 0.1),
                target: Vec3::new(0.1, 0.0, 0.2),
                ..Camera::default()
            };
            let list = patches(&camera.view_projection(16.0 / 9.0), camera.position, &p, None);
            list.contains(&IVec2::ZERO)
        };
        assert!(size < 6.0, "patches of {size} fit well within the inner radius");
        assert!(under(30.0), "the patch under an eye 30 units up was left out");
        assert!(
            !under(1.7),
            "the patch under a walker's eye was generated within the inner radius"
        );
    }

    /// The middles of `patch`'s cells over the ground (x, z), for patches `size` wide of cells
    /// `spacing` apart.
    fn cells_of(patch: IVec2, size: f32, spacing: f32) -> impl Iterator<Item = Vec2> {
        (0..PATCH_CELLS * PATCH_CELLS).map(move |c| {
            let local = Vec2::new((c % PATCH_CELLS) as f32 + 0.5, (c / PATCH_CELLS) as f32 + 0.5);
            patch.as_vec2() * size + local * spacing
        })
    }

    /// The lists sized by the sector the camera sees still hold every cell of every patch the
    /// frustum keeps, level by level, for cameras low and high, level and pitched, narrow and
    /// wide; and a camera looking over the ground needs less than half of the whole disk's.
    #[test]
    fn the_seen_sector_holds_every_kept_patch_and_cuts_the_lists() {
        let p = InstancedParams {
            splat_distance: f32::INFINITY,
            raster_distance: f32::INFINITY,
            ..InstancedParams::default()
        };
        let (size, spacing) = (patch_size(&p), p.spacing());
        let candidates = patch_candidates(&p) as usize;
        let reach = std::f32::consts::SQRT_2 * (size + patch_top(&p));
        let outer = [
            p.lod_distances[0],
            p.lod_distances[1],
            p.lod_distances[2],
            p.grid.radius,
        ];
        let mut checked = 0;
        for (k, (height, yaw, pitch, fov)) in [
            (1.7, 0.0, -5.0, 55.0),
            (1.7, 130.0, 0.0, 90.0),
            (8.0, 45.0, -35.0, 40.0),
            (30.0, 200.0, -60.0, 70.0),
            (0.4, 300.0, 10.0, 60.0),
            (3.0, 80.0, -89.0, 55.0),
        ]
        .into_iter()
        .enumerate()
        {
            let (yaw, pitch) = (f32::to_radians(yaw), f32::to_radians(pitch));
            let eye = Vec3::new(3.3 * k as f32, height, -2.1 * k as f32);
            let look = Vec3::new(yaw.sin() * pitch.cos(), pitch.sin(), -yaw.cos() * pitch.cos());
            let camera = Camera {
                position: eye,
                target: eye + look,
                fov_y_degrees: fov,
                ..Camera::default()
            };
            let frame = crate::frame::FrameCamera::from_camera(&camera, [1920, 1080]);
            let seen = SeenSector::of(&frame);
            let kept = patches(&(frame.projection * frame.view), eye, &p, None);
            let capacities = lod_capacities(&p, candidates, seen.as_ref());
            for patch in &kept {
                for cell in cells_of(*patch, size, spacing) {
                    if let Some(s) = &seen {
                        assert!(
                            s.holds(Vec2::new(eye.x, eye.z), cell, reach),
                            "camera {k}: {cell} of {patch}"
                        );
                    }
                }
            }
            for (level, distance) in outer.iter().enumerate() {
                let within = kept
                    .iter()
                    .flat_map(|patch| cells_of(*patch, size, spacing))
                    .filter(|cell| cell.distance(Vec2::new(eye.x, eye.z)) <= *distance)
                    .count() as f64;
                let cells = within * p.grid.density as f64 * (spacing * spacing) as f64;
                assert!(
                    capacities[level] as f64 >= cells,
                    "camera {k}, level {level}: {} listed at most, {cells} kept",
                    capacities[level]
                );
            }
            checked += seen.is_some() as u32;
        }
        assert!(checked >= 4, "most of these cameras see a sector");
        let level = Camera {
            position: Vec3::new(0.0, 1.7, 0.0),
            target: Vec3::new(0.0, 1.5, -10.0),
            ..Camera::default()
        };
        let seen = SeenSector::of(&crate::frame::FrameCamera::from_camera(&level, [1920, 1080]));
        let [with, without] = [seen.as_ref(), None].map(|s| lod_capacities(&p, candidates, s)[3]);
        assert!(2 * with < without, "{with} of {without}");
    }

    /// The compute rasterizer takes over no nearer than its parameter, nor where the biggest
    /// blade would span more than `RASTER_MAX_CELLS` cells; the meadow's blades (up to 1.15 of
    /// their height from their middle, settled or laid down) at 1920 × 1080 (55° high) from
    /// about 3.3 units.
    #[test]
    fn the_rasterizer_takes_over_where_blades_fit_its_cells() {
        let focal = Camera {
            fov_y_degrees: 55.0,
            ..Camera::default()
        }
        .focal(1080);
        let p = InstancedParams {
            raster_distance: 0.0,
            ..InstancedParams::default()
        };
        let from = raster_from(&p, focal);
        let extent = p.grid.height[1] * (1.0 + p.bend + p.grid.sway).max(1.15) + p.grid.width[1];
        let cells = 2.0 * focal * extent / (from - extent);
        assert!((cells - RASTER_MAX_CELLS).abs() < 1.0, "{cells} cells at {from}");
        assert!((3.0..3.6).contains(&from), "{from}");
        let far = InstancedParams {
            raster_distance: 9.0,
            ..p
        };
        assert_eq!(raster_from(&far, focal), 9.0);
        // Off by default.
        assert!(raster_from(&InstancedParams::default(), focal) >= InstancedParams::default().splat_distance);
    }
}
