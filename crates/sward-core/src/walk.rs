//! Walking through the grass (the viewer's walk mode): a player who follows the ground — the
//! plane, a terrain or height map, or any mesh — at a person's pace, sees from eye height, and is
//! a collider (a capsule of spheres) that presses a trail into the grass. Pure maths on the
//! ground's shape, independent of the window system.

use glam::{Vec2, Vec3};

use crate::field::Surface;
use crate::mesh::{HeightGrid, Mesh};
use crate::physics::Collider;

/// Walking pace, units (metres) per second.
pub const WALK_SPEED: f32 = 1.4;
/// Running pace (shift held).
pub const RUN_SPEED: f32 = 4.0;
/// Eye height above the feet.
pub const EYE_HEIGHT: f32 = 1.7;
/// Radius of each sphere of the player's legs.
const LEG_RADIUS: f32 = 0.22;

/// The ground to walk on: the height under a point of the xz plane, if there is ground there.
pub enum Ground<'a> {
    /// The plane y = 0.
    Plane,
    /// A mesh (any triangles): the highest surface under the point.
    Mesh(&'a Mesh),
    /// A mesh laid out as a height grid (terrain, height map): its triangles' height under the
    /// point, found in constant time (a walk over a large terrain tests no triangle list).
    Grid(&'a HeightGrid),
    /// A sphere: no walking (there is no "down" to follow on a planet's underside).
    None,
}

impl<'a> Ground<'a> {
    /// The ground of a scene's surface, given the mesh its field grew on and that mesh's
    /// height grid where it is one (`Mesh::height_grid`).
    pub fn of(surface: &Surface, mesh: Option<&'a Mesh>, grid: Option<&'a HeightGrid>) -> Ground<'a> {
        match (surface, mesh, grid) {
            (Surface::Plane, _, _) => Ground::Plane,
            (Surface::Sphere { .. }, _, _) => Ground::None,
            (_, _, Some(grid)) => Ground::Grid(grid),
            (_, Some(mesh), None) => Ground::Mesh(mesh),
            (_, None, None) => Ground::Plane,
        }
    }

    /// Height of the ground under `xz`: the highest triangle a vertical line there meets.
    pub fn height_at(&self, xz: Vec2) -> Option<f32> {
        match self {
            Ground::Plane => Some(0.0),
            Ground::None => None,
            Ground::Mesh(mesh) => mesh
                .triangles
                .iter()
                .filter_map(|t| vertical_hit(t.map(|i| mesh.positions[i as usize]), xz))
                .reduce(f32::max),
            Ground::Grid(grid) => grid.height_at(xz.x, xz.y),
        }
    }
}

/// Where a vertical line through `xz` meets triangle `[a, b, c]`, if it does.
fn vertical_hit([a, b, c]: [Vec3; 3], xz: Vec2) -> Option<f32> {
    let flat = |v: Vec3| Vec2::new(v.x, v.z);
    let (a2, b2, c2) = (flat(a), flat(b), flat(c));
    let area = (b2 - a2).perp_dot(c2 - a2);
    if area.abs() < 1e-12 {
        return None;
    }
    let u = (b2 - xz).perp_dot(c2 - xz) / area;
    let v = (c2 - xz).perp_dot(a2 - xz) / area;
    let w = 1.0 - u - v;
    (u >= -1e-5 && v >= -1e-5 && w >= -1e-5).then_some(u * a.y + v * b.y + w * c.y)
}

/// Which ways the walker is asked to go this frame.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stride {
    /// Along the view.
    pub forward: bool,
    /// Against the view.
    pub back: bool,
    /// To the view's left.
    pub left: bool,
    /// To the view's right.
    pub right: bool,
    /// At a run rather than a walk.
    pub run: bool,
}

/// A person walking through the grass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Walker {
    /// Where the feet are.
    pub feet: Vec3,
}

impl Walker {
    /// A walker standing on `ground` under `eye` (or at the eye's height less the eye height,
    /// where there is no ground under it).
    pub fn under(eye: Vec3, ground: &Ground) -> Walker {
        let xz = Vec2::new(eye.x, eye.z);
        let y = ground.height_at(xz).unwrap_or(eye.y - EYE_HEIGHT);
        Walker {
            feet: Vec3::new(eye.x, y, eye.z),
        }
    }

