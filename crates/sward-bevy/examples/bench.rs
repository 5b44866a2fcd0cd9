//! The grass in a Bevy game, timed the way Bevy games time it: the open world's terrain (2 × 2
//! km of hills, `scenes/openworld.toml`) under a sun casting cascaded shadows, sward's whole
//! level-of-detail chain on the device Bevy opens itself, 1920×1080 with Bevy's 4× MSAA, and the
//! camera flying a fixed path driven by the frame counter (frame k is always the same view), so
//! two runs — with the grass and `--no-grass` — draw the same frames and their difference is
//! what the grass costs.
//!
//! `cargo run --release -p sward-bevy --example bench [-- OPTIONS]`
//!
//! - `--frames N` frames (900 unless given), the first `--warmup W` (120) untimed;
//! - `--speed S` metres a second along the loop (10; 1.5 walks, 38 runs a fast vehicle);
//! - `--height H` the eye's height over the ground, metres (1.7);
//! - `--from M` metres along the loop where frame 0 is (0);
//! - `--no-grass` the grass hidden (its terrain stays);
//! - `--no-splats` the far field drawn as geometry where the device could splat it (its splat
//!   distances set past its reach: the route a device without 64-bit atomics takes);
//! - `--prepass` a depth and motion-vector prepass with TAA instead of MSAA;
//! - `--no-shadows` the sun casts no shadow (what the shadow passes cost, with `--no-grass` and
//!   without);
//! - `--reach M` the grass ends M metres from the eye (the billboards' radius, and the instanced
//!   grass's where it reached further; the shipped world's reaches 450 m), and `--shadow-distance
//!   M` the grass casts into the sun's cascades within M metres (40): to match another plugin's
//!   view and shadow distances;
//! - `--quality TIER` the [`GrassQuality`](sward_bevy::GrassQuality) tier: `low`, `medium`,
//!   `high` (the default: the scene as authored), `ultra` or `high-refresh`;
//! - `--csv PATH` every timed frame: its period and each span Bevy's render diagnostics
//!   measured (`RenderDiagnosticsPlugin`: each of Bevy's passes, and sward's compute as
//!   "sward/grass", on the GPU and recording its commands on the CPU) and sward's host work
//!   (`SwardPlugin::timing`: its extract, its grass pass, and its submission, where a frame
//!   waits when the GPU is the floor);
//! - `--shot OUT.png [--size W H]` headless (where there is no display): the frames drawn into an
//!   image of W×H (1920×1080), the last one written to OUT.png.
//!
//! The flight waits at its first frame until Bevy has compiled every pipeline, then warms up.
//! It prints the frame period's median, 95th and 99th percentiles and each span's median.
//! The frame period is the wall time of one frame of the app (`App::update`, its render world's
//! frame and the GPU's wait included).

#[path = "common/open_world.rs"]
mod open_world;
#[path = "common/shot.rs"]
mod shot;

use std::collections::BTreeMap;
use std::error::Error;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use bevy::anti_alias::taa::TemporalAntiAliasing;
use bevy::app::AppExit;
use bevy::core_pipeline::prepass::{DepthPrepass, MotionVectorPrepass};
use bevy::diagnostic::DiagnosticsStore;
use bevy::prelude::*;
use bevy::render::diagnostic::RenderDiagnosticsPlugin;
use bevy::render::render_resource::PipelineCache;
use bevy::render::{Render, RenderApp, RenderSystems};
use bevy::time::TimeUpdateStrategy;
use sward_bevy::{Grass, GrassQuality, GrassTimings, SwardPlugin};
use sward_core::mesh::HeightGrid;
use sward_core::Scene;

/// What the run draws and how long.
#[derive(Resource, Clone, Debug)]
struct Bench {
    frames: u32,
    warmup: u32,
    /// Metres a second along the scene's loop.
    speed: f32,
    /// The eye over the ground, metres.
    height: f32,
    /// Metres along the loop where frame 0 is.
    from: f32,
    grass: bool,
    /// The far field splatted where the device can (else drawn as geometry).
    splats: bool,
    prepass: bool,
    /// The sun casting into its cascades.
    shadows: bool,
    /// How far the grass reaches, metres (the scene's own unless given).
    reach: Option<f32>,
    /// How far from the eye the grass casts into the sun's cascades, metres.
    shadow_distance: f32,
    /// The quality tier.
    quality: GrassQuality,
    csv: Option<String>,
}

