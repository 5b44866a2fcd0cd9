//! The streamed field (`sward_core::stream`): the blades the GPU makes for a tile entering the
//! window are the CPU reference's, on the plane and on terrain; a trail pressed, walked away from
//! (its tiles reused for others) and come back to is still there; ten kilometres from the
//! world's origin the blades are the reference's to a hair, walk without jitter and look as
//! they do at home.

mod common;
#[path = "common/repaint.rs"]
mod repaint;

use glam::{DVec3, Vec2, Vec3};
use sward_core::field::Surface;
use sward_core::mesh::Mesh;
use sward_core::stream::{tile_blades, StreamWindow, ORIGIN_STEP, TILE_CELLS};
use sward_core::{Blade, Collider, Scene};
use sward_gpu::renderer::Passes;
use sward_gpu::Headless;

use common::{assert_validation_clean, context};
use repaint::streamed;

/// Every slot's blades as the CPU reference makes the tile the slot holds around `eye`.
fn reference(scene: &Scene, eye: Vec3, ground: Option<&Mesh>) -> Vec<Blade> {
    let window = scene.stream_window().unwrap();
    let grid = ground.and_then(Mesh::height_grid);
    let base = window.base(eye);
    (0..window.tiles * window.tiles)
        .flat_map(|slot| {
            tile_blades(
                window.tile_in(slot, base),
                &scene.instanced,
                scene.field.stiffness,
                grid.as_ref(),
            )
        })
        .collect()
}

/// The attributes physics never changes (root, orientation, height, width, up, stiffness) of
/// `gpu` and `cpu` agree to a hair (the noise's sines and cosines differ by rounding between
/// the two); the moving control points are finite and the blade no farther from its root than
/// it is long and bent.
fn assert_same_blades(gpu: &[Blade], cpu: &[Blade], what: &str) {
    assert_eq!(gpu.len(), cpu.len());
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * (1.0 + b.abs());
    for (i, (g, c)) in gpu.iter().zip(cpu).enumerate() {
        let same = (0..4).all(|k| close(g.v0[k], c.v0[k]) && close(g.up[k], c.up[k]))
            && close(g.height(), c.height())
            && close(g.width(), c.width());
        assert!(same, "{what}: blade {i} is {g:?} on the GPU, {c:?} by the reference");
        let reach = g.tip().distance(g.root());
        assert!(
            g.tip().is_finite() && g.guide().is_finite() && reach <= 2.0 * g.height() + 1e-4,
            "{what}: blade {i} is not a blade of its height: {g:?}"
        );
    }
}

#[test]
fn gpu_made_tiles_hold_the_blades_of_the_cpu_reference() {
    let ctx = context();
    let terrain = Surface::Terrain {
        size: Vec2::splat(60.0),
        height: 5.0,
        resolution: 48,
        seed: 4,
    };
    for (surface, what) in [(Surface::Plane, "plane"), (terrain, "terrain")] {
        let mut scene = streamed(surface);
        let field = scene.grow_field().unwrap();
        assert_eq!(field.blades.len() as u32, scene.bezier_blades());
        let mut headless = Headless::new(&ctx, 64, 48, None).unwrap();
        headless.renderer.upload(&field).unwrap();
        headless.renderer.upload_ground(field.ground.as_ref()).unwrap();
        // Two places: the window's first tiles, then the eye 1.6 tiles on (a column and a row
        // of tiles enter, the rest stay as they were).
        for eye in [scene.camera.position, scene.camera.position + Vec3::new(13.0, 0.0, 9.0)] {
            scene.camera.position = eye;
            let desc = headless.frame(&scene, field.size, (0.0, 0));
            headless.renderer.run_compute(&desc, Passes::SIMULATE).unwrap();
            let gpu = headless.renderer.read_blades().unwrap();
            assert_same_blades(&gpu, &reference(&scene, eye, field.ground.as_ref()), what);
        }
    }
    assert_validation_clean(&ctx);
}

/// The ids of the blades whose roots lie within `radius` of `at` (ground plane distance).
fn near(blades: &[Blade], at: Vec2, radius: f32) -> Vec<usize> {
    (0..blades.len())
        .filter(|&i| blades[i].height() > 0.0 && Vec2::new(blades[i].v0.x, blades[i].v0.z).distance(at) < radius)
        .collect()
}

/// How far, on average, the tips of blades `ids` stand above their roots, as a share of height.
fn standing(blades: &[Blade], ids: &[usize]) -> f32 {
    let sum: f32 = ids
        .iter()
        .map(|&i| (blades[i].v2.y - blades[i].v0.y) / blades[i].height())
        .sum();
    sum / ids.len().max(1) as f32
}

