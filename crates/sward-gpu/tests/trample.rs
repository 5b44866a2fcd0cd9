//! The trample map on the GPU against its CPU reference (`sward_core::trample`): the same texels,
//! stamped by the same colliders and recovering at the Bezier blades' rate, as the window follows
//! the eye; and in the picture, colliders that flatten the generated grass where they roll and
//! nowhere else.

mod common;

use glam::{Vec2, Vec3};
use sward_core::instanced::Technique;
use sward_core::physics::Collider;
use sward_core::trample::{TrampleMap, TrampleParams};
use sward_core::FrameDesc;
use sward_core::{Camera, Scene};
use sward_gpu::Passes;

use common::{assert_validation_clean, context, renderer};

fn scene(eye: Vec3, colliders: Vec<Collider>) -> Scene {
    let mut scene = Scene {
        technique: Technique::Instanced,
        camera: Camera {
            position: eye,
            target: eye + Vec3::new(0.0, -1.0, 6.0),
            ..Camera::default()
        },
        colliders,
        trample: TrampleParams {
            enabled: true,
            resolution: 96,
            extent: 24.0,
            regrow: 0.5,
        },
        ..Scene::default()
    };
    scene.simulation.eta_decay = 0.6;
    scene
}

#[test]
fn the_gpu_trample_map_is_the_cpu_references() {
    let ctx = context();
    let mut renderer = renderer(&ctx, 0, false);
    let balls = vec![
        Collider::sphere(Vec3::new(1.0, 0.3, 4.0), 0.6),
        Collider::sphere(Vec3::new(-3.2, 0.9, 7.5), 1.0),
        Collider::sphere(Vec3::new(2.5, 2.5, 2.0), 0.5), // above the grass: presses nothing
        // A cutter mowing down to its underside (0.1 units up at its lowest).
        Collider {
            cut: true,
            clear: false,
            ..Collider::sphere(Vec3::new(-1.0, 1.3, 6.0), 1.2)
        },
    ];
    let mut eye = Vec3::new(0.0, 1.7, 0.0);
    let reference = scene(eye, balls.clone());
    let mut cpu = TrampleMap::new(reference.trample);
    let lowest_cut = |map: &TrampleMap| {
        map.texels
            .iter()
            .map(|t| t.cut)
            .filter(|&c| c > 0.0)
            .fold(f32::MAX, f32::min)
    };
    let mut last_cut = 0.0;
    let grass_top = reference.instanced.grid.height[1].max(reference.billboard.grid.height[1]);
    for frame in 0..12 {
        // The balls press for four frames, then the grass recovers as the eye walks on.
        let colliders = if frame < 4 { balls.clone() } else { Vec::new() };
        let steps = 3;
        let scene = scene(eye, colliders.clone());
        let desc = FrameDesc::of_scene(&scene, Vec2::splat(30.0), (frame as f32 * 0.1, steps), [320, 240]);
        renderer.run_compute(&desc, Passes::SIMULATE).unwrap();
        let dt = steps as f32 * scene.simulation.step;
        cpu.step(eye, &colliders, grass_top, scene.simulation.eta_decay, dt);
        let gpu = renderer.read_trample_map().unwrap();
        assert_eq!(gpu.len(), cpu.texels.len());
        let (mut pressed, mut mown) = (0, 0);
        for (k, (texel, on_gpu)) in cpu.texels.iter().zip(&gpu).enumerate() {
            assert_eq!(texel.tag, on_gpu.tag, "frame {frame}, texel {k}: another cell");
            assert!(
                (texel.push - on_gpu.push).length() < 1e-4,
                "frame {frame}, texel {k}: CPU {} GPU {}",
                texel.push,
                on_gpu.push
            );
            assert!(
                (texel.cut - on_gpu.cut).abs() < 1e-4,
                "frame {frame}, texel {k}: mown to {} on the CPU, {} on the GPU",
                texel.cut,
                on_gpu.cut
            );
            pressed += usize::from(on_gpu.push.length() > 0.05);
            mown += usize::from(on_gpu.cut > 0.0);
        }
        if frame < 4 {
            assert!(pressed > 40, "frame {frame}: only {pressed} texels pressed");
            assert!(mown > 40, "frame {frame}: only {mown} texels mown");
            last_cut = lowest_cut(&cpu);
        }
        eye += Vec3::new(0.9, 0.0, -0.4);
    }
    // Recovered: 0.6 a second over 8 frames of 3 steps — what was not flattened fully is up.
    let left = cpu.texels.iter().filter(|t| t.push.length() > 0.0).count();
    assert!(left < 60, "{left} texels still pressed");
    // Regrowing: 0.5 units a second over the 8 frames of 3 steps since the cutter left.
    let grown = 0.5 * 8.0 * 3.0 * reference.simulation.step;
    let lowest = lowest_cut(&cpu);
    assert!(
        last_cut < 0.25 && (lowest - last_cut - grown).abs() < 1e-3,
        "the lowest cut went from {last_cut} to {lowest}, not up by {grown}"
    );
    assert_validation_clean(&ctx);
}

