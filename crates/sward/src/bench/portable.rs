//! `sward bench --renderer wgpu`: the sweep's scenes measured on the portable renderer (WGSL
//! through wgpu's safe API, on the wgpu backend asked for) with wgpu's timestamps around its
//! simulate, depth pyramid (the occluders column, as the Vulkan renderer's), cull and draw, into
//! the same tables and CSV files as the Vulkan renderer's, so the two renderers compare case by
//! case. The device gets the adapter's own limits (a field of
//! millions of blades needs more than WebGPU's default bindings).

use std::time::Instant;

use anyhow::{bail, Context as _};
use sward_core::{Field, FrameDesc, Scene};
use sward_gpu::timer::PassTimes;
use sward_wgpu::portable::{open_device_with, portable_limits, PortableHeadless, PortablePasses};
use sward_wgpu::wgpu;

use super::{Case, Job, Plan, RunInfo, Sample};
use crate::args::{BenchArgs, GpuArgs};

/// Timestamps a frame writes: before simulate, the occluders, cull, the shadow map and the
/// draw, and after the draw.
const STAMPS: u32 = 6;

/// The route name the portable renderer's cases carry.
const ROUTE: &str = "wgpu-strips";

/// Measure `jobs` as `plan` says on the portable renderer: the run's description and its cases,
/// and a line for each job it could not measure.
pub fn sweep(
    args: &BenchArgs,
    gpu: &GpuArgs,
    plan: &Plan,
    jobs: &[Job],
) -> anyhow::Result<(RunInfo, Vec<Case>, Vec<String>)> {
    let timestamps = wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
    let ask = |adapter: &wgpu::Adapter| {
        let features = (adapter.features() & timestamps) | gpu.portable_features(adapter);
        (features, portable_limits(adapter))
    };
    let (adapter, device, queue) = open_device_with(args.renderer.wgpu_backends(), gpu.validation, ask)?;
    let info = adapter.get_info();
    if !device.features().contains(timestamps) {
        bail!(
            "the portable bench times passes with GPU timestamps inside command encoders, which {} on wgpu's {:?} backend does not have",
            info.name,
            info.backend
        );
    }
    let run = RunInfo {
        device: info.name.clone(),
        driver: format!("{} {} (wgpu {:?})", info.driver, info.driver_info, info.backend),
        resolution: [plan.width, plan.height],
        commit: env!("SWARD_COMMIT"),
        warmup: plan.warmup,
        frames: plan.frames,
        bandwidth: None,
        variant: format!(
            "portable renderer (--renderer wgpu){}{}",
            if args.wgsl_checks {
                ", WGSL with WebGPU's checks"
            } else {
                ""
            },
            if gpu.narrow_splats { ", 32-bit splat cells" } else { "" }
        ),
        command: std::env::args().collect::<Vec<_>>().join(" "),
    };
    let mut cases = Vec::new();
    let mut stopped = Vec::new();
    let device = (adapter, device, queue);
    let modules = crate::portable::shader_modules(args.shaders.as_deref())?.with_checks(args.wgsl_checks);
    let modules = gpu.splat_modules(modules)?;
    for &quality in &plan.qualities {
        let size = [plan.width, plan.height];
        let mut headless = PortableHeadless::made_of(device.clone(), size, quality.msaa_samples(), modules.clone())?;
        for job in jobs {
            let name = job.label.clone().unwrap_or_else(|| job.preset.clone());
            let mut scene = job.scene.clone();
            scene.quality.preset = quality;
            let field = match grow(&mut headless, &scene) {
                Ok(field) => field,
                Err(e) => {
                    stopped.push(format!("{name}: stopped at {} blades: {e:#}", job.count));
                    continue;
                }
            };
            for (&mode, &speed) in job.modes.iter().flat_map(|m| job.speeds.iter().map(move |v| (m, v))) {
                eprintln!(
                    "sward: {name} {} blades, culling {}, {}",
                    job.count,
                    mode.name(),
                    quality.name()
                );
                let mut scene = scene.clone();
                scene.cull = mode.apply(&scene.cull);
                scene.camera_path = super::moving_at(&scene, speed);
                let samples = measure(&mut headless, (&scene, &field), plan)?;
                cases.push(Case {
                    label: job.label.clone(),
                    preset: job.preset.clone(),
                    technique: scene.technique.name(),
                    route: ROUTE,
                    quality: quality.name(),
                    msaa: quality.msaa_samples(),
                    blades: job.count,
                    mode: mode.name(),
                    speed,
                    memory_mib: headless.memory_bytes() as f64 / (1 << 20) as f64,
                    largest_allocations: headless.largest_allocations(super::LARGEST_ALLOCATIONS),
                    samples,
                });
            }
        }
    }
    Ok((run, cases, stopped))
}