#[test]
fn a_trail_walked_away_from_and_come_back_to_is_still_there() {
    let ctx = context();
    let mut scene = streamed(Surface::Plane);
    scene.simulation.eta_decay = 0.02;
    let trail = Vec2::new(2.0, 3.0);
    scene.colliders = vec![Collider::sphere(Vec3::new(trail.x, 0.3, trail.y), 0.9)];
    let field = scene.grow_field().unwrap();
    let mut headless = Headless::new(&ctx, 64, 48, None).unwrap();
    headless.renderer.upload(&field).unwrap();
    headless.simulate(&scene, field.size, 0, 60).unwrap();
    let pressed = headless.renderer.read_blades().unwrap();
    let (at_trail, aside) = (
        near(&pressed, trail, 0.5),
        near(&pressed, trail + Vec2::new(4.0, 0.0), 0.5),
    );
    assert!(at_trail.len() > 20 && aside.len() > 20);
    let (down, up) = (standing(&pressed, &at_trail), standing(&pressed, &aside));
    assert!(down < 0.5 * up, "the ball pressed nothing: {down} against {up}");

    // Away (the ball gone): the window's tiles are made anew for the ground 40 units on.
    scene.colliders.clear();
    let home = scene.camera.position;
    scene.camera.position = home + Vec3::new(40.0, 0.0, 0.0);
    scene.camera.target += Vec3::new(40.0, 0.0, 0.0);
    headless.simulate(&scene, field.size, 60, 30).unwrap();
    let away = headless.renderer.read_blades().unwrap();
    assert!(near(&away, trail, 3.0).is_empty(), "the trail's tiles were not reused");

    // Back: the tiles are made again, and take the trail from the trample map.
    scene.camera.position = home;
    scene.camera.target -= Vec3::new(40.0, 0.0, 0.0);
    headless.simulate(&scene, field.size, 90, 10).unwrap();
    let back = headless.renderer.read_blades().unwrap();
    let (down_again, up_again) = (
        standing(&back, &near(&back, trail, 0.5)),
        standing(&back, &near(&back, trail + Vec2::new(4.0, 0.0), 0.5)),
    );
    assert!(
        down_again < 0.6 * up_again,
        "the trail is gone: blades there stand {down_again} of their height, beside it {up_again}"
    );
    drop(headless);
    assert_validation_clean(&ctx);
}

/// A stroke painted over a streamed field needs no new field: the tile under it is made again
/// from the new paint (its blades under the stroke mowed), and every other blade, in that tile
/// beyond the stroke's reach or in any other tile, keeps its pose and trail to the bit (against
/// the same steps with no stroke): nothing jolts where the stroke did not paint. (Before a made
/// again tile kept its unchanged blades, 56 of its 3,351 blades beyond the stroke moved their
/// tips by more than a tenth of their height in that frame, one by 0.77.)
#[test]
fn a_stroke_on_a_streamed_field_makes_only_the_tiles_under_it_anew() {
    let ctx = context();
    let scene = repaint::trailed();
    let field = scene.grow_field().unwrap();
    let run = |painted: bool| {
        let mut headless = Headless::new(&ctx, 64, 48, None).unwrap();
        headless.renderer.upload(&field).unwrap();
        headless.simulate(&scene, field.size, 0, 60).unwrap();
        let before = headless.renderer.read_blades().unwrap();
        let mut remade = 0;
        if painted {
            let (paint, added, texel) = repaint::painted(&scene, &field.paint);
            headless.renderer.upload_paint(paint.as_ref()).unwrap();
            remade = headless.renderer.repaint_under(&added, texel);
        }
        headless.simulate(&scene, field.size, 60, 2).unwrap();
        let after = headless.renderer.read_blades().unwrap();
        let etas = headless.renderer.read_etas().unwrap();
        (before, after, etas, remade)
    };
    let (plain_before, plain, plain_etas, _) = run(false);
    let (before, after, etas, remade) = run(true);
    assert_eq!(remade, 1, "the stroke lies within one tile");
    assert!(before == plain_before, "the same steps gave other blades");
    repaint::assert_only_the_stroke_changed(&scene, (&plain, &plain_etas), (&after, &etas));
    assert_validation_clean(&ctx);
}

#[test]
fn the_window_holds_the_budget_and_reaches_past_the_hand_over() {
    let scene = streamed(Surface::Plane);
    let window: StreamWindow = scene.stream_window().unwrap();
    assert_eq!(window.tiles, 3);
    assert!(window.reach() >= scene.hand_over());
    let mut short = scene.clone();
    short.field.blades = 4 * TILE_CELLS * TILE_CELLS;
    short.instanced.grid.inner_radius = 20.0;
    let err = short.validate("short.toml").unwrap_err().to_string();
    assert!(err.contains("field.blades") && err.contains("at least"), "{err}");
    let mut huge = scene.clone();
    huge.field.blades = 40_000_000;
    let err = huge.validate("huge.toml").unwrap_err().to_string();
    assert!(err.contains("field.blades") && err.contains("at most"), "{err}");
    let mut planet = scene.clone();
    planet.surface = Surface::Sphere {
        center: Vec3::ZERO,
        radius: 10.0,
    };
    let err = planet.validate("planet.toml").unwrap_err().to_string();
    assert!(err.contains("field.stream"), "{err}");
}

