//! The GPU passes against sward-core's CPU reference on random input: simulation (forces,
//! validation, collisions, every wind field) and culling (every test, random cameras).

mod common;

use glam::{Vec2, Vec3};
use sward_core::commands::{
    bucket_range, distance_bucket, COMMAND_BUCKETS, COMMAND_SORT_DISPATCH, COMMAND_SPLITS, DISTANCE_BUCKETS,
    STRIP_STRIDE,
};
use sward_core::cull::{cull_blade, cull_blade_loosened, CullVerdict};
use sward_core::gpu::DrawCommand;
use sward_core::physics::{simulate, Collider};
use sward_core::plan::{FrameDecisions, RendererCan};
use sward_core::rng::Pcg32;
use sward_core::wind::{Wind, WindKind, Winds};
use sward_core::FrameDesc;
use sward_core::{Blade, Scene};
use sward_gpu::Passes;

use common::parity_cases::{
    ill_conditioned, random_camera, random_cull, random_scene, relative_error, worst_error, TOLERANCE,
};
use common::{assert_validation_clean, context, random_blades, renderer};

/// Blade count deliberately not a multiple of the workgroup size (the `id < N` guard).
const BLADES: usize = 3001;
const STEPS: u32 = 100;
const STEPS_PER_SUBMIT: u32 = 25;

fn uniforms(scene: &Scene, time: f32, steps: u32) -> FrameDesc {
    FrameDesc::of_scene(scene, Vec2::splat(30.0), (time, steps), [320, 240])
}

#[test]
fn gpu_simulation_matches_the_cpu_reference_for_every_wind() {
    let ctx = context();
    let mut renderer = renderer(&ctx, 0, false);
    // Every field alone, then the four-field maximum summed.
    let combined = [WindKind::Waves, WindKind::Radial, WindKind::Whirl, WindKind::Noise];
    let cases = WindKind::ALL.map(|k| vec![k]).into_iter().chain([combined.to_vec()]);
    for (case, kinds) in cases.enumerate() {
        let mut rng = Pcg32::new(100 + case as u64, 3);
        let scene = random_scene(&mut rng, &kinds);
        let start = random_blades(&mut rng, BLADES, 6.0);
        renderer.upload_field(&start, &[]).unwrap();
        let mut done = 0;
        while done < STEPS {
            let u = uniforms(&scene, done as f32 * scene.simulation.step, STEPS_PER_SUBMIT);
            renderer.run_compute(&u, Passes::SIMULATE).unwrap();
            done += STEPS_PER_SUBMIT;
        }
        let gpu_blades = renderer.read_blades().unwrap();
        let gpu_etas = renderer.read_etas().unwrap();

        let mut cpu_blades = start.clone();
        let mut cpu_etas = vec![0.0; BLADES];
        simulate(
            &mut cpu_blades,
            &mut cpu_etas,
            &scene.simulation,
            &scene.colliders,
            &scene.wind,
            0.0,
            STEPS,
        );

        let chaotic = ill_conditioned(&start, &cpu_blades, &scene, STEPS);
        assert!(
            chaotic.len() < BLADES / 50,
            "{kinds:?}: {} of {BLADES} trajectories are ill-conditioned",
            chaotic.len()
        );
        let trampled = cpu_etas.iter().filter(|e| **e > 0.0).count();
        assert!(
            trampled > 20,
            "{kinds:?}: the colliders should trample some blades, trampled {trampled}"
        );
        let moved = cpu_blades
            .iter()
            .zip(&start)
            .filter(|(a, b)| a.tip().distance(b.tip()) > 0.01)
            .count();
        assert!(moved > BLADES / 2, "{kinds:?}: forces should move most blades");
        let worst = worst_error(&gpu_blades, &gpu_etas, &cpu_blades, &cpu_etas, &chaotic);
        let (err, i, what) = worst;
        assert!(
            err <= TOLERANCE,
            "{kinds:?}: blade {i} {what} differs by {err:e} (GPU {:?} η {} vs CPU {:?} η {})",
            gpu_blades[i],
            gpu_etas[i],
            cpu_blades[i],
            cpu_etas[i]
        );
    }
    assert_validation_clean(&ctx);
}

