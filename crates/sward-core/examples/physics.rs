//! sward-core alone, on the CPU, no Vulkan: grow a small field, roll a sphere across it in a
//! breeze, and print every half second how many blades are flattened — while the sphere passes
//! and while they recover after it has gone.
//!
//! `cargo run --release -p sward-core --example physics`

use glam::Vec3;
use sward_core::physics::{simulate, Collider};
use sward_core::{FieldDesc, Scene};

fn main() {
    let scene = Scene {
        field: FieldDesc {
            blades: 4000,
            size: glam::Vec2::new(6.0, 6.0),
            ..FieldDesc::default()
        },
        ..Scene::default()
    };
    let mut field = scene.grow_field().expect("a plane field always grows");
    // Each blade's collision strength η: how hard it was pressed, decaying as it recovers.
    let mut etas = vec![0.0_f32; field.blades.len()];
    let ball = Collider {
        path: vec![Vec3::new(-4.0, 0.3, 0.0), Vec3::new(4.0, 0.3, 0.0)],
        speed: 4.0,
        ..Collider::sphere(Vec3::ZERO, 0.8)
    };
    let params = &scene.simulation;
    let steps_per_report = (0.5 / params.step).round() as u32;
    println!(
        "{} blades; a ball of radius 0.8 rolls across for 2 s, then leaves",
        field.blades.len()
    );
    for report in 1..=12 {
        let t0 = (report - 1) as f32 * steps_per_report as f32 * params.step;
        for k in 0..steps_per_report {
            let t = t0 + k as f32 * params.step;
            // Two seconds of rolling, then the ball is gone and the grass is left to recover.
            let colliders = if t < 2.0 { vec![ball.at(t)] } else { Vec::new() };
            simulate(&mut field.blades, &mut etas, params, &colliders, &scene.wind, t, 1);
        }
        // The ball's track (where it touches the ground and near it) against the rest.
        let in_track = |b: &sward_core::Blade| b.v0.z.abs() < 0.6;
        let (track, rest): (Vec<_>, Vec<_>) = field.blades.iter().partition(|b| in_track(b));
        let share = |blades: &[&sward_core::Blade]| {
            100.0 * blades.iter().filter(|b| is_flattened(b)).count() as f32 / blades.len().max(1) as f32
        };
        let pressed = etas.iter().filter(|&&eta| eta > 0.01).count();
        println!(
            "t = {:4.1} s: {:5.1} % of the {} blades in the ball's track flattened, {:4.1} % elsewhere; {pressed} still remember a collision",
            report as f32 * 0.5,
            share(&track),
            track.len(),
            share(&rest),
        );
    }
}

/// Whether a blade's tip is lower than half its height above its root.
fn is_flattened(blade: &sward_core::Blade) -> bool {
    let up = blade.up.truncate();
    let tip_height = (blade.v2.truncate() - blade.v0.truncate()).dot(up);
    tip_height < 0.5 * blade.v1.w
}
