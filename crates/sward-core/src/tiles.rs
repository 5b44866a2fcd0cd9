//! Tiles (SPEC §2, §4): the field cut into spatially compact runs of blades, each with a bounding
//! box, so whole tiles can skip simulation and drawing. Blades are ordered along a Morton curve of
//! small grid cells and cut into runs of `TILE_BLADES`; every tile but the last holds exactly that
//! many, so one tile is a fixed number of workgroups. Within a cell the field's shuffled order is
//! kept, so the distance test's `id mod n` buckets stay spatially random.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4};

use crate::blade::Blade;

/// Blades per tile: a few thousand (SPEC §2), a multiple of every workgroup size sward uses.
pub const TILE_BLADES: u32 = 4096;

/// One tile as the renderer keeps it: a run of blades and the box that holds every shape they can
/// take (roots ± height + width, since a blade keeps its length h however it bends).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tile {
    /// Index of the tile's first blade in the field.
    pub first: u32,
    /// Blades in the tile.
    pub count: u32,
    /// Smallest corner of the box every shape of its blades fits in.
    pub min: Vec3,
    /// Largest corner of that box.
    pub max: Vec3,
}

/// What a frame does with a tile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TileFate {
    /// Far outside the view: neither simulated nor drawn.
    Skipped,
    /// Just outside the view: simulated (so grass entering view is settled) but not drawn.
    Simulated,
    /// In view: simulated and its blades culled one by one.
    Drawn,
}

/// A tile to run this frame, as the compute shaders read it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct ActiveTile {
    /// Index of the tile's first blade in the field.
    pub first: u32,
    /// Blades in the tile.
    pub count: u32,
    /// 1: cull and draw its blades, 0: simulate only.
    pub drawn: u32,
    /// Padding to 16 bytes.
    pub unused: u32,
}

/// Reorder `blades` into tiles and return the tiles. `area` is the surface area the blades cover,
/// which sets the cell size so that a tile spans about 16 cells.
pub fn build(blades: &mut Vec<Blade>, area: f32) -> Vec<Tile> {
    if blades.is_empty() {
        return Vec::new();
    }
    let (lo, hi) = blades.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), b| {
        (lo.min(b.root()), hi.max(b.root()))
    });
    // A tile covers TILE_BLADES / density of surface; a cell a sixteenth of that.
    let tile_area = area.max(f32::MIN_POSITIVE) * TILE_BLADES as f32 / blades.len() as f32;
    let cell = (tile_area / 16.0)
        .sqrt()
        .max((hi - lo).max_element() / 1023.0)
        .max(1e-6);
    let mut order: Vec<(u32, u32)> = blades
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let c = ((b.root() - lo) / cell).as_uvec3().min(glam::UVec3::splat(1023));
            (morton3(c.x, c.y, c.z), i as u32)
        })
        .collect();
    // Ties keep the original (shuffled) order: the index is the second key.
    order.sort_unstable();
    *blades = order.iter().map(|&(_, i)| blades[i as usize]).collect();
    blades
        .chunks(TILE_BLADES as usize)
        .enumerate()
        .map(|(k, run)| bound(k as u32 * TILE_BLADES, run))
        .collect()
}

/// `tiles` bounding `blades` again, after the blades changed in place (their roots, which
/// ordered them, kept).
pub fn rebound(blades: &[Blade], tiles: &[Tile]) -> Vec<Tile> {
    tiles
        .iter()
        .map(|t| bound(t.first, &blades[t.first as usize..(t.first + t.count) as usize]))
        .collect()
}

/// The tile of `run`, which starts at blade `first`.
fn bound(first: u32, run: &[Blade]) -> Tile {
    let mut min = Vec3::MAX;
    let mut max = Vec3::MIN;
    for b in run {
        let reach = Vec3::splat(b.height() + b.width());
        min = min.min(b.root() - reach);
        max = max.max(b.root() + reach);
    }
    Tile {
        first,
        count: run.len() as u32,
        min,
        max,
    }
}

/// Spread the low 10 bits of `v` to every third bit.
fn spread(v: u32) -> u32 {
    let mut x = v & 0x3ff;
    x = (x | x << 16) & 0x030000ff;
    x = (x | x << 8) & 0x0300f00f;
    x = (x | x << 4) & 0x030c30c3;
    (x | x << 2) & 0x09249249
}

