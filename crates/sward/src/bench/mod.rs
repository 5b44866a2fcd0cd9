//! `sward bench`: reproducible per-pass GPU timings. Offscreen frames with a fixed simulation step
//! and a fixed camera, warm-up, then many timed frames (GPU timestamps around every pass), swept
//! over blade counts × culling modes × scene presets; tables, a CSV of every frame and plots. Two
//! named sets run instead of a sweep: the regression set (`regression.rs`), compared between two
//! runs by `--compare` (`compare.rs`), and every shipped scene as it ships (`shipped.rs`), the
//! table BENCHMARKS.md opens with.

mod compare;
mod floor;
mod plot;
mod portable;
mod regression;
mod report;
mod shipped;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::Context as _;
use ash::vk;
use glam::Vec2;
use gpu_allocator::MemoryLocation;
use indicatif::{ProgressBar, ProgressStyle};
use sward_core::cull::CullParams;
use sward_core::instanced::{Technique, SPLAT_LEVEL};
use sward_core::quality::QualityPreset;
use sward_core::scene::MAX_BLADES;
use sward_core::FrameDesc;
use sward_core::{Field, Scene};
use sward_gpu::buffer::Buffer;
use sward_gpu::pipelines::ComputeOptions;
use sward_gpu::probe::shader_bandwidth;
use sward_gpu::shaders::ShaderSet;
use sward_gpu::target::OFFSCREEN_FORMAT;
use sward_gpu::timer::{DrawCounter, GpuTimer};
use sward_gpu::{Context, Headless};
use sward_gpu::{DrawRoute, RendererDesc};

use crate::args::{BenchArgs, CullMode, GpuArgs, Preset, RendererArg, TechniqueArg};
pub use report::{Case, Sample};

/// Allocations `memory.csv` names for each case: where most of its GPU memory goes.
const LARGEST_ALLOCATIONS: usize = 8;

impl Preset {
    pub fn name(self) -> &'static str {
        match self {
            Preset::Cis565 => "cis565",
            Preset::Meadow => "meadow",
            Preset::Hills => "hills",
            Preset::Prairie => "prairie",
            Preset::Trample => "trample",
            Preset::Openworld => "openworld",
            Preset::Landscape => "landscape",
            Preset::Park => "park",
            Preset::Planet => "planet",
            Preset::Trail => "trail",
        }
    }

    /// The preset's scene with `blades` blades.
    pub fn scene(self, blades: u32) -> Scene {
        match self {
            Preset::Cis565 => Scene::cis565(blades),
            Preset::Meadow => {
                let mut scene = crate::scenes::load("meadow").expect("the shipped meadow is valid");
                let density = scene.field.blades as f32 / (scene.field.size.x * scene.field.size.y);
                scene.field.size = Vec2::splat((blades as f32 / density).sqrt());
                scene.field.blades = blades;
                scene
            }
            shipped => {
                let name = shipped.name();
                let mut scene =
                    crate::scenes::load(name).unwrap_or_else(|e| panic!("the shipped {name} is valid: {e}"));
                scene.field.blades = blades;
                scene
            }
        }
    }
}

impl CullMode {
    pub fn name(self) -> &'static str {
        match self {
            CullMode::None => "none",
            CullMode::Orientation => "orientation",
            CullMode::Frustum => "frustum",
            CullMode::Distance => "distance",
            CullMode::Tiles => "tiles",
            CullMode::Occlusion => "occlusion",
            CullMode::All => "all",
        }
    }

    /// The preset's culling parameters with only this mode's tests on.
    pub fn apply(self, base: &CullParams) -> CullParams {
        let on = |m: CullMode| self == m || self == CullMode::All;
        CullParams {
            orientation: on(CullMode::Orientation),
            frustum: on(CullMode::Frustum),
            distance: on(CullMode::Distance),
            tiles: on(CullMode::Tiles),
            occlusion: on(CullMode::Occlusion),
            ..*base
        }
    }
}

