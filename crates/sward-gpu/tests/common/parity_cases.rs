//! The physics cases both renderers' GPU simulations are held to sward-core's CPU reference
//! with (sward-gpu's parity tests and sward-wgpu's portable ones include this file): random
//! blades, random scenes of forces, winds and spheres, and the blades whose trajectories are too
//! ill-conditioned to compare; random cameras and culling tests.
#![allow(dead_code)]

use glam::Vec3;
use sward_core::cull::CullParams;
use sward_core::physics::{simulate, Collider};
use sward_core::rng::Pcg32;
use sward_core::wind::{Wind, WindKind, Winds};
use sward_core::{physics, Blade, Camera, Scene};

/// How far a GPU's blade may lie from the CPU reference's (relative, `relative_error`).
pub const TOLERANCE: f32 = 1e-3;

pub fn unit(rng: &mut Pcg32) -> Vec3 {
    loop {
        let v = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        if v.length_squared() > 0.05 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

/// Random blades, a quarter of them on tilted ground, some already bent.
pub fn random_blades(rng: &mut Pcg32, count: usize, extent: f32) -> Vec<Blade> {
    (0..count)
        .map(|i| {
            let root = Vec3::new(
                rng.range(-extent, extent),
                rng.range(-0.5, 0.5),
                rng.range(-extent, extent),
            );
            let up = if i % 4 == 0 {
                (Vec3::Y + 0.8 * unit(rng)).normalize_or(Vec3::Y)
            } else {
                Vec3::Y
            };
            let mut blade = Blade::at_rest(
                root,
                up,
                rng.range(0.0, std::f32::consts::TAU),
                rng.range(0.5, 2.5),
                rng.range(0.02, 0.14),
                rng.range(5.0, 40.0),
            );
            if i % 3 == 0 {
                let lean = blade.rest_tip() + unit(rng) * blade.height() * rng.range(0.0, 0.9);
                physics::validate(&mut blade, lean);
            }
            blade
        })
        .collect()
}

/// |gpu − cpu| relative to the CPU value, with magnitudes below 1 compared absolutely.
pub fn relative_error(gpu: f32, cpu: f32) -> f32 {
    (gpu - cpu).abs() / cpu.abs().max(1.0)
}

pub fn random_wind(rng: &mut Pcg32, kind: WindKind) -> Wind {
    Wind {
        kind,
        direction: unit(rng),
        strength: rng.range(2.0, 25.0),
        gust: rng.range(0.0, 1.0),
        gust_frequency: rng.range(0.1, 3.0),
        scale: rng.range(0.05, 1.0),
        speed: rng.range(0.0, 8.0),
        center: Vec3::new(rng.range(-5.0, 5.0), 0.0, rng.range(-5.0, 5.0)),
    }
}

/// A scene with random forces and 12 spheres, blown by the fields `kinds` summed.
pub fn random_scene(rng: &mut Pcg32, kinds: &[WindKind]) -> Scene {
    let mut scene = Scene {
        wind: Winds(kinds.iter().map(|&k| random_wind(rng, k)).collect()),
        ..Scene::default()
    };
    scene.simulation.point_gravity = Vec3::new(rng.range(-10.0, 10.0), 3.0, rng.range(-10.0, 10.0));
    scene.simulation.point_gravity_strength = rng.range(0.0, 10.0);
    scene.simulation.point_gravity_blend = rng.range(0.0, 0.5);
    scene.colliders = (0..12)
        .map(|_| {
            Collider::sphere(
                Vec3::new(rng.range(-6.0, 6.0), rng.range(-0.5, 1.5), rng.range(-6.0, 6.0)),
                rng.range(0.3, 2.0),
            )
        })
        .collect();
    scene
}

/// The largest relative error of a guide, tip or η over the blades not in `chaotic` (those must
/// still be valid blades), with the blade and what it was.
pub fn worst_error(
    gpu: &[Blade],
    gpu_etas: &[f32],
    cpu: &[Blade],
    cpu_etas: &[f32],
    chaotic: &[usize],
) -> (f32, usize, &'static str) {
    let mut worst = (0.0f32, 0usize, "");
    for i in 0..cpu.len() {
        let (g, c) = (&gpu[i], &cpu[i]);
        if chaotic.contains(&i) {
            assert!(
                g.v2.is_finite() && g.up().dot(g.tip() - g.root()) >= -1e-4,
                "blade {i} invalid on the GPU: {g:?}"
            );
            continue;
        }
        let pairs = [
            ("v1", g.v1.to_array(), c.v1.to_array()),
            ("v2", g.v2.to_array(), c.v2.to_array()),
        ];
        for (name, gv, cv) in pairs {
            for k in 0..3 {
                let e = relative_error(gv[k], cv[k]);
                if e > worst.0 || e.is_nan() {
                    worst = (e, i, name);
                }
            }
        }
        let e = relative_error(gpu_etas[i], cpu_etas[i]);
        if e > worst.0 || e.is_nan() {
            worst = (e, i, "eta");
        }
    }
    worst
}

/// Blades whose `steps`-step trajectory a 1e-6 relative nudge of the start (either way) already
/// moves by more than a tenth of the tolerance. A blade pressed into a sphere can oscillate
/// against it chaotically; there the GPU's rounding (fused multiply-adds, its own sin/cos)
/// legitimately ends elsewhere.
pub fn ill_conditioned(start: &[Blade], cpu: &[Blade], scene: &Scene, steps: u32) -> Vec<usize> {
    let nudges = [
        (1.0 + 1e-6, 1.0),
        (1.0 - 1e-6, 1.0),
        (1.0, 1.0 + 1e-6),
        (1.0, 1.0 - 1e-6),
    ];
    let mut chaotic: Vec<usize> = nudges
        .into_iter()
        .flat_map(|(tips, winds)| moved_by_nudge(start, cpu, scene, steps, tips, winds))
        .collect();
    chaotic.sort_unstable();
    chaotic.dedup();
    chaotic
}

/// The blades whose end moves by more than a tenth of the tolerance when their tips start
/// scaled by `tips` and the winds blow scaled by `winds` (a GPU's own sin, cos and log2 round
/// the wind differently at every step).
fn moved_by_nudge(start: &[Blade], cpu: &[Blade], scene: &Scene, steps: u32, tips: f32, winds: f32) -> Vec<usize> {
    let mut nudged = start.to_vec();
    for b in &mut nudged {
        b.v2 = (b.v2.truncate() * tips).extend(b.v2.w);
    }
    let mut wind = scene.wind.clone();
    for w in wind.0.iter_mut() {
        w.strength *= winds;
    }
    let mut etas = vec![0.0; start.len()];
    let sim = &scene.simulation;
    simulate(&mut nudged, &mut etas, sim, &scene.colliders, &wind, 0.0, steps);
    (0..start.len())
        .filter(|&i| {
            let (a, b) = (nudged[i].v2.to_array(), cpu[i].v2.to_array());
            (0..3).any(|k| relative_error(a[k], b[k]) > TOLERANCE / 10.0)
        })
        .collect()
}

/// A random camera over the random blades.
pub fn random_camera(rng: &mut Pcg32) -> Camera {
    let position = Vec3::new(rng.range(-15.0, 15.0), rng.range(0.3, 8.0), rng.range(-15.0, 15.0));
    let target = Vec3::new(rng.range(-5.0, 5.0), rng.range(-1.0, 1.0), rng.range(-5.0, 5.0));
    Camera {
        position,
        target,
        fov_y_degrees: rng.range(30.0, 90.0),
        near: 0.1,
        far: rng.range(20.0, 100.0),
        ..Camera::default()
    }
}

/// Random culling tests and thresholds, occlusion off (the per-blade reference has no depth
/// pyramid).
pub fn random_cull(rng: &mut Pcg32) -> CullParams {
    CullParams {
        orientation: rng.next_f32() < 0.7,
        orientation_threshold: rng.range(0.5, 0.99),
        frustum: rng.next_f32() < 0.7,
        frustum_tolerance: rng.range(0.0, 1.0),
        distance: rng.next_f32() < 0.7,
        distance_levels: 1 + rng.below(150),
        distance_max: rng.range(5.0, 40.0),
        // The per-blade reference has no depth pyramid; occlusion has its own test.
        occlusion: false,
        ..CullParams::default()
    }
}