#[test]
fn gpu_culling_matches_the_cpu_reference() {
    let ctx = context();
    for (case, patches_per_draw) in [0u32, 0, 0, 1024, 333, 64].into_iter().enumerate() {
        let mut renderer = renderer(&ctx, patches_per_draw, false);
        let mut rng = Pcg32::new(900 + case as u64, 5);
        let blades: Vec<Blade> = random_blades(&mut rng, 5003, 12.0);
        renderer.upload_field(&blades, &[]).unwrap();
        for _ in 0..4 {
            let mut scene = Scene {
                camera: random_camera(&mut rng),
                cull: random_cull(&mut rng),
                ..Scene::default()
            };
            scene.simulation.forces.wind = false;
            let u = uniforms(&scene, 0.0, 0);
            renderer.run_compute(&u, Passes::CULL).unwrap();
            let (mut gpu, draws) = renderer.read_visible().unwrap();
            let count = gpu.len();
            check_draw_order(&gpu, &draws, &blades, &u);
            gpu.sort_unstable();
            gpu.dedup();
            assert_eq!(gpu.len(), count, "a blade was appended twice");
            assert_eq!(draws[0].vertex_count as usize, count);
            if patches_per_draw > 0 {
                check_split_commands(&draws[COMMAND_SPLITS as usize..], count, patches_per_draw);
            }

            let eye = scene.camera.position;
            let view_proj = u.camera.view_projection();
            let mut on_threshold = 0;
            let mut gpu_iter = gpu.iter().peekable();
            for (id, blade) in blades.iter().enumerate() {
                let id = id as u32;
                let on_gpu = gpu_iter.next_if_eq(&&id).is_some();
                let loose = cull_blade_loosened(blade, id, eye, &view_proj, &scene.cull, 1e-4) == CullVerdict::Visible;
                let strict =
                    cull_blade_loosened(blade, id, eye, &view_proj, &scene.cull, -1e-4) == CullVerdict::Visible;
                if loose != strict {
                    on_threshold += 1;
                    continue;
                }
                let cpu = cull_blade(blade, id, eye, &view_proj, &scene.cull) == CullVerdict::Visible;
                assert_eq!(
                    on_gpu, cpu,
                    "blade {id} {blade:?}: GPU visible {on_gpu}, CPU {:?} ({:?})",
                    cpu, scene.cull
                );
            }
            assert!(
                on_threshold < blades.len() / 100,
                "{on_threshold} blades within 1e-4 of a threshold"
            );
        }
    }
    assert_validation_clean(&ctx);
}