/// The frames measured so far: each timed frame's period and the spans of its passes (milliseconds).
#[derive(Resource, Default)]
struct Measured {
    /// The flight's frame: it stays at 0 until every pipeline is compiled.
    frame: u32,
    /// Updates in a row with every pipeline compiled, and when the app began to wait.
    compiled_for: u32,
    waiting_since: Option<Instant>,
    last: Option<Instant>,
    periods: Vec<f64>,
    /// Per span ("gpu PASS", "cpu PASS"), its time in each timed frame it was measured.
    spans: BTreeMap<String, Vec<(u32, f64)>>,
}

/// The flight: the scene whose loop the camera flies, and the ground under it.
#[derive(Resource)]
struct Flight {
    scene: Scene,
    ground: Option<HeightGrid>,
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let bench = bench_of(&args)?;
    let mut scene = open_world::scene()?;
    if !bench.splats {
        drawn_far_field(&mut scene);
    }
    if let Some(reach) = bench.reach {
        reach_to(&mut scene, reach)?;
    }
    let ground = scene
        .surface
        .mesh(&scene.contents)?
        .as_ref()
        .and_then(|g| g.height_grid());
    let mut app = App::new();
    app.insert_resource(ClearColor(Color::srgb(0.55, 0.66, 0.84)))
        .insert_resource(bench.clone())
        .insert_resource(bench.quality)
        .insert_resource(Measured::default())
        .insert_resource(Flight {
            scene: scene.clone(),
            ground,
        })
        .add_systems(PostStartup, (sun_shadows, grass_shadows))
        .add_systems(Update, fly)
        .add_systems(Last, measure);
    let after = |name: &str, k: usize| args.iter().position(|a| a == name).and_then(|i| args.get(i + k));
    let Some(out) = after("--shot", 1) else {
        app.add_plugins((DefaultPlugins, RenderDiagnosticsPlugin, sward_plugin()))
            .add_systems(Startup, setup(scene, None, bench));
        watch_pipelines(&mut app);
        app.run();
        return Ok(());
    };
    let size = match (after("--size", 1), after("--size", 2)) {
        (None, _) => [1920, 1080],
        (Some(w), Some(h)) => match (w.parse::<u32>(), h.parse::<u32>()) {
            (Ok(w), Ok(h)) if w > 0 && h > 0 => [w, h],
            _ => return Err(format!("--size needs a width and a height in pixels, not {w:?} {h:?}").into()),
        },
        _ => return Err("--size needs a width and a height in pixels".into()),
    };
    app.add_plugins((shot::headless_plugins(true)?, RenderDiagnosticsPlugin, sward_plugin()))
        // Headless, the clock stands still while the pipelines compile (however long that takes,
        // frame k sees the same grass), then steps a sixtieth of a second a frame.
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::ZERO))
        .insert_resource(FixedStep(Duration::from_secs_f64(1.0 / 60.0)));
    watch_pipelines(&mut app);
    let target = shot::target_image(&mut app.world_mut().resource_mut::<Assets<Image>>(), size);
    app.add_systems(Startup, setup(scene, Some(target.clone()), bench.clone()));
    app.finish();
    app.cleanup();
    while app.world().resource::<Measured>().frame < bench.frames {
        app.update();
    }
    shot::shoot(&mut app, target, size, out)
}

/// Whether the render world has compiled every pipeline it was asked for (and asked for some):
/// the flight waits at its first frame until then, so that no timed frame lacks a pass whose
/// pipeline was still compiling (Bevy skips those draws; with the sun's cascades that took the
/// first hundred frames after a warm-up of 120 on the H200).
#[derive(Resource, Clone, Default)]
struct Compiled(Arc<AtomicBool>);

/// The render world's system that keeps [`Compiled`] up to date, and its resource.
fn watch_pipelines(app: &mut App) {
    let compiled = Compiled::default();
    app.insert_resource(compiled.clone());
    app.sub_app_mut(RenderApp)
        .insert_resource(compiled)
        .add_systems(Render, note_compiled.in_set(RenderSystems::Cleanup));
}

