//! Camera controls of the viewer: orbit (drag to rotate, right-drag to pan, scroll to zoom), fly
//! (WASD + mouse look, shift for speed, Q/E down/up) and walk (WASD at a person's pace on the
//! ground, shift to run, eyes 1.7 units up; `sward_core::walk`), switched in turn, with a reset
//! to the scene's starting view. Pure maths on the scene's [`Camera`], independent of the window
//! system.

use glam::{Vec2, Vec3};
use sward_core::walk::{Ground, Stride, Walker};
use sward_core::{Camera, Collider};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Orbit,
    Fly,
    /// On foot: the walker's legs tread the grass.
    Walk,
}

/// Keys held down for flying, each a direction.
#[derive(Clone, Copy, Debug, Default)]
pub struct FlyKeys {
    pub forward: bool,
    pub back: bool,
    pub left: bool,
    pub right: bool,
    pub up: bool,
    pub down: bool,
    pub fast: bool,
}

#[derive(Clone, Debug)]
pub struct CameraControl {
    pub mode: Mode,
    /// Rotation about +y, radians.
    yaw: f32,
    /// Elevation, radians, kept away from the poles.
    pitch: f32,
    /// Orbit centre.
    target: Vec3,
    /// Orbit radius.
    distance: f32,
    /// Fly position.
    position: Vec3,
    /// Fly speed in units per second.
    pub speed: f32,
    pub keys: FlyKeys,
    /// The walker (walk mode).
    walker: Walker,
    start: Camera,
}

const MAX_PITCH: f32 = 1.55;

impl CameraControl {
    pub fn new(start: Camera) -> Self {
        let mut control = CameraControl {
            mode: Mode::Orbit,
            yaw: 0.0,
            pitch: 0.0,
            target: start.target,
            distance: 1.0,
            position: start.position,
            speed: 4.0,
            keys: FlyKeys::default(),
            walker: Walker::under(start.position, &Ground::Plane),
            start,
        };
        control.reset();
        control
    }