/// Everything about the run that a reader of the results needs.
pub struct RunInfo {
    pub device: String,
    pub driver: String,
    pub resolution: [u32; 2],
    pub commit: &'static str,
    pub warmup: u32,
    pub frames: u32,
    /// Shader copy bandwidth, GB/s read + written (`None`: the timestamps did not resolve it).
    pub bandwidth: Option<f64>,
    /// The renderer options this run used.
    pub variant: String,
    pub command: String,
}

pub fn run(args: &BenchArgs, gpu: &GpuArgs) -> anyhow::Result<()> {
    if let [old, new] = args.compare.as_slice() {
        return compare::run(old, new, args.tolerance / 100.0);
    }
    let plan = Plan::from_args(args);
    if args.renderer.renderer == RendererArg::Wgpu || args.renderer.wgpu_backend.is_some() {
        return run_portable(args, gpu, &plan);
    }
    gpu.check_splat_cells(false)?;
    let ctx = Context::new(&gpu.context_desc())?;
    std::fs::create_dir_all(&plan.out).with_context(|| format!("cannot create {}", plan.out.display()))?;
    // The probe copies within one storage buffer, which must fit the device's range.
    let bandwidth_bytes = if plan.quick { 32 << 20 } else { 240 << 20 };
    let bandwidth_bytes = bandwidth_bytes.min(ctx.info.max_storage_buffer_range / 64 * 64);
    let info = RunInfo {
        device: ctx.info.name.clone(),
        driver: format!("{} {}", ctx.info.driver_name, ctx.info.driver_info),
        resolution: [plan.width, plan.height],
        commit: env!("SWARD_COMMIT"),
        warmup: plan.warmup,
        frames: plan.frames,
        bandwidth: shader_bandwidth(&ctx, bandwidth_bytes)?,
        variant: variant(args),
        command: std::env::args().collect::<Vec<_>>().join(" "),
    };
    let mut timer = GpuTimer::new(&ctx)?;
    let mut counter = DrawCounter::new(&ctx)?;
    let visible = Buffer::new(
        &ctx,
        "visible and simulated counts",
        8,
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )?;
    let mut probes = floor::Probes {
        timer: &mut timer,
        counter: counter.as_mut(),
        visible: &visible,
    };
    let jobs = jobs(args, &plan)?;
    let (cases, stopped) = match args.floor {
        true => (Vec::new(), Vec::new()),
        false => sweep(&ctx, args, &plan, &jobs, &mut probes)?,
    };
    // The floor: on its own with --floor, after the sweep of every full run (not the named sets).
    let floor_rows = if args.floor || !(plan.quick || args.regression_set || args.shipped) {
        floor::measure_floor(&ctx, &plan, &mut probes)?
    } else {
        Vec::new()
    };
    let validation = ctx.take_validation_messages();
    if gpu.validation && !validation.is_empty() {
        anyhow::bail!(
            "the Vulkan validation layer reported {} problem(s), the first: {}",
            validation.len(),
            validation[0]
        );
    }
    let mut md = report::markdown(&info, &cases, &stopped);
    if !floor_rows.is_empty() {
        md.push_str(&floor::markdown(&floor_rows, info.bandwidth));
        let csv = floor::csv(&floor_rows, &info.device);
        let path = plan.out.join("floor.csv");
        std::fs::write(&path, csv).with_context(|| format!("cannot write {}", path.display()))?;
    }
    report::write_all(&plan.out, &md, &info, &cases)?;
    plot::write_all(&plan.out, &cases)?;
    println!("{md}");
    if args.shipped || !args.scenes.is_empty() {
        let table = shipped::expect_table(&info, &cases, &stopped);
        let path = plan.out.join("expect.md");
        std::fs::write(&path, &table).with_context(|| format!("cannot write {}", path.display()))?;
        println!("{table}");
    }
    println!("results written to {}", plan.out.display());
    Ok(())
}

