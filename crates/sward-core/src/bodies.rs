//! Mesh colliders (SPEC §3.7): a closed mesh approximated by a set of spheres (sphere packing), so
//! the sphere-only collision model pushes grass aside along the mesh's shape. A body travels a
//! looped path like a collider sphere and, if it rolls, turns as a ball of its size would.

use std::sync::{Arc, Mutex, OnceLock};

use glam::{Quat, Vec3, Vec4};
use serde::{Deserialize, Serialize};

use crate::content::Contents;
use crate::mesh::{Mesh, MeshError};
use crate::physics::{travel, Collider};
use crate::validate::{Checks, Validate};

/// The shape of a body.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum BodyShape {
    /// A lumpy, slightly flattened rock of about `radius`, made from `seed`.
    Boulder {
        /// About how far its surface is from its centre.
        radius: f32,
        /// Seed of its lumps.
        seed: u32,
    },
    /// A closed mesh file (OBJ or glTF; relative to the scene file), scaled about its origin.
    Mesh {
        /// The mesh file.
        path: String,
        /// Scale about the mesh's origin.
        scale: f32,
    },
}

/// A mesh collider, as a `[[body]]` table of the scene file holds it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// What the body is: a procedural boulder or a mesh file.
    pub shape: BodyShape,
    /// How many spheres approximate it (they count toward the collider limit).
    pub spheres: u32,
    /// Where its origin is when it stands still.
    pub center: Vec3,
    /// Points its origin travels through in a loop, as for collider spheres.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub path: Vec<Vec3>,
    /// Speed along the path, units per second.
    #[serde(default = "default_speed")]
    pub speed: f32,
    /// Turn as it travels, as a ball rolling on the ground would.
    #[serde(default)]
    pub roll: bool,
    /// Grass does not grow where it stands (a standing body only): each of its spheres that
    /// reaches into the grass clears the disc under it (`Collider::clear`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub clear: bool,
}

fn default_speed() -> f32 {
    2.0
}

impl Body {
    /// The mesh of the body's shape (its file the one given in `contents`, where given).
    pub fn mesh(&self, contents: &Contents) -> Result<Mesh, MeshError> {
        match &self.shape {
            BodyShape::Boulder { radius, seed } => Ok(boulder(*radius, *seed)),
            BodyShape::Mesh { path, scale } => Mesh::load_from(contents, std::path::Path::new(path), *scale),
        }
    }

    /// The packing of the body in its own frame (xyz centre, w radius), computed once per shape,
    /// count and given mesh (the serial of what `contents` holds under its name) and then
    /// shared. Looked up every frame, so by comparing shapes in a short list rather than through
    /// a formatted key.
    pub fn packing(&self, contents: &Contents) -> Result<Arc<Vec<Vec4>>, MeshError> {
        type Packings = Vec<(BodyShape, u32, Option<u64>, Arc<Vec<Vec4>>)>;
        static CACHE: OnceLock<Mutex<Packings>> = OnceLock::new();
        let cache = CACHE.get_or_init(Default::default);
        let given = match &self.shape {
            BodyShape::Mesh { path, .. } => contents.serial(path),
            BodyShape::Boulder { .. } => None,
        };
        let find = |packings: &Packings| {
            packings
                .iter()
                .find(|(shape, spheres, serial, _)| {
                    *shape == self.shape && *spheres == self.spheres && *serial == given
                })
                .map(|(_, _, _, packed)| packed.clone())
        };
        if let Some(found) = find(&cache.lock().expect("packing cache")) {
            return Ok(found);
        }
        let packed = Arc::new(pack_spheres(&self.mesh(contents)?, self.spheres as usize));
        cache
            .lock()
            .expect("packing cache")
            .push((self.shape.clone(), self.spheres, given, packed.clone()));
        Ok(packed)
    }

    /// The body's spheres at time `t` (none if its mesh cannot be packed; validation reports that).
    pub fn colliders_at(&self, t: f32, contents: &Contents) -> Vec<Collider> {
        self.spheres_at(t, contents)
            .map(|s| Collider::sphere(s.truncate(), s.w))
            .collect()
    }

    /// The body's spheres at time `t` as (centre, radius), without allocating: what each frame's
    /// uniforms place.
    pub fn spheres_at(&self, t: f32, contents: &Contents) -> impl Iterator<Item = Vec4> + use<> {
        let packing = self.packing(contents).unwrap_or_default();
        let origin = self.origin_at(t);
        let turn = if self.roll {
            self.turn_at(t, &packing)
        } else {
            Quat::IDENTITY
        };
        (0..packing.len()).map(move |i| (origin + turn * packing[i].truncate()).extend(packing[i].w))
    }