    /// Back to the scene's starting view.
    pub fn reset(&mut self) {
        let offset = self.start.position - self.start.target;
        self.target = self.start.target;
        self.position = self.start.position;
        self.distance = offset.length().max(1e-3);
        let dir = -offset / self.distance; // view direction
        self.yaw = dir.x.atan2(-dir.z);
        self.pitch = dir.y.clamp(-1.0, 1.0).asin().clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// A new starting view (after loading a scene).
    pub fn set_start(&mut self, start: Camera) {
        self.start = start;
        self.reset();
    }

    /// The next mode: orbit, fly, walk (where there is `ground` to walk on), orbit again.
    pub fn toggle_mode(&mut self, ground: &Ground) {
        let eye = self.eye();
        self.mode = match self.mode {
            Mode::Orbit => Mode::Fly,
            Mode::Fly if !matches!(ground, Ground::None) => Mode::Walk,
            Mode::Fly | Mode::Walk => Mode::Orbit,
        };
        // Keep the view where it is (walking: from eye height over the ground below it).
        self.walker = Walker::under(eye, ground);
        let eye = if self.mode == Mode::Walk {
            self.walker.eye()
        } else {
            eye
        };
        self.position = eye;
        self.target = eye + self.direction() * self.distance;
    }

    /// The walker's legs, while walking: colliders that tread the grass.
    pub fn walker_colliders(&self) -> Option<[Collider; 2]> {
        (self.mode == Mode::Walk).then(|| self.walker.colliders())
    }

    /// Unit view direction from yaw and pitch.
    fn direction(&self) -> Vec3 {
        Vec3::new(
            self.yaw.sin() * self.pitch.cos(),
            self.pitch.sin(),
            -self.yaw.cos() * self.pitch.cos(),
        )
    }

    fn eye(&self) -> Vec3 {
        match self.mode {
            Mode::Orbit => self.target - self.direction() * self.distance,
            Mode::Fly => self.position,
            Mode::Walk => self.walker.eye(),
        }
    }

    /// Mouse drag by `delta` pixels with the primary button: rotate (orbit) or look (fly).
    pub fn rotate(&mut self, delta: Vec2) {
        self.yaw += delta.x * 0.005;
        self.pitch = (self.pitch - delta.y * 0.005).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// Drag with the secondary button: move the orbit centre in the view plane.
    pub fn pan(&mut self, delta: Vec2) {
        let forward = self.direction();
        let right = forward.cross(Vec3::Y).normalize_or_zero();
        let up = right.cross(forward);
        let scale = self.distance * 0.0015;
        let shift = (-right * delta.x + up * delta.y) * scale;
        self.target += shift;
        self.position += shift;
    }

    /// Scroll by `lines`: zoom (orbit) or change speed (fly; walking keeps a person's pace).
    pub fn zoom(&mut self, lines: f32) {
        match self.mode {
            Mode::Orbit => self.distance = (self.distance * 0.9f32.powf(lines)).clamp(0.2, 500.0),
            Mode::Fly => self.speed = (self.speed * 1.15f32.powf(lines)).clamp(0.1, 200.0),
            Mode::Walk => {}
        }
    }

    /// Advance flying or walking (over `ground`) by `dt` seconds with the held keys.
    pub fn update(&mut self, dt: f32, ground: &Ground) {
        let k = self.keys;
        if self.mode == Mode::Walk {
            let stride = Stride {
                forward: k.forward,
                back: k.back,
                left: k.left,
                right: k.right,
                run: k.fast,
            };
            self.walker.step(dt, self.direction(), stride, ground);
            return;
        }
        if self.mode != Mode::Fly {
            return;
        }
        let forward = self.direction();
        let right = forward.cross(Vec3::Y).normalize_or_zero();
        let axis = |plus: bool, minus: bool| plus as i32 as f32 - minus as i32 as f32;
        let motion = forward * axis(k.forward, k.back) + right * axis(k.right, k.left) + Vec3::Y * axis(k.up, k.down);
        let speed = if k.fast { self.speed * 4.0 } else { self.speed };
        self.position += motion.normalize_or_zero() * speed * dt;
    }

    /// The camera to render with, keeping the scene camera's lens.
    pub fn camera(&self, lens: &Camera) -> Camera {
        let eye = self.eye();
        Camera {
            position: eye,
            target: eye + self.direction(),
            up: Vec3::Y,
            ..*lens
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn start() -> Camera {
        Camera {
            position: Vec3::new(0.0, 2.0, -10.0),
            target: Vec3::new(0.0, 0.5, 0.0),
            ..Camera::default()
        }
    }

    #[test]
    fn starts_at_the_scene_view() {
        let control = CameraControl::new(start());
        let cam = control.camera(&start());
        assert!(cam.position.distance(start().position) < 1e-4, "{}", cam.position);
        let dir = (start().target - start().position).normalize();
        assert!((cam.target - cam.position).normalize().dot(dir) > 0.9999);
    }

    #[test]
    fn orbit_keeps_distance_and_reset_returns() {
        let mut control = CameraControl::new(start());
        let d0 = control.camera(&start()).position.distance(start().target);
        control.rotate(Vec2::new(300.0, -80.0));
        control.zoom(0.0);
        let moved = control.camera(&start()).position;
        assert!((moved.distance(start().target) - d0).abs() < 1e-3);
        assert!(moved.distance(start().position) > 1.0);
        control.reset();
        assert!(control.camera(&start()).position.distance(start().position) < 1e-4);
    }

    #[test]
    fn flying_forward_moves_along_the_view() {
        let mut control = CameraControl::new(start());
        control.toggle_mode(&Ground::Plane);
        let before = control.camera(&start());
        control.keys.forward = true;
        control.update(1.0, &Ground::Plane);
        let after = control.camera(&start());
        let moved = after.position - before.position;
        assert!((moved.length() - control.speed).abs() < 1e-3);
        assert!(moved.normalize().dot((before.target - before.position).normalize()) > 0.999);
    }

    #[test]
    fn walking_keeps_the_eyes_at_a_persons_height_and_treads_the_grass() {
        let mut control = CameraControl::new(start());
        control.toggle_mode(&Ground::Plane);
        assert_eq!(control.walker_colliders(), None, "flying treads nothing");
        control.toggle_mode(&Ground::Plane);
        assert_eq!(control.mode, Mode::Walk);
        let eye = control.camera(&start()).position;
        assert!((eye.y - sward_core::walk::EYE_HEIGHT).abs() < 1e-5, "{eye}");
        control.keys.forward = true;
        control.update(1.0, &Ground::Plane);
        let walked = control.camera(&start()).position - eye;
        assert!((walked.length() - sward_core::walk::WALK_SPEED).abs() < 1e-4 && walked.y == 0.0);
        let legs = control.walker_colliders().expect("walking treads the grass");
        assert!(legs[0].center.y < 0.5);
        // A planet has no ground to walk on: fly goes back to orbit.
        control.toggle_mode(&Ground::None);
        control.toggle_mode(&Ground::None);
        assert_eq!(control.mode, Mode::Fly);
        control.toggle_mode(&Ground::None);
        assert_eq!(control.mode, Mode::Orbit);
    }
}