/// The run on the portable renderer: its tables and CSV files as the Vulkan renderer's.
fn run_portable(args: &BenchArgs, gpu: &GpuArgs, plan: &Plan) -> anyhow::Result<()> {
    if args.floor {
        anyhow::bail!("--floor measures the Vulkan renderer's fill and geometry floor; it takes no --renderer wgpu");
    }
    std::fs::create_dir_all(&plan.out).with_context(|| format!("cannot create {}", plan.out.display()))?;
    let jobs = jobs(args, plan)?;
    let (info, cases, stopped) = portable::sweep(args, gpu, plan, &jobs)?;
    let messages = crate::logging::take_backend_messages();
    if gpu.validation && !messages.is_empty() {
        anyhow::bail!(
            "wgpu's backend reported {} problem(s) with validation on, the first: {}",
            messages.len(),
            messages[0]
        );
    }
    let md = report::markdown(&info, &cases, &stopped);
    report::write_all(&plan.out, &md, &info, &cases)?;
    plot::write_all(&plan.out, &cases)?;
    println!("{md}");
    println!("results written to {}", plan.out.display());
    Ok(())
}

/// One scene a run grows and measures, under each draw route, culling mode and camera speed.
struct Job {
    /// Its name in a named set (the regression set's, the shipped set's).
    label: Option<String>,
    /// The scene it grows: a bench preset's name, or a scene file's scene name.
    preset: String,
    /// Its blades as the sweep counts them (a generated technique's candidates).
    count: u32,
    scene: Scene,
    modes: Vec<CullMode>,
    speeds: Vec<f32>,
}

/// The scenes the run measures: the regression set, the shipped set, or the sweep's presets ×
/// counts.
fn jobs(args: &BenchArgs, plan: &Plan) -> anyhow::Result<Vec<Job>> {
    if args.regression_set {
        return regression::REGRESSION_SET
            .iter()
            .map(|c| {
                Ok(Job {
                    label: Some(c.name.to_string()),
                    preset: c.preset.name().to_string(),
                    count: c.count,
                    scene: bench_scene(args, c.preset, c.count, c.technique)?,
                    modes: vec![CullMode::All],
                    speeds: vec![c.speed],
                })
            })
            .collect();
    }
    if args.shipped || !args.scenes.is_empty() {
        let shipped_set = if args.shipped { &shipped::SHIPPED_SET[..] } else { &[] };
        let mut jobs = shipped_set
            .iter()
            .map(|c| {
                let scene = with_run_overrides(c.scene(), args)?;
                Ok(as_it_ships(c.label(), c.preset.name().to_string(), scene, c.speed))
            })
            .collect::<anyhow::Result<Vec<Job>>>()?;
        for arg in &args.scenes {
            let scene = with_run_overrides(crate::scenes::load(arg)?, args)?;
            let name = scene.name.clone();
            jobs.push(as_it_ships(name.clone(), name, scene, 0.0));
        }
        return Ok(jobs);
    }
    let mut jobs = Vec::new();
    for &preset in &plan.presets {
        for &count in &plan.counts {
            jobs.push(Job {
                label: None,
                preset: preset.name().to_string(),
                count,
                scene: bench_scene(args, preset, count, args.technique)?,
                modes: plan.modes.clone(),
                speeds: plan.speeds.clone(),
            });
        }
    }
    Ok(jobs)
}

/// A scene measured as it ships (its own blades, technique, camera and paint), every culling
/// test on, its camera at `speed` along its path.
fn as_it_ships(label: String, preset: String, scene: Scene, speed: f32) -> Job {
    Job {
        label: Some(label),
        preset,
        count: scene.field.blades,
        scene,
        modes: vec![CullMode::All],
        speeds: vec![speed],
    }
}