    /// Where the body's origin is at time `t`: travelling its path like a collider sphere.
    fn origin_at(&self, t: f32) -> Vec3 {
        travel(self.center, &self.path, self.speed, t)
    }

    /// Rolling: the angle travelled over the rolling radius (the packing's lowest reach), about
    /// the horizontal axis across the current direction of travel.
    fn turn_at(&self, t: f32, packing: &[Vec4]) -> Quat {
        let ahead = self.origin_at(t + 0.01) - self.origin_at(t);
        let axis = Vec3::Y.cross(ahead).normalize_or_zero();
        let radius = packing.iter().map(|s| s.w - s.y).fold(0.0, f32::max).max(1e-3);
        if axis == Vec3::ZERO {
            return Quat::IDENTITY;
        }
        Quat::from_axis_angle(axis, self.speed * t / radius)
    }
}

/// A lumpy rock: a sphere of `radius` displaced by smooth noise and flattened a little.
pub fn boulder(radius: f32, seed: u32) -> Mesh {
    let ball = Mesh::sphere(1.0, 12, 24);
    let offset = glam::Vec2::splat(seed as f32 * 7.31);
    let positions = ball
        .positions
        .iter()
        .map(|p| {
            let lump = crate::wind::value_noise(glam::Vec2::new(p.x + p.y, p.z - p.y) * 1.8 + offset);
            *p * radius * (0.8 + 0.4 * lump) * Vec3::new(1.15, 0.8, 1.0)
        })
        .collect();
    Mesh::new(positions, ball.triangles).expect("a displaced sphere is a valid mesh")
}

