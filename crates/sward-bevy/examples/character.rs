//! A character walking through grass with Avian (the `avian` feature): a kinematic capsule moved
//! with W, A, S, D (headless, along a loop) and balls and crates that Avian drops and rolls over
//! the ground, each pressing the grass in its own collider's shape (`GrassFromCollider`): the
//! capsule a row of spheres, a ball one, a crate spheres packed inside it.
//!
//! `cargo run --release -p sward-bevy --features avian --example character` (Bevy's own device).
//! Esc quits.
//!
//! `-- --shot OUT.png [--frames N] [--size W H]` draws it headless instead.

#[path = "common/run.rs"]
mod run;

use std::error::Error;

use avian3d::prelude::*;
use bevy::prelude::*;
use sward_bevy::{GrassFromCollider, GrassLighting, GrassPreset};

/// The character's walking speed (metres a second).
const WALK: f32 = 1.6;

/// The character Avian moves where it is told to.
#[derive(Component)]
struct Character;

fn main() -> Result<(), Box<dyn Error>> {
    let mut app = App::new();
    app.insert_resource(ClearColor(Color::srgb(0.62, 0.7, 0.82)))
        .add_plugins(PhysicsPlugins::default())
        .add_systems(Startup, setup)
        .add_systems(Update, (steer, follow));
    run::run(app)
}

fn setup(mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>, mut materials: ResMut<Assets<StandardMaterial>>) {
    let mut grass = sward_bevy::Grass::new(GrassPreset::Meadow.scene()).expect("the meadow preset");
    grass.lighting = GrassLighting::Pbr;
    commands.spawn(grass);
    let mut material = |r: f32, g: f32, b: f32| {
        materials.add(StandardMaterial {
            base_color: Color::srgb(r, g, b),
            perceptual_roughness: 0.8,
            ..default()
        })
    };
    // The ground, to Avian a half-space that presses no grass.
    commands.spawn((
        RigidBody::Static,
        Collider::half_space(Vec3::Y),
        Mesh3d(meshes.add(Plane3d::default().mesh().size(400.0, 400.0))),
        MeshMaterial3d(material(0.2, 0.16, 0.09)),
    ));
    commands.spawn((
        Character,
        RigidBody::Kinematic,
        Collider::capsule(0.3, 1.1),
        GrassFromCollider::default(),
        Mesh3d(meshes.add(Capsule3d::new(0.3, 1.1))),
        MeshMaterial3d(material(0.25, 0.3, 0.6)),
        Transform::from_xyz(0.0, 0.85, 0.0),
    ));
    // Balls and crates dropped into the grass, rolling and tumbling where they land.
    for k in 0..6 {
        let at = Vec3::new(-3.0 + 1.2 * k as f32, 2.0 + k as f32, 4.0 + (k % 2) as f32);
        let (collider, mesh) = match k % 2 {
            0 => (Collider::sphere(0.4), meshes.add(Sphere::new(0.4))),
            _ => (Collider::cuboid(0.7, 0.7, 0.7), meshes.add(Cuboid::new(0.7, 0.7, 0.7))),
        };
        commands.spawn((
            RigidBody::Dynamic,
            collider,
            LinearVelocity(Vec3::new(0.0, 0.0, -1.5)),
            GrassFromCollider::default(),
            Mesh3d(mesh),
            MeshMaterial3d(material(0.8, 0.55 + 0.05 * k as f32, 0.3)),
            Transform::from_translation(at),
        ));
    }
    commands.spawn((
        DirectionalLight {
            illuminance: 25_000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_xyz(-1.0, 2.0, -1.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.spawn((
        Camera3d::default(),
        Msaa::Sample4,
        Transform::from_xyz(0.0, 3.5, -7.0).looking_at(Vec3::new(0.0, 0.5, 2.0), Vec3::Y),
    ));
}

/// W, A, S, D walk the character; headless, it walks a loop.
fn steer(
    keys: Res<ButtonInput<KeyCode>>,
    time: Res<Time>,
    headless: Res<run::Headless>,
    mut character: Single<&mut LinearVelocity, With<Character>>,
) {
    let along = |key, v: Vec3| if keys.pressed(key) { v } else { Vec3::ZERO };
    let wanted = match headless.0 {
        true => {
            let t = time.elapsed_secs() * 0.4;
            Vec3::new(t.cos(), 0.0, t.sin())
        }
        false => {
            along(KeyCode::KeyW, Vec3::Z)
                + along(KeyCode::KeyS, -Vec3::Z)
                + along(KeyCode::KeyA, Vec3::X)
                + along(KeyCode::KeyD, -Vec3::X)
        }
    };
    character.0 = wanted.normalize_or_zero() * WALK;
}

/// The camera keeps the character in view from behind.
fn follow(
    character: Single<&Transform, With<Character>>,
    mut camera: Single<&mut Transform, (With<Camera3d>, Without<Character>)>,
) {
    let at = character.translation;
    **camera = Transform::from_translation(at + Vec3::new(0.0, 2.7, -6.0)).looking_at(at + Vec3::Z * 2.0, Vec3::Y);
}