/// Measure every job under every quality preset and draw route: the cases, and a line for each
/// job whose field did not fit (a sweep's larger counts of that preset are then left out).
fn sweep(
    ctx: &Arc<Context>,
    args: &BenchArgs,
    plan: &Plan,
    jobs: &[Job],
    probes: &mut floor::Probes,
) -> anyhow::Result<(Vec<Case>, Vec<String>)> {
    // A route this device lacks is measured as the route it falls back to, said once before
    // anything is measured; a route reached twice that way is measured once.
    let mut routes: Vec<DrawRoute> = Vec::new();
    for &route in &plan.routes {
        let (drawn, note) = sward_gpu::passes::routes::resolve(route, &ctx.info, args.copy_blades);
        if let Some(note) = note {
            eprintln!("sward: {note}");
        }
        if !routes.contains(&drawn) {
            routes.push(drawn);
        }
    }
    let per_job = |j: &Job| (routes.len() * j.modes.len() * j.speeds.len()) as u64;
    let total = plan.qualities.len() as u64 * jobs.iter().map(per_job).sum::<u64>();
    let progress = ProgressBar::new(total).with_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}").unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut cases = Vec::new();
    let mut stopped = Vec::new();
    for &quality in &plan.qualities {
        let desc = RendererDesc {
            patches_per_draw: args.patches_per_draw,
            compute: ComputeOptions {
                workgroup: args.workgroup,
                instanced_workgroup: args.instanced_workgroup,
                subgroup_atomics: !args.no_subgroup_atomics,
                copy_blades: args.copy_blades,
                wgsl_checks: args.wgsl_checks,
            },
            fused: !args.separate,
            ..RendererDesc::for_quality(&ctx.info, OFFSCREEN_FORMAT, quality, 1)
        };
        let renderer = || -> anyhow::Result<Headless> {
            let mut headless = Headless::with_desc(ctx, plan.width, plan.height, &desc)?;
            if let Some(shaders) = &args.shaders {
                use_shaders_from(&mut headless, shaders)?;
            }
            headless.renderer.keep_recordings = !args.record_every_frame;
            Ok(headless)
        };
        let mut headless = renderer()?;
        let samples = desc.target.samples.as_raw();
        let mut stopped_at: Vec<(&str, u32)> = Vec::new();
        for (k, job) in jobs.iter().enumerate() {
            // A named set's case is measured by a renderer of its own, so what an earlier case
            // left (lists and targets grown for more blades) does not weigh on it.
            if job.label.is_some() && k > 0 {
                headless = renderer()?;
            }
            let past_a_stop = stopped_at.iter().any(|&(p, c)| p == job.preset && job.count >= c);
            if job.label.is_none() && past_a_stop {
                progress.inc(per_job(job));
                continue;
            }
            let mut scene = job.scene.clone();
            scene.quality.preset = quality;
            let field = match grow(ctx, &mut headless, &scene) {
                Ok(field) => field,
                Err(e) => {
                    let name = job.label.clone().unwrap_or_else(|| job.preset.clone());
                    let line = format!("{name}: stopped at {} blades: {e:#}", job.count);
                    progress.println(&line);
                    stopped.push(line);
                    stopped_at.push((&job.preset, job.count));
                    progress.inc(per_job(job));
                    continue;
                }
            };
            for &route in &routes {
                headless.renderer.set_route(route);
                scene.quality.route = route;
                for (&mode, &speed) in job.modes.iter().flat_map(|m| job.speeds.iter().map(move |v| (m, v))) {
                    let route_name = headless.renderer.route().name();
                    progress.set_message(format!(
                        "{} {} blades, culling {}, {route_name}, {}, {speed} m/s",
                        job.label.as_deref().unwrap_or(&job.preset),
                        job.count,
                        mode.name(),
                        quality.name()
                    ));
                    let mut scene = scene.clone();
                    scene.cull = mode.apply(&scene.cull);
                    scene.camera_path = moving_at(&scene, speed);
                    let frames = measure(&mut headless, probes, (&scene, &field), plan)?;
                    cases.push(Case {
                        label: job.label.clone(),
                        preset: job.preset.clone(),
                        technique: scene.technique.name(),
                        route: route_name,
                        quality: quality.name(),
                        msaa: samples,
                        blades: job.count,
                        mode: mode.name(),
                        speed,
                        memory_mib: ctx.allocated_bytes() as f64 / (1 << 20) as f64,
                        largest_allocations: ctx.largest_allocations(LARGEST_ALLOCATIONS),
                        samples: frames,
                    });
                    progress.inc(1);
                }
            }
        }
    }
    progress.finish_and_clear();
    Ok((cases, stopped))
}