/// Approximate the inside of closed `mesh` by at most `count` spheres: candidate centres on a grid
/// inside the mesh, each with the radius of the largest sphere that fits there (its distance to
/// the surface); greedily take the largest candidate not yet covered by a chosen sphere.
pub fn pack_spheres(mesh: &Mesh, count: usize) -> Vec<Vec4> {
    const GRID: usize = 16;
    let (lo, hi) = mesh
        .positions
        .iter()
        .fold((Vec3::MAX, Vec3::MIN), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let step = (hi - lo) / GRID as f32;
    let mut candidates: Vec<Vec4> = (0..GRID * GRID * GRID)
        .map(|i| lo + step * (Vec3::new((i % GRID) as f32, (i / GRID % GRID) as f32, (i / GRID / GRID) as f32) + 0.5))
        .filter(|p| inside(mesh, *p))
        .map(|p| p.extend(distance_to_surface(mesh, p)))
        .collect();
    candidates.sort_by(|a, b| b.w.total_cmp(&a.w));
    let mut chosen: Vec<Vec4> = Vec::new();
    for c in candidates {
        if chosen.len() >= count {
            break;
        }
        // Covered: well inside a chosen sphere already.
        if chosen
            .iter()
            .any(|s| s.truncate().distance(c.truncate()) + 0.5 * c.w < s.w)
        {
            continue;
        }
        chosen.push(c);
    }
    chosen
}

/// Inside a closed mesh: an odd number of crossings along a ray (skewed off the axes so it does
/// not graze edges).
fn inside(mesh: &Mesh, p: Vec3) -> bool {
    let dir = Vec3::new(1.0, 0.013, 0.021).normalize();
    let crossings = mesh
        .triangles
        .iter()
        .filter(|t| ray_hits(p, dir, t.map(|i| mesh.positions[i as usize])))
        .count();
    crossings % 2 == 1
}

/// Möller–Trumbore: whether the ray from `origin` along `dir` crosses triangle `t` ahead.
fn ray_hits(origin: Vec3, dir: Vec3, t: [Vec3; 3]) -> bool {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return false;
    }
    let s = origin - t[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = dir.dot(q) / det;
    u >= 0.0 && v >= 0.0 && u + v <= 1.0 && e2.dot(q) / det > 0.0
}

fn distance_to_surface(mesh: &Mesh, p: Vec3) -> f32 {
    mesh.triangles
        .iter()
        .map(|t| p.distance(closest_on_triangle(p, t.map(|i| mesh.positions[i as usize]))))
        .fold(f32::MAX, f32::min)
}

/// The point of triangle `t` nearest `p` (Ericson, Real-Time Collision Detection §5.1.5).
fn closest_on_triangle(p: Vec3, [a, b, c]: [Vec3; 3]) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

impl Validate for Body {
    fn validate(&self, c: &mut Checks) {
        let size = match &self.shape {
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
            (1..=64).contains(&self.spheres),
            "body.spheres",
            self.spheres,
            "1 to 64 spheres per body",
        );
        c.check(
            self.center.is_finite() && self.path.iter().all(|p| p.is_finite()) && self.speed >= 0.0,
            "body.path",
            self.path.len(),
            "a finite centre and path and a finite speed ≥ 0",
        );
        // Packing the mesh into spheres (which loads it) is the scene's check: its contents
        // may hold the mesh file.
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packed_spheres_stay_inside_and_fill_most_of_a_boulder() {
        let rock = boulder(1.0, 3);
        let spheres = pack_spheres(&rock, 16);
        assert_eq!(spheres.len(), 16);
        for s in &spheres {
            assert!(inside(&rock, s.truncate()));
            // Each sphere fits: its radius is at most the distance to the surface.
            assert!(s.w <= distance_to_surface(&rock, s.truncate()) + 1e-4);
        }
        // Sample the rock's inside: most of it lies in some sphere.
        let mut rng = crate::rng::Pcg32::new(5, 5);
        let (mut total, mut covered) = (0, 0);
        while total < 400 {
            let p = Vec3::new(rng.range(-1.3, 1.3), rng.range(-1.0, 1.0), rng.range(-1.3, 1.3));
            if inside(&rock, p) {
                total += 1;
                covered += spheres.iter().any(|s| s.truncate().distance(p) <= s.w) as u32;
            }
        }
        assert!(
            covered as f32 / total as f32 > 0.7,
            "{covered} of {total} inside points covered"
        );
    }

    #[test]
    fn a_rolling_body_travels_its_path_and_turns() {
        let body = Body {
            shape: BodyShape::Boulder { radius: 1.0, seed: 1 },
            spheres: 8,
            center: Vec3::ZERO,
            path: vec![Vec3::new(-10.0, 0.8, 0.0), Vec3::new(10.0, 0.8, 0.0)],
            speed: 2.0,
            roll: true,
            clear: false,
        };
        let start = body.colliders_at(0.0, &Contents::default());
        let later = body.colliders_at(1.0, &Contents::default());
        assert_eq!(start.len(), 8);
        let centroid = |s: &[Collider]| s.iter().map(|c| c.center).sum::<Vec3>() / s.len() as f32;
        // It moved about 2 units along +x ...
        assert!((centroid(&later).x - centroid(&start).x - 2.0).abs() < 0.6);
        // ... and turned: the spheres are not merely shifted.
        let shifted = start
            .iter()
            .zip(&later)
            .all(|(a, b)| ((b.center - a.center) - Vec3::X * 2.0).length() < 1e-3);
        assert!(!shifted);
        // Radii never change.
        assert!(start.iter().zip(&later).all(|(a, b)| a.radius == b.radius));
    }

    #[test]
    fn a_rolling_boulder_flattens_the_grass_on_its_way() {
        use crate::physics::{step_blade, SimParams};
        let body = Body {
            shape: BodyShape::Boulder { radius: 1.0, seed: 2 },
            spheres: 12,
            center: Vec3::ZERO,
            path: vec![Vec3::new(-6.0, 0.7, 0.0), Vec3::new(60.0, 0.7, 0.0)],
            speed: 3.0,
            roll: true,
            clear: false,
        };
        let params = SimParams::default();
        // Blades on the boulder's track, and blades well beside it.
        let row = |z: f32| {
            (0..8).map(move |i| crate::Blade::at_rest(Vec3::new(i as f32, 0.0, z), Vec3::Y, 0.3, 0.8, 0.03, 10.0))
        };
        let mut blades: Vec<crate::Blade> = row(0.0).chain(row(4.0)).collect();
        let mut etas = vec![0.0; blades.len()];
        // The highest η each blade reached (η decays again once the boulder has passed).
        let mut peaks = vec![0.0f32; blades.len()];
        let mut t = 0.0;
        while t < 5.5 {
            let spheres = body.colliders_at(t, &Contents::default());
            for ((b, eta), peak) in blades.iter_mut().zip(&mut etas).zip(&mut peaks) {
                step_blade(b, eta, &params, &spheres, &[crate::Wind::calm()], t);
                *peak = peak.max(*eta);
            }
            t += params.step;
        }
        let trampled = peaks[..8].iter().filter(|&&e| e > 0.0).count();
        assert!(
            trampled >= 7,
            "only {trampled} of 8 blades on the track were hit: {peaks:?}"
        );
        assert!(peaks[8..].iter().all(|&e| e == 0.0), "blades beside the track were hit");
    }
}