fn morton3(x: u32, y: u32, z: u32) -> u32 {
    spread(x) | spread(y) << 1 | spread(z) << 2
}

/// The six planes of a Vulkan clip volume (depth in [0, w]) in world space, normalised so that
/// `plane · (p, 1)` is a signed distance, positive inside.
pub fn frustum_planes(view_proj: &Mat4) -> [Vec4; 6] {
    let r = [view_proj.row(0), view_proj.row(1), view_proj.row(2), view_proj.row(3)];
    [r[3] + r[0], r[3] - r[0], r[3] + r[1], r[3] - r[1], r[2], r[3] - r[2]].map(|p| {
        let length = p.truncate().length();
        // An infinite far plane (an application's infinite projection) has no normal: it
        // keeps everything, as the plane at w = 1 does.
        if length > 0.0 {
            p / length
        } else {
            Vec4::W
        }
    })
}

/// Whether a box lies entirely on the outer side of some plane by more than `margin`.
fn outside(planes: &[Vec4; 6], min: Vec3, max: Vec3, margin: f32) -> bool {
    planes.iter().any(|p| {
        // The corner furthest along the plane's normal.
        let corner = Vec3::select(p.truncate().cmpge(Vec3::ZERO), max, min);
        p.truncate().dot(corner) + p.w < -margin
    })
}

/// What this frame does with `tile`: drawn if its box meets the view frustum, simulated if it
/// is within `margin` units of it, else skipped.
pub fn fate(tile: &Tile, planes: &[Vec4; 6], margin: f32) -> TileFate {
    if !outside(planes, tile.min, tile.max, 0.0) {
        TileFate::Drawn
    } else if !outside(planes, tile.min, tile.max, margin) {
        TileFate::Simulated
    } else {
        TileFate::Skipped
    }
}

/// `tile` with its box grown to hold its shadow under the sun (`toward_sun`): the box moved
/// away from the sun by the length of the shadow of its height, at most five heights (a low sun).
fn with_shadow(tile: &Tile, toward_sun: Vec3) -> Tile {
    let sun = toward_sun.normalize_or_zero();
    let offset = -sun * (tile.max.y - tile.min.y) / sun.y.max(0.2);
    if !offset.is_finite() {
        return *tile; // the unbounded tile of a field without tiles
    }
    Tile {
        min: tile.min.min(tile.min + offset),
        max: tile.max.max(tile.max + offset),
        ..*tile
    }
}

/// The tiles to run this frame, nearest to `eye` first. With tile culling off every tile is drawn.
///
/// The order matters for the draw: blades are appended to the visible list roughly in the order
/// their workgroups run, so near tiles first means the blades are drawn roughly front to back and
/// depth testing rejects most hidden fragments before they are shaded.
///
/// Where blades cast shadows (`toward_sun`), a tile is drawn too where its blades' shadows may
/// fall in view: its box is stretched along the sun's rays down to the ground (as the cull's
/// per-blade test, `cull::ShadowCasting`), so blades just off screen cast into it.
pub fn active(
    tiles: &[Tile],
    view_proj: &Mat4,
    eye: Vec3,
    margin: f32,
    culling: bool,
    toward_sun: Option<Vec3>,
) -> Vec<ActiveTile> {
    let planes = frustum_planes(view_proj);
    let runs = tiles.iter().filter_map(|t| {
        let f = if culling {
            shadowed_fate(t, &planes, margin, toward_sun)
        } else {
            TileFate::Drawn
        };
        to_run(t, f, eye)
    });
    nearest_first(runs.collect())
}

/// `fate` of the tile's box, stretched along the sun's rays where blades cast shadows.
fn shadowed_fate(tile: &Tile, planes: &[Vec4; 6], margin: f32, toward_sun: Option<Vec3>) -> TileFate {
    match toward_sun {
        Some(sun) => fate(&with_shadow(tile, sun), planes, margin),
        None => fate(tile, planes, margin),
    }
}

/// Steps of a tile's sort key per doubling of 1 + its distance (tile_cull.wesl `tile_key`).
pub const TILE_KEY_STEPS: u32 = 16384;
/// Bits of a tile's sort key that hold its index (tile_cull.wesl): the distance has the rest.
pub const TILE_INDEX_BITS: u32 = 13;
/// The largest sort key a distance gets.
const KEY_MOST: f32 = ((1u32 << (32 - TILE_INDEX_BITS)) - 1) as f32;

