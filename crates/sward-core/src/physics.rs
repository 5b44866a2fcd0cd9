//! The CPU reference of the physical model (SPEC §3): η decay, recovery, gravity, wind, state
//! validation and sphere collisions, acting on the tip guide v2 with a fixed step. The compute
//! pass (`shaders/physics.wesl`, both renderers') runs the same steps in the same order.

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

use crate::blade::Blade;
use crate::validate::{finite_non_negative, Checks, Validate};
use crate::wind::{sum_at, wind_force, Wind};

/// The largest number of collider spheres the GPU uniform block holds.
pub const MAX_COLLIDERS: usize = 128;

/// A sphere that pushes grass aside (SPEC §3.7), standing still or travelling a looped path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(deny_unknown_fields)]
pub struct Collider {
    /// Centre of the sphere (where it is when it has no path).
    pub center: Vec3,
    /// Radius of the sphere.
    pub radius: f32,
    /// Points the sphere travels through in a loop (fewer than two: it stays at `center`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub path: Vec<Vec3>,
    /// Speed along the path, units per second.
    #[serde(default = "default_collider_speed")]
    pub speed: f32,
    /// A cutter: it mows the grass under it down to its underside (the trample map keeps the
    /// cut; grass regrows at `trample.regrow`) instead of pushing blades aside.
    #[serde(default)]
    pub cut: bool,
    /// Grass does not grow where it stands: a standing sphere that reaches into the grass
    /// clears the disc under it, at every distance (it paints the ground's density to zero
    /// there; see `paint.rs`). It pushes the grass at its edge as any collider does.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub clear: bool,
}

fn default_collider_speed() -> f32 {
    2.0
}

impl Collider {
    /// A sphere that stays where it is.
    pub fn sphere(center: Vec3, radius: f32) -> Collider {
        Collider {
            center,
            radius,
            path: Vec::new(),
            speed: default_collider_speed(),
            cut: false,
            clear: false,
        }
    }

    /// The sphere where it is at time `t`: `speed · t` along its closed path (a cutter stays
    /// one).
    pub fn at(&self, t: f32) -> Collider {
        Collider {
            cut: self.cut,
            ..Collider::sphere(self.center_at(t), self.radius)
        }
    }

    fn center_at(&self, t: f32) -> Vec3 {
        travel(self.center, &self.path, self.speed, t)
    }

    /// Move the sphere (and its whole path) by `delta`.
    pub fn shift(&mut self, delta: Vec3) {
        self.center += delta;
        self.path.iter_mut().for_each(|p| *p += delta);
    }
}

/// Where something that stands at `center`, or loops through `path` (two points or more) at
/// `speed`, is at time `t`: a collider sphere's centre, a body's origin.
pub fn travel(center: Vec3, path: &[Vec3], speed: f32, t: f32) -> Vec3 {
    if path.len() < 2 {
        return center;
    }
    let segment = |i: usize| (path[i], path[(i + 1) % path.len()]);
    let loop_length: f32 = (0..path.len()).map(|i| segment(i).0.distance(segment(i).1)).sum();
    let mut along = if loop_length > 0.0 {
        (speed * t).rem_euclid(loop_length)
    } else {
        0.0
    };
    for i in 0..path.len() {
        let (a, b) = segment(i);
        let length = a.distance(b);
        if along <= length && length > 0.0 {
            return a.lerp(b, along / length);
        }
        along -= length;
    }
    path[0]
}

/// Which forces act; each can be switched off on its own.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct Forces {
    /// The blade springs back toward its rest pose.
    pub recovery: bool,
    /// Gravity bends the blade.
    pub gravity: bool,
    /// Wind pushes the blade.
    pub wind: bool,
    /// Colliders push the blade aside.
    pub collisions: bool,
}

impl Default for Forces {
    fn default() -> Self {
        Self {
            recovery: true,
            gravity: true,
            wind: true,
            collisions: true,
        }
    }
}

