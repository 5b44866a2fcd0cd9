//! Property tests of the SPEC §3 invariants over random blades, winds and colliders.

use glam::Vec3;
use proptest::prelude::*;
use sward_core::physics::{simulate, step_blade, Collider, SimParams};
use sward_core::wind::{Wind, WindKind};
use sward_core::Blade;

fn unit_vector() -> impl Strategy<Value = Vec3> {
    (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0)
        .prop_filter("non-degenerate", |(x, y, z)| x * x + y * y + z * z > 0.01)
        .prop_map(|(x, y, z)| Vec3::new(x, y, z).normalize())
}

fn blade() -> impl Strategy<Value = Blade> {
    (
        (-20.0f32..20.0, -5.0f32..5.0, -20.0f32..20.0),
        unit_vector(),
        0.0f32..std::f32::consts::TAU,
        0.2f32..3.0,
        0.01f32..0.2,
        1.0f32..60.0,
    )
        .prop_map(|((x, y, z), up, theta, h, w, s)| Blade::at_rest(Vec3::new(x, y, z), up, theta, h, w, s))
}

fn wind() -> impl Strategy<Value = Wind> {
    (
        0usize..WindKind::ALL.len(),
        unit_vector(),
        0.0f32..30.0,
        0.0f32..1.0,
        (-10.0f32..10.0, -10.0f32..10.0),
    )
        .prop_map(|(kind, direction, strength, gust, (cx, cz))| Wind {
            kind: WindKind::ALL[kind],
            direction,
            strength,
            gust,
            center: Vec3::new(cx, 0.0, cz),
            ..Wind::default()
        })
}

fn colliders() -> impl Strategy<Value = Vec<Collider>> {
    prop::collection::vec(
        ((-20.0f32..20.0, -3.0f32..4.0, -20.0f32..20.0), 0.1f32..3.0)
            .prop_map(|((x, y, z), radius)| Collider::sphere(Vec3::new(x, y, z), radius)),
        0..6,
    )
}

fn approx_length(b: &Blade) -> f32 {
    let (v0, v1, v2) = (b.root(), b.guide(), b.tip());
    (2.0 * (v2 - v0).length() + (v1 - v0).length() + (v2 - v1).length()) / 3.0
}

proptest! {
    // A fixed seed: the same 256 cases on every run, so CI is reproducible. (The length checked
    // is the model's own estimate (2·L0 + L1)/3; the exact Bezier length differs from it by the
    // estimate's error, up to a third for a folded blade, which SPEC §3 sets aside.)
    #![proptest_config(ProptestConfig {
        cases: 256,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x5eed_6a55),
        ..ProptestConfig::default()
    })]

    #[test]
    fn every_step_keeps_the_blade_finite_above_ground_and_h_long(
        start in blade(), wind in wind(), colliders in colliders(), steps in 1u32..200,
    ) {
        let params = SimParams { step: 1.0 / 120.0, ..SimParams::default() };
        let mut b = start;
        // Colliders placed near this blade so collisions actually happen.
        let near: Vec<Collider> = colliders.iter().map(|c| Collider::sphere(c.center * 0.1 + b.root(), c.radius)).collect();
        let mut eta = 0.0;
        for k in 0..steps {
            step_blade(&mut b, &mut eta, &params, &near, std::slice::from_ref(&wind), k as f32 * params.step);
            prop_assert!(b.v1.is_finite() && b.v2.is_finite() && eta.is_finite(), "NaN/Inf at step {}: {:?}", k, b);
            let above = b.up().dot(b.tip() - b.root());
            prop_assert!(above >= -1e-4 * b.height(), "tip below ground by {} at step {}", above, k);
            let l = approx_length(&b);
            prop_assert!((l - b.height()).abs() <= 0.01 * b.height(), "length {} vs h {}", l, b.height());
        }
    }

    #[test]
    fn without_wind_or_colliders_a_blade_settles_and_stays(start in blade()) {
        let params = SimParams::default();
        let calm = [Wind::calm()];
        let mut blades = vec![start];
        let mut etas = vec![0.0];
        simulate(&mut blades, &mut etas, &params, &[], &calm, 0.0, 3000);
        let settled = blades[0];
        simulate(&mut blades, &mut etas, &params, &[], &calm, 25.0, 120);
        let moved = settled.tip().distance(blades[0].tip());
        prop_assert!(moved < 1e-3 * settled.height(), "tip still moving by {} after settling", moved);
        prop_assert!(blades[0].up().dot(blades[0].tip() - blades[0].root()) >= -1e-5);
    }

    #[test]
    fn trampled_grass_recovers_as_eta_decays(start in blade()) {
        let params = SimParams { gravity_strength: 0.0, ..SimParams::default() };
        let mut b = start;
        let mut eta = 0.0;
        // A sphere sitting on the blade's tip pushes it over and builds up η.
        let sphere = Collider::sphere(b.rest_tip() + b.up() * 0.2 * b.height(), 0.5 * b.height());
        for k in 0..60 {
            step_blade(&mut b, &mut eta, &params, std::slice::from_ref(&sphere), &[Wind::calm()], k as f32 * params.step);
        }
        let trampled = b.tip().distance(b.rest_tip());
        prop_assert!(trampled > 0.05 * b.height());
        prop_assert!(eta > 0.0);
        // η decays linearly; once it is gone, recovery needs a few more seconds.
        let steps = (eta / (params.eta_decay * params.step)).ceil() as u32 + 2000;
        for k in 0..steps {
            step_blade(&mut b, &mut eta, &params, &[], &[Wind::calm()], k as f32 * params.step);
        }
        prop_assert!(eta == 0.0);
        prop_assert!(b.tip().distance(b.rest_tip()) < 0.02 * b.height(), "did not recover: {}", b.tip().distance(b.rest_tip()));
    }
}
