//! Footsteps and hiding through the sampler: a walker crosses the prairie and a fox waits in
//! it. Each frame `GrassSampler` asks the grass at their feet, on the CPU: the walker rustles
//! where it walks through standing grass (its steps counted), and the fox is hidden where the
//! grass over it stands taller than its back (it shows red where it is seen, green where the
//! grass hides it). The walker's legs press the grass (`GrassCollider`), and what they
//! pressed is the sampler's too.
//!
//! `cargo run --release -p sward-bevy --example footsteps` (Bevy's own device: any backend).
//! Arrow keys move the fox; Esc quits.
//!
//! `-- --shot OUT.png [--frames N] [--size W H]` draws it headless instead.

#[path = "common/run.rs"]
mod run;

use std::error::Error;

use bevy::prelude::*;
use sward_bevy::{Grass, GrassCollider, GrassLighting, GrassPreset, GrassSampler, GrassSystems};

/// The walker's circle (radius, metres a second) and the fox's back above the ground.
const WALK: (f32, f32) = (6.0, 1.4);
const FOX_BACK: f32 = 0.45;

/// The walker, and the steps it has rustled.
#[derive(Component, Default)]
struct Walker {
    rustles: u32,
    rustling: bool,
}

/// The fox, and whether the grass hides it.
#[derive(Component, Default)]
struct Fox {
    hidden: Option<bool>,
}

/// The fox's colours: seen and hidden.
#[derive(Resource)]
struct FoxLooks {
    seen: Handle<StandardMaterial>,
    hidden: Handle<StandardMaterial>,
}

fn main() -> Result<(), Box<dyn Error>> {
    let mut app = App::new();
    app.insert_resource(ClearColor(Color::srgb(0.62, 0.7, 0.82)))
        .add_systems(Startup, setup)
        .add_systems(Update, (walk, move_fox))
        // After the plugin has sampled this frame's grass and presses.
        .add_systems(PostUpdate, (footsteps, hiding).after(GrassSystems));
    run::run(app)
}

fn setup(mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>, mut materials: ResMut<Assets<StandardMaterial>>) {
    let mut grass = Grass::new(GrassPreset::Prairie.scene()).expect("the prairie preset");
    grass.lighting = GrassLighting::Pbr;
    commands.spawn(grass);
    let mut material = |r: f32, g: f32, b: f32| {
        materials.add(StandardMaterial {
            base_color: Color::srgb(r, g, b),
            perceptual_roughness: 0.9,
            ..default()
        })
    };
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::default().mesh().size(400.0, 400.0))),
        MeshMaterial3d(material(0.22, 0.18, 0.1)),
    ));
    let looks = FoxLooks {
        seen: material(0.9, 0.15, 0.05),
        hidden: material(0.1, 0.7, 0.2),
    };
    // The walker: a capsule whose legs press the grass (spheres along its lower half).
    let legs = (0..4)
        .map(|k| Vec4::new(0.0, 0.15 + 0.2 * k as f32, 0.0, 0.3))
        .collect();
    commands.spawn((
        Walker::default(),
        Mesh3d(meshes.add(Capsule3d::new(0.3, 1.2))),
        MeshMaterial3d(material(0.25, 0.3, 0.6)),
        GrassCollider {
            spheres: legs,
            cuts: false,
        },
        Transform::from_xyz(WALK.0, 0.9, 0.0),
    ));
    commands.spawn((
        Fox::default(),
        Mesh3d(meshes.add(Cuboid::new(0.3, 0.35, 0.8))),
        MeshMaterial3d(looks.seen.clone()),
        Transform::from_xyz(-1.5, FOX_BACK - 0.175, 3.0),
    ));
    commands.insert_resource(looks);
    commands.spawn((
        DirectionalLight {
            illuminance: 25_000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_xyz(-1.0, 2.0, -0.5).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.spawn((
        Camera3d::default(),
        Msaa::Sample4,
        Transform::from_xyz(0.0, 5.0, -10.0).looking_at(Vec3::new(0.0, 0.0, 2.0), Vec3::Y),
    ));
}

/// The walker goes round its circle.
fn walk(time: Res<Time>, mut walker: Single<&mut Transform, With<Walker>>) {
    let (radius, speed) = WALK;
    let angle = time.elapsed_secs() * speed / radius;
    walker.translation = Vec3::new(radius * angle.cos(), 0.9, radius * angle.sin());
}

/// Arrow keys move the fox.
fn move_fox(keys: Res<ButtonInput<KeyCode>>, time: Res<Time>, mut fox: Single<&mut Transform, With<Fox>>) {
    let step = 2.0 * time.delta_secs();
    let along = |key, v: Vec3| if keys.pressed(key) { v * step } else { Vec3::ZERO };
    fox.translation += along(KeyCode::ArrowLeft, Vec3::X)
        + along(KeyCode::ArrowRight, -Vec3::X)
        + along(KeyCode::ArrowUp, Vec3::Z)
        + along(KeyCode::ArrowDown, -Vec3::Z);
}

/// A step rustles where the walker enters standing grass (dense, not yet pressed by it).
fn footsteps(grass: GrassSampler, walker: Single<(&GlobalTransform, &mut Walker)>) {
    let (at, mut walker) = walker.into_inner();
    let Some(here) = grass.at(at.translation()) else {
        return;
    };
    let rustling = here.density > 0.5 && here.height > 0.3 && here.pressed < 0.5;
    if rustling && !walker.rustling {
        walker.rustles += 1;
        info!(
            "rustle {} (grass {:.2} m tall, density {:.2})",
            walker.rustles, here.height, here.density
        );
    }
    walker.rustling = rustling;
}

/// The fox is hidden where the grass over it, as pressed as it is, stands above its back.
fn hiding(
    grass: GrassSampler,
    looks: Res<FoxLooks>,
    fox: Single<(&GlobalTransform, &mut Fox, &mut MeshMaterial3d<StandardMaterial>)>,
) {
    let (at, mut fox, mut look) = fox.into_inner();
    let Some(here) = grass.at(at.translation()) else {
        return;
    };
    let hidden = here.density > 0.3 && here.height * (1.0 - here.pressed) > FOX_BACK;
    if fox.hidden != Some(hidden) {
        info!("the fox is {}", if hidden { "hidden" } else { "seen" });
        fox.hidden = Some(hidden);
        look.0 = if hidden {
            looks.hidden.clone()
        } else {
            looks.seen.clone()
        };
    }
}