    /// Walk `dt` seconds facing `heading` (a view direction; only its horizontal part counts),
    /// then stand on the ground there. Off the ground's edge the walker stays where it was.
    pub fn step(&mut self, dt: f32, heading: Vec3, stride: Stride, ground: &Ground) {
        let forward = Vec2::new(heading.x, heading.z).normalize_or_zero();
        let right = Vec2::new(-forward.y, forward.x);
        let axis = |plus: bool, minus: bool| plus as i32 as f32 - minus as i32 as f32;
        let way =
            (forward * axis(stride.forward, stride.back) + right * axis(stride.right, stride.left)).normalize_or_zero();
        let pace = if stride.run { RUN_SPEED } else { WALK_SPEED };
        let xz = Vec2::new(self.feet.x, self.feet.z) + way * pace * dt;
        if let Some(y) = ground.height_at(xz) {
            self.feet = Vec3::new(xz.x, y, xz.y);
        }
    }

    /// Where the eyes are.
    pub fn eye(&self) -> Vec3 {
        self.feet + Vec3::Y * EYE_HEIGHT
    }

    /// The walker's legs as colliders: two spheres, one at the feet (reaching the ground, so
    /// the grass it crosses lies flat) and one at the knees.
    pub fn colliders(&self) -> [Collider; 2] {
        [0.8, 2.6].map(|up| Collider::sphere(self.feet + Vec3::Y * (LEG_RADIUS * up), LEG_RADIUS))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_walker_keeps_a_persons_pace_and_eye_height_on_the_plane() {
        let mut walker = Walker::under(Vec3::new(1.0, 5.0, 2.0), &Ground::Plane);
        assert_eq!(walker.feet, Vec3::new(1.0, 0.0, 2.0));
        let stride = Stride {
            forward: true,
            ..Stride::default()
        };
        // Looking down and along +z: only the horizontal part of the view leads.
        walker.step(2.0, Vec3::new(0.0, -0.8, 0.6), stride, &Ground::Plane);
        assert!(
            (walker.feet - Vec3::new(1.0, 0.0, 2.0 + 2.0 * WALK_SPEED)).length() < 1e-5,
            "{}",
            walker.feet
        );
        assert!((walker.eye().y - EYE_HEIGHT).abs() < 1e-6);
        let run = Stride {
            run: true,
            right: true,
            ..Stride::default()
        };
        let before = walker.feet;
        walker.step(1.0, Vec3::Z, run, &Ground::Plane);
        assert!(((walker.feet - before).length() - RUN_SPEED).abs() < 1e-4);
        // The feet sphere reaches the ground: the grass there lies flat.
        let [feet, knees] = walker.colliders();
        assert!(feet.center.y - feet.radius <= walker.feet.y && knees.center.y > feet.center.y);
    }

    #[test]
    fn a_walker_follows_a_terrain_up_and_down_and_stops_at_its_edge() {
        let terrain = Mesh::terrain(Vec2::splat(40.0), 5.0, 64, 9);
        let grid = terrain.height_grid().expect("a terrain is a height grid");
        let surface = Surface::Terrain {
            size: Vec2::splat(40.0),
            height: 5.0,
            resolution: 64,
            seed: 9,
        };
        assert!(matches!(
            Ground::of(&surface, Some(&terrain), Some(&grid)),
            Ground::Grid(_)
        ));
        // The triangles and the grid are the same ground.
        for ground in [Ground::Mesh(&terrain), Ground::Grid(&grid)] {
            walk_the_terrain(&ground, &grid);
        }
        assert_eq!(Ground::None.height_at(Vec2::ZERO), None);
    }

    fn walk_the_terrain(ground: &Ground, grid: &HeightGrid) {
        let mut walker = Walker::under(Vec3::new(-15.0, 30.0, 0.0), ground);
        let stride = Stride {
            forward: true,
            run: true,
            ..Stride::default()
        };
        let mut heights = Vec::new();
        for _ in 0..40 {
            walker.step(0.25, Vec3::X, stride, ground);
            let expected = grid.height_at(walker.feet.x, walker.feet.z).unwrap();
            assert!(
                (walker.feet.y - expected).abs() < 1e-3,
                "{} against {expected}",
                walker.feet
            );
            heights.push(walker.feet.y);
        }
        let (low, high) = heights
            .iter()
            .fold((f32::MAX, f32::MIN), |(l, h), &y| (l.min(y), h.max(y)));
        assert!(high - low > 0.5, "the walk should climb and descend: {low}..{high}");
        // Past the terrain's edge (x = 20) there is no ground: the walker waits at the edge.
        assert!(walker.feet.x <= 20.0, "{}", walker.feet);
    }
}
