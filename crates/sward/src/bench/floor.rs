//! The raster floor (`sward bench --floor`, and a section of every full run): what this device
//! does at best per second along each way a blade can reach the screen, measured with the
//! renderer's own passes on cases built to be bound by one thing each —
//!
//! - geometry: many blades on a 64 × 64 target, one sample, no culling (blades of about a pixel:
//!   the cost is the route's vertices and triangles, not its pixels), per hardware route;
//! - fragments: a few hundred huge blades filling the sweep's full resolution, no culling, at each
//!   sample count the device has (the cost is shading and testing pixels);
//! - compute rasterizer: the geometry case with every blade splatted (the compute route with its
//!   hand-over at 0); its splat pass time is its cull column less the strip case's.
//!
//! `auto` (`sward_gpu::DrawRoute::resolve`) was chosen from these and the full sweep.

use std::fmt::Write as _;

use sward_core::quality::QualityPreset;
use sward_gpu::buffer::Buffer;
use sward_gpu::target::OFFSCREEN_FORMAT;
use sward_gpu::timer::{DrawCounter, GpuTimer};
use sward_gpu::{Context, DrawRoute, Headless, RendererDesc};

use super::{grow, measure, Plan};
use crate::args::{CullMode, Preset};

/// Side of the geometry cases' target: few pixels per blade.
const TINY: u32 = 64;

/// The fewest timestamp ticks a time must span to give a rate: below it the rate would be the
/// timer's resolution, not the device's.
const RESOLVED_TICKS: f64 = 10.0;

/// `count` per second over `seconds`, where the device's timestamps (ticks of `tick_s`
/// seconds) resolve that time.
fn rate(count: f64, seconds: f64, tick_s: f64) -> Option<f64> {
    (seconds.is_finite() && seconds >= RESOLVED_TICKS * tick_s).then(|| count / seconds)
}

/// One measured rate.
pub struct FloorRow {
    /// What bounds the case: geometry, fragments or compute.
    pub kind: &'static str,
    pub route: &'static str,
    pub samples: u32,
    /// The case, as a reader would rerun it.
    pub case: String,
    /// Per second; `None` where the device's timestamps could not resolve the time it took.
    pub rate: Option<f64>,
    pub unit: &'static str,
}

/// The timer, pipeline counters and visible-count buffer the cases share.
pub struct Probes<'a> {
    pub timer: &'a mut GpuTimer,
    pub counter: Option<&'a mut DrawCounter>,
    pub visible: &'a Buffer,
}

/// Blades of the geometry cases: fewer on a CPU driver, whose every frame takes seconds.
fn geometry_blades(ctx: &Context) -> u32 {
    if ctx.info.kind == ash::vk::PhysicalDeviceType::CPU {
        1 << 14
    } else {
        1 << 20
    }
}

/// Measure every rate on this device.
pub fn measure_floor(ctx: &std::sync::Arc<Context>, plan: &Plan, probes: &mut Probes) -> anyhow::Result<Vec<FloorRow>> {
    let mut rows = Vec::new();
    let tick_s = ctx.info.timestamp_period as f64 * 1e-9;
    let blades = geometry_blades(ctx);
    let mut strips_cull_ms = 0.0;
    for route in [DrawRoute::Tessellation, DrawRoute::Strips, DrawRoute::Compute] {
        let mut scene = Preset::Cis565.scene(blades);
        scene.cull = CullMode::None.apply(&scene.cull);
        scene.lod.splat_distance = 0.0;
        let tiny = Plan {
            width: TINY,
            height: TINY,
            ..plan.clone()
        };
        let case = run_case(ctx, &tiny, probes, &scene, QualityPreset::Low, route)?;
        let draw_s = case.draw_ms * 1e-3;
        let label = format!("cis565, {blades} blades, {TINY}×{TINY}, no culling");
        if route == DrawRoute::Compute {
            // The splat pass is what the compute route's cull adds to the strips': a rate only
            // where that is more than the timer's resolution and the medians' noise (5 %).
            let added_ms = case.cull_ms - strips_cull_ms;
            let splat_s = match added_ms > 0.05 * strips_cull_ms {
                true => added_ms * 1e-3,
                false => 0.0,
            };
            rows.push(row(
                "compute",
                route,
                1,
                &label,
                rate(case.visible, splat_s, tick_s),
                "blades/s",
            ));
            continue;
        }
        if route == DrawRoute::Strips {
            strips_cull_ms = case.cull_ms;
        }
        rows.push(row(
            "geometry",
            route,
            1,
            &label,
            rate(case.visible, draw_s, tick_s),
            "blades/s",
        ));
        if case.triangles > 0.0 {
            rows.push(row(
                "geometry",
                route,
                1,
                &label,
                rate(case.triangles, draw_s, tick_s),
                "triangles/s",
            ));
        }
    }
    for quality in QualityPreset::ALL {
        let samples = ctx.info.samples_up_to(quality.msaa_samples()).as_raw();
        if samples != quality.msaa_samples() {
            continue;
        }
        let mut scene = Preset::Cis565.scene(1 << 9);
        scene.cull = CullMode::None.apply(&scene.cull);
        let case = run_case(ctx, plan, probes, &scene, quality, DrawRoute::Tessellation)?;
        if case.fragments > 0.0 {
            let label = format!("cis565, 512 huge blades, {}×{}, no culling", plan.width, plan.height);
            let rate = rate(case.fragments, case.draw_ms * 1e-3, tick_s);
            rows.push(row(
                "fragments",
                DrawRoute::Tessellation,
                samples,
                &label,
                rate,
                "fragments/s",
            ));
        }
    }
    Ok(rows)
}

