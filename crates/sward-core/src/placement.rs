//! Where a field stands in an application's world: its own space — the one its scene is
//! written in, where its blades grow, sway and are culled — turned, scaled and moved. A frame
//! of a placed field is described in the field's own space ([`FrameDesc::placed`]): the eye,
//! the world's colliders, gravity, winds and lights are carried into it, so the passes run as
//! they do for a field at the world's origin, and only an engine's draw carries the points it
//! makes back into the world (`FrameUniforms::placed`).
//!
//! The scale is the same along every axis (a field scaled twice as large grows blades twice as
//! tall): a blade's physics and its level of detail keep their shape, since what the eye sees
//! of a blade is its size over its distance, and both scale alike.

use glam::{Mat3, Mat4, Quat, Vec3};

use crate::frame::{FrameCamera, FrameColliders, FrameDesc, Sphere};

/// A field's place in the world: its own space turned by `rotation`, scaled by `scale` and
/// moved by `translation`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Where the field's origin stands in the world.
    pub translation: Vec3,
    /// How the field is turned.
    pub rotation: Quat,
    /// How much larger than its scene says the field is (the same along every axis; above 0).
    pub scale: f32,
}

impl Default for Placement {
    fn default() -> Self {
        Placement::IDENTITY
    }
}

impl Placement {
    /// The field where its scene puts it.
    pub const IDENTITY: Placement = Placement {
        translation: Vec3::ZERO,
        rotation: Quat::IDENTITY,
        scale: 1.0,
    };

    /// A placement from an engine's transform: its largest scale along any axis (as colliders
    /// are scaled; a scale that is zero or not a number leaves the field its own size), its
    /// rotation and its translation.
    pub fn from_scale_rotation_translation(scale: Vec3, rotation: Quat, translation: Vec3) -> Placement {
        let largest = scale.abs().max_element();
        Placement {
            translation,
            rotation: rotation.normalize(),
            scale: if largest.is_finite() && largest > 0.0 {
                largest
            } else {
                1.0
            },
        }
    }

    /// Whether the field stands where its scene puts it.
    pub fn is_identity(&self) -> bool {
        *self == Placement::IDENTITY
    }

    /// The field's space to the world's.
    pub fn to_world(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(Vec3::splat(self.scale), self.rotation, self.translation)
    }

    /// A point of the field's space in the world.
    pub fn point_to_world(&self, p: Vec3) -> Vec3 {
        self.rotation * (p * self.scale) + self.translation
    }

    /// A point of the world in the field's space.
    pub fn point_to_field(&self, p: Vec3) -> Vec3 {
        self.rotation.inverse() * (p - self.translation) / self.scale
    }

    /// A direction of the world in the field's space (unit stays unit).
    pub fn direction_to_field(&self, d: Vec3) -> Vec3 {
        self.rotation.inverse() * d
    }

    /// A sphere of the world in the field's space.
    pub fn sphere_to_field(&self, s: Sphere) -> Sphere {
        Sphere {
            center: self.point_to_field(s.center),
            radius: s.radius / self.scale,
        }
    }

    /// A sphere of the field's space in the world.
    pub fn sphere_to_world(&self, s: Sphere) -> Sphere {
        Sphere {
            center: self.point_to_world(s.center),
            radius: s.radius * self.scale,
        }
    }

    /// Every sphere of `colliders` (world) in the field's space.
    pub fn colliders_to_field(&self, colliders: &FrameColliders) -> FrameColliders {
        each_sphere(colliders, |s| self.sphere_to_field(s))
    }

    /// Every sphere of `colliders` (the field's space) in the world.
    pub fn colliders_to_world(&self, colliders: &FrameColliders) -> FrameColliders {
        each_sphere(colliders, |s| self.sphere_to_world(s))
    }

    /// The eye `camera` (world) as the field sees it: its view measured in the field's units
    /// (still rigid: the field's scale is taken out of it), and a projection that puts every
    /// field point where the world's would, depth included, so an engine's depth buffer is the
    /// cull's. The lens's pixels per unit at unit depth do not change: both scale alike.
    pub fn camera_to_field(&self, camera: &FrameCamera) -> FrameCamera {
        let s = self.scale;
        let rigid = Mat4::from_rotation_translation(self.rotation, self.translation);
        // S(1/s)·V·T·R·S(s) is rigid again: its rotation V's and R's, its translation in field units.
        let view = Mat4::from_scale(Vec3::splat(1.0 / s)) * camera.view * rigid * Mat4::from_scale(Vec3::splat(s));
        FrameCamera {
            eye: self.point_to_field(camera.eye),
            view: without_drift(view),
            projection: camera.projection * Mat4::from_scale(Vec3::splat(s)),
            near: camera.near / s,
            far: camera.far / s,
            focal: camera.focal,
        }
    }
}

/// `colliders` with `carried` applied to each sphere, each list kept apart.
fn each_sphere(colliders: &FrameColliders, carried: impl Fn(Sphere) -> Sphere) -> FrameColliders {
    let all = |list: &[Sphere]| list.iter().map(|&s| carried(s)).collect();
    FrameColliders {
        pushing: all(&colliders.pushing),
        cutting: all(&colliders.cutting),
        hiding: all(&colliders.hiding),
    }
}

/// `view` with its linear part made exactly a rotation again (products of rotations drift).
fn without_drift(view: Mat4) -> Mat4 {
    let rotation = Quat::from_mat3(&Mat3::from_mat4(view)).normalize();
    Mat4::from_rotation_translation(rotation, view.w_axis.truncate())
}

