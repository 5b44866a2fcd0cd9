//! Tile culling on the GPU: tiles far outside the view keep their blades untouched, tiles just
//! outside are simulated but draw nothing, tiles in view are simulated and drawn.

mod common;

use glam::Vec3;
use sward_core::plan::{FrameDecisions, RendererCan};
use sward_core::tiles::{self, fate, frustum_planes, ActiveTile, TileFate};
use sward_core::FrameDesc;
use sward_core::{Camera, FieldDesc, Scene};
use sward_gpu::Passes;

use common::{assert_validation_clean, context, renderer};

fn scene() -> Scene {
    let mut scene = Scene {
        field: FieldDesc {
            blades: 120_000,
            size: glam::Vec2::splat(120.0),
            ..FieldDesc::default()
        },
        camera: Camera {
            position: Vec3::new(0.0, 3.0, 0.0),
            target: Vec3::new(0.0, 1.0, -20.0),
            fov_y_degrees: 50.0,
            ..Camera::default()
        },
        ..Scene::default()
    };
    scene.cull.tile_margin = 8.0;
    scene
}

/// A 320×240 frame of `scene` over `field` at time 0, stepping `steps`.
fn frame(scene: &Scene, field: &sward_core::Field, steps: u32) -> FrameDesc {
    FrameDesc::of_scene(scene, field.size, (0.0, steps), [320, 240])
}

#[test]
fn tiles_outside_the_view_are_skipped_and_those_beside_it_only_simulated() {
    let ctx = context();
    let scene = scene();
    let field = scene.grow_field().unwrap();
    for fused in [false, true] {
        let mut renderer = renderer(&ctx, 0, fused);
        renderer.upload(&field).unwrap();
        let desc = frame(&scene, &field, 30);
        renderer.run_compute(&desc, Passes::ALL).unwrap();
        let after = renderer.read_blades().unwrap();
        let (visible, _) = renderer.read_visible().unwrap();
        let mut drawn = vec![false; after.len()];
        visible.iter().for_each(|&id| drawn[id as usize] = true);

        let planes = frustum_planes(&desc.camera.view_projection());
        let mut seen = [0; 3];
        for tile in &field.tiles {
            let range = tile.first as usize..(tile.first + tile.count) as usize;
            let moved = range
                .clone()
                .filter(|&i| after[i].tip() != field.blades[i].tip())
                .count();
            let shown = range.clone().filter(|&i| drawn[i]).count();
            let f = fate(tile, &planes, scene.cull.tile_margin);
            seen[f as usize] += 1;
            match f {
                TileFate::Skipped => assert!(moved == 0 && shown == 0, "skipped tile ran: {tile:?}"),
                TileFate::Simulated => assert!(
                    moved == range.len() && shown == 0,
                    "margin tile: {moved} moved, {shown} drawn of {}",
                    range.len()
                ),
                TileFate::Drawn => assert!(moved == range.len(), "drawn tile not simulated: {tile:?}"),
            }
        }
        assert!(
            seen.iter().all(|&n| n > 0),
            "every fate should occur: {seen:?} (fused: {fused})"
        );
        assert!(!visible.is_empty());
    }
    assert_validation_clean(&ctx);
}

/// The tiles a frame runs are decided on the GPU (`tile_cull.wesl`): the same tiles with the
/// same fates as the CPU rule `tiles::active`, from cameras inside, above and outside the
/// field, with and without blade shadows stretching the boxes, nearest first.
#[test]
fn the_gpu_decides_the_tiles_the_cpu_rule_does() {
    let ctx = context();
    let mut scene = scene();
    scene.field.blades = 1 << 19;
    scene.field.size = glam::Vec2::splat(300.0);
    let field = scene.grow_field().unwrap();
    let mut renderer = renderer(&ctx, 0, false);
    renderer.upload(&field).unwrap();
    let cameras = [
        (Vec3::new(0.0, 3.0, 0.0), Vec3::new(0.0, 1.0, -20.0)),
        (Vec3::new(40.0, 1.5, -60.0), Vec3::new(-30.0, 0.5, 20.0)),
        (Vec3::new(0.0, 150.0, 10.0), Vec3::new(0.0, 0.0, 0.0)),
        (Vec3::new(-200.0, 20.0, 0.0), Vec3::new(0.0, 0.0, 0.0)),
        (Vec3::new(0.0, 5.0, 400.0), Vec3::new(0.0, 5.0, 800.0)),
    ];
    let mut cases = 0;
    for (k, (position, target)) in cameras.into_iter().enumerate() {
        for casting in [false, true] {
            scene.camera.position = position;
            scene.camera.target = target;
            scene.cull.tile_margin = 4.0 * k as f32;
            scene.shading.blade_shadows = if casting {
                sward_core::look::BladeShadows::On
            } else {
                sward_core::look::BladeShadows::Off
            };
            let desc = frame(&scene, &field, 1);
            renderer.run_compute(&desc, Passes::CULL).unwrap();
            let gpu = renderer.read_active_tiles(0).unwrap();
            let eye = desc.camera.eye;
            let sun = FrameDecisions::of(&desc, RendererCan::strips()).toward_sun(&desc);
            assert_eq!(sun.is_some(), casting, "blade shadows on: {casting}");
            let cpu = tiles::active(
                &field.tiles,
                &desc.camera.view_projection(),
                eye,
                scene.cull.tile_margin,
                true,
                sun,
            );
            let key = |t: &ActiveTile| (t.first, t.count, t.drawn);
            let mut gpu_set: Vec<_> = gpu.iter().map(key).collect();
            let mut cpu_set: Vec<_> = cpu.iter().map(key).collect();
            gpu_set.sort_unstable();
            cpu_set.sort_unstable();
            assert_eq!(gpu_set, cpu_set, "camera {k}, shadows {casting}");
            // Nearest first, in the CPU rule's order (one key, tiles.rs `distance_key`): the
            // portable renderer's host-written list runs the blades in the order this one does.
            let place = |t: &ActiveTile| (t.first, t.drawn);
            let (gpu_order, cpu_order): (Vec<_>, Vec<_>) =
                (gpu.iter().map(place).collect(), cpu.iter().map(place).collect());
            assert_eq!(gpu_order, cpu_order, "camera {k}, shadows {casting}: the tiles' order");
            cases += usize::from(!gpu.is_empty() && gpu.len() < field.tiles.len());
        }
    }
    assert!(cases >= 6, "only {cases} views keep some tiles and leave others out");
    assert_validation_clean(&ctx);
}