/// Where the far tests stand: ten kilometres out along x and z.
const FAR: Vec3 = Vec3::new(10000.0, 0.0, 10000.0);

/// `scene` with its camera (and target) moved by `by`.
fn moved(scene: &Scene, by: Vec3) -> Scene {
    let mut scene = scene.clone();
    scene.camera.position += by;
    scene.camera.target += by;
    scene
}

/// `blades` measured from the frame origin `origin` (world x, z), as the GPU holds them.
fn from_origin(blades: &[Blade], origin: Vec2) -> Vec<Blade> {
    let by = glam::Vec4::new(origin.x, 0.0, origin.y, 0.0);
    blades
        .iter()
        .map(|b| Blade {
            v0: b.v0 - by,
            v1: b.v1 - by,
            v2: b.v2 - by,
            ..*b
        })
        .collect()
}

#[test]
fn ten_kilometres_out_the_blades_are_the_references_held_around_a_near_origin() {
    let ctx = context();
    let scene = moved(&streamed(Surface::Plane), FAR);
    let field = scene.grow_field().unwrap();
    let mut headless = Headless::new(&ctx, 64, 48, None).unwrap();
    headless.renderer.upload(&field).unwrap();
    let desc = headless.frame(&scene, field.size, (0.0, 0));
    headless.renderer.run_compute(&desc, Passes::SIMULATE).unwrap();
    // The origin moved to the eye's kilometre step: what the GPU holds is small again.
    let origin = headless.renderer.origin();
    assert_eq!(origin, Vec2::splat(10240.0));
    let gpu = headless.renderer.read_blades().unwrap();
    assert!(gpu.iter().all(|b| b.root().abs().max_element() < 300.0));
    let cpu = reference(&scene, scene.camera.position, None);
    assert_same_blades(&gpu, &from_origin(&cpu, origin), "ten kilometres out");
    drop(headless);
    assert_validation_clean(&ctx);
}

/// Every near blade's tip in world coordinates (in f64: the frame origin added back) over
/// `frames` frames of one step each, the eye walking at 1.5 units a second along `way` from
/// `scene`'s camera after 60 steps standing — the blades within four units of the eye's ground
/// point when the walk begins —, and the frame origin of each frame.
fn walked_tips(
    ctx: &std::sync::Arc<sward_gpu::Context>,
    scene: &Scene,
    frames: u32,
    way: Vec3,
) -> (Vec<Vec<DVec3>>, Vec<Vec2>) {
    let field = scene.grow_field().unwrap();
    let mut headless = Headless::new(ctx, 64, 48, None).unwrap();
    headless.renderer.upload(&field).unwrap();
    headless.simulate(scene, field.size, 0, 60).unwrap();
    let start = headless.renderer.read_blades().unwrap();
    let eye = scene.camera.position;
    let origin = headless.renderer.origin();
    let ids = near(&start, Vec2::new(eye.x - origin.x, eye.z - origin.y), 4.0);
    assert!(ids.len() > 1000, "only {} blades near the eye", ids.len());
    let stride = way * 1.5 * scene.simulation.step;
    let mut tips = vec![Vec::new(); ids.len()];
    let mut origins = Vec::new();
    for k in 0..frames {
        let walker = moved(scene, stride * (k + 1) as f32);
        headless.simulate(&walker, field.size, 60 + k as u64, 1).unwrap();
        let blades = headless.renderer.read_blades().unwrap();
        let origin = headless.renderer.origin();
        let from = DVec3::new(origin.x as f64, 0.0, origin.y as f64);
        for (track, &i) in tips.iter_mut().zip(&ids) {
            track.push(blades[i].tip().as_dvec3() + from);
        }
        origins.push(origin);
    }
    (tips, origins)
}

/// How far the tips' steps change from frame to frame (|tip(k+1) − 2 tip(k) + tip(k−1)|): the
/// median and the 99th percentile over every near blade and frame. Wind bends a blade smoothly;
/// positions rounded to what 32-bit floats keep far out move in jerks of that rounding.
fn jerk(tips: &[Vec<DVec3>]) -> (f64, f64) {
    let mut all: Vec<f64> = tips
        .iter()
        .flat_map(|t| t.windows(3).map(|w| (w[2] - 2.0 * w[1] + w[0]).length()))
        .collect();
    all.sort_by(f64::total_cmp);
    (all[all.len() / 2], all[all.len() * 99 / 100])
}

