//! Occlusion culling with the depth pyramid (SPEC §4): a blade wholly behind a wall is culled, one
//! whose tip just clears the wall's top is kept, and blades in front of or beside the wall are kept.

mod common;

use glam::{Vec2, Vec3};
use sward_core::gpu::{FrameState, FrameUniforms};
use sward_core::mesh::Mesh;
use sward_core::scene::Surface;
use sward_core::{Blade, Camera, CullParams, Scene};
use sward_gpu::{Passes, Renderer};

use common::{assert_validation_clean, context, renderer};

/// A wall 6 wide and 5 high (y from -1 to 4) across the view, 10 units ahead of the camera.
fn wall() -> Mesh {
    let positions = vec![
        Vec3::new(-3.0, -1.0, -10.0),
        Vec3::new(3.0, -1.0, -10.0),
        Vec3::new(3.0, 4.0, -10.0),
        Vec3::new(-3.0, 4.0, -10.0),
    ];
    Mesh::new(positions, vec![[0, 1, 2], [0, 2, 3]]).unwrap()
}

fn scene(occlusion: bool) -> Scene {
    Scene {
        // The uniforms then tell the shaders to draw the uploaded mesh as the ground.
        surface: Surface::Mesh {
            path: "wall".into(),
            scale: 1.0,
        },
        camera: Camera {
            position: Vec3::new(0.0, 2.0, 0.0),
            target: Vec3::new(0.0, 2.0, -10.0),
            fov_y_degrees: 50.0,
            near: 0.1,
            far: 100.0,
            ..Camera::default()
        },
        cull: CullParams {
            orientation: false,
            distance: false,
            tiles: false,
            occlusion,
            ..CullParams::default()
        },
        ..Scene::default()
    }
}

fn upright(x: f32, z: f32, height: f32) -> Blade {
    Blade::at_rest(Vec3::new(x, 0.0, z), Vec3::Y, 0.0, height, 0.1, 10.0)
}

/// The ids the cull pass keeps of `blades`, seen by `scene`'s camera.
fn visible(renderer: &mut Renderer, scene: &Scene, blades: &[Blade]) -> Vec<u32> {
    renderer.upload_field(blades, &[]).unwrap();
    renderer.upload_ground(Some(&wall())).unwrap();
    let state = FrameState {
        time: 0.0,
        steps: 0,
        viewport: [320, 240],
        blade_count: blades.len() as u32,
        patches_per_draw: 0,
    };
    let uniforms = FrameUniforms::new(scene, Vec2::splat(30.0), &state);
    renderer.run_compute(&uniforms, Passes::CULL).unwrap();
    let mut ids = renderer.read_visible().unwrap().0;
    ids.sort();
    ids
}

#[test]
fn blades_behind_a_wall_are_culled_and_barely_visible_ones_kept() {
    let ctx = context();
    let mut renderer = renderer(&ctx, 0, false);
    // Seen from (0, 2, 0) over the wall's top edge, at z = -15 everything below y = 5 is hidden.
    let blades = [
        upright(0.0, -15.0, 1.0),  // 0: wholly behind the wall
        upright(1.0, -15.0, 5.6),  // 1: only its tip clears the wall, by 0.6
        upright(0.0, -5.0, 1.0),   // 2: in front of the wall
        upright(6.5, -15.0, 1.0),  // 3: beside the wall
        upright(-1.0, -15.0, 4.8), // 4: tall, but its tip stays 0.2 below the line of sight
    ];
    assert_eq!(visible(&mut renderer, &scene(true), &blades), [1, 2, 3]);
    assert_eq!(visible(&mut renderer, &scene(false), &blades), [0, 1, 2, 3, 4]);
    assert_validation_clean(&ctx);
}
