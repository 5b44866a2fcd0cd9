//! sward's open world in a Bevy game, on the device Bevy opens itself (Vulkan, Metal, DX12, a
//! browser's WebGPU: sward's portable passes): the whole level-of-detail chain — the streamed
//! Bezier blades around the eye, the generated grass's four levels, the billboards to the
//! horizon — drawn in Bevy's own passes, lit by Bevy's sun and casting into its cascaded
//! shadow maps, in its prepass with motion vectors so TAA keeps the swaying grass sharp. The
//! camera walks the scene's loop over two kilometres of hills (`scenes/openworld.toml`), 1.2 km
//! a side, at a walker's pace unless told otherwise; the ground is the scene's own terrain as a
//! Bevy mesh the plugin makes (`GrassGround`).
//!
//! `cargo run --release -p sward-bevy --example openworld [-- --speed 10]`
//!
//! Keys: Space stops and starts the walk, S turns the sun's shadows on and off, T turns TAA
//! (and the prepass it needs) on and off, Esc quits.
//!
//! `-- --shot OUT.png [--frames N] [--size W H] [--speed S] [--no-shadows] [--no-prepass]
//! [--no-grass]` draws it headless instead: N frames (240 unless given) at W×H (1920×1080
//! unless given), a sixtieth of a second apart, the camera walking at S metres a second (1.5
//! unless given: 10 runs, 100 flies), and writes the last frame to OUT.png and each frame's
//! period (the wall time of one frame of the app, after a warm-up) as its median and 99th
//! percentile. `--no-grass` hides the grass (its terrain stays): the same frames without it,
//! so that the difference is what the grass costs.

#[path = "common/open_world.rs"]
mod open_world;
#[path = "common/shot.rs"]
mod shot;

use std::error::Error;
use std::time::{Duration, Instant};

use bevy::anti_alias::taa::TemporalAntiAliasing;
use bevy::app::AppExit;
use bevy::core_pipeline::prepass::{DepthPrepass, MotionVectorPrepass};
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use sward_bevy::SwardPlugin;
use sward_core::mesh::HeightGrid;
use sward_core::Scene;

/// How the camera renders and moves.
#[derive(Resource, Clone, Copy, Debug)]
struct Look {
    /// The sun casts into shadow maps (the grass's and the terrain's shadows).
    shadows: bool,
    /// The depth and motion-vector prepass, and TAA on it.
    prepass: bool,
    /// Metres a second along the loop.
    speed: f32,
    /// The grass is drawn (else hidden: the terrain alone).
    grass: bool,
}

/// The walk: whether it goes on, how far along the loop it is (seconds at the scene's pace), and
/// the ground under it.
#[derive(Resource)]
struct Walk {
    moving: bool,
    along: f32,
    ground: Option<HeightGrid>,
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().collect();
    let has = |name: &str| args.iter().any(|a| a == name);
    let after = |name: &str, k: usize| args.iter().position(|a| a == name).and_then(|i| args.get(i + k));
    let speed = match after("--speed", 1) {
        Some(s) => s
            .parse::<f32>()
            .ok()
            .filter(|s| s.is_finite() && *s >= 0.0)
            .ok_or_else(|| format!("--speed needs metres a second (0 or more), not {s:?}"))?,
        None => 1.5,
    };
    let look = Look {
        shadows: !has("--no-shadows"),
        prepass: !has("--no-prepass"),
        speed,
        grass: !has("--no-grass"),
    };
    let scene = open_world::scene()?;
    let ground = scene.surface.mesh(&scene.contents)?;
    let mut app = App::new();
    app.insert_resource(ClearColor(Color::srgb(0.55, 0.66, 0.84)))
        .insert_resource(look)
        .insert_resource(Walk {
            moving: true,
            along: 0.0,
            ground: ground.as_ref().and_then(|g| g.height_grid()),
        })
        .add_systems(Update, (walk, follow_look));
    let Some(out) = after("--shot", 1) else {
        app.add_plugins((DefaultPlugins, SwardPlugin::default()))
            .add_systems(Startup, setup(scene, None, look))
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
    app.add_plugins((shot::headless_plugins(true)?, SwardPlugin::default()))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(1.0 / 60.0)));
    let target = shot::target_image(&mut app.world_mut().resource_mut::<Assets<Image>>(), size);
    app.add_systems(Startup, setup(scene, Some(target.clone()), look));
    app.finish();
    app.cleanup();
    let periods = run_frames(&mut app, frames);
    println!("{look:?}");
    report(&periods);
    shot::shoot(&mut app, target, size, out)
}