/// A still frame of the instanced grass after `steps` steps of `scene`.
fn picture(scene: &Scene, steps: u32) -> Vec<u8> {
    let ctx = context();
    let mut headless = sward_gpu::Headless::new(&ctx, 200, 150, None).unwrap();
    let pixels = headless.render_scene(scene, Vec2::splat(30.0), steps).unwrap();
    drop(headless);
    assert_validation_clean(&ctx);
    pixels
}

/// Pixels whose colour differs by more than 24 in some channel.
fn differing(a: &[u8], b: &[u8]) -> usize {
    a.as_chunks::<4>()
        .0
        .iter()
        .zip(b.as_chunks::<4>().0.iter())
        .filter(|(p, q)| (0..3).any(|k| p[k].abs_diff(q[k]) > 24))
        .count()
}

#[test]
fn a_rolling_ball_flattens_the_generated_grass_it_crosses_and_nothing_else() {
    let eye = Vec3::new(0.0, 5.0, 0.0);
    let rolling = Collider {
        center: Vec3::new(-2.0, 0.35, 4.0),
        radius: 0.45,
        path: vec![Vec3::new(-2.0, 0.35, 4.0), Vec3::new(2.0, 0.35, 4.0)],
        speed: 2.0,
        cut: false,
        clear: false,
    };
    let mut with = scene(eye, vec![rolling]);
    with.camera.target = Vec3::new(0.0, 0.0, 4.0);
    let mut without = with.clone();
    without.trample.enabled = false;
    let trampled = picture(&with, 120);
    let untouched = picture(&without, 120);
    if let Ok(dir) = std::env::var("SWARD_TRAMPLE_PICTURES") {
        for (name, px) in [("with", &trampled), ("without", &untouched)] {
            image::save_buffer(format!("{dir}/{name}.png"), px, 200, 150, image::ColorType::Rgba8).unwrap();
        }
    }
    let changed = differing(&trampled, &untouched);
    assert!(changed > 300, "the ball's trail changed only {changed} pixels");
    // Without a collider the map holds nothing, and the picture is the same with it on.
    let mut empty = with.clone();
    empty.colliders.clear();
    let mut empty_off = empty.clone();
    empty_off.trample.enabled = false;
    assert_eq!(differing(&picture(&empty, 120), &picture(&empty_off, 120)), 0);
    // The trail is where the ball rolled: the top third of the picture (far beyond it) is
    // untouched.
    let top = 200 * 4 * 50;
    assert_eq!(
        differing(&trampled[..top], &untouched[..top]),
        0,
        "grass far from the ball moved"
    );
}

