//! The camera, with Vulkan's clip conventions: right-handed world, depth in [0, w], and y pointing
//! down in normalised device coordinates (the projection flips it, so the world's up is up on screen).

use glam::{Mat4, Vec3};
use serde::{Deserialize, Serialize};

use crate::physics::Collider;
use crate::validate::{Checks, Validate};

/// A perspective camera: where it is, what it looks at, and its lens.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct Camera {
    /// Eye position.
    pub position: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Up direction of the view (not parallel to the view direction).
    pub up: Vec3,
    /// Vertical field of view, degrees.
    pub fov_y_degrees: f32,
    /// Near clip distance.
    pub near: f32,
    /// Far clip distance.
    pub far: f32,
}

impl Default for Camera {
    /// The course setup: looking at the origin from 10 units away, 45° field of view.
    fn default() -> Self {
        Self {
            position: Vec3::new(0.0, 4.0, -9.2),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_degrees: 45.0,
            near: 0.1,
            far: 100.0,
        }
    }
}

impl Camera {
    /// The camera whose world-to-view matrix is `view` (right-handed, looking down −z, as
    /// [`Camera::view`] makes them), with the lens given: for an application that keeps its own
    /// view matrix and draws sward's grass into its frame.
    pub fn from_view(view: Mat4, fov_y_degrees: f32, near: f32, far: f32) -> Camera {
        let world = view.inverse();
        let position = world.w_axis.truncate();
        Camera {
            position,
            target: position - world.z_axis.truncate(),
            up: world.y_axis.truncate(),
            fov_y_degrees,
            near,
            far,
        }
    }

    /// World to view space (right-handed, looking down −z).
    pub fn view(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.position, self.target, self.up)
    }

    /// Perspective projection to Vulkan clip space (depth 0 at `near`, w at `far`, y down).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let mut p =
            glam::camera::rh::proj::directx::perspective(self.fov_y_degrees.to_radians(), aspect, self.near, self.far);
        p.y_axis.y = -p.y_axis.y;
        p
    }

    /// Pixels per unit at unit depth on a target `height` pixels tall.
    pub fn focal(&self, height: u32) -> f32 {
        0.5 * height as f32 / (0.5 * self.fov_y_degrees.to_radians()).tan()
    }

    /// World to Vulkan clip space: `projection(aspect) · view()`.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }
}

/// A path the camera travels in animations (the scene file's `[camera_path]`): through
/// `points` in a loop at `speed` units per second, looking at the camera's target — or, with
/// `dolly`, carrying the target along so the view keeps its direction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct CameraPath {
    /// Eye positions the camera passes in turn, back to the first (fewer than two: it stays).
    pub points: Vec<Vec3>,
    /// Speed along the path, units per second.
    pub speed: f32,
    /// Move the target with the eye (a tracking shot) instead of looking at it from everywhere.
    pub dolly: bool,
    /// The points' heights (and a tracking shot's target's) are above the ground under the eye,
    /// not above y = 0: a player walking, running or flying over hills.
    pub above_ground: bool,
}

impl Default for CameraPath {
    /// No points (the camera stays), a walking pace once it has some.
    fn default() -> Self {
        CameraPath {
            points: Vec::new(),
            speed: 1.5,
            dolly: false,
            above_ground: false,
        }
    }
}

impl CameraPath {
    /// Whether the camera moves at all.
    pub fn is_still(&self) -> bool {
        self.points.len() < 2 || self.speed == 0.0
    }

    /// `camera_at`, lifted over `ground` (a height grid; none: the plane y = 0) where the path
    /// runs `above_ground` — standing still too.
    pub fn camera_over(&self, camera: &Camera, t: f32, ground: Option<&crate::mesh::HeightGrid>) -> Camera {
        let mut moved = self.camera_at(camera, t);
        if self.above_ground {
            let eye = moved.position;
            let lift = ground.and_then(|g| g.height_at(eye.x, eye.z)).unwrap_or(0.0);
            moved.position.y += lift;
            if self.dolly {
                moved.target.y += lift;
            }
        }
        moved
    }

    /// `camera` where the path takes it `t` seconds in (unchanged if the path is still).
    pub fn camera_at(&self, camera: &Camera, t: f32) -> Camera {
        if self.is_still() {
            return *camera;
        }
        // The eye follows the path as a collider sphere follows its own: one rule for both.
        let eye = Collider {
            path: self.points.clone(),
            speed: self.speed,
            ..Collider::sphere(camera.position, 0.0)
        }
        .at(t)
        .center;
        let target = if self.dolly {
            camera.target + (eye - self.points[0])
        } else {
            camera.target
        };
        Camera {
            position: eye,
            target,
            ..*camera
        }
    }
}

impl Validate for Camera {
    fn validate(&self, c: &mut Checks) {
        c.check(
            self.fov_y_degrees > 1.0 && self.fov_y_degrees < 179.0,
            "camera.fov_y_degrees",
            self.fov_y_degrees,
            "an angle in (1, 179) degrees",
        );
        c.check(
            self.near >= 1e-3 && self.near < self.far,
            "camera.near",
            self.near,
            "0.001 ≤ near < far",
        );
        c.check(
            self.position.distance(self.target) > 1e-4 && self.position.is_finite() && self.target.is_finite(),
            "camera.target",
            self.target,
            "a finite point other than camera.position",
        );
        let forward = (self.target - self.position).normalize_or_zero();
        c.check(
            self.up.length() > 1e-6 && self.up.normalize_or_zero().cross(forward).length() > 1e-3,
            "camera.up",
            self.up,
            "a non-zero direction not along the line of sight",
        );
    }
}