impl Forces {
    /// The `FORCE_*` flags of the forces that act (`FrameUniforms::counts.w`).
    pub fn bits(&self) -> u32 {
        use crate::flags::{when, FORCE_COLLISIONS, FORCE_GRAVITY, FORCE_RECOVERY, FORCE_WIND};
        when(self.recovery, FORCE_RECOVERY)
            | when(self.gravity, FORCE_GRAVITY)
            | when(self.wind, FORCE_WIND)
            | when(self.collisions, FORCE_COLLISIONS)
    }
}

/// Everything the physical model needs besides the blade itself.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct SimParams {
    /// Fixed simulation step in seconds (SPEC §3.8).
    pub step: f32,
    /// Most sub-steps one frame may take to catch up with wall-clock time.
    pub max_substeps: u32,
    /// Direction of environmental gravity (normalised on use).
    pub gravity_direction: Vec3,
    /// Magnitude of environmental gravity.
    pub gravity_strength: f32,
    /// Position of the optional point gravity.
    pub point_gravity: Vec3,
    /// Magnitude of the point gravity.
    pub point_gravity_strength: f32,
    /// Blend t ∈ [0, 1] between environmental (0) and point (1) gravity.
    pub point_gravity_blend: f32,
    /// Rate a at which collision strength η decays per second.
    pub eta_decay: f32,
    /// Which forces act.
    pub forces: Forces,
}

impl Default for SimParams {
    fn default() -> Self {
        Self {
            step: 1.0 / 120.0,
            max_substeps: 4,
            gravity_direction: Vec3::NEG_Y,
            gravity_strength: 9.8,
            point_gravity: Vec3::ZERO,
            point_gravity_strength: 0.0,
            point_gravity_blend: 0.0,
            eta_decay: 0.5,
            forces: Forces::default(),
        }
    }
}

/// Gravity on a blade: environmental (optionally blended with point gravity) plus front gravity
/// `¼·‖gE‖·f`, which makes blades fall over their face rather than straight down.
fn gravity_force(blade: &Blade, params: &SimParams) -> Vec3 {
    let environmental = params.gravity_direction.normalize_or_zero() * params.gravity_strength;
    let toward_point = (params.point_gravity - blade.tip()).normalize_or_zero() * params.point_gravity_strength;
    let g_e = environmental.lerp(toward_point, params.point_gravity_blend);
    let g_f = 0.25 * g_e.length() * blade.front_dir();
    g_e + g_f
}

/// One fixed step of the model for one blade at time `t` (SPEC §3.1–3.7, in order).
pub fn step_blade(blade: &mut Blade, eta: &mut f32, params: &SimParams, colliders: &[Collider], wind: &[Wind], t: f32) {
    step_mown_blade(blade, eta, params, colliders, wind, t, f32::INFINITY);
}

/// One fixed step of a blade mown down to `cut` units (the trample map's cut; physics.wesl
/// `simulate_blade`; `f32::INFINITY`: uncut, [`step_blade`]): stepped as a blade no taller than
/// the cut — validation keeps it that long — with gravity and wind acting by the square of the
/// share of it left (less blade to weigh and catch the wind, a stiffer stub; with the full
/// forces a stub lies flat). The blade keeps its own height, to grow back to as the cut grows
/// past it.
pub fn step_mown_blade(
    blade: &mut Blade,
    eta: &mut f32,
    params: &SimParams,
    colliders: &[Collider],
    wind: &[Wind],
    t: f32,
    cut: f32,
) {
    step_trampled_blade(blade, eta, params, (colliders, wind), t, (cut, Vec2::ZERO));
}