fn note_compiled(cache: Res<PipelineCache>, compiled: Res<Compiled>) {
    let done = cache.pipelines().next().is_some() && cache.waiting_pipelines().next().is_none();
    compiled.0.store(done, Ordering::Relaxed);
}

/// Headless, the clock's step once the flight begins (it stands still until then).
#[derive(Resource, Clone, Copy)]
struct FixedStep(Duration);

/// How long the flight waits for the pipelines at most, and how many updates in a row they must
/// stay compiled (a part first drawn a frame later asks for its own).
const COMPILING_AT_MOST: Duration = Duration::from_secs(120);
const COMPILED_FOR: u32 = 30;

/// sward's plugin, timing its host work (`SwardPlugin::timing`: the extract and the grass pass).
fn sward_plugin() -> SwardPlugin {
    SwardPlugin {
        timing: true,
        ..default()
    }
}

/// The run the command line asks for, or what is wrong with it.
fn bench_of(args: &[String]) -> Result<Bench, String> {
    let after = |name: &str| args.iter().position(|a| a == name).map(|i| args.get(i + 1));
    let number = |name: &str, default: f32| -> Result<f32, String> {
        match after(name) {
            None => Ok(default),
            Some(v) => v
                .and_then(|v| v.parse::<f32>().ok())
                .filter(|v| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| format!("{name} needs a number, 0 or more")),
        }
    };
    let known = [
        "--frames",
        "--warmup",
        "--speed",
        "--height",
        "--from",
        "--csv",
        "--shot",
        "--size",
        "--no-grass",
        "--no-splats",
        "--prepass",
        "--no-shadows",
        "--reach",
        "--shadow-distance",
        "--quality",
    ];
    if let Some(unknown) = args
        .iter()
        .find(|a| a.starts_with("--") && !known.contains(&a.as_str()))
    {
        return Err(format!(
            "{unknown} is not an option of the bench (it takes {})",
            known.join(", ")
        ));
    }
    let bench = Bench {
        frames: number("--frames", 900.0)? as u32,
        warmup: number("--warmup", 120.0)? as u32,
        speed: number("--speed", 10.0)?,
        height: number("--height", 1.7)?,
        from: number("--from", 0.0)?,
        grass: !args.iter().any(|a| a == "--no-grass"),
        splats: !args.iter().any(|a| a == "--no-splats"),
        prepass: args.iter().any(|a| a == "--prepass"),
        shadows: !args.iter().any(|a| a == "--no-shadows"),
        reach: after("--reach").is_some().then(|| number("--reach", 0.0)).transpose()?,
        shadow_distance: number("--shadow-distance", Grass::SHADOW_DISTANCE)?,
        quality: match after("--quality").map(|v| v.map(String::as_str)) {
            None => GrassQuality::High,
            Some(Some("low")) => GrassQuality::Low,
            Some(Some("medium")) => GrassQuality::Medium,
            Some(Some("high")) => GrassQuality::High,
            Some(Some("ultra")) => GrassQuality::Ultra,
            Some(Some("high-refresh")) => GrassQuality::HighRefresh,
            Some(other) => {
                return Err(format!(
                    "--quality takes low, medium, high, ultra or high-refresh, not {}",
                    other.map_or("nothing".into(), |v| format!("{v:?}"))
                ))
            }
        },
        csv: after("--csv").flatten().cloned(),
    };
    if bench.frames <= bench.warmup {
        return Err(format!(
            "--frames ({}) must be more than --warmup ({})",
            bench.frames, bench.warmup
        ));
    }
    Ok(bench)
}

/// `scene` with nothing splatted: its generated grass and billboards drawn as geometry to the
/// horizon.
fn drawn_far_field(scene: &mut Scene) {
    scene.instanced.splat_distance = scene.instanced.grid.radius;
    let beyond = scene.billboard.grid.radius + 1.0;
    scene.billboard.splat_distance = beyond;
    scene.billboard.raster_distance = beyond;
}

