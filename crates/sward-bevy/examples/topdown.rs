//! Grass under a top-down camera, as a strategy or twin-stick game sees it: the lawn preset from
//! 30 m straight above, eight balls rolling loops through it, each pressing a trail that
//! stands up again slowly behind it.
//!
//! `cargo run --release -p sward-bevy --example topdown` (Bevy's own device: any backend).
//! Arrow keys pan the camera; Esc quits.
//!
//! `-- --shot OUT.png [--frames N] [--size W H]` draws it headless instead.

#[path = "common/run.rs"]
mod run;

use std::error::Error;

use bevy::prelude::*;
use sward_bevy::{Grass, GrassCollider, GrassLighting, GrassPreset};

/// The camera's height over the ground, and its lens (vertical degrees).
const HEIGHT: f32 = 30.0;
const FOV: f32 = 40.0;

/// A ball's loop: its centre, radius and turns a second.
#[derive(Component)]
struct Rolling {
    centre: Vec2,
    radius: f32,
    turns: f32,
}

fn main() -> Result<(), Box<dyn Error>> {
    let mut app = App::new();
    app.insert_resource(ClearColor(Color::srgb(0.62, 0.7, 0.82)))
        .add_systems(Startup, setup)
        .add_systems(Update, (roll, pan));
    run::run(app)
}

fn setup(mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>, mut materials: ResMut<Assets<StandardMaterial>>) {
    let mut scene = GrassPreset::Lawn.scene();
    // Splatted grass is a point a blade, which from high above leaves the ground between the
    // points showing (a level view stacks them): every generated blade within the camera's
    // sight is drawn as a blade instead.
    scene.instanced.splat_distance = scene.instanced.grid.radius;
    let mut grass = Grass::new(scene).expect("the lawn preset, drawn without splats");
    grass.lighting = GrassLighting::Pbr;
    commands.spawn(grass);
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::default().mesh().size(400.0, 400.0))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.12, 0.16, 0.06),
            perceptual_roughness: 1.0,
            ..default()
        })),
    ));
    let ball = meshes.add(Sphere::new(0.6));
    let paint = materials.add(StandardMaterial {
        base_color: Color::srgb(0.85, 0.85, 0.8),
        ..default()
    });
    for k in 0..8 {
        let along = k as f32 / 8.0 * std::f32::consts::TAU;
        commands.spawn((
            Rolling {
                centre: Vec2::from_angle(along) * 5.0,
                radius: 2.0 + (k % 3) as f32,
                turns: 0.05 + 0.02 * (k % 4) as f32,
            },
            GrassCollider::sphere(0.6),
            Mesh3d(ball.clone()),
            MeshMaterial3d(paint.clone()),
            Transform::from_xyz(0.0, 0.5, 0.0),
        ));
    }
    commands.spawn((
        DirectionalLight {
            illuminance: 25_000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_xyz(-1.0, 3.0, -1.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.spawn((
        Camera3d::default(),
        Msaa::Sample4,
        Projection::Perspective(PerspectiveProjection {
            fov: FOV.to_radians(),
            ..default()
        }),
        // Straight down, the world's +z up the screen.
        Transform::from_xyz(0.0, HEIGHT, 0.0).looking_at(Vec3::ZERO, Vec3::Z),
    ));
}

/// Each ball rolls its loop.
fn roll(time: Res<Time>, mut balls: Query<(&Rolling, &mut Transform)>) {
    for (rolling, mut at) in &mut balls {
        let angle = time.elapsed_secs() * rolling.turns * std::f32::consts::TAU;
        let xz = rolling.centre + Vec2::from_angle(angle) * rolling.radius;
        at.translation = Vec3::new(xz.x, 0.5, xz.y);
    }
}

/// The arrow keys pan the camera over the ground.
fn pan(keys: Res<ButtonInput<KeyCode>>, time: Res<Time>, mut camera: Single<&mut Transform, With<Camera3d>>) {
    let step = 10.0 * time.delta_secs();
    let along = |key, v: Vec3| if keys.pressed(key) { v * step } else { Vec3::ZERO };
    camera.translation += along(KeyCode::ArrowLeft, Vec3::X)
        + along(KeyCode::ArrowRight, -Vec3::X)
        + along(KeyCode::ArrowUp, Vec3::Z)
        + along(KeyCode::ArrowDown, -Vec3::Z);
}
