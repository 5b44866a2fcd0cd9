//! A Bevy scene in sward's meadow: a ball you roll with W, A, S and D presses a trail through
//! the grass, rocks standing in the field press the grass around them, and Bevy's PBR lights
//! the ball, the rocks and the ground. The camera follows the ball. Esc quits.
//!
//! `cargo run --release -p sward-bevy --example ball [-- --frames N]` (N: quit after N frames)
//!
//! `-- --bench FRAMES [--warm-up N] [--msaa S] [--no-grass] [--pbr [--no-cast] [--prepass]
//! [--deferred]] [--minimap] [--bevy-device] [--out SHOT.png]` draws the meadow
//! headless at 1920×1080 as `sward bench` sees it (the scene's camera, S samples — 4 unless
//! given, as `sward bench`'s `high` —, one fixed step a frame, no ball or rocks) for N warm-up
//! frames (300 unless given) and FRAMES timed ones, and prints the median and 99th
//! percentile of sward's GPU passes, of the host time sward adds to the frame and of Bevy's
//! whole frame (`--no-grass`: the same app without grass, for the frame it costs without).
//! `--pbr` has Bevy draw the grass in its own passes (`GrassLighting::Pbr`), casting into the
//! sun's shadow maps unless `--no-cast`; `--prepass` gives the camera Bevy's depth and
//! motion-vector prepass, `--deferred` makes it a deferred camera (no MSAA); `--minimap` adds a
//! second camera looking down on the field into the image's top right quarter;
//! `--bevy-device` runs on the device Bevy opens itself (sward's portable passes, which Bevy
//! draws in its passes: use it with `--pbr`) instead of the one `render_plugin` opens.

#[path = "ball/bench.rs"]
mod bench;
#[path = "common/shot.rs"]
mod shot;

use bevy::app::AppExit;
use bevy::prelude::*;
use sward_bevy::{Grass, GrassCollider, SwardPlugin};

const BALL_RADIUS: f32 = 0.45;
/// Metres per second the ball rolls at.
const SPEED: f32 = 3.0;

#[derive(Component)]
struct Ball;

/// Quit after this many frames, if given.
#[derive(Resource)]
struct QuitAfter(Option<u32>);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    if let Some(frames) = flag("--bench")? {
        let out = std::env::args().skip_while(|a| a != "--out").nth(1);
        let grass = !std::env::args().any(|a| a == "--no-grass");
        let warm_up = flag("--warm-up")?.unwrap_or(300);
        let msaa = match flag("--msaa")?.unwrap_or(4) {
            1 => Msaa::Off,
            2 => Msaa::Sample2,
            4 => Msaa::Sample4,
            8 => Msaa::Sample8,
            n => return Err(format!("--msaa is 1, 2, 4 or 8 samples, not {n}").into()),
        };
        let has = |name: &str| std::env::args().any(|a| a == name);
        let options = bench::Options {
            msaa,
            grass,
            pbr: has("--pbr"),
            casts: !has("--no-cast"),
            prepass: has("--prepass"),
            deferred: has("--deferred"),
            minimap: has("--minimap"),
            bevy_device: has("--bevy-device"),
        };
        return bench::run([warm_up as usize, frames as usize], options, out);
    }
    let frames = flag("--frames")?;
    App::new()
        .add_plugins((DefaultPlugins.set(sward_bevy::render_plugin()?), SwardPlugin::default()))
        .insert_resource(ClearColor(Color::srgb(0.55, 0.7, 0.9)))
        .insert_resource(QuitAfter(frames))
        .add_systems(Startup, setup)
        .add_systems(Update, (roll, follow, quit))
        .run();
    Ok(())
}

/// The number after `name` on the command line, if it is there.
fn flag(name: &str) -> Result<Option<u32>, String> {
    let Some(value) = std::env::args().skip_while(|a| a != name).nth(1) else {
        return match std::env::args().any(|a| a == name) {
            true => Err(format!("{name} needs a number")),
            false => Ok(None),
        };
    };
    value
        .parse()
        .map(Some)
        .map_err(|_| format!("{name} needs a whole number, not {value:?}"))
}

/// The ground under the grass, lit by Bevy.
fn ground(meshes: &mut Assets<Mesh>, materials: &mut Assets<StandardMaterial>) -> impl Bundle {
    (
        Mesh3d(meshes.add(Plane3d::default().mesh().size(200.0, 200.0))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.16, 0.22, 0.08),
            perceptual_roughness: 1.0,
            ..default()
        })),
    )
}

