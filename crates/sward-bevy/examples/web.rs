//! Grass in a web page: the same Bevy app a desktop game runs, built for
//! `wasm32-unknown-unknown`, drawing into the page's `<canvas id="grass">` through the browser's
//! WebGPU (compute shaders are needed: WebGL2 draws no grass and says why). A meadow with a
//! ball rolling a loop through it, pressing a trail that stands up again behind it.
//!
//! In a browser: `scripts/web-example.sh OUT_DIR`, then serve OUT_DIR (`python3 -m http.server
//! -d OUT_DIR`) and open its `index.html` in a browser with WebGPU.
//! On the desktop: `cargo run --release -p sward-bevy --example web` (any backend), or
//! `-- --shot OUT.png [--frames N] [--size W H]` headless.

#[path = "common/run.rs"]
mod run;

use std::error::Error;

use bevy::prelude::*;
use sward_bevy::prelude::Scene;
use sward_bevy::{Grass, GrassCollider};

/// The ball's loop: its radius in metres and its turns a second.
const LOOP_RADIUS: f32 = 4.0;
const TURNS: f32 = 0.08;
const BALL_RADIUS: f32 = 1.0;

/// The ball that rolls through the meadow.
#[derive(Component)]
struct Ball;

fn main() -> Result<(), Box<dyn Error>> {
    let mut app = App::new();
    app.insert_resource(ClearColor(Color::srgb(0.62, 0.72, 0.86)))
        .add_systems(Startup, setup)
        .add_systems(Update, roll);
    run::run(app)
}

fn setup(mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>, mut materials: ResMut<Assets<StandardMaterial>>) {
    // sward's default meadow, built in code: a page has no files to read unless it serves them.
    commands.spawn(Grass::new(Scene::default()).expect("the default meadow"));
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::default().mesh().size(200.0, 200.0))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.2, 0.17, 0.1),
            perceptual_roughness: 1.0,
            ..default()
        })),
    ));
    commands.spawn((
        GrassCollider::sphere(BALL_RADIUS),
        Ball,
        Mesh3d(meshes.add(Sphere::new(BALL_RADIUS))),
        MeshMaterial3d(materials.add(Color::srgb(0.9, 0.1, 0.08))),
        Transform::from_xyz(LOOP_RADIUS, BALL_RADIUS, 0.0),
    ));
    commands.spawn((
        DirectionalLight {
            illuminance: 20_000.0,
            ..default()
        },
        Transform::from_xyz(1.0, 3.0, -2.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.spawn((
        Camera3d::default(),
        Transform::from_xyz(0.0, 4.5, -14.0).looking_at(Vec3::new(0.0, 0.5, 0.0), Vec3::Y),
    ));
}

/// The ball rolls its loop.
fn roll(time: Res<Time>, mut ball: Single<&mut Transform, With<Ball>>) {
    let angle = time.elapsed_secs() * TURNS * std::f32::consts::TAU;
    let xz = Vec2::from_angle(angle) * LOOP_RADIUS;
    ball.translation = Vec3::new(xz.x, BALL_RADIUS, xz.y);
}