impl FrameDesc {
    /// This frame, described in the world, as the field placed by `placement` sees it: the
    /// eye, the colliders, gravity, the winds and the lights carried into the field's space
    /// (lengths, speeds and accelerations divided by its scale), and the placement kept for
    /// the engine's draw. A scene's own colliders belong to its field: carry them into the
    /// world first ([`Placement::colliders_to_world`]) where the frame was made of the scene.
    pub fn placed(mut self, placement: Placement, last: Placement) -> FrameDesc {
        self.placement = [placement, last];
        if placement.is_identity() {
            return self;
        }
        let s = placement.scale;
        self.camera = placement.camera_to_field(&self.camera);
        self.colliders = placement.colliders_to_field(&self.colliders);
        let sim = &mut self.simulation;
        sim.gravity_direction = placement.direction_to_field(sim.gravity_direction);
        sim.gravity_strength /= s;
        sim.point_gravity = placement.point_to_field(sim.point_gravity);
        sim.point_gravity_strength /= s;
        for wind in &mut self.winds {
            wind.direction = placement.direction_to_field(wind.direction);
            wind.center = placement.point_to_field(wind.center);
            wind.strength /= s;
            wind.scale *= s;
            wind.speed /= s;
        }
        self.shading.light_direction = placement.direction_to_field(self.shading.light_direction);
        for lamp in &mut self.lamps {
            lamp.position = placement.point_to_field(lamp.position);
            lamp.range /= s;
            // Its light falls off with the square of the distance, which is the world's over s.
            lamp.color /= s * s;
            if let Some(spot) = lamp.spot.as_mut() {
                spot.direction = placement.direction_to_field(spot.direction);
            }
        }
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Camera;

    fn turned() -> Placement {
        Placement::from_scale_rotation_translation(
            Vec3::new(2.0, 1.5, 2.0),
            Quat::from_rotation_y(0.7) * Quat::from_rotation_x(0.2),
            Vec3::new(30.0, 1.0, -12.0),
        )
    }

    #[test]
    fn a_point_goes_there_and_back() {
        let p = turned();
        let point = Vec3::new(1.0, 2.0, -3.0);
        assert!(p.point_to_field(p.point_to_world(point)).abs_diff_eq(point, 1e-5));
        assert!(p
            .to_world()
            .transform_point3(point)
            .abs_diff_eq(p.point_to_world(point), 1e-4));
        assert_eq!(p.scale, 2.0, "the largest scale");
        let flat = Placement::from_scale_rotation_translation(Vec3::ZERO, Quat::IDENTITY, Vec3::ZERO);
        assert_eq!(flat.scale, 1.0, "no scale is none");
    }

    #[test]
    fn a_field_point_lands_where_the_world_s_camera_puts_it() {
        let p = turned();
        let camera = Camera {
            position: Vec3::new(25.0, 4.0, -20.0),
            target: Vec3::new(31.0, 0.5, -11.0),
            ..Camera::default()
        };
        let world = FrameCamera::from_camera(&camera, [640, 480]);
        let field = p.camera_to_field(&world);
        for point in [Vec3::ZERO, Vec3::new(1.0, 0.3, 2.0), Vec3::new(-2.0, 0.1, 3.0)] {
            let seen = world.view_projection().project_point3(p.point_to_world(point));
            let ours = field.view_projection().project_point3(point);
            assert!(seen.abs_diff_eq(ours, 1e-4), "{seen} {ours}");
        }
        // A rigid view in the field's units: distances there are the world's over the scale.
        let point = Vec3::new(1.0, 0.3, 2.0);
        let depth = -(field.view.transform_point3(point)).z;
        let world_depth = -(world.view.transform_point3(p.point_to_world(point))).z;
        assert!((depth * p.scale - world_depth).abs() < 1e-3, "{depth} {world_depth}");
        assert!(field.eye.abs_diff_eq(p.point_to_field(world.eye), 1e-5));
        assert!((field.near * p.scale - world.near).abs() < 1e-6);
        let from_view = field.view.inverse().w_axis.truncate();
        assert!(from_view.abs_diff_eq(field.eye, 1e-3), "{from_view} {}", field.eye);
    }

    #[test]
    fn gravity_and_colliders_are_carried_into_the_field() {
        let scene = crate::Scene::default();
        let mut desc = FrameDesc::of_scene(&scene, glam::Vec2::splat(10.0), (1.0, 1), [64, 64]);
        desc.colliders.pushing = vec![Sphere {
            center: Vec3::new(31.0, 1.0, -12.0),
            radius: 1.0,
        }];
        let p = turned();
        let placed = desc.clone().placed(p, p);
        let g = placed.simulation.gravity_direction;
        assert!(g.abs_diff_eq(p.direction_to_field(Vec3::NEG_Y), 1e-5), "{g}");
        assert!((placed.simulation.gravity_strength * 2.0 - desc.simulation.gravity_strength).abs() < 1e-5);
        let ball = placed.colliders.pushing[0];
        assert!(p
            .sphere_to_world(ball)
            .center
            .abs_diff_eq(Vec3::new(31.0, 1.0, -12.0), 1e-4));
        assert_eq!(ball.radius, 0.5);
        assert_eq!(placed.placement, [p, p]);
        let unplaced = desc.clone().placed(Placement::IDENTITY, Placement::IDENTITY);
        assert_eq!(unplaced, desc, "the identity changes nothing");
    }
}