fn row(
    kind: &'static str,
    route: DrawRoute,
    samples: u32,
    case: &str,
    rate: Option<f64>,
    unit: &'static str,
) -> FloorRow {
    FloorRow {
        kind,
        route: route.name(),
        samples,
        case: case.to_string(),
        rate,
        unit,
    }
}

/// Medians of one case.
struct Measured {
    draw_ms: f64,
    cull_ms: f64,
    visible: f64,
    triangles: f64,
    fragments: f64,
}

fn run_case(
    ctx: &std::sync::Arc<Context>,
    plan: &Plan,
    probes: &mut Probes,
    scene: &sward_core::Scene,
    quality: QualityPreset,
    route: DrawRoute,
) -> anyhow::Result<Measured> {
    let desc = RendererDesc::for_quality(&ctx.info, OFFSCREEN_FORMAT, quality, 1);
    let mut headless = Headless::with_desc(ctx, plan.width, plan.height, &desc)?;
    let mut scene = scene.clone();
    scene.quality.preset = quality;
    scene.quality.route = route;
    let field = grow(ctx, &mut headless, &scene)?;
    let samples = measure(&mut headless, probes, (&scene, &field), plan)?;
    let median = |f: &dyn Fn(&super::Sample) -> f64| {
        let values: Vec<f64> = samples.iter().map(f).collect();
        super::report::quantile(&values, 0.5)
    };
    Ok(Measured {
        draw_ms: median(&|s| s.gpu.draw),
        cull_ms: median(&|s| s.gpu.cull),
        visible: median(&|s| s.visible as f64),
        triangles: median(&|s| s.counts.primitives as f64),
        fragments: median(&|s| s.counts.fragments as f64),
    })
}

/// A rate as the floor prints it: a number where it was measured.
fn shown(rate: Option<f64>, unit: &str) -> String {
    match rate {
        Some(rate) => format!("{rate:.3e} {unit}"),
        None => format!("not measured (too fast for the device's timestamps to resolve) {unit}"),
    }
}

/// The floor as a Markdown section.
pub fn markdown(rows: &[FloorRow], bandwidth: Option<f64>) -> String {
    let mut md =
        String::from("### Raster floor: the most this device does per second along each way to the screen\n\n");
    let _ = writeln!(md, "| bound by | route | samples | case | rate |");
    let _ = writeln!(md, "|---|---|---|---|---|");
    for r in rows {
        let _ = writeln!(
            md,
            "| {} | {} | {}× | {} | {} |",
            r.kind,
            r.route,
            r.samples,
            r.case,
            shown(r.rate, r.unit)
        );
    }
    let _ = writeln!(
        md,
        "| memory | — | — | shader copy, read + write | {} |\n",
        shown(bandwidth.map(|gbs| gbs * 1e9), "bytes/s")
    );
    md
}

/// The floor as CSV rows.
pub fn csv(rows: &[FloorRow], device: &str) -> String {
    let mut csv = String::from("device,bound_by,route,samples,case,rate,unit\n");
    for r in rows {
        let _ = writeln!(
            csv,
            "\"{device}\",{},{},{},\"{}\",{},{}",
            r.kind,
            r.route,
            r.samples,
            r.case,
            r.rate.map_or(String::new(), |rate| format!("{rate:.6e}")),
            r.unit
        );
    }
    csv
}