/// The sun, casting Bevy's shadows.
fn sun() -> impl Bundle {
    (
        DirectionalLight {
            illuminance: 8_000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_xyz(4.0, 8.0, -3.0).looking_at(Vec3::ZERO, Vec3::Y),
    )
}

/// The meadow the example stands in: `scenes/meadow.toml` from the working directory (the
/// repository's root, where a built example is run elsewhere), else from the source tree.
fn meadow() -> Result<Grass, sward_core::SceneError> {
    let here = std::path::Path::new("scenes/meadow.toml");
    match here.exists() {
        true => Grass::load(here),
        false => Grass::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/meadow.toml")),
    }
}

fn setup(mut commands: Commands, mut meshes: ResMut<Assets<Mesh>>, mut materials: ResMut<Assets<StandardMaterial>>) {
    commands.spawn(meadow().expect("scenes/meadow.toml"));
    commands.spawn(ground(&mut meshes, &mut materials));
    commands.spawn(sun());
    // The ball.
    commands.spawn((
        Ball,
        GrassCollider::sphere(BALL_RADIUS),
        Mesh3d(meshes.add(Sphere::new(BALL_RADIUS))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.85, 0.2, 0.1),
            metallic: 0.1,
            perceptual_roughness: 0.4,
            ..default()
        })),
        Transform::from_xyz(0.0, BALL_RADIUS, -6.0),
    ));
    // Rocks standing in the grass, each packed into spheres that press it.
    let rock_material = materials.add(StandardMaterial {
        base_color: Color::srgb(0.45, 0.43, 0.4),
        perceptual_roughness: 0.9,
        ..default()
    });
    for (x, z, size) in [(-3.0, 2.0, 1.2), (2.5, 4.0, 1.6), (4.0, -3.0, 0.9), (-5.0, -2.0, 1.0)] {
        let mesh = Cuboid::new(size, size, size).mesh().build();
        let collider = GrassCollider::from_mesh(&mesh, 24).expect("a triangle mesh");
        commands.spawn((
            collider,
            Mesh3d(meshes.add(mesh)),
            MeshMaterial3d(rock_material.clone()),
            Transform::from_xyz(x, size * 0.4, z).with_rotation(Quat::from_rotation_y(x + z)),
        ));
    }
    commands.spawn((
        Camera3d::default(),
        // HDR: Bevy tonemaps the grass with its meshes after the passes that draw.
        bevy::camera::Hdr,
        // The meadow's haze, on the grass as on the ground and the rocks.
        DistanceFog {
            color: Color::linear_rgb(0.65, 0.75, 0.85),
            falloff: FogFalloff::Exponential { density: 0.01 },
            ..default()
        },
        Transform::from_xyz(0.0, 3.0, -12.0).looking_at(Vec3::new(0.0, 0.0, -6.0), Vec3::Y),
    ));
}

/// W, A, S and D roll the ball over the ground, turning it as it goes.
fn roll(keys: Res<ButtonInput<KeyCode>>, time: Res<Time>, mut ball: Single<&mut Transform, With<Ball>>) {
    let mut direction = Vec3::ZERO;
    for (key, toward) in [
        (KeyCode::KeyW, Vec3::Z),
        (KeyCode::KeyS, -Vec3::Z),
        (KeyCode::KeyA, Vec3::X),
        (KeyCode::KeyD, -Vec3::X),
    ] {
        if keys.pressed(key) {
            direction += toward;
        }
    }
    let step = direction.normalize_or_zero() * SPEED * time.delta_secs();
    ball.translation += step;
    let axis = Vec3::Y.cross(step);
    if axis.length() > 0.0 {
        ball.rotate(Quat::from_axis_angle(axis.normalize(), step.length() / BALL_RADIUS));
    }
}

/// The camera behind and above the ball.
fn follow(
    ball: Single<&Transform, (With<Ball>, Without<Camera3d>)>,
    mut camera: Single<&mut Transform, With<Camera3d>>,
) {
    let target = ball.translation;
    let wanted = target + Vec3::new(0.0, 2.6, -5.5);
    camera.translation = camera.translation.lerp(wanted, 0.08);
    camera.look_at(target, Vec3::Y);
}

fn quit(
    keys: Res<ButtonInput<KeyCode>>,
    quit_after: Res<QuitAfter>,
    mut frames: Local<u32>,
    mut exit: MessageWriter<AppExit>,
) {
    *frames += 1;
    if keys.just_pressed(KeyCode::Escape) || quit_after.0.is_some_and(|n| *frames >= n) {
        exit.write(AppExit::Success);
    }
}