/// One fixed step of a blade where the trample map holds grass mown to `cut` units
/// (`f32::INFINITY`: uncut) and flattened by `push` (the map's texel at its root: which way and
/// how far; zero: upright), as physics.wesl's `simulate_blade` steps it:
/// [`step_mown_blade`], then held down by the map ([`press_by_map`]) where collisions act.
/// `colliders` are the pushing spheres only (a cutter pushes nothing).
pub fn step_trampled_blade(
    blade: &mut Blade,
    eta: &mut f32,
    params: &SimParams,
    (colliders, wind): (&[Collider], &[Wind]),
    t: f32,
    (cut, push): (f32, Vec2),
) {
    let height = blade.height();
    let outer = if cut < height {
        blade.v1.w = cut;
        (cut / height).powi(2)
    } else {
        1.0
    };
    let dt = params.step;
    let forces = params.forces;
    *eta = (*eta - params.eta_decay * dt).max(0.0);

    let mut v2 = blade.tip();
    let mut delta = Vec3::ZERO;
    if forces.recovery {
        delta += (blade.rest_tip() - v2) * blade.stiffness() * (1.0 - *eta).max(0.1);
    }
    if forces.gravity {
        delta += gravity_force(blade, params) * outer;
    }
    if forces.wind {
        delta += wind_force(
            sum_at(wind, blade.root(), t),
            blade.root(),
            v2,
            blade.up(),
            blade.height(),
        ) * outer;
    }
    v2 += delta * dt;
    validate(blade, v2);

    if forces.collisions && collide(blade, eta, colliders) {
        validate(blade, blade.tip());
    }
    if forces.collisions && press_by_map(blade, eta, push) {
        validate(blade, blade.tip());
    }
    blade.v1.w = height;
}

/// SPEC §11: where the trample map says the grass at a blade's root lies along `push` (length
/// 1: flat), a blade standing higher than that is held down to it, as the generated grass
/// beside it is laid (from upright towards lying along the push, by the pressing), and its
/// collision strength is at least the pressing, so a trail recovers at one rate in every kind
/// of grass. True where it held the tip (which then wants validating).
pub fn press_by_map(blade: &mut Blade, eta: &mut f32, push: Vec2) -> bool {
    let pressed = push.length().min(1.0);
    if pressed <= 0.0 {
        return false;
    }
    let (root, up, height) = (blade.root(), blade.up(), blade.height());
    let flat_push = Vec3::new(push.x, 0.0, push.y);
    let along = (flat_push - up * flat_push.dot(up)).normalize_or_zero();
    let lying = root + height * (0.95 * along + 0.1 * up);
    let held = (root + height * up).lerp(lying, pressed);
    *eta = eta.max(pressed);
    if (blade.tip() - root).dot(up) <= (held - root).dot(up) {
        return false;
    }
    blade.v2 = held.extend(blade.width());
    true
}

/// State validation a–c (paper §5.2): keep v2 above the ground, place v1 from v2, and restore the
/// curve's length to h. Writes v1 and v2 of `blade`.
pub fn validate(blade: &mut Blade, v2: Vec3) {
    let v0 = blade.root();
    let up = blade.up();
    let h = blade.height();

    // a. above the local ground plane
    let v2 = v2 - up * up.dot(v2 - v0).min(0.0);

    // b. v1 from v2: the more v2 leans away from up, the lower v1 sits
    let rel = v2 - v0;
    let l_proj = (rel - up * rel.dot(up)).length();
    let v1 = v0 + up * (h * (1.0 - l_proj / h).max(0.05 * (l_proj / h).max(1.0)));

    // c. length: approximate the Bezier length and scale both segments about v0
    let length = estimated_length(v0, v1, v2);
    let ratio = if length > 1e-12 { h / length } else { 1.0 };
    let v1_new = v0 + (v1 - v0) * ratio;
    let v2_new = v1_new + (v2 - v1) * ratio;

    blade.v1 = v1_new.extend(h);
    blade.v2 = v2_new.extend(blade.width());
}

/// The curve length state validation keeps at h (paper §5.2): (2·L0 + L1) / 3, with L0 the chord
/// and L1 the control polygon's length.
pub fn estimated_length(v0: Vec3, v1: Vec3, v2: Vec3) -> f32 {
    (2.0 * (v2 - v0).length() + (v1 - v0).length() + (v2 - v1).length()) / 3.0
}

/// How far a sphere pushes point `p` out of itself: `min(‖c − p‖ − R, 0)·d̂(c − p)`.
fn push_out(sphere: &Collider, p: Vec3) -> Vec3 {
    let to_center = sphere.center - p;
    (to_center.length() - sphere.radius).min(0.0) * to_center.normalize_or_zero()
}

