//! The meadow as part of Bevy's renderer (`GrassLighting::Pbr`): a low evening sun throws the
//! long shadows of a house and of rocks across the grass, and the grass's own shadow onto the
//! ground; TAA keeps the swaying blades sharp (their motion vectors include the wind), SSAO
//! darkens the roots, fog hazes the distance. The camera circles the house.
//!
//! `cargo run --release -p sward-bevy --example garden`
//!
//! Keys: F switches the camera between forward and deferred rendering, T turns TAA on and off,
//! O turns SSAO on and off, Space stops and starts the camera, Esc quits.
//!
//! `-- --shot OUT.png [--deferred] [--no-taa] [--no-ssao] [--frames N] [--size W H]` draws it
//! headless instead, the camera still (N frames, 240 unless given, at W×H, 1920×1080 unless
//! given) and writes the last frame to OUT.png.

#[path = "common/shot.rs"]
mod shot;

use std::error::Error;
use std::time::Duration;

use bevy::anti_alias::taa::TemporalAntiAliasing;
use bevy::app::AppExit;
use bevy::camera::RenderTarget;
use bevy::core_pipeline::prepass::DeferredPrepass;
use bevy::light::CascadeShadowConfigBuilder;
use bevy::material::OpaqueRendererMethod;
use bevy::pbr::{DefaultOpaqueRendererMethod, ScreenSpaceAmbientOcclusion};
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use sward_bevy::{Grass, GrassCollider, GrassLighting, SwardPlugin};

/// The camera's circle around the house: radius, height, radians per second.
const ORBIT: (f32, f32, f32) = (11.0, 3.2, 0.06);
/// Where on its circle the camera starts (radians from the house's south): the house's sunlit
/// west wall in sight, its shadow reaching toward the camera.
const START: f32 = -0.35;
/// Where the house stands.
const HOUSE: Vec3 = Vec3::new(1.5, 0.0, 2.0);

/// How the camera renders.
#[derive(Resource, Clone, Copy, Debug)]
struct Look {
    deferred: bool,
    taa: bool,
    ssao: bool,
}

/// Whether the camera circles, and how far round it has come.
#[derive(Resource)]
struct Orbit {
    moving: bool,
    angle: f32,
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().collect();
    let has = |name: &str| args.iter().any(|a| a == name);
    let after = |name: &str, k: usize| args.iter().position(|a| a == name).and_then(|i| args.get(i + k));
    let look = Look {
        deferred: has("--deferred"),
        taa: !has("--no-taa"),
        ssao: !has("--no-ssao"),
    };
    let mut app = App::new();
    app.insert_resource(ClearColor(Color::srgb(0.62, 0.68, 0.8)))
        .insert_resource(look)
        .insert_resource(Orbit {
            moving: true,
            angle: START,
        })
        // Bevy reads it when it first prepares a material; F changes each material's own.
        .insert_resource(match look.deferred {
            true => DefaultOpaqueRendererMethod::deferred(),
            false => DefaultOpaqueRendererMethod::forward(),
        })
        .add_systems(Update, (circle, follow_look));
    let Some(out) = after("--shot", 1) else {
        app.add_plugins((DefaultPlugins.set(sward_bevy::render_plugin()?), SwardPlugin::default()))
            .add_systems(
                Startup,
                |commands: Commands, meshes: ResMut<Assets<Mesh>>, materials: ResMut<Assets<StandardMaterial>>| {
                    setup(commands, meshes, materials, None)
                },
            )
            .add_systems(Update, keys);
        app.run();
        return Ok(());
    };
    let number = |name: &str, k: usize| -> Result<Option<u32>, String> {
        after(name, k)
            .map(|v| v.parse().map_err(|_| format!("{name} needs whole numbers, not {v:?}")))
            .transpose()
    };
    let frames = number("--frames", 1)?.unwrap_or(240);
    let size = match (number("--size", 1)?, number("--size", 2)?) {
        (Some(w), Some(h)) if w > 0 && h > 0 => [w, h],
        (None, _) => [1920, 1080],
        _ => return Err("--size needs a width and a height in pixels, both above 0".into()),
    };
    shoot(app, look, (frames, size), out)
}

/// Draw `frames` frames headless at `size` and write the last to `out`.
fn shoot(mut app: App, look: Look, (frames, size): (u32, [u32; 2]), out: &str) -> Result<(), Box<dyn Error>> {
    app.add_plugins((shot::headless_plugins(false)?, SwardPlugin::default()))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(1.0 / 60.0)))
        // A still camera: the picture is the same whatever the frames.
        .insert_resource(Orbit {
            moving: false,
            angle: START,
        });
    let target = shot::target_image(&mut app.world_mut().resource_mut::<Assets<Image>>(), size);
    let into = target.clone();
    app.add_systems(
        Startup,
        move |commands: Commands, meshes: ResMut<Assets<Mesh>>, materials: ResMut<Assets<StandardMaterial>>| {
            setup(commands, meshes, materials, Some(into.clone()))
        },
    );
    app.finish();
    app.cleanup();
    for _ in 0..frames {
        app.update();
    }
    println!("{look:?}");
    shot::shoot(&mut app, target, size, out)
}

/// The meadow (`scenes/meadow.toml` from the working directory, else from the source tree),
/// drawn in Bevy's passes.
fn meadow() -> Result<Grass, sward_core::SceneError> {
    let here = std::path::Path::new("scenes/meadow.toml");
    let mut grass = match here.exists() {
        true => Grass::load(here)?,
        false => Grass::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/meadow.toml"))?,
    };
    grass.lighting = GrassLighting::Pbr;
    Ok(grass)
}