/// Grow `scene`'s field and upload it, or say why the portable renderer cannot hold it.
fn grow(headless: &mut PortableHeadless, scene: &Scene) -> anyhow::Result<Field> {
    let field = scene.grow_field()?;
    headless.upload(&field)?;
    Ok(field)
}

/// Warm up, then time frames until `plan.frames` are in (or the case's time budget is spent,
/// keeping at least 20).
fn measure(
    headless: &mut PortableHeadless,
    (scene, field): (&Scene, &Field),
    plan: &Plan,
) -> anyhow::Result<Vec<Sample>> {
    let timer = StampReader::new(&headless.device);
    let period = headless.queue.get_timestamp_period() as f64 * 1e-6;
    let ground = field.ground.as_ref().and_then(|m| m.height_grid());
    let mut moved = scene.clone();
    let mut window = super::SampleWindow::new(plan);
    let mut samples = Vec::new();
    for frame in 0..plan.warmup + plan.frames {
        let cpu_start = Instant::now();
        let clock = (frame as f32 * scene.simulation.step, 1);
        moved.camera = scene.camera_path.camera_over(&scene.camera, clock.0, ground.as_ref());
        let desc = FrameDesc::of_scene(&moved, field.size, clock, [plan.width, plan.height]);
        let mut encoder = headless.device.create_command_encoder(&Default::default());
        let passes = [
            PortablePasses {
                occluders: true,
                ..Default::default()
            },
            PortablePasses::SIMULATE,
            PortablePasses {
                cull: true,
                ..Default::default()
            },
        ];
        for (k, passes) in passes.into_iter().enumerate() {
            encoder.write_timestamp(&timer.queries, k as u32);
            headless.record(&mut encoder, &desc, passes)?;
        }
        encoder.write_timestamp(&timer.queries, 3);
        headless.record_shadow_map(&mut encoder)?;
        encoder.write_timestamp(&timer.queries, 4);
        headless.record_lit_draw(&mut encoder)?;
        encoder.write_timestamp(&timer.queries, 5);
        timer.resolve(&mut encoder);
        headless.queue.submit([encoder.finish()]);
        let cpu_ms = cpu_start.elapsed().as_secs_f64() * 1e3;
        let at = timer.read(&headless.device)?;
        headless.take_fault()?;
        if !window.samples(frame) {
            continue;
        }
        let ms = |k: usize| at[k + 1].saturating_sub(at[k]) as f64 * period;
        samples.push(Sample {
            gpu: PassTimes {
                simulate: ms(0),
                occluders: ms(1),
                cull: ms(2),
                shadows: ms(3),
                draw: ms(4),
                ..PassTimes::default()
            },
            cpu_ms,
            visible: headless.visible_count()?,
            splatted: headless.splatted_count()?,
            simulated: headless.blades_run()?,
            counts: Default::default(),
        });
        if window.full(samples.len()) {
            break;
        }
    }
    Ok(samples)
}

/// A frame's timestamps: the query set, and the buffers they are resolved into and read from.
struct StampReader {
    queries: wgpu::QuerySet,
    resolved: wgpu::Buffer,
    read: wgpu::Buffer,
}

impl StampReader {
    fn new(device: &wgpu::Device) -> StampReader {
        let buffer = |usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sward bench timestamps"),
                size: 8 * STAMPS as u64,
                usage,
                mapped_at_creation: false,
            })
        };
        StampReader {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("sward bench timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: STAMPS,
            }),
            resolved: buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC),
            read: buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST),
        }
    }

    /// Resolve the frame's timestamps at the end of `encoder`.
    fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.queries, 0..STAMPS, &self.resolved, 0);
        encoder.copy_buffer_to_buffer(&self.resolved, 0, &self.read, 0, 8 * STAMPS as u64);
    }

    /// The timestamps, once the frame has finished.
    fn read(&self, device: &wgpu::Device) -> anyhow::Result<Vec<u64>> {
        self.read.slice(..).map_async(wgpu::MapMode::Read, |_| {});
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .context("waiting for the frame's timestamps")?;
        let stamps = self
            .read
            .slice(..)
            .get_mapped_range()
            .context("reading the frame's timestamps")?
            .as_chunks::<8>()
            .0
            .iter()
            .map(|b| u64::from_le_bytes(*b))
            .collect();
        self.read.unmap();
        Ok(stamps)
    }
}
