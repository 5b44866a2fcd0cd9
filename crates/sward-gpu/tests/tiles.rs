//! Tile culling on the GPU: tiles far outside the view keep their blades untouched, tiles just
//! outside are simulated but draw nothing, tiles in view are simulated and drawn.

mod common;

use glam::Vec3;
use sward_core::gpu::{FrameState, FrameUniforms};
use sward_core::tiles::{fate, frustum_planes, TileFate};
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

#[test]
fn tiles_outside_the_view_are_skipped_and_those_beside_it_only_simulated() {
    let ctx = context();
    let scene = scene();
    let field = scene.grow_field().unwrap();
    for fused in [false, true] {
        let mut renderer = renderer(&ctx, 0, fused);
        renderer.upload_field(&field.blades, &field.tiles).unwrap();
        let state = FrameState {
            time: 0.0,
            steps: 30,
            viewport: [320, 240],
            blade_count: field.blades.len() as u32,
            patches_per_draw: 0,
        };
        let uniforms = FrameUniforms::new(&scene, field.size, &state);
        renderer.run_compute(&uniforms, Passes::ALL).unwrap();
        let after = renderer.read_blades().unwrap();
        let (visible, _) = renderer.read_visible().unwrap();
        let mut drawn = vec![false; after.len()];
        visible.iter().for_each(|&id| drawn[id as usize] = true);

        let planes = frustum_planes(&uniforms.view_proj);
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