/// Rebuild `headless`'s pipelines from the shaders in `dir`, compiled now.
pub(crate) fn use_shaders_from(headless: &mut Headless, dir: &Path) -> anyhow::Result<()> {
    let shaders =
        ShaderSet::compile(dir).map_err(|e| anyhow::anyhow!("the shaders in {} do not compile: {e}", dir.display()))?;
    headless.renderer.use_shaders(&shaders)?;
    Ok(())
}

fn variant(args: &BenchArgs) -> String {
    let lod = args
        .lod_max
        .map_or("preset LOD".to_string(), |l| format!("LOD max {l}"));
    format!(
        "workgroup {} (instanced grass {}), {} atomics, {} simulate+cull, {}, {lod}, {}",
        args.workgroup,
        args.instanced_workgroup,
        if args.no_subgroup_atomics {
            "per-blade"
        } else {
            "subgroup-aggregated"
        },
        if args.separate { "separate" } else { "fused" },
        if args.copy_blades {
            "culled blades copied"
        } else {
            "visible-index list"
        },
        if args.record_every_frame {
            "passes recorded every frame"
        } else {
            "passes kept recorded"
        },
    ) + if args.wgsl_checks {
        ", WGSL with naga's checks"
    } else {
        ""
    }
}

/// The preset's scene with `count` blades, drawn by `technique` where given, and the run's
/// overrides. With a generated technique alone, `count` is the candidates within its cut-off
/// radius.
fn bench_scene(args: &BenchArgs, preset: Preset, count: u32, technique: Option<TechniqueArg>) -> anyhow::Result<Scene> {
    let mut scene = with_run_overrides(preset.scene(count.min(MAX_BLADES)), args)?;
    if let Some(technique) = technique {
        scene.technique = technique.into();
    }
    match scene.technique {
        Technique::Instanced => {
            let disk = std::f32::consts::PI * scene.instanced.grid.radius.powi(2);
            scene.instanced.grid.density = count as f32 / disk;
        }
        Technique::Billboard => {
            let disk = std::f32::consts::PI * scene.billboard.grid.radius.powi(2);
            scene.billboard.grid.density = count as f32 / disk;
        }
        _ => {}
    }
    if scene.technique.draws_bezier() && count > MAX_BLADES {
        anyhow::bail!(
            "{count} blades is more than a Bezier field holds: counts above 2^26 ({MAX_BLADES}) are \
             allowed only with --technique instanced or billboard"
        );
    }
    Ok(scene)
}

/// `scene` with the run's `--set` values and `--lod-max`.
fn with_run_overrides(scene: Scene, args: &BenchArgs) -> anyhow::Result<Scene> {
    let mut scene = scene.with_overrides(&args.set)?;
    if let Some(level) = args.lod_max {
        scene.lod.max_level = level.max(scene.lod.min_level);
    }
    Ok(scene)
}

/// Grow and upload the field, or say why this count does not fit.
fn grow(ctx: &Context, headless: &mut Headless, scene: &Scene) -> anyhow::Result<Field> {
    sward_gpu::renderer::check_field_fits(ctx, scene.bezier_blades() as u64)?;
    let field = scene.grow_field()?;
    headless.renderer.upload(&field)?;
    headless.renderer.upload_ground(field.ground.as_ref())?;
    Ok(field)
}