/// The ordered list is in draw order: each blade lies in the range of its distance bucket (the
/// bucket commands' `first_instance`, `instance_count`), the buckets tile the list nearest first,
/// and each bucket's strip is as long as its segments ask. A blade within 1e-4 of a bucket
/// boundary may fall on either side of it.
fn check_draw_order(ordered: &[u32], draws: &[DrawCommand], blades: &[Blade], u: &FrameDesc) {
    let buckets = &draws[COMMAND_BUCKETS as usize..(COMMAND_BUCKETS + DISTANCE_BUCKETS) as usize];
    let mut start = 0;
    for (k, b) in buckets.iter().enumerate() {
        assert_eq!(
            b.first_instance,
            start,
            "bucket {k} does not start where bucket {} ends",
            k.max(1) - 1
        );
        assert_eq!(
            b.first_vertex,
            k as u32 * STRIP_STRIDE,
            "bucket {k}'s first vertex names it"
        );
        let columns = if u.blades.ridge { 4 } else { 2 };
        assert!(
            b.vertex_count >= columns * 3 && b.vertex_count % columns == 0,
            "bucket {k}: {b:?}"
        );
        start += b.instance_count;
    }
    assert_eq!(start as usize, ordered.len(), "the buckets hold every visible blade");
    let eye = u.camera.eye;
    // The compute route's decisions: the first bucket it splats is the hand-over itself.
    let decided = FrameDecisions::of(
        u,
        RendererCan {
            splat: true,
            route: sward_core::quality::DrawRoute::Compute,
            ..RendererCan::strips()
        },
    );
    let range = bucket_range(decided.lod.far, u.cull.distance_max);
    for (slot, &id) in ordered.iter().enumerate() {
        let dist = blades[id as usize].v0.truncate().distance(eye);
        let lo = distance_bucket(range, dist * (1.0 - 1e-4));
        let hi = distance_bucket(range, dist * (1.0 + 1e-4));
        let within = (lo..=hi).any(|k| {
            let b = buckets[k as usize];
            (b.first_instance..b.first_instance + b.instance_count).contains(&(slot as u32))
        });
        assert!(
            within,
            "blade {id} at {dist} (bucket {lo}..={hi}) sits at slot {slot}, outside its bucket"
        );
    }
    // Within each run the sort pass sorts (order.wesl `order_sort`) nearest first, up to its key's
    // resolution: a 2^13th of a bucket (of x / (1 + x) past the last bucket's start).
    let place = |slot: usize| {
        let dist = blades[ordered[slot] as usize].v0.truncate().distance(eye);
        let f = (dist / range).sqrt() * DISTANCE_BUCKETS as f32;
        let last = (DISTANCE_BUCKETS - 1) as f32;
        if f < last {
            f
        } else {
            last + (f - last) / (1.0 + f - last)
        }
    };
    // It sorts what a rasterizer draws, the buckets before the compute route's splats.
    let sorted = draws[COMMAND_SORT_DISPATCH as usize];
    let splatted_from = buckets[..decided.buckets[1] as usize]
        .iter()
        .map(|b| b.instance_count)
        .sum::<u32>();
    assert_eq!(sorted.first_instance, splatted_from);
    assert_eq!(
        sorted.vertex_count as usize,
        (splatted_from as usize).div_ceil(SORT_RUN)
    );
    for slot in 1..splatted_from as usize {
        if slot % SORT_RUN != 0 {
            assert!(
                place(slot) >= place(slot - 1) - 2.0 / 8191.0,
                "slot {slot} (bucket place {}) is drawn after slot {} ({})",
                place(slot),
                slot - 1,
                place(slot - 1)
            );
        }
    }
}

/// Entries the sort pass sorts together (order.wesl `order_sort`).
const SORT_RUN: usize = 8192;

/// Split commands cover slots 0..count in order, at most `per_draw` patches each.
fn check_split_commands(commands: &[sward_core::gpu::DrawCommand], count: usize, per_draw: u32) {
    let mut covered = 0u32;
    for (k, cmd) in commands.iter().enumerate() {
        if cmd.vertex_count == 0 {
            continue;
        }
        assert_eq!(
            cmd.first_vertex,
            k as u32 * per_draw,
            "command {k} starts at the wrong slot"
        );
        assert_eq!(cmd.instance_count, 1);
        assert!(cmd.vertex_count <= per_draw);
        assert_eq!(cmd.first_vertex, covered, "commands leave a gap before command {k}");
        covered += cmd.vertex_count;
    }
    assert_eq!(
        covered as usize, count,
        "split commands draw {covered} of {count} visible blades"
    );
}

/// The fused simulate+cull pass computes exactly what the two separate passes compute.
#[test]
fn fused_simulate_and_cull_match_the_separate_passes() {
    let ctx = context();
    let mut rng = Pcg32::new(4242, 9);
    let scene = Scene {
        camera: random_camera(&mut rng),
        ..random_scene(&mut rng, &[WindKind::Noise])
    };
    let blades = random_blades(&mut rng, BLADES, 8.0);
    let run = |fused: bool| {
        let mut renderer = renderer(&ctx, 0, fused);
        renderer.upload_field(&blades, &[]).unwrap();
        for k in 0..4 {
            let u = uniforms(&scene, k as f32 * 10.0 * scene.simulation.step, 10);
            renderer
                .run_compute(
                    &u,
                    Passes {
                        simulate: true,
                        cull: true,
                        draw: false,
                    },
                )
                .unwrap();
        }
        let (mut visible, _) = renderer.read_visible().unwrap();
        visible.sort_unstable();
        (renderer.read_blades().unwrap(), renderer.read_etas().unwrap(), visible)
    };
    let (fused, separate) = (run(true), run(false));
    assert!(
        !fused.2.is_empty() && fused.2.len() < BLADES,
        "the camera should see some blades, not all"
    );
    assert_eq!(fused.2, separate.2, "visible sets differ");
    for i in 0..BLADES {
        let (a, b) = (&fused.0[i], &separate.0[i]);
        assert!(
            (a.v2 - b.v2).abs().max_element() < 1e-5 && (a.v1 - b.v1).abs().max_element() < 1e-5,
            "blade {i}"
        );
        assert!((fused.1[i] - separate.1[i]).abs() < 1e-5);
    }
    assert_validation_clean(&ctx);
}