/// `scene` with its grass ending `reach` metres from the eye: the billboards' radius, and the
/// instanced grass's where it reached further; or why that scene is not valid.
fn reach_to(scene: &mut Scene, reach: f32) -> Result<(), String> {
    scene.billboard.grid.radius = scene.billboard.grid.radius.min(reach);
    scene.instanced.grid.radius = scene.instanced.grid.radius.min(reach);
    Grass::new(scene.clone())
        .map(|_| ())
        .map_err(|e| format!("--reach {reach} leaves a scene that is not valid: {e}"))
}

/// The grass (hidden with `--no-grass`), its terrain, the sun and the camera (into `target`
/// where headless), with 4× MSAA or the prepass and TAA.
fn setup(
    scene: Scene,
    target: Option<Handle<Image>>,
    bench: Bench,
) -> impl FnMut(Commands, ResMut<Assets<StandardMaterial>>) {
    move |mut commands, mut materials| {
        let camera = open_world::spawn(&mut commands, &mut materials, (&scene, bench.grass), target.as_ref());
        let mut camera = commands.entity(camera);
        match bench.prepass {
            true => camera.insert((
                Msaa::Off,
                DepthPrepass,
                MotionVectorPrepass,
                TemporalAntiAliasing::default(),
            )),
            false => camera.insert(Msaa::Sample4),
        };
    }
}

/// The sun's shadows, off with `--no-shadows`.
fn sun_shadows(bench: Res<Bench>, mut suns: Query<&mut DirectionalLight>) {
    for mut sun in &mut suns {
        sun.shadow_maps_enabled &= bench.shadows;
    }
}

/// The grass casting within `--shadow-distance` of the eye.
fn grass_shadows(bench: Res<Bench>, mut fields: Query<&mut Grass>) {
    for mut grass in &mut fields {
        grass.shadow_distance = bench.shadow_distance;
    }
}

/// The camera where frame k of the flight puts it: `speed` metres a second along the scene's
/// loop from `from` metres, a sixtieth of a second a frame, `height` over the ground.
fn fly(
    bench: Res<Bench>,
    flight: Res<Flight>,
    measured: Res<Measured>,
    mut camera: Single<&mut Transform, With<Camera3d>>,
) {
    let path = &flight.scene.camera_path;
    let metres = bench.from + measured.frame as f32 / 60.0 * bench.speed;
    // The path's parameter is seconds at its own pace.
    let along = metres / path.speed.max(1e-6);
    let eye = path.camera_over(&flight.scene.camera, along, flight.ground.as_ref());
    let lift = bench.height - flight.scene.camera.position.y;
    let [p, t] = [eye.position, eye.target].map(|v| Vec3::from_array(v.to_array()) + Vec3::Y * lift);
    **camera = Transform::from_translation(p).looking_at(t, Vec3::Y);
}

/// Count the frame; past the warm-up keep its period and the spans Bevy's render
/// diagnostics hold; after the last, report (and leave, in a window).
fn measure(
    bench: Res<Bench>,
    mut measured: ResMut<Measured>,
    (store, timings, compiled): (Res<DiagnosticsStore>, Option<Res<GrassTimings>>, Res<Compiled>),
    (step, mut clock): (Option<Res<FixedStep>>, ResMut<TimeUpdateStrategy>),
    mut exit: MessageWriter<AppExit>,
) {
    // sward's host work in the frames the render world finished since the last.
    let host = timings.map(|t| t.take()).unwrap_or_default();
    if measured.frame == 0 {
        if !pipelines_compiled(&mut measured, compiled.0.load(Ordering::Relaxed)) {
            return;
        }
        if let Some(step) = step {
            *clock = TimeUpdateStrategy::ManualDuration(step.0);
        }
    }
    let now = Instant::now();
    let timed = measured.frame >= bench.warmup;
    if let (true, Some(last)) = (timed, measured.last) {
        let period = now.duration_since(last).as_secs_f64() * 1e3;
        measured.periods.push(period);
        let frame = measured.frame;
        for diagnostic in store.iter() {
            let path = diagnostic.path().as_str();
            let Some(value) = diagnostic.value() else { continue };
            // Each pass's GPU time, and the CPU time its commands took to record.
            let span = match path.strip_prefix("render/") {
                Some(pass) if pass.ends_with("/elapsed_gpu") => {
                    format!("gpu {}", pass.trim_end_matches("/elapsed_gpu"))
                }
                Some(pass) if pass.ends_with("/elapsed_cpu") => {
                    format!("cpu {}", pass.trim_end_matches("/elapsed_cpu"))
                }
                _ => continue,
            };
            measured.spans.entry(span).or_default().push((frame, value));
        }
        // The render world runs a frame behind: its last frame's host times stand for this one.
        if let Some(last) = host.last() {
            let ms = |d: Duration| d.as_secs_f64() * 1e3;
            for (span, value) in [
                ("host sward/extract", ms(last.extract)),
                ("host sward/grass", ms(last.draw.saturating_sub(last.gpu_wait))),
                ("host sward/submit", ms(last.gpu_wait)),
            ] {
                measured.spans.entry(span.to_string()).or_default().push((frame, value));
            }
        }
    }
    measured.last = Some(now);
    measured.frame += 1;
    if measured.frame == bench.frames {
        report(&bench, &measured);
        exit.write(AppExit::Success);
    }
}