/// Warm up, then time frames until `plan.frames` are in (or the case's time budget is spent,
/// keeping at least 20).
fn measure(
    headless: &mut Headless,
    probes: &mut floor::Probes,
    (scene, field): (&Scene, &Field),
    plan: &Plan,
) -> anyhow::Result<Vec<Sample>> {
    let floor::Probes {
        timer,
        counter,
        visible,
    } = probes;
    let visible: &Buffer = visible;
    // The ground a path above the ground follows, looked up in O(1) per frame.
    let ground = field.ground.as_ref().and_then(|m| m.height_grid());
    let mut moved = scene.clone();
    let mut samples = Vec::new();
    let mut window = SampleWindow::new(plan);
    for frame in 0..plan.warmup + plan.frames {
        let cpu_start = Instant::now();
        let clock = (frame as f32 * scene.simulation.step, 1);
        moved.camera = scene.camera_path.camera_over(&scene.camera, clock.0, ground.as_ref());
        let desc = FrameDesc::of_scene(&moved, field.size, clock, [plan.width, plan.height]);
        let uniforms_time = cpu_start.elapsed();
        let host_frame = headless.timed_frame(&desc, timer, counter.as_deref_mut(), visible)?;
        if !window.samples(frame) {
            continue;
        }
        let gpu = timer
            .read()
            .context("timestamps were not available after the frame finished")?;
        let (count, splatted) = visible_blades(headless, visible, scene.technique)?;
        samples.push(Sample {
            gpu,
            cpu_ms: (uniforms_time + host_frame).as_secs_f64() * 1e3,
            visible: count,
            splatted,
            simulated: visible
                .mapped()
                .map_or(0, |b| u32::from_le_bytes([b[4], b[5], b[6], b[7]])),
            counts: counter.as_deref().and_then(|c| c.read()).unwrap_or_default(),
        });
        if window.full(samples.len()) {
            break;
        }
    }
    Ok(samples)
}

/// Which frames of a case are timed, the same for both renderers (so their visible counts are
/// medians of the same frames where both run them in time): after `plan.warmup` frames, or
/// once half the case's time budget is spent (at least 3 frames: heavy cases), until
/// `plan.frames` are in or the budget is spent with at least 20.
pub(crate) struct SampleWindow {
    started: Instant,
    warmup: u32,
    max_seconds: f32,
    warmed: bool,
}

impl SampleWindow {
    pub(crate) fn new(plan: &Plan) -> SampleWindow {
        SampleWindow::of(plan.warmup, plan.max_seconds)
    }

    /// The window of a case warmed up `warmup` frames within a budget of `max_seconds`.
    fn of(warmup: u32, max_seconds: f32) -> SampleWindow {
        SampleWindow {
            started: Instant::now(),
            warmup,
            max_seconds,
            warmed: false,
        }
    }

    /// Whether frame `frame` (just run) is timed.
    pub(crate) fn samples(&mut self, frame: u32) -> bool {
        if frame >= self.warmup {
            return true;
        }
        if frame >= 3 && self.started.elapsed().as_secs_f32() > self.max_seconds / 2.0 {
            self.warmed = true;
        }
        self.warmed
    }

    /// Whether `taken` samples end the case.
    pub(crate) fn full(&self, taken: usize) -> bool {
        taken >= 20 && self.started.elapsed().as_secs_f32() > self.max_seconds
    }
}

/// The blades the frame drew, of every kind its technique draws — the Bezier blades the cull
/// kept, the instanced blades listed and splatted, the billboards — and of them those drawn by
/// compute (splatted or rasterized).
fn visible_blades(headless: &Headless, visible: &Buffer, technique: Technique) -> anyhow::Result<(u32, u32)> {
    let mut count = 0;
    if technique.draws_bezier() {
        count += visible
            .mapped()
            .map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    }
    if !(technique.draws_instanced() || technique.draws_billboards()) {
        return Ok((count, 0));
    }
    let draws = headless.renderer.read_instanced_draws()?;
    // The fifth command counts the splatted and rasterized blades and billboards, drawn by no one.
    let splatted = draws[SPLAT_LEVEL].instance_count;
    if technique.draws_instanced() {
        count += draws[..SPLAT_LEVEL].iter().map(|d| d.instance_count).sum::<u32>();
    }
    if technique.draws_billboards() {
        // The billboards the raster hardware draws: the command after the splat count.
        count += draws[SPLAT_LEVEL + 1].instance_count;
    }
    Ok((count + splatted, splatted))
}