/// Bezier blades near the eye, generated blades beyond (technique `both`, bands overlapping
/// from 8 to 9 units from an eye 5 units up). A ball rolls from the near field out across the
/// hand-over while the eye looks the other way — the Bezier blades there are not simulated, so
/// only the trample map sees it pass — then the eye turns: the trail is one band, pressed both
/// sides of the hand-over (the Bezier blades held down by the map as they come into view, the
/// generated ones laid down by it), where the picture without the ball shows upright grass.
#[test]
fn a_trail_crosses_the_hand_over_to_the_generated_grass_without_a_seam() {
    let eye = Vec3::new(0.0, 5.0, 0.0);
    let rolling = Collider {
        center: Vec3::new(0.0, 0.3, 3.0),
        radius: 0.4,
        path: vec![Vec3::new(0.0, 0.3, 3.0), Vec3::new(0.0, 0.3, 13.0)],
        speed: 3.5,
        cut: false,
        clear: false,
    };
    let mut with = scene(eye, vec![rolling]);
    with.technique = Technique::Both;
    with.camera.target = Vec3::new(0.0, 0.0, 8.0);
    with.field = sward_core::FieldDesc {
        // Tiles of about 2 × 2 units, so those the ball crosses lie outside the view looking
        // back.
        blades: 96_000,
        size: Vec2::splat(20.0),
        // As tall as the generated grass.
        height: [0.35, 0.9],
        width: [0.02, 0.04],
        stiffness: [14.0, 28.0],
        ..sward_core::FieldDesc::default()
    };
    with.cull.distance_max = 9.0;
    with.instanced.grid.inner_radius = 8.0;
    with.simulation.eta_decay = 0.1;
    let mut without = with.clone();
    without.colliders.clear();
    // The ball reaches the far end of its path (10 units at 3.5 a second) and is on its way back.
    let steps = 360;
    let [a, b] = [&with, &without].map(|s| {
        let ctx = context();
        let field = s.grow_field().unwrap();
        let mut headless = sward_gpu::Headless::new(&ctx, 200, 150, None).unwrap();
        headless.renderer.upload(&field).unwrap();
        let mut away = s.clone();
        away.camera.target = Vec3::new(0.0, 0.0, -8.0);
        headless.simulate(&away, field.size, 0, steps).unwrap();
        let pixels = headless.render_after(s, field.size, steps as u64, 2).unwrap();
        drop(headless);
        assert_validation_clean(&ctx);
        pixels
    });
    if let Ok(dir) = std::env::var("SWARD_TRAMPLE_PICTURES") {
        for (name, px) in [("seam-with", &a), ("seam-without", &b)] {
            image::save_buffer(format!("{dir}/{name}.png"), px, 200, 150, image::ColorType::Rgba8).unwrap();
        }
    }
    let view_proj = with.camera.view_projection(200.0 / 150.0);
    let pressed_near = |z: f32| {
        let clip = view_proj * Vec3::new(0.0, 0.05, z).extend(1.0);
        let (x, y) = (
            ((clip.x / clip.w * 0.5 + 0.5) * 200.0) as i32,
            ((clip.y / clip.w * 0.5 + 0.5) * 150.0) as i32,
        );
        let mut changed = 0;
        for py in (y - 5).max(0)..(y + 6).min(150) {
            for px in (x - 5).max(0)..(x + 6).min(200) {
                let k = 4 * (py * 200 + px) as usize;
                changed += usize::from((0..3).any(|c| a[k + c].abs_diff(b[k + c]) > 24));
            }
        }
        changed
    };
    // Along the path, every half unit from the Bezier field through the overlap into the generated
    // grass (the hand-over: 6.2–7.5 units out along the ground).
    // (The map's window reaches 12 units out; the path's last units lie beyond it.)
    for z in [5.0, 6.0, 6.5, 7.0, 7.5, 8.0, 8.5, 9.0, 9.5, 10.0] {
        let changed = pressed_near(z);
        assert!(
            changed >= 6,
            "the trail breaks {z} units out: {changed} of 121 pixels differ"
        );
    }
    // Beside the path, two units off, the grass stands as it would without the ball.
    let beside = {
        let clip = view_proj * Vec3::new(2.5, 0.05, 8.0).extend(1.0);
        let (x, y) = (
            ((clip.x / clip.w * 0.5 + 0.5) * 200.0) as usize,
            ((clip.y / clip.w * 0.5 + 0.5) * 150.0) as usize,
        );
        let k = 4 * (y * 200 + x);
        (0..3).map(|c| a[k + c].abs_diff(b[k + c])).max().unwrap()
    };
    assert!(beside <= 24, "grass beside the trail moved: {beside}");
}

/// A Bezier field's blades under a cutter, their tips' heights above their roots: (under the
/// cutter, far from it), the mean of each.
fn tip_heights(blades: &[sward_core::Blade], cutter: Vec3) -> (f32, f32) {
    let mean = |near: bool| {
        let picked: Vec<f32> = blades
            .iter()
            .filter(|b| (Vec2::new(b.v0.x - cutter.x, b.v0.z - cutter.z).length() < 0.3) == near)
            .filter(|b| near || Vec2::new(b.v0.x - cutter.x, b.v0.z - cutter.z).length() > 1.5)
            .map(|b| b.v2.y - b.v0.y)
            .collect();
        assert!(picked.len() > 20, "only {} blades", picked.len());
        picked.iter().sum::<f32>() / picked.len() as f32
    };
    (mean(true), mean(false))
}