/// Spheres travelling their paths: the GPU places each at the frame's start time, as the CPU
/// reference does frame by frame; the trampled blades agree.
#[test]
fn travelling_colliders_trample_the_same_blades_on_gpu_and_cpu() {
    const FRAMES: u32 = 60;
    let ctx = context();
    let mut rng = Pcg32::new(77, 4);
    let mut scene = Scene {
        wind: Winds(vec![Wind::calm()]),
        ..Scene::default()
    };
    scene.colliders = (0..8)
        .map(|_| {
            let start = Vec3::new(rng.range(-6.0, 6.0), 0.4, rng.range(-6.0, 6.0));
            let path = vec![
                start,
                start + Vec3::new(3.0, 0.0, 0.0),
                start + Vec3::new(3.0, 0.0, 3.0),
            ];
            Collider {
                path,
                speed: 3.0,
                ..Collider::sphere(start, 0.8)
            }
        })
        .collect();
    let start = random_blades(&mut rng, BLADES, 8.0);
    let mut renderer = renderer(&ctx, 0, false);
    renderer.upload_field(&start, &[]).unwrap();
    let cpu_run = |nudge: f32| {
        let mut blades = start.clone();
        for b in &mut blades {
            b.v2 = (b.v2.truncate() * (1.0 + nudge)).extend(b.v2.w);
        }
        let mut etas = vec![0.0; BLADES];
        for k in 0..FRAMES {
            let t = k as f32 * scene.simulation.step;
            let spheres: Vec<Collider> = scene.colliders.iter().map(|c| c.at(t)).collect();
            simulate(&mut blades, &mut etas, &scene.simulation, &spheres, &scene.wind, t, 1);
        }
        (blades, etas)
    };
    for k in 0..FRAMES {
        let u = uniforms(&scene, k as f32 * scene.simulation.step, 1);
        renderer.run_compute(&u, Passes::SIMULATE).unwrap();
    }
    let (gpu, gpu_etas) = (renderer.read_blades().unwrap(), renderer.read_etas().unwrap());
    let (cpu, cpu_etas) = cpu_run(0.0);
    let (nudged, _) = cpu_run(1e-6);
    let trampled = cpu_etas.iter().filter(|e| **e > 0.0).count();
    assert!(
        trampled > 50,
        "the travelling spheres should trample blades, trampled {trampled}"
    );
    let mut compared = 0;
    for i in 0..BLADES {
        let chaotic = (0..3).any(|k| relative_error(nudged[i].v2[k], cpu[i].v2[k]) > TOLERANCE / 10.0);
        if chaotic {
            continue;
        }
        compared += 1;
        for k in 0..3 {
            assert!(
                relative_error(gpu[i].v2[k], cpu[i].v2[k]) <= TOLERANCE,
                "blade {i}: {:?} vs {:?}",
                gpu[i],
                cpu[i]
            );
        }
        assert!(
            relative_error(gpu_etas[i], cpu_etas[i]) <= TOLERANCE,
            "blade {i} η {} vs {}",
            gpu_etas[i],
            cpu_etas[i]
        );
    }
    assert!(compared > BLADES * 98 / 100, "only {compared} well-conditioned blades");
    assert_validation_clean(&ctx);
}
