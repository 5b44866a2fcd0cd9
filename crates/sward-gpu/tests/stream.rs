//! The streamed field (`sward_core::stream`): the blades the GPU makes for a tile entering the
//! window are the CPU reference's, on the plane and on terrain; a trail pressed, walked away from
//! (its tiles reused for others) and come back to is still there.

mod common;

use glam::{Vec2, Vec3};
use sward_core::field::Surface;
use sward_core::instanced::Technique;
use sward_core::mesh::Mesh;
use sward_core::stream::{tile_blades, StreamWindow, TILE_CELLS};
use sward_core::{Blade, Collider, Scene};
use sward_gpu::renderer::Passes;
use sward_gpu::Headless;

use common::{assert_validation_clean, context};

/// A streamed field of 3 × 3 tiles handing over to the instanced grass 6 units from the eye.
fn streamed(surface: Surface) -> Scene {
    let mut scene = Scene {
        technique: Technique::Both,
        surface,
        ..Scene::default()
    };
    scene.field.stream = true;
    scene.field.blades = 9 * TILE_CELLS * TILE_CELLS;
    // Short grass stands under gravity only if stiff.
    scene.field.stiffness = [14.0, 28.0];
    scene.instanced.grid.inner_radius = 6.0;
    scene.instanced.grid.radius = 30.0;
    scene.instanced.lod_distances = [10.0, 15.0, 20.0];
    scene.camera.position = Vec3::new(0.3, 2.0, -0.2);
    scene.camera.target = Vec3::new(0.3, 0.0, 8.0);
    scene.validate("test").unwrap();
    scene
}

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
    let mut planet = scene.clone();
    planet.surface = Surface::Sphere {
        center: Vec3::ZERO,
        radius: 10.0,
    };
    let err = planet.validate("planet.toml").unwrap_err().to_string();
    assert!(err.contains("field.stream"), "{err}");
}