impl Validate for CameraPath {
    fn validate(&self, c: &mut Checks) {
        c.check(
            self.points.iter().all(|p| p.is_finite()) && self.speed.is_finite() && self.speed >= 0.0,
            "camera_path.points",
            self.points.len(),
            "finite points and a finite speed ≥ 0",
        );
    }
}

/// Which way a target's depth runs. sward computes in [`DepthDirection::Forward`] whatever
/// its target (its depth pyramid, its shadow map, the projection it culls with); a reversed
/// target gets the same depths mirrored, `1 − z`, by the viewport's depth range (minDepth 1,
/// maxDepth 0) and the depth tests turned round. `1 − z` of a forward projection with near `n`
/// and far `f` is the reversed projection with the same `n` and `f`, infinite far included, so
/// sward's blades land at the depths the application's own meshes have.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DepthDirection {
    /// 0 at the near plane, 1 at the far; nearer is smaller (sward's own targets).
    #[default]
    Forward,
    /// 1 at the near plane, 0 at the far (or at infinity); nearer is larger: reverse Z, as
    /// Bevy's cameras and many engines draw.
    Reverse,
}

impl DepthDirection {
    /// The depth the attachment is cleared to: the far plane.
    pub fn far(self) -> f32 {
        match self {
            DepthDirection::Forward => 1.0,
            DepthDirection::Reverse => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    #[test]
    fn clip_space_follows_vulkan() {
        let cam = Camera {
            position: Vec3::ZERO,
            target: Vec3::NEG_Z,
            ..Camera::default()
        };
        let vp = cam.view_projection(1.0);
        let near = vp * Vec4::new(0.0, 0.0, -cam.near, 1.0);
        let far = vp * Vec4::new(0.0, 0.0, -cam.far, 1.0);
        assert!((near.z / near.w).abs() < 1e-5, "near plane maps to depth 0");
        assert!((far.z / far.w - 1.0).abs() < 1e-5, "far plane maps to depth 1");
        let above = vp * Vec4::new(0.0, 1.0, -5.0, 1.0);
        assert!(above.y < 0.0, "world up is NDC -y in Vulkan");
    }

    #[test]
    fn a_camera_path_loops_through_its_points_and_a_dolly_carries_the_target() {
        let camera = Camera::default();
        let mut path = CameraPath {
            points: vec![Vec3::new(0.0, 2.0, -10.0), Vec3::new(10.0, 2.0, -10.0)],
            speed: 5.0,
            dolly: false,
            above_ground: false,
        };
        assert_eq!(path.camera_at(&camera, 0.0).position, path.points[0]);
        let later = path.camera_at(&camera, 1.0);
        assert!((later.position - Vec3::new(5.0, 2.0, -10.0)).length() < 1e-4);
        assert_eq!(later.target, camera.target);
        // The loop goes back: 20 units round, so at 4 s it is half-way home.
        assert!((path.camera_at(&camera, 3.0).position.x - 5.0).abs() < 1e-4);
        path.dolly = true;
        let tracked = path.camera_at(&camera, 1.0);
        assert!((tracked.target - (camera.target + Vec3::new(5.0, 0.0, 0.0))).length() < 1e-4);
        assert_eq!(CameraPath::default().camera_at(&camera, 3.0), camera);
    }

    #[test]
    fn a_path_above_the_ground_follows_the_hills_standing_or_moving() {
        let hills = crate::mesh::Mesh::terrain(glam::Vec2::splat(40.0), 6.0, 32, 2);
        let grid = hills.height_grid().unwrap();
        // The camera stands at the path's start (a still path leaves it there).
        let camera = Camera {
            position: Vec3::new(-10.0, 1.7, 3.0),
            ..Camera::default()
        };
        let mut path = CameraPath {
            points: vec![Vec3::new(-10.0, 1.7, 3.0), Vec3::new(12.0, 1.7, -4.0)],
            speed: 4.0,
            dolly: true,
            above_ground: true,
        };
        for (speed, t) in [(4.0, 0.0), (4.0, 2.5), (0.0, 7.0)] {
            path.speed = speed;
            let moved = path.camera_over(&camera, t, Some(&grid));
            let under = grid.height_at(moved.position.x, moved.position.z).unwrap();
            assert!(
                (moved.position.y - under - 1.7).abs() < 1e-4,
                "{speed} m/s at {t} s: {moved:?}"
            );
        }
        path.above_ground = false;
        assert_eq!(
            path.camera_over(&camera, 1.0, Some(&grid)),
            path.camera_at(&camera, 1.0)
        );
    }

    #[test]
    fn a_camera_made_from_its_view_matrix_has_that_view() {
        let camera = Camera::default();
        let again = Camera::from_view(camera.view(), camera.fov_y_degrees, camera.near, camera.far);
        assert!(again.view().abs_diff_eq(camera.view(), 1e-4));
        assert!(again
            .view_projection(1.5)
            .abs_diff_eq(camera.view_projection(1.5), 1e-4));
    }
}
