//! Avian's colliders in the grass (the `avian` feature): an entity with an Avian `Collider` and
//! a [`GrassFromCollider`] presses the grass (or mows it) in its collider's own shape. The
//! shape is packed into spheres once, as sward packs its mesh bodies — a ball is one sphere, a
//! capsule a row of them along its segment, a box, a convex hull or a triangle mesh spheres
//! packed inside it, a compound each part's — and kept as the entity's [`GrassCollider`],
//! which follows the body wherever Avian moves it. sward's collision model (spheres pushing
//! blades, a trail that decays) is the same as for every collider.

use avian3d::parry::shape::{Shape, SharedShape};
use avian3d::prelude::Collider;
use bevy::app::{App, PostUpdate};
use bevy::ecs::prelude::*;
use bevy::math::{Quat, Vec3, Vec4};
use bevy::prelude::ReflectDefault;

use crate::components::GrassCollider;

/// The entity's Avian `Collider` presses the grass in its own shape, or mows it.
#[derive(Component, Clone, Copy, Debug, PartialEq, bevy::reflect::Reflect)]
#[reflect(Component, Default, Clone, PartialEq)]
pub struct GrassFromCollider {
    /// Whether it cuts the grass under it instead of pressing it.
    pub cuts: bool,
    /// At most how many spheres a box, hull or mesh is packed into (more follow its shape
    /// closer; each is tested against every blade near it).
    pub spheres: usize,
}

impl Default for GrassFromCollider {
    /// Pressing, in up to 24 spheres.
    fn default() -> Self {
        GrassFromCollider {
            cuts: false,
            spheres: 24,
        }
    }
}

impl GrassFromCollider {
    /// Mowing the grass under it.
    pub fn cutting() -> Self {
        GrassFromCollider {
            cuts: true,
            ..Default::default()
        }
    }
}

pub(crate) fn build(app: &mut App) {
    app.add_systems(PostUpdate, follow_colliders.in_set(crate::GrassSystems));
}

/// An Avian collider that presses the grass, new or changed since the last frame.
type ChangedCollider = Or<(Changed<Collider>, Changed<GrassFromCollider>)>;

/// A [`GrassCollider`] for each new or changed Avian collider that presses the grass.
fn follow_colliders(mut commands: Commands, changed: Query<(Entity, &Collider, &GrassFromCollider), ChangedCollider>) {
    for (entity, collider, wanted) in &changed {
        let spheres = spheres_of(collider.shape(), wanted.spheres.max(1));
        if spheres.is_empty() {
            bevy::log::warn!(
                "entity {entity}'s collider has no finite shape sward can press the grass with (a ball, capsule, box, cylinder, cone, convex hull, triangle mesh or a compound of them): it leaves the grass alone"
            );
        }
        commands.entity(entity).insert(GrassCollider {
            spheres,
            cuts: wanted.cuts,
        });
    }
}

/// `shape` packed into spheres (centre and radius) in its collider's space, at most `budget`
/// where it is packed: none for a shape without a finite size (a half-space) or a height
/// field (a terrain presses every blade).
pub fn spheres_of(shape: &SharedShape, budget: usize) -> Vec<Vec4> {
    let shape: &dyn Shape = &**shape;
    if let Some(ball) = shape.as_ball() {
        return vec![Vec3::ZERO.extend(ball.radius)];
    }
    if let Some(capsule) = shape.as_capsule() {
        let [a, b] = [capsule.segment.a, capsule.segment.b].map(|p| Vec3::new(p.x, p.y, p.z));
        return capsule_spheres(a, b, capsule.radius, budget);
    }
    if let Some(compound) = shape.as_compound() {
        let parts = compound.shapes();
        let share = (budget / parts.len().max(1)).max(1);
        return parts
            .iter()
            .flat_map(|(pose, part)| {
                let rotation = Quat::from_xyzw(pose.rotation.x, pose.rotation.y, pose.rotation.z, pose.rotation.w);
                let at = Vec3::new(pose.translation.x, pose.translation.y, pose.translation.z);
                spheres_of(part, share)
                    .into_iter()
                    .map(move |s| (at + rotation * s.truncate()).extend(s.w))
            })
            .collect();
    }
    if shape.as_halfspace().is_some() || shape.as_heightfield().is_some() {
        return Vec::new();
    }
    let Some((vertices, triangles)) = triangles_of(shape) else {
        return Vec::new();
    };
    crate::components::pack_triangles(vertices, triangles, budget)
}

/// Spheres of `radius` along the segment from `a` to `b`, overlapping by half a radius at
/// most (the capsule's own surface, give or take a tenth of its radius between them).
fn capsule_spheres(a: Vec3, b: Vec3, radius: f32, budget: usize) -> Vec<Vec4> {
    let length = a.distance(b);
    let count = ((length / (0.5 * radius.max(1e-4))).ceil() as usize + 1).clamp(2, budget.max(2));
    (0..count)
        .map(|k| a.lerp(b, k as f32 / (count - 1) as f32).extend(radius))
        .collect()
}