/// Sphere collisions at the tip and the curve midpoint (SPEC §3.7). Adds the squared
/// displacements to η and returns whether the blade moved.
pub fn collide(blade: &mut Blade, eta: &mut f32, colliders: &[Collider]) -> bool {
    let mut moved = false;
    for sphere in colliders {
        if (blade.root() - sphere.center).length() - sphere.radius >= blade.height() {
            continue;
        }
        let d_tip = push_out(sphere, blade.tip());
        let d_mid = 4.0 * push_out(sphere, blade.midpoint());
        let d = d_tip + d_mid;
        if d != Vec3::ZERO {
            blade.v2 = (blade.tip() + d).extend(blade.width());
            *eta += d_tip.length_squared() + d_mid.length_squared();
            moved = true;
        }
    }
    moved
}

/// Fixed-step clock: turns wall-clock frame times into whole simulation steps (SPEC §3.8), so
/// results do not depend on frame rate and a long frame never feeds a huge Δt to the model.
#[derive(Clone, Debug, Default)]
pub struct SimClock {
    /// Simulated time of the next step.
    pub time: f32,
    backlog: f32,
}

impl SimClock {
    /// Advance by `frame_seconds`; returns how many steps to run now (≤ `max_substeps`) and the
    /// simulated time of the first. Time that cannot be caught up is dropped.
    pub fn advance(&mut self, frame_seconds: f32, params: &SimParams) -> (u32, f32) {
        self.backlog += frame_seconds.max(0.0);
        let wanted = (self.backlog / params.step).floor() as u32;
        let steps = wanted.min(params.max_substeps);
        self.backlog = if wanted > steps {
            0.0
        } else {
            self.backlog - steps as f32 * params.step
        };
        let start = self.time;
        self.time += steps as f32 * params.step;
        (steps, start)
    }
}

/// Run `steps` fixed steps over a whole field, starting at time `t0` (the CPU reference).
pub fn simulate(
    blades: &mut [Blade],
    etas: &mut [f32],
    params: &SimParams,
    colliders: &[Collider],
    wind: &[Wind],
    t0: f32,
    steps: u32,
) {
    for k in 0..steps {
        let t = t0 + k as f32 * params.step;
        for (blade, eta) in blades.iter_mut().zip(etas.iter_mut()) {
            step_blade(blade, eta, params, colliders, wind, t);
        }
    }
}

impl Validate for SimParams {
    fn validate(&self, c: &mut Checks) {
        c.check(
            self.step > 0.0 && self.step <= 0.05,
            "simulation.step",
            self.step,
            "a step in seconds in (0, 0.05]",
        );
        c.check(
            (1..=64).contains(&self.max_substeps),
            "simulation.max_substeps",
            self.max_substeps,
            "1 to 64",
        );
        c.non_negative("simulation.gravity_strength", self.gravity_strength);
        c.check(
            self.gravity_direction.length() > 1e-6 && self.gravity_direction.is_finite(),
            "simulation.gravity_direction",
            self.gravity_direction,
            "a non-zero direction",
        );
        c.check(
            (0.0..=1.0).contains(&self.point_gravity_blend),
            "simulation.point_gravity_blend",
            self.point_gravity_blend,
            "a blend in [0, 1]",
        );
        c.non_negative("simulation.point_gravity_strength", self.point_gravity_strength);
        c.check(
            finite_non_negative(self.eta_decay),
            "simulation.eta_decay",
            self.eta_decay,
            "a finite rate ≥ 0",
        );
    }
}