/// A tile's sort key `distance` from the eye, as tile_cull.wesl `tile_key` makes it on the GPU
/// for the Vulkan renderer: log-spaced, so tiles within a step of each other keep the field's
/// order. The portable renderer's host-written list is in the same order, so both renderers list
/// a bucket's blades in one order (which blades a budget of occluders takes from a bucket, and
/// which of two blades at one depth is drawn over the other).
fn distance_key(distance: f32) -> u32 {
    ((1.0 + distance).log2() * TILE_KEY_STEPS as f32).clamp(0.0, KEY_MOST) as u32
}

/// The tile as the frame runs it, with its sort key ([`distance_key`]); none where it is
/// skipped.
fn to_run(tile: &Tile, fate: TileFate, eye: Vec3) -> Option<(u32, ActiveTile)> {
    let distance = eye.clamp(tile.min, tile.max).distance(eye);
    (fate != TileFate::Skipped).then_some((
        distance_key(distance),
        ActiveTile {
            first: tile.first,
            count: tile.count,
            drawn: (fate == TileFate::Drawn) as u32,
            unused: 0,
        },
    ))
}

/// The runs nearest first, tiles at one distance in the field's order: the keys (distance, then
/// place in `runs`) are unique, so an unstable sort of plain integers gives the stable order.
fn nearest_first(runs: Vec<(u32, ActiveTile)>) -> Vec<ActiveTile> {
    let mut keys: Vec<u64> = runs
        .iter()
        .enumerate()
        .map(|(k, &(distance, _))| (distance as u64) << 32 | k as u64)
        .collect();
    keys.sort_unstable();
    keys.iter().map(|&key| runs[key as u32 as usize].1).collect()
}

/// Tiles consecutive in the field's order: a run of them is compact in space (the Morton
/// curve), so one box holds it.
pub const GROUP_TILES: usize = 32;

/// The field's tiles with a box per group of `GROUP_TILES`, so that a frame decides most tiles
/// a group at a time — a group outside the view is skipped and one inside it drawn whole, and
/// only the tiles of groups across the view's edges are tested one by one. The frame's cost
/// then follows the tiles near the view's edges, not the field's size; the result is
/// `active`'s, tile for tile and in the same order.
#[derive(Clone, Debug, Default)]
pub struct TileGroups {
    tiles: Vec<Tile>,
    groups: Vec<Tile>,
}

impl TileGroups {
    /// Group `tiles` (in the field's order).
    pub fn new(tiles: Vec<Tile>) -> TileGroups {
        let groups = tiles
            .chunks(GROUP_TILES)
            .enumerate()
            .map(|(k, run)| Tile {
                first: (k * GROUP_TILES) as u32,
                count: run.len() as u32,
                min: run.iter().fold(Vec3::MAX, |m, t| m.min(t.min)),
                max: run.iter().fold(Vec3::MIN, |m, t| m.max(t.max)),
            })
            .collect();
        TileGroups { tiles, groups }
    }

    /// The tiles, in the field's order.
    pub fn tiles(&self) -> &[Tile] {
        &self.tiles
    }

    /// What `active` returns for these tiles. A group's box holds its tiles' boxes, and its
    /// shadow (stretched by the group's height, at least each tile's) holds theirs, so a group
    /// outside a plane by more than the margin has every tile outside it, and a group inside
    /// every plane has every tile inside.
    pub fn active(
        &self,
        view_proj: &Mat4,
        eye: Vec3,
        margin: f32,
        culling: bool,
        toward_sun: Option<Vec3>,
    ) -> Vec<ActiveTile> {
        if !culling {
            return active(&self.tiles, view_proj, eye, margin, culling, toward_sun);
        }
        let planes = frustum_planes(view_proj);
        let mut runs = Vec::new();
        for group in &self.groups {
            let bounds = match toward_sun {
                Some(sun) => with_shadow(group, sun),
                None => *group,
            };
            if outside(&planes, bounds.min, bounds.max, margin) {
                continue;
            }
            let whole = inside(&planes, bounds.min, bounds.max);
            let first = group.first as usize;
            for t in &self.tiles[first..first + group.count as usize] {
                let f = if whole {
                    TileFate::Drawn
                } else {
                    shadowed_fate(t, &planes, margin, toward_sun)
                };
                runs.extend(to_run(t, f, eye));
            }
        }
        nearest_first(runs)
    }
}