/// The surface of a box, cylinder, cone, convex hull or triangle mesh as triangles.
fn triangles_of(shape: &dyn Shape) -> Option<(Vec<glam::Vec3>, Vec<[u32; 3]>)> {
    let v = |p: &avian3d::parry::math::Vector| glam::Vec3::new(p.x, p.y, p.z);
    let (vertices, triangles) = if let Some(cuboid) = shape.as_cuboid() {
        cuboid.to_trimesh()
    } else if let Some(hull) = shape.as_convex_polyhedron() {
        hull.to_trimesh()
    } else if let Some(cylinder) = shape.as_cylinder() {
        cylinder.to_trimesh(16)
    } else if let Some(cone) = shape.as_cone() {
        cone.to_trimesh(16)
    } else {
        let mesh = shape.as_trimesh()?;
        (mesh.vertices().to_vec(), mesh.indices().to_vec())
    };
    Some((vertices.iter().map(v).collect(), triangles))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on a grid over `shape`'s box: those inside the shape, and those inside the
    /// spheres.
    fn coverage(collider: &Collider, spheres: &[Vec4]) -> (usize, usize, usize) {
        let shape: &dyn Shape = &**collider.shape();
        let aabb = shape.compute_local_aabb();
        let (lo, hi) = (aabb.mins, aabb.maxs);
        let (mut inside, mut covered, mut spilled) = (0, 0, 0);
        let n = 24;
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let t = |a: f32, b: f32, s: usize| a + (b - a) * (s as f32 + 0.5) / n as f32;
                    let p = avian3d::parry::math::Vector::new(t(lo.x, hi.x, i), t(lo.y, hi.y, j), t(lo.z, hi.z, k));
                    let q = Vec3::new(p.x, p.y, p.z);
                    let in_spheres = spheres.iter().any(|s| s.truncate().distance(q) <= s.w);
                    let in_shape = shape.contains_local_point(p);
                    inside += in_shape as usize;
                    covered += (in_shape && in_spheres) as usize;
                    spilled += (!in_shape && in_spheres) as usize;
                }
            }
        }
        (inside, covered, spilled)
    }

    #[test]
    fn a_ball_is_one_sphere_of_its_radius() {
        assert_eq!(
            spheres_of(Collider::sphere(0.7).shape(), 24),
            vec![Vec4::new(0.0, 0.0, 0.0, 0.7)]
        );
    }

    #[test]
    fn a_capsule_is_a_row_of_spheres_that_fills_it() {
        let capsule = Collider::capsule(0.3, 2.0);
        let spheres = spheres_of(capsule.shape(), 24);
        assert!(spheres.len() >= 5, "{} spheres along a capsule 2.6 long", spheres.len());
        let (inside, covered, spilled) = coverage(&capsule, &spheres);
        assert!(
            covered as f32 > 0.97 * inside as f32,
            "{covered} of {inside} points inside covered"
        );
        assert_eq!(spilled, 0, "points outside the capsule pressed");
    }

    #[test]
    fn a_box_a_convex_hull_and_a_triangle_mesh_are_packed_inside_their_shape() {
        let cuboid = Collider::cuboid(2.0, 0.6, 1.0);
        let hull = Collider::convex_hull(&[
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(1.0, 0.0, -1.0),
            Vec3::new(0.0, 0.0, 1.0),
        ])
        .expect("a tetrahedron's hull");
        // A closed mesh: the box's own triangles.
        let (vertices, triangles) =
            avian3d::parry::shape::Cuboid::new(avian3d::parry::math::Vector::new(1.0, 0.3, 0.5)).to_trimesh();
        let mesh = Collider::trimesh(vertices.iter().map(|p| Vec3::new(p.x, p.y, p.z)).collect(), triangles);
        // A triangle mesh has no inside of its own: the box it bounds is its shape.
        for (what, collider, shape) in [
            ("box", &cuboid, &cuboid),
            ("hull", &hull, &hull),
            ("mesh", &mesh, &cuboid),
        ] {
            let spheres = spheres_of(collider.shape(), 24);
            let (inside, covered, spilled) = coverage(shape, &spheres);
            assert!(
                covered as f32 > 0.5 * inside as f32,
                "{what}: {covered} of {inside} points inside covered by {} spheres",
                spheres.len()
            );
            assert!(
                (spilled as f32) < 0.25 * covered as f32,
                "{what}: {spilled} points outside pressed, against {covered} inside"
            );
        }
    }

    #[test]
    fn a_compound_s_parts_stand_where_it_puts_them_and_a_half_space_presses_nothing() {
        let parts = Collider::compound(vec![
            (Vec3::new(2.0, 0.0, 0.0), Quat::IDENTITY, Collider::sphere(0.5)),
            (Vec3::new(-2.0, 0.0, 0.0), Quat::IDENTITY, Collider::sphere(0.25)),
        ]);
        let mut spheres = spheres_of(parts.shape(), 24);
        spheres.sort_by(|a, b| a.x.total_cmp(&b.x));
        assert_eq!(
            spheres,
            vec![Vec4::new(-2.0, 0.0, 0.0, 0.25), Vec4::new(2.0, 0.0, 0.0, 0.5)]
        );
        assert!(spheres_of(Collider::half_space(Vec3::Y).shape(), 24).is_empty());
    }
}