/// The scene's camera path at `speed` units per second: its own path, or straight ahead along
/// the ground where it has none (still at 0).
fn moving_at(scene: &Scene, speed: f32) -> sward_core::camera::CameraPath {
    let mut path = scene.camera_path.clone();
    if path.points.len() < 2 {
        let eye = scene.camera.position;
        let ahead = (scene.camera.target - eye) * glam::Vec3::new(1.0, 0.0, 1.0);
        path.points = vec![eye, eye + ahead.normalize_or(glam::Vec3::Z) * 1.0e5];
        path.dolly = true;
    }
    path.speed = speed;
    path
}

/// A resolved sweep.
#[derive(Clone)]
pub struct Plan {
    pub counts: Vec<u32>,
    pub modes: Vec<CullMode>,
    pub presets: Vec<Preset>,
    /// Draw routes of the Bezier blades.
    pub routes: Vec<DrawRoute>,
    /// Quality presets (each a renderer of its own: samples and shadow map differ).
    pub qualities: Vec<QualityPreset>,
    pub width: u32,
    pub height: u32,
    pub warmup: u32,
    pub frames: u32,
    pub max_seconds: f32,
    pub out: PathBuf,
    pub quick: bool,
    /// Camera speeds, units per second (0: standing).
    pub speeds: Vec<f32>,
}