/// Whether a box lies entirely on the inner side of every plane.
fn inside(planes: &[Vec4; 6], min: Vec3, max: Vec3) -> bool {
    planes.iter().all(|p| {
        // The corner furthest against the plane's normal.
        let corner = Vec3::select(p.truncate().cmpge(Vec3::ZERO), min, max);
        p.truncate().dot(corner) + p.w >= 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;
    use crate::field::{Field, FieldDesc};

    fn field(blades: u32) -> (Vec<Blade>, Vec<Tile>) {
        let desc = FieldDesc {
            blades,
            size: glam::Vec2::splat(60.0),
            ..FieldDesc::default()
        };
        let mut blades = Field::on_plane(&desc).blades;
        let tiles = build(&mut blades, 3600.0);
        (blades, tiles)
    }

    /// A 64 × 64 grid of tiles of random heights in Morton order, as `build` leaves them.
    fn tile_grid(rng: &mut crate::rng::Pcg32) -> Vec<Tile> {
        let mut cells: Vec<(u32, u32, u32)> = (0..64 * 64).map(|k| (k % 64, k / 64, 0)).collect();
        cells.iter_mut().for_each(|c| c.2 = morton3(c.0, 0, c.1));
        cells.sort_by_key(|c| c.2);
        cells
            .iter()
            .enumerate()
            .map(|(k, &(i, j, _))| {
                let min = Vec3::new(i as f32 * 6.0 - 192.0, rng.range(-2.0, 0.0), j as f32 * 6.0 - 192.0);
                Tile {
                    first: k as u32 * TILE_BLADES,
                    count: TILE_BLADES,
                    min,
                    max: min + Vec3::new(6.5, rng.range(0.5, 4.0), 6.5),
                }
            })
            .collect()
    }

    #[test]
    fn grouped_tiles_run_exactly_what_each_tile_tested_alone_runs() {
        let mut rng = crate::rng::Pcg32::new(17, 3);
        let tiles = tile_grid(&mut rng);
        let groups = TileGroups::new(tiles.clone());
        let mut skipped_groups = 0;
        for case in 0..200 {
            let eye = Vec3::new(rng.range(-250.0, 250.0), rng.range(0.5, 60.0), rng.range(-250.0, 250.0));
            let look = Vec3::new(rng.range(-1.0, 1.0), rng.range(-0.6, 0.1), rng.range(-1.0, 1.0));
            let cam = Camera {
                position: eye,
                target: eye + look,
                fov_y_degrees: rng.range(20.0, 100.0),
                far: rng.range(50.0, 900.0),
                ..Camera::default()
            };
            let vp = cam.view_projection(16.0 / 9.0);
            let margin = rng.range(0.0, 10.0);
            let sun =
                (case % 2 == 0).then(|| Vec3::new(rng.range(-1.0, 1.0), rng.range(0.05, 1.0), rng.range(-1.0, 1.0)));
            let culling = case % 7 != 0;
            let alone = active(&tiles, &vp, eye, margin, culling, sun);
            assert_eq!(groups.active(&vp, eye, margin, culling, sun), alone, "case {case}");
            skipped_groups += usize::from(alone.len() < tiles.len() / 2);
        }
        assert!(
            skipped_groups > 50,
            "the views leave most tiles out only {skipped_groups} times"
        );
    }

    #[test]
    fn tiles_are_full_compact_runs_that_bound_their_blades() {
        let (blades, tiles) = field(50_000);
        assert_eq!(tiles.len(), 50_000usize.div_ceil(TILE_BLADES as usize));
        assert_eq!(tiles.iter().map(|t| t.count).sum::<u32>(), 50_000);
        for t in &tiles {
            for b in &blades[t.first as usize..(t.first + t.count) as usize] {
                assert!(b.tip().cmpge(t.min).all() && b.tip().cmple(t.max).all());
            }
        }
        // 13 tiles on 3600 units²: about 17 units across each; Morton runs stay well under the field.
        let mean_extent = tiles
            .iter()
            .map(|t| (t.max - t.min).x.max((t.max - t.min).z))
            .sum::<f32>()
            / tiles.len() as f32;
        assert!(mean_extent < 35.0, "tiles are not compact: mean extent {mean_extent}");
    }

    #[test]
    fn distance_buckets_stay_spatially_random_after_tiling() {
        let (blades, _) = field(40_000);
        // The distance test keeps `id mod 100 < k`; with k = 25 every 10 × 10 patch keeps about a quarter.
        let mut kept = [[0u32; 2]; 36];
        for (id, b) in blades.iter().enumerate() {
            let cell =
                ((b.root().x + 30.0) / 10.0).min(5.0) as usize * 6 + ((b.root().z + 30.0) / 10.0).min(5.0) as usize;
            kept[cell][0] += (id % 100 < 25) as u32;
            kept[cell][1] += 1;
        }
        for [k, n] in kept {
            let share = k as f32 / n as f32;
            assert!((0.18..0.32).contains(&share), "a patch keeps {share} instead of 0.25");
        }
    }

    #[test]
    fn tiles_behind_the_camera_are_skipped_and_those_beside_it_simulated() {
        let (_, tiles) = field(200_000);
        let camera = Camera {
            position: Vec3::new(0.0, 2.0, 0.0),
            target: Vec3::new(0.0, 2.0, -10.0),
            ..Camera::default()
        };
        let view_proj = camera.view_projection(1.0);
        let planes = frustum_planes(&view_proj);
        let fates: Vec<TileFate> = tiles.iter().map(|t| fate(t, &planes, 2.0)).collect();
        let count = |f: TileFate| fates.iter().filter(|&&x| x == f).count();
        assert!(count(TileFate::Skipped) > 0 && count(TileFate::Drawn) > 0, "{fates:?}");
        for (t, f) in tiles.iter().zip(&fates) {
            // Far behind the eye (z > 0 is behind): never drawn.
            if t.min.z > 3.0 {
                assert_eq!(*f, TileFate::Skipped, "{t:?}");
            }
            // In front, around the line of sight: drawn.
            if t.max.z < -5.0 && t.min.x < 0.0 && t.max.x > 0.0 && t.min.z > -50.0 {
                assert_eq!(*f, TileFate::Drawn, "{t:?}");
            }
        }
        // A bigger margin only ever turns skipped tiles into simulated ones.
        let wide: Vec<TileFate> = tiles.iter().map(|t| fate(t, &planes, 10.0)).collect();
        assert!(wide.iter().filter(|&&x| x == TileFate::Simulated).count() > count(TileFate::Simulated));
        let all = active(&tiles, &view_proj, camera.position, 2.0, false, None);
        assert!(all.len() == tiles.len() && all.iter().all(|a| a.drawn == 1));
        // Nearest first, so the draw runs roughly front to back.
        let distance = |a: &ActiveTile| {
            let t = tiles.iter().find(|t| t.first == a.first).unwrap();
            camera.position.clamp(t.min, t.max).distance(camera.position)
        };
        assert!(all.windows(2).all(|w| distance(&w[0]) <= distance(&w[1])));
    }

    #[test]
    fn a_tile_off_screen_is_drawn_where_its_shadow_falls_in_view() {
        let camera = Camera {
            position: Vec3::new(0.0, 1.0, 0.0),
            target: Vec3::new(0.0, 1.0, 5.0),
            ..Camera::default()
        };
        let view_proj = camera.view_projection(1.0);
        // Blades up to a unit tall, 4 units to the side at 4 ahead (the view is 1.7 wide there).
        let tile = Tile {
            first: 0,
            count: 1,
            min: Vec3::new(3.8, 0.0, 3.8),
            max: Vec3::new(4.2, 1.0, 4.2),
        };
        let drawn = |sun: Option<Vec3>| {
            active(&[tile], &view_proj, camera.position, 0.5, true, sun)
                .first()
                .map_or(0, |a| a.drawn)
        };
        assert_eq!(drawn(None), 0);
        assert_eq!(
            drawn(Some(Vec3::new(1.0, 0.25, 0.0))),
            1,
            "a low sun on its side casts it into view"
        );
        assert_eq!(
            drawn(Some(Vec3::new(-1.0, 0.25, 0.0))),
            0,
            "a sun on the far side casts it away"
        );
    }
}