#[test]
fn walking_ten_kilometres_out_and_across_the_origins_step_the_near_blades_move_as_at_home() {
    let ctx = context();
    let home = streamed(Surface::Plane);
    assert!(!home.wind.is_empty(), "the test needs wind to move the blades");
    let (tips, _) = walked_tips(&ctx, &home, 12, Vec3::Z);
    let (home_median, home_p99) = jerk(&tips);
    let (tips, origins) = walked_tips(&ctx, &moved(&home, FAR), 12, Vec3::Z);
    let (far_median, far_p99) = jerk(&tips);
    assert!(origins.iter().all(|&o| o == Vec2::splat(10240.0)), "{origins:?}");
    // From just short of the origin's first step along x to past it: the origin moves mid-walk.
    let short = Vec3::new(ORIGIN_STEP - 0.05 - home.camera.position.x, 0.0, 0.0);
    let (tips, origins) = walked_tips(&ctx, &moved(&home, short), 12, Vec3::X);
    let (across_median, across_p99) = jerk(&tips);
    assert_eq!(origins.first(), Some(&Vec2::ZERO));
    assert_eq!(origins.last(), Some(&Vec2::new(ORIGIN_STEP, 0.0)));
    let mm = |x: f64| 1000.0 * x;
    eprintln!(
        "tip jerk, median and p99 (mm): home {:.4} {:.4}, ten kilometres out {:.4} {:.4}, across the step {:.4} {:.4}",
        mm(home_median),
        mm(home_p99),
        mm(far_median),
        mm(far_p99),
        mm(across_median),
        mm(across_p99)
    );
    assert!(home_median > 1.0e-6, "the wind should move the blades: {home_median}");
    // Other blades in other gusts: alike, not the same. Held in world coordinates (a millimetre
    // is what they keep at ten kilometres) the far tips jerk far more (measured: median ×5.6,
    // p99 ×2.6; with the origin ×1.2 and ×1.1); a blade carried to the new origin wrongly
    // would jump by the step. Tiles enter standing where the physics comes to rest in the
    // wind, so most blades hardly move at all and the median is a few thousandths of a
    // millimetre: where the wind there stirs more of them it may be many times home's
    // (measured: 0.0153 mm ten kilometres out against 0.0012 at home; 0.0042 at home while the
    // tiles entered short of that rest), still under a fifth of home's p99 (rounding far out
    // would jerk by tenths of a millimetre).
    for (what, median, p99) in [
        ("ten kilometres out", far_median, far_p99),
        ("across the origin's step", across_median, across_p99),
    ] {
        assert!(
            p99 < 2.0 * home_p99 && median < (1.8 * home_median).max(0.2 * home_p99),
            "{what} the tips jerk by {median} (median), {p99} (p99); at home {home_median}, {home_p99}"
        );
    }
    assert_validation_clean(&ctx);
}

/// Mean red, green and blue of an RGBA8 image, and the share of its pixels where green leads
/// (grass).
fn picture_statistics(pixels: &[u8]) -> ([f32; 3], f32) {
    let n = (pixels.len() / 4) as f32;
    let mut sum = [0.0f32; 3];
    let mut grass = 0.0;
    for p in pixels.as_chunks::<4>().0.iter() {
        for c in 0..3 {
            sum[c] += p[c] as f32;
        }
        grass += f32::from(p[1] > p[0] && p[1] > p[2]);
    }
    (sum.map(|s| s / n), grass / n)
}

#[test]
fn a_view_ten_kilometres_out_looks_like_the_same_view_at_home() {
    let ctx = context();
    let home = streamed(Surface::Plane);
    let mut stats = Vec::new();
    for scene in [home.clone(), moved(&home, FAR)] {
        let field = scene.grow_field().unwrap();
        let mut headless = Headless::new(&ctx, 160, 120, None).unwrap();
        headless.renderer.upload(&field).unwrap();
        let pixels = headless.render_scene(&scene, field.size, 30).unwrap();
        stats.push(picture_statistics(&pixels));
    }
    let [(home_mean, home_grass), (far_mean, far_grass)] = [stats[0], stats[1]];
    eprintln!("home {home_mean:?} {home_grass}, far {far_mean:?} {far_grass}");
    assert!(home_grass > 0.3, "little grass at home: {home_grass}");
    // Other blades (other cells' hashes) and other clumps: the same kind of picture, not the
    // same pixels.
    for c in 0..3 {
        assert!(
            (home_mean[c] - far_mean[c]).abs() < 6.0,
            "channel {c}: {} at home, {} ten kilometres out",
            home_mean[c],
            far_mean[c]
        );
    }
    assert!(
        (home_grass - far_grass).abs() < 0.05,
        "grass covers {home_grass} at home, {far_grass} far out"
    );
    assert_validation_clean(&ctx);
}