/// The grass (hidden where `look` says so), the terrain under it, the sun and the camera (into
/// `target` where headless).
fn setup(
    scene: Scene,
    target: Option<Handle<Image>>,
    look: Look,
) -> impl FnMut(Commands, ResMut<Assets<StandardMaterial>>) {
    move |mut commands, mut materials| {
        open_world::spawn(&mut commands, &mut materials, (&scene, look.grass), target.as_ref());
        commands.insert_resource(Path(scene.clone()));
    }
}

/// The scene whose camera path the walk follows.
#[derive(Resource)]
struct Path(Scene);

/// The camera along the scene's loop, over the ground, at the look's speed.
fn walk(
    time: Res<Time>,
    look: Res<Look>,
    path: Option<Res<Path>>,
    mut walk: ResMut<Walk>,
    mut camera: Single<&mut Transform, With<Camera3d>>,
) {
    let Some(path) = path else { return };
    let scene = &path.0;
    if walk.moving && scene.camera_path.speed > 0.0 {
        // The path's own pace is its speed: scaled to the look's.
        walk.along += time.delta_secs() * look.speed / scene.camera_path.speed;
    }
    let eye = scene
        .camera_path
        .camera_over(&scene.camera, walk.along, walk.ground.as_ref());
    let [p, t] = [eye.position, eye.target].map(|v| Vec3::from_array(v.to_array()));
    **camera = Transform::from_translation(p).looking_at(t, Vec3::Y);
}

/// Space, S, T and Esc.
fn keys(
    pressed: Res<ButtonInput<KeyCode>>,
    mut look: ResMut<Look>,
    mut walk: ResMut<Walk>,
    mut exit: MessageWriter<AppExit>,
) {
    if pressed.just_pressed(KeyCode::Space) {
        walk.moving = !walk.moving;
    }
    if pressed.just_pressed(KeyCode::KeyS) {
        look.shadows = !look.shadows;
    }
    if pressed.just_pressed(KeyCode::KeyT) {
        look.prepass = !look.prepass;
    }
    if pressed.just_pressed(KeyCode::Escape) {
        exit.write(AppExit::Success);
    }
}

/// The sun's shadows, and the camera's prepass and TAA, as `Look` asks.
fn follow_look(
    look: Res<Look>,
    mut commands: Commands,
    camera: Single<Entity, With<Camera3d>>,
    mut suns: Query<&mut DirectionalLight>,
) {
    if !look.is_changed() {
        return;
    }
    for mut sun in &mut suns {
        sun.shadow_maps_enabled = look.shadows;
    }
    let mut camera = commands.entity(*camera);
    match look.prepass {
        // TAA wants no MSAA.
        true => camera.insert((
            Msaa::Off,
            DepthPrepass,
            MotionVectorPrepass,
            TemporalAntiAliasing::default(),
        )),
        false => camera
            .remove::<(DepthPrepass, MotionVectorPrepass, TemporalAntiAliasing)>()
            .insert(Msaa::default()),
    };
    info!(
        "shadows {}, prepass and TAA {}, {} m/s",
        if look.shadows { "on" } else { "off" },
        if look.prepass { "on" } else { "off" },
        look.speed
    );
}

/// Run `frames` frames, each the app's update (its render world's frame included, the GPU's
/// wait where it is the floor), and the wall time of each after the first fifth (the warm-up:
/// pipelines compiled, the streamed window filled).
fn run_frames(app: &mut App, frames: u32) -> Vec<Duration> {
    let warm_up = frames / 5;
    let mut periods = Vec::new();
    for k in 0..frames {
        let start = Instant::now();
        app.update();
        if k >= warm_up {
            periods.push(start.elapsed());
        }
    }
    periods
}

/// The frame periods' median and 99th percentile, in milliseconds.
fn report(periods: &[Duration]) {
    let mut ms: Vec<f64> = periods.iter().map(|d| d.as_secs_f64() * 1e3).collect();
    if ms.is_empty() {
        return;
    }
    ms.sort_by(f64::total_cmp);
    let at = |q: f64| ms[((ms.len() - 1) as f64 * q).round() as usize];
    println!(
        "frame period over {} frames: median {:.2} ms, p99 {:.2} ms",
        ms.len(),
        at(0.5),
        at(0.99)
    );
}
