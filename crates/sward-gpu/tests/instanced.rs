//! The instanced field against its CPU reference: the same patches, the same blades from the same
//! cell hashes, the same bounding-sphere and distance culling, hence the same number of visible
//! blades per level of detail (blades within rounding of a threshold aside).

mod common;

use glam::{IVec2, Vec2, Vec3};
use sward_core::gpu::{FrameState, FrameUniforms};
use sward_core::instanced::{
    blade_at, lod_of, patches, splatted, InstancedParams, Technique, PATCH_CELLS, SPLAT_LEVEL,
};
use sward_core::mesh::{HeightGrid, Mesh};
use sward_core::tiles::frustum_planes;
use sward_core::{Camera, Scene};
use sward_gpu::Passes;

use common::{assert_validation_clean, context, renderer};

fn scene(camera: Camera, params: InstancedParams) -> Scene {
    Scene {
        technique: Technique::Instanced,
        instanced: params,
        camera,
        ..Scene::default()
    }
}

/// Blades per level, the splatted ones last.
type Counts = [u32; SPLAT_LEVEL + 1];

/// Per level: blades the CPU reference keeps, and blades whose decision a rounding could flip.
fn cpu_counts(scene: &Scene, uniforms: &FrameUniforms, ground: Option<&HeightGrid>) -> (Counts, u32) {
    let p = &scene.instanced;
    let eye = scene.camera.position;
    let planes = frustum_planes(&uniforms.view_proj);
    let mut counts = [0; SPLAT_LEVEL + 1];
    let mut ambiguous = 0;
    for patch in patches(&uniforms.view_proj, eye, p, ground) {
        for k in 0..PATCH_CELLS * PATCH_CELLS {
            let cell = patch * PATCH_CELLS + IVec2::new(k % PATCH_CELLS, k / PATCH_CELLS);
            let blade = blade_at(cell, p, ground);
            if let Some(lod) = lod_of(&blade, eye, &planes, p) {
                counts[lod] += 1;
            }
            let dist = (blade.root - eye).length();
            let near_threshold = [
                p.lod_distances[0],
                p.lod_distances[1],
                p.lod_distances[2],
                p.radius,
                p.inner_radius,
            ]
            .iter()
            .any(|d| (dist - d).abs() < 1e-3 * d.max(1.0))
                || splatted(dist * 0.999, blade.hash, p.splat_distance)
                    != splatted(dist * 1.001, blade.hash, p.splat_distance);
            let center = blade.root + Vec3::Y * (0.5 * blade.height);
            let radius = 0.5 * blade.height * (1.0 + p.bend + p.sway) + blade.width;
            let near_plane = planes
                .iter()
                .any(|pl| (pl.truncate().dot(center) + pl.w + radius).abs() < 1e-3);
            ambiguous += (near_threshold || near_plane) as u32;
        }
    }
    (counts, ambiguous)
}

#[test]
fn gpu_levels_hold_as_many_blades_as_the_cpu_reference() {
    let ctx = context();
    let mut renderer = renderer(&ctx, 0, true);
    // Rolling terrain 80 units across: the blades stand on its triangles.
    let terrain = Mesh::terrain(Vec2::splat(80.0), 6.0, 64, 3);
    let grid = terrain.height_grid().expect("a terrain is a height grid");
    let views = [
        (Vec3::new(0.0, 1.7, 0.0), Vec3::new(3.0, 0.8, -10.0), 15.0, 0.0, None),
        (Vec3::new(-40.0, 6.0, 25.0), Vec3::new(0.0, 0.0, 0.0), 25.0, 0.0, None),
        // With an inner radius left to the Bezier field (technique `both`).
        (Vec3::new(5.0, 2.5, 5.0), Vec3::new(-5.0, 0.0, -20.0), 8.0, 6.0, None),
        (
            Vec3::new(-10.0, 9.0, 30.0),
            Vec3::new(0.0, 2.0, 0.0),
            12.0,
            0.0,
            Some(&terrain),
        ),
    ];
    for (view, (position, target, density, inner, ground)) in views.into_iter().enumerate() {
        renderer.upload_ground(ground).unwrap();
        let params = InstancedParams {
            density,
            radius: 60.0,
            inner_radius: inner,
            lod_distances: [8.0, 20.0, 35.0],
            splat_distance: 45.0,
            ..InstancedParams::default()
        };
        let camera = Camera {
            position,
            target,
            fov_y_degrees: 50.0,
            ..Camera::default()
        };
        let scene = scene(camera, params);
        let state = FrameState {
            time: 1.0,
            steps: 0,
            viewport: [320, 240],
            blade_count: 0,
            patches_per_draw: 0,
        };
        let uniforms = FrameUniforms::new(&scene, Vec2::splat(30.0), &state);
        renderer.run_compute(&uniforms, Passes::CULL).unwrap();
        let gpu: Vec<u32> = renderer
            .read_instanced_draws()
            .unwrap()
            .iter()
            .map(|d| d.instance_count)
            .collect();
        let (cpu, ambiguous) = cpu_counts(&scene, &uniforms, ground.map(|_| &grid));
        assert!(cpu.iter().sum::<u32>() > 1000, "the view should hold blades: {cpu:?}");
        if view == 0 {
            assert!(cpu.iter().all(|&c| c > 100), "every level should hold blades: {cpu:?}");
        }
        for k in 0..=SPLAT_LEVEL {
            assert!(
                gpu[k].abs_diff(cpu[k]) <= ambiguous,
                "level {k}: GPU {} vs CPU {} blades ({ambiguous} on a threshold) from {position}",
                gpu[k],
                cpu[k]
            );
        }
        let draws = renderer.read_instanced_draws().unwrap();
        assert_eq!(
            draws.iter().map(|d| d.vertex_count).collect::<Vec<_>>(),
            [17, 9, 5, 3, 0]
        );
    }
    assert_validation_clean(&ctx);
}