/// A cutter over a Bezier field (technique bezier: the map runs for the cutter) mows the blades
/// under it down to its underside — their tips no higher, while blades beyond it stand — and
/// once it is gone they grow back with the cut (`trample.regrow`) to their own height.
#[test]
fn a_cutter_shortens_bezier_blades_and_they_grow_back() {
    let ctx = context();
    let mut renderer = renderer(&ctx, 0, false);
    let cutter = Collider {
        cut: true,
        clear: false,
        // Its underside 0.35 units above the ground.
        ..Collider::sphere(Vec3::new(0.0, 1.15, 1.0), 0.8)
    };
    let mut mowing = scene(Vec3::new(0.0, 2.0, -2.0), vec![cutter.clone()]);
    mowing.technique = Technique::Bezier;
    mowing.field.blades = 8000;
    mowing.field.size = glam::Vec2::new(8.0, 8.0);
    mowing.field.height = [0.9, 1.1];
    mowing.trample.regrow = 1.0;
    // Standing straight (no wind or gravity), so a tip's height is the blade's length.
    mowing.simulation.forces.wind = false;
    mowing.simulation.forces.gravity = false;
    mowing.camera.target = Vec3::new(0.0, 0.0, 1.0);
    let field = mowing.grow_field().unwrap();
    renderer.upload(&field).unwrap();
    let mut grown = mowing.clone();
    grown.colliders.clear();
    let frame = |renderer: &mut sward_gpu::Renderer, scene: &Scene, n: u32| {
        let desc = FrameDesc::of_scene(scene, field.size, (n as f32 * 0.1, 6), [320, 240]);
        renderer.run_compute(&desc, Passes::SIMULATE).unwrap();
    };
    for n in 0..20 {
        frame(&mut renderer, &mowing, n);
    }
    let (under, beyond) = tip_heights(&renderer.read_blades().unwrap(), cutter.center);
    assert!(under < 0.4, "mown blades stand {under} tall");
    assert!(beyond > 0.85, "blades beyond the cutter stand only {beyond} tall");
    // Gone: a unit of height a second grows the cut past the blades in about a second.
    for n in 20..50 {
        frame(&mut renderer, &grown, n);
    }
    let (regrown, beyond) = tip_heights(&renderer.read_blades().unwrap(), cutter.center);
    assert!(
        regrown > 0.85 && (regrown - beyond).abs() < 0.1,
        "grown back to {regrown}, blades beyond stand {beyond}"
    );
    assert_validation_clean(&ctx);
}

/// A cutter rolling over the generated grass mows a strip: against the same scene without the
/// trample map (the sphere and its shadow in both), the picture changes where it went (shorter
/// grass, more ground between the blades) and neither far beyond it nor near the eye.
#[test]
fn a_cutter_mows_a_strip_of_the_generated_grass() {
    let eye = Vec3::new(0.0, 5.0, 0.0);
    // Its underside 0.1 units above the ground, in grass a unit tall.
    let mower = Collider {
        center: Vec3::new(-2.0, 0.9, 4.0),
        radius: 0.8,
        path: vec![Vec3::new(-2.0, 0.9, 4.0), Vec3::new(2.0, 0.9, 4.0)],
        speed: 2.0,
        cut: true,
        clear: false,
    };
    let mut with = scene(eye, vec![mower]);
    with.camera.target = Vec3::new(0.0, 0.0, 4.0);
    with.instanced.grid.height = [0.9, 1.1];
    let mut without = with.clone();
    without.trample.enabled = false;
    let mown = picture(&with, 120);
    let standing = picture(&without, 120);
    if let Ok(dir) = std::env::var("SWARD_TRAMPLE_PICTURES") {
        for (name, px) in [("mown", &mown), ("standing", &standing)] {
            image::save_buffer(format!("{dir}/{name}.png"), px, 200, 150, image::ColorType::Rgba8).unwrap();
        }
    }
    let changed = differing(&mown, &standing);
    assert!(changed > 300, "the cutter's strip changed only {changed} pixels");
    let (far, near) = (200 * 4 * 25, 200 * 4 * 115);
    assert_eq!(
        differing(&mown[..far], &standing[..far]),
        0,
        "grass far beyond the cutter changed"
    );
    assert_eq!(
        differing(&mown[near..], &standing[near..]),
        0,
        "grass near the eye changed"
    );
}