impl Validate for Collider {
    fn validate(&self, c: &mut Checks) {
        c.check(
            self.radius > 0.0 && self.center.is_finite(),
            "collider.radius",
            self.radius,
            "a positive radius and a finite centre",
        );
        c.check(
            self.path.iter().all(|p| p.is_finite()) && self.speed.is_finite() && self.speed >= 0.0,
            "collider.path",
            self.path.len(),
            "finite path points and a finite speed ≥ 0",
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn upright() -> Blade {
        Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.3, 1.5, 0.1, 10.0)
    }

    /// A blade mown to 0.3 of its 1.5 units stands as a stub no taller than the cut (with the
    /// full forces the stub lay flat: its tip 0.0 above the ground), keeps its own height, and
    /// grows back to stand as the uncut blade does once the cut grows past it.
    #[test]
    fn a_mown_blade_stands_as_a_stub_and_grows_back() {
        let params = SimParams {
            step: 1.0 / 60.0,
            ..SimParams::default()
        };
        let wind = [Wind::default()];
        let run = |blade: &mut Blade, cut: f32, steps: u32| {
            let mut eta = 0.0;
            for k in 0..steps {
                step_mown_blade(blade, &mut eta, &params, &[], &wind, k as f32 * params.step, cut);
            }
        };
        let mut blade = upright();
        run(&mut blade, 0.3, 240);
        let stub = blade.tip().y;
        assert!((0.2..=0.3 + 1e-4).contains(&stub), "the stub's tip is {stub} up");
        assert_eq!(blade.height(), 1.5, "the blade keeps its own height");
        let mut uncut = upright();
        run(&mut uncut, 10.0, 480);
        run(&mut blade, 10.0, 480);
        assert!(
            (blade.tip() - uncut.tip()).length() < 0.05,
            "grown back to {}, the uncut blade stands at {}",
            blade.tip(),
            uncut.tip()
        );
    }

    #[test]
    fn gravity_bends_a_blade_and_validation_keeps_its_length() {
        let mut blade = upright();
        let mut eta = 0.0;
        for k in 0..240 {
            step_blade(
                &mut blade,
                &mut eta,
                &SimParams::default(),
                &[],
                &[Wind::calm()],
                k as f32 / 120.0,
            );
        }
        assert!(
            blade.tip().y < 1.5 - 0.1,
            "gravity should bend the blade, tip at {}",
            blade.tip()
        );
        assert!(blade.tip().y > 0.0);
        let approx = {
            let (v0, v1, v2) = (blade.root(), blade.guide(), blade.tip());
            (2.0 * (v2 - v0).length() + (v1 - v0).length() + (v2 - v1).length()) / 3.0
        };
        assert!((approx - 1.5).abs() < 1e-4);
    }

    #[test]
    fn a_sphere_on_the_tip_pushes_it_and_raises_eta() {
        let mut blade = upright();
        let mut eta = 0.0;
        let sphere = Collider::sphere(Vec3::new(0.2, 1.5, 0.0), 0.5);
        assert!(collide(&mut blade, &mut eta, std::slice::from_ref(&sphere)));
        assert!(eta > 0.0);
        assert!(blade.tip().distance(sphere.center) >= 0.5 - 1e-5);
        // A sphere farther than h from the root is skipped by the broad phase.
        let far = Collider::sphere(Vec3::new(5.0, 0.0, 0.0), 1.0);
        let mut eta2 = 0.0;
        assert!(!collide(&mut upright(), &mut eta2, &[far]));
    }

    #[test]
    fn a_collider_loops_along_its_path() {
        let square = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, 1.0), Vec3::Z];
        let ball = Collider {
            path: square.to_vec(),
            speed: 1.0,
            ..Collider::sphere(Vec3::ZERO, 0.5)
        };
        assert!((ball.at(0.5).center - Vec3::new(0.5, 0.0, 0.0)).length() < 1e-5);
        assert!((ball.at(2.5).center - Vec3::new(0.5, 0.0, 1.0)).length() < 1e-5);
        assert!(
            (ball.at(4.25).center - ball.at(0.25).center).length() < 1e-5,
            "the path is a loop"
        );
        assert_eq!(Collider::sphere(Vec3::ONE, 1.0).at(7.0).center, Vec3::ONE);
    }

    #[test]
    fn the_clock_never_runs_more_than_max_substeps() {
        let params = SimParams::default();
        let mut clock = SimClock::default();
        assert_eq!(clock.advance(1.0 / 60.0 + 1e-4, &params).0, 2);
        assert_eq!(clock.advance(10.0, &params).0, params.max_substeps);
        assert_eq!(
            clock.advance(0.0, &params).0,
            0,
            "a long frame's backlog is dropped, not replayed"
        );
    }
}