fn setup(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    target: Option<Handle<Image>>,
) {
    commands.spawn(meadow().expect("scenes/meadow.toml"));
    let mut material = |base_color: Color, perceptual_roughness: f32| {
        materials.add(StandardMaterial {
            base_color,
            perceptual_roughness,
            ..default()
        })
    };
    let ground = material(Color::srgb(0.17, 0.21, 0.09), 1.0);
    let plaster = material(Color::srgb(0.82, 0.77, 0.68), 0.9);
    let tiles = material(Color::srgb(0.42, 0.13, 0.08), 0.7);
    let stone = material(Color::srgb(0.46, 0.44, 0.41), 0.85);
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::default().mesh().size(200.0, 200.0))),
        MeshMaterial3d(ground),
    ));
    // The house: its walls mow the grass where they stand; a square beam turned on its edge is
    // the gabled roof.
    let walls = Cuboid::new(3.0, 2.4, 4.0).mesh().build();
    commands.spawn((
        GrassCollider::from_mesh(&walls, 32).expect("a triangle mesh").cutting(),
        Mesh3d(meshes.add(walls)),
        MeshMaterial3d(plaster),
        Transform::from_translation(HOUSE + Vec3::Y * 1.2),
    ));
    commands.spawn((
        Mesh3d(meshes.add(Cuboid::new(2.2, 2.2, 3.96))),
        MeshMaterial3d(tiles),
        Transform::from_translation(HOUSE + Vec3::Y * 2.4)
            .with_rotation(Quat::from_rotation_z(std::f32::consts::FRAC_PI_4)),
    ));
    // Rocks that press the grass around them.
    for (x, z, size) in [(-3.0, -1.0, 0.9), (-1.5, -3.5, 0.6), (4.5, -2.5, 1.1), (-4.5, 3.0, 0.7)] {
        let rock = Sphere::new(0.5).mesh().ico(3).expect("a small icosphere");
        commands.spawn((
            GrassCollider::from_mesh(&rock, 12).expect("a triangle mesh"),
            Mesh3d(meshes.add(rock)),
            MeshMaterial3d(stone.clone()),
            Transform::from_xyz(x, size * 0.25, z).with_scale(Vec3::new(size * 1.3, size * 0.8, size)),
        ));
    }
    // The evening sun, low in the west: long shadows over the field.
    commands.spawn((
        DirectionalLight {
            color: Color::srgb(1.0, 0.84, 0.62),
            illuminance: 12_000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        CascadeShadowConfigBuilder {
            maximum_distance: 40.0,
            first_cascade_far_bound: 8.0,
            ..default()
        }
        .build(),
        Transform::from_xyz(-12.0, 2.6, 12.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    let camera = commands
        .spawn((
            Camera3d::default(),
            bevy::camera::Hdr,
            // TAA and SSAO want no MSAA.
            Msaa::Off,
            DistanceFog {
                color: Color::srgb(0.62, 0.66, 0.74),
                falloff: FogFalloff::Exponential { density: 0.015 },
                ..default()
            },
            Transform::default(),
        ))
        .id();
    if let Some(target) = target {
        commands.entity(camera).insert(RenderTarget::Image(target.into()));
    }
}

/// The camera around the house, looking at it.
fn circle(time: Res<Time>, mut orbit: ResMut<Orbit>, mut camera: Single<&mut Transform, With<Camera3d>>) {
    let (radius, height, speed) = ORBIT;
    if orbit.moving {
        orbit.angle += speed * time.delta_secs();
    }
    let eye = HOUSE + Vec3::new(radius * orbit.angle.sin(), height, -radius * orbit.angle.cos());
    **camera = Transform::from_translation(eye).looking_at(HOUSE + Vec3::Y * 1.2, Vec3::Y);
}

/// F, T, O, Space and Esc.
fn keys(
    pressed: Res<ButtonInput<KeyCode>>,
    mut look: ResMut<Look>,
    mut orbit: ResMut<Orbit>,
    mut exit: MessageWriter<AppExit>,
) {
    if pressed.just_pressed(KeyCode::KeyF) {
        look.deferred = !look.deferred;
    }
    if pressed.just_pressed(KeyCode::KeyT) {
        look.taa = !look.taa;
    }
    if pressed.just_pressed(KeyCode::KeyO) {
        look.ssao = !look.ssao;
    }
    if pressed.just_pressed(KeyCode::Space) {
        orbit.moving = !orbit.moving;
    }
    if pressed.just_pressed(KeyCode::Escape) {
        exit.write(AppExit::Success);
    }
}

/// The camera's TAA, SSAO and deferred prepass, and every material's way of rendering, as
/// `Look` asks.
fn follow_look(
    look: Res<Look>,
    mut commands: Commands,
    camera: Single<Entity, With<Camera3d>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    if !look.is_changed() {
        return;
    }
    let mut camera = commands.entity(*camera);
    match look.taa {
        true => camera.insert(TemporalAntiAliasing::default()),
        false => camera.remove::<TemporalAntiAliasing>(),
    };
    match look.ssao {
        true => camera.insert(ScreenSpaceAmbientOcclusion::default()),
        false => camera.remove::<ScreenSpaceAmbientOcclusion>(),
    };
    match look.deferred {
        true => camera.insert(DeferredPrepass),
        false => camera.remove::<DeferredPrepass>(),
    };
    let method = match look.deferred {
        true => OpaqueRendererMethod::Deferred,
        false => OpaqueRendererMethod::Forward,
    };
    for (_, material) in materials.iter_mut() {
        material.opaque_render_method = method;
    }
    info!(
        "{} rendering, TAA {}, SSAO {}",
        if look.deferred { "deferred" } else { "forward" },
        if look.taa { "on" } else { "off" },
        if look.ssao { "on" } else { "off" }
    );
}