impl Plan {
    /// The sweep the flags ask for, defaults filled in.
    pub fn from_args(args: &BenchArgs) -> Plan {
        let quick = args.quick;
        let counts = if !args.counts.is_empty() {
            args.counts.clone()
        } else if quick {
            vec![1 << 10, 1 << 12]
        } else {
            (5..=12).map(|k| 1u32 << (2 * k)).collect()
        };
        let modes = if args.modes.is_empty() {
            vec![
                CullMode::None,
                CullMode::Orientation,
                CullMode::Frustum,
                CullMode::Distance,
                CullMode::Tiles,
                CullMode::Occlusion,
                CullMode::All,
            ]
        } else {
            args.modes.clone()
        };
        let presets = if args.presets.is_empty() {
            vec![Preset::Cis565, Preset::Meadow]
        } else {
            args.presets.clone()
        };
        let routes = if args.draw_route.is_empty() {
            vec![DrawRoute::Auto]
        } else {
            args.draw_route.iter().map(|&r| r.into()).collect()
        };
        let qualities = if args.quality.is_empty() {
            vec![QualityPreset::High]
        } else {
            args.quality.iter().map(|&q| q.into()).collect()
        };
        Plan {
            counts,
            modes,
            presets,
            routes,
            qualities,
            width: args.width.unwrap_or(if quick { 320 } else { 1920 }),
            height: args.height.unwrap_or(if quick { 240 } else { 1080 }),
            warmup: args.warmup.unwrap_or(if quick { 3 } else { 30 }),
            frames: args.frames.unwrap_or(if quick { 10 } else { 200 }).max(1),
            max_seconds: args.max_seconds,
            out: args.out.clone(),
            quick,
            speeds: match args.speeds.is_empty() {
                true => vec![0.0],
                false => args.speeds.clone(),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_case_is_timed_after_its_warm_up_or_once_half_its_budget_is_spent() {
        let mut roomy = SampleWindow::of(10, 1000.0);
        assert!(
            !(0..10).any(|frame| roomy.samples(frame)),
            "warm-up frames are not timed"
        );
        assert!(
            roomy.samples(10) && !roomy.full(20),
            "timed after the warm-up, until the budget"
        );
        let mut spent = SampleWindow::of(10, 0.0);
        assert!(!(0..3).any(|frame| spent.samples(frame)), "at least 3 frames warm up");
        assert!(spent.samples(3) && spent.samples(4), "a spent budget ends the warm-up");
        assert!(!spent.full(19) && spent.full(20), "at least 20 samples");
    }

    use super::*;
    use crate::args::{Args, Command};
    use clap::Parser as _;

    fn bench_args(words: &[&str]) -> BenchArgs {
        let all: Vec<&str> = ["sward", "bench"].iter().chain(words).copied().collect();
        match Args::parse_from(all).command {
            Some(Command::Bench(args)) => args,
            _ => unreachable!("'sward bench' parses as the bench command"),
        }
    }

    #[test]
    fn the_regression_set_s_jobs_are_its_cases_with_their_techniques_and_densities() {
        let args = bench_args(&["--regression-set", "--set", "wind.strength=1.0"]);
        let jobs = jobs(&args, &Plan::from_args(&args)).unwrap();
        assert_eq!(jobs.len(), regression::REGRESSION_SET.len());
        let largest = jobs
            .iter()
            .find(|j| j.label.as_deref() == Some("instanced 2^26"))
            .unwrap();
        assert_eq!(largest.scene.technique, Technique::Instanced);
        let grid = largest.scene.instanced.grid;
        assert!(
            (grid.candidates() / (1u64 << 26) as f64 - 1.0).abs() < 1e-3,
            "{}",
            grid.candidates()
        );
        let walking = jobs
            .iter()
            .find(|j| j.label.as_deref() == Some("open world walking"))
            .unwrap();
        assert_eq!(
            (walking.speeds.as_slice(), walking.modes.as_slice()),
            ([1.5].as_slice(), [CullMode::All].as_slice())
        );
        // The run's --set reaches every case.
        assert!(jobs.iter().all(|j| j.scene.wind[0].strength == 1.0));
    }

    #[test]
    fn the_shipped_set_s_jobs_keep_each_scene_s_own_blades() {
        let args = bench_args(&["--shipped"]);
        let jobs = jobs(&args, &Plan::from_args(&args)).unwrap();
        assert_eq!(jobs.len(), shipped::SHIPPED_SET.len());
        let prairie = jobs.iter().find(|j| j.label.as_deref() == Some("prairie")).unwrap();
        assert_eq!(prairie.count, 1 << 24);
        let instanced = jobs
            .iter()
            .find(|j| j.label.as_deref() == Some("meadow · instanced"))
            .unwrap();
        assert_eq!(instanced.scene.technique, Technique::Instanced);
    }

    #[test]
    fn a_scene_file_is_measured_as_it_is_after_the_shipped_set() {
        let file = std::env::temp_dir().join(format!("sward-bench-{}.toml", std::process::id()));
        std::fs::write(
            &file,
            "name = \"my field\"\ntechnique = \"landscape\"\n[field]\nblades = 12345\n",
        )
        .unwrap();
        let path = file.display().to_string();
        let args = bench_args(&[
            "--shipped",
            "--scene",
            &path,
            "--scene",
            "hills",
            "--set",
            "cull.distance_max=33.0",
        ]);
        let jobs = jobs(&args, &Plan::from_args(&args)).unwrap();
        std::fs::remove_file(&file).unwrap();
        assert_eq!(jobs.len(), shipped::SHIPPED_SET.len() + 2);
        let mine = &jobs[shipped::SHIPPED_SET.len()];
        assert_eq!(mine.label.as_deref(), Some("my field"));
        assert_eq!((mine.count, mine.scene.technique), (12345, Technique::Landscape));
        assert_eq!(
            jobs.last().unwrap().count,
            crate::scenes::load("hills").unwrap().field.blades
        );
        assert!(jobs.iter().all(|j| j.scene.cull.distance_max == 33.0));
        // A scene that is not there is said, not skipped.
        let args = bench_args(&["--scene", "no/such/field.toml"]);
        assert!(super::jobs(&args, &Plan::from_args(&args)).is_err());
    }
}