/// Whether the flight may leave its first frame: every pipeline compiled for `COMPILED_FOR`
/// updates in a row (`compiled` this one), or waited for `COMPILING_AT_MOST` (said).
fn pipelines_compiled(measured: &mut Measured, compiled: bool) -> bool {
    let since = *measured.waiting_since.get_or_insert_with(Instant::now);
    measured.compiled_for = if compiled { measured.compiled_for + 1 } else { 0 };
    if measured.compiled_for >= COMPILED_FOR {
        println!(
            "bench: every pipeline compiled after {:.1} s",
            since.elapsed().as_secs_f64()
        );
        return true;
    }
    if since.elapsed() > COMPILING_AT_MOST {
        eprintln!(
            "bench: pipelines still compiling after {} s; flying anyway",
            COMPILING_AT_MOST.as_secs()
        );
        return true;
    }
    false
}

/// The `q` quantile of `values` (sorted in place).
fn quantile(values: &mut [f64], q: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    let at = ((values.len().max(1) - 1) as f64 * q).round() as usize;
    values.get(at).copied().unwrap_or(f64::NAN)
}

/// Print the frame period's median, p95 and p99 and each span's median; write the CSV.
fn report(bench: &Bench, measured: &Measured) {
    let mut periods = measured.periods.clone();
    println!(
        "bench: {} timed frames at {} m/s, eye {} m, grass {} ({:?}), far field {}, {}, sun shadows {}",
        periods.len(),
        bench.speed,
        bench.height,
        if bench.grass { "on" } else { "off" },
        bench.quality,
        if bench.splats { "splatted" } else { "drawn" },
        if bench.prepass { "prepass + TAA" } else { "4x MSAA" },
        if bench.shadows { "on" } else { "off" },
    );
    let [p50, p95, p99] = [0.5, 0.95, 0.99].map(|q| quantile(&mut periods, q));
    println!("frame period: median {p50:.2} ms, p95 {p95:.2} ms, p99 {p99:.2} ms");
    for (span, values) in &measured.spans {
        let mut ms: Vec<f64> = values.iter().map(|(_, v)| *v).collect();
        println!(
            "{span}: median {:.3} ms over {} frames",
            quantile(&mut ms, 0.5),
            ms.len()
        );
    }
    if let Some(path) = &bench.csv {
        match std::fs::write(path, csv(measured)) {
            Ok(()) => println!("wrote {path}"),
            Err(e) => eprintln!("could not write {path}: {e}"),
        }
    }
}

/// Every timed frame as a CSV row: its number, its period, then each span's time (empty
/// where the span was not measured that frame).
fn csv(measured: &Measured) -> String {
    let spans: Vec<&String> = measured.spans.keys().collect();
    let mut out = String::from("frame,period_ms");
    for span in &spans {
        out += &format!(",{span} ms");
    }
    out.push('\n');
    let first = measured.frame - measured.periods.len() as u32;
    for (k, period) in measured.periods.iter().enumerate() {
        let frame = first + k as u32;
        out += &format!("{frame},{period:.4}");
        for span in &spans {
            let value = measured.spans[*span].iter().find(|(f, _)| *f == frame);
            out += &value.map_or(",".to_string(), |(_, v)| format!(",{v:.4}"));
        }
        out.push('\n');
    }
    out
}
