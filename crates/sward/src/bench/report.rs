//! Bench results: statistics (median, p95), the Markdown tables (blade counts × culling modes, and
//! per pass), the fitted growth exponent, the bandwidth floor of simulate + cull, and CSV files.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Context as _;
use sward_gpu::timer::{DrawCounts, PassTimes};

use super::RunInfo;

/// One timed frame.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    pub gpu: PassTimes,
    /// The host's frame: the uniforms worked out, the frame recorded (or its kept passes
    /// replayed) and submitted, without waiting for the GPU.
    pub cpu_ms: f64,
    pub visible: u32,
    /// Of the visible blades, those the generated grass drew by compute (splatted or
    /// rasterized) instead of by the raster hardware.
    pub splatted: u32,
    /// Blades in the tiles the frame ran (all blades without tile culling).
    pub simulated: u32,
    /// Geometry and pixels the GPU counted (zero where it has no pipeline statistics).
    pub counts: DrawCounts,
}

/// All frames of one (preset, blade count, culling mode).
#[derive(Clone, Debug)]
pub struct Case {
    /// Its name in a named set (`--regression-set`, `--shipped`).
    pub label: Option<String>,
    pub preset: String,
    /// The technique the scene was drawn with.
    pub technique: &'static str,
    /// The Bezier blades' draw route (resolved, never `auto`).
    pub route: &'static str,
    /// The quality preset and the samples per pixel it got on this device.
    pub quality: &'static str,
    pub msaa: u32,
    pub blades: u32,
    pub mode: &'static str,
    /// How fast the camera moves along the scene's path, units per second (0: it stands).
    pub speed: f32,
    /// GPU memory sward held for the case, MiB: the field's blades, the lists, maps and targets.
    pub memory_mib: f64,
    /// Its largest allocations, by name, bytes, largest first (`memory.csv`).
    pub largest_allocations: Vec<(String, u64)>,
    pub samples: Vec<Sample>,
}

/// Bytes simulate + cull must move per blade, however they are scheduled: read the 64-byte blade
/// and its 4-byte η, write back the 32 bytes of v1 and v2 that change, and η. Each visible blade
/// adds a 4-byte index. (Separate passes read the blade a second time; the floor does not count it.)
pub const BYTES_PER_BLADE: f64 = 64.0 + 4.0 + 32.0 + 4.0;
pub const BYTES_PER_VISIBLE: f64 = 4.0;

/// The `q`-quantile (0..=1) of `values`, nearest rank.
pub fn quantile(values: &[f64], q: f64) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let rank = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[rank - 1]
}

impl Case {
    /// What the case's tables are headed by: preset, route and quality.
    pub fn setup(&self) -> String {
        format!(
            "{}{} · {} · {} ({}× MSAA)",
            self.preset,
            self.moving(" at ", " m/s"),
            self.route,
            self.quality,
            self.msaa
        )
    }

    /// The setup as a file name.
    pub fn setup_file_name(&self) -> String {
        format!(
            "{}{}-{}-{}",
            self.preset,
            self.moving("-", "ms"),
            self.route,
            self.quality
        )
    }

    /// The camera's speed between `before` and `after` where it moves, else nothing.
    fn moving(&self, before: &str, after: &str) -> String {
        match self.speed > 0.0 {
            true => format!("{before}{}{after}", self.speed),
            false => String::new(),
        }
    }

    /// Frames that took over 1.5 times the median of the ten frames around them: hitches, not
    /// a change of view.
    pub fn hitches(&self) -> usize {
        let frames = self.series(|s| s.gpu.frame());
        (0..frames.len())
            .filter(|&i| {
                let around = &frames[i.saturating_sub(5)..(i + 6).min(frames.len())];
                frames[i] > 1.5 * quantile(around, 0.5)
            })
            .count()
    }

    pub fn series(&self, f: impl Fn(&Sample) -> f64) -> Vec<f64> {
        self.samples.iter().map(f).collect()
    }
    pub fn median(&self, f: impl Fn(&Sample) -> f64) -> f64 {
        quantile(&self.series(f), 0.5)
    }
    pub fn p95(&self, f: impl Fn(&Sample) -> f64) -> f64 {
        quantile(&self.series(f), 0.95)
    }
    /// Median GPU time of simulate + cull + draw, ms.
    pub fn frame_ms(&self) -> f64 {
        self.median(|s| s.gpu.frame())
    }
    pub fn visible(&self) -> f64 {
        self.median(|s| s.visible as f64)
    }

    pub fn splatted(&self) -> f64 {
        self.median(|s| s.splatted as f64)
    }
    pub fn simulated(&self) -> f64 {
        self.median(|s| s.simulated as f64)
    }
    /// Simulate + cull time if they only moved their bytes at the measured copy bandwidth, ms
    /// (`None` where the bandwidth was not measured).
    pub fn bandwidth_floor_ms(&self, bandwidth_gbs: Option<f64>) -> Option<f64> {
        let bytes = self.simulated() * BYTES_PER_BLADE + self.visible() * BYTES_PER_VISIBLE;
        bandwidth_gbs.map(|gbs| bytes / (gbs * 1e9) * 1e3)
    }
}

fn blades_label(n: u32) -> String {
    if n.is_power_of_two() {
        format!("2^{} ({n})", n.trailing_zeros())
    } else {
        n.to_string()
    }
}

/// Least-squares slope of log(time) over log(blades): time ∝ blades^slope.
pub fn growth_exponent(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(b, t)| *b > 0.0 && *t > 0.0)
        .map(|(b, t)| (b.ln(), t.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// The setups (preset, route, quality) among `cases`, in order of first appearance.
pub fn setups<'a>(cases: impl IntoIterator<Item = &'a Case>) -> Vec<String> {
    let mut seen: Vec<String> = Vec::new();
    for setup in cases.into_iter().map(Case::setup) {
        if !seen.contains(&setup) {
            seen.push(setup);
        }
    }
    seen
}

/// The culling modes among `cases`, in order of first appearance.
pub fn modes_of<'a>(cases: impl IntoIterator<Item = &'a Case>) -> Vec<&'static str> {
    distinct(cases.into_iter().map(|c| c.mode))
}

fn distinct(names: impl Iterator<Item = &'static str>) -> Vec<&'static str> {
    let mut seen = Vec::new();
    for name in names {
        if !seen.contains(&name) {
            seen.push(name);
        }
    }
    seen
}

/// The whole report as Markdown.
pub fn markdown(info: &RunInfo, cases: &[Case], stopped: &[String]) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "device: {} — driver: {} — {}×{} — commit {}",
        info.device, info.driver, info.resolution[0], info.resolution[1], info.commit
    );
    let _ = writeln!(
        md,
        "{} warm-up frames, up to {} timed frames per case; shader copy bandwidth {} (read + write)",
        info.warmup,
        info.frames,
        info.bandwidth
            .map_or("not measured".to_string(), |gbs| format!("{gbs:.1} GB/s"))
    );
    let _ = writeln!(md, "renderer: {}", info.variant);
    let _ = writeln!(md, "command: `{}`\n", info.command);
    for setup in setups(cases) {
        let of: Vec<&Case> = cases.iter().filter(|c| c.setup() == setup).collect();
        frame_table(&mut md, &setup, &of);
        pass_table(&mut md, &setup, &of, info.bandwidth);
        exponents(&mut md, &of);
    }
    pacing_table(&mut md, cases);
    for line in stopped {
        let _ = writeln!(md, "- {line}");
    }
    md
}

/// Frame pacing of every case: what a player feels while the camera moves.
fn pacing_table(md: &mut String, cases: &[Case]) {
    let _ = writeln!(
        md,
        "### frame pacing, ms\n\n| setup | blades | culling | GPU median | GPU p99 | GPU worst | hitches | CPU median | CPU p99 |\n|---|---|---|---|---|---|---|---|---|"
    );
    for c in cases {
        let gpu = c.series(|s| s.gpu.frame());
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.3} | {:.3} | {:.3} | {} of {} | {:.3} | {:.3} |",
            c.setup(),
            c.blades,
            c.mode,
            quantile(&gpu, 0.5),
            quantile(&gpu, 0.99),
            gpu.iter().copied().fold(f64::NAN, f64::max),
            c.hitches(),
            gpu.len(),
            c.median(|s| s.cpu_ms),
            quantile(&c.series(|s| s.cpu_ms), 0.99),
        );
    }
    md.push('\n');
}

fn frame_table(md: &mut String, preset: &str, cases: &[&Case]) {
    let modes = modes_of(cases.iter().copied());
    let _ = writeln!(
        md,
        "### {preset}: GPU frame time (simulate + cull + draw, median) by culling mode\n"
    );
    let _ = writeln!(md, "| blades | {} |", modes.join(" | "));
    let _ = writeln!(md, "|---|{}", "---|".repeat(modes.len()));
    let mut counts: Vec<u32> = cases.iter().map(|c| c.blades).collect();
    counts.dedup();
    for count in counts {
        let cells: Vec<String> = modes
            .iter()
            .map(|m| match cases.iter().find(|c| c.blades == count && c.mode == *m) {
                Some(c) => format!("{:.1} FPS ({:.3} ms)", 1000.0 / c.frame_ms(), c.frame_ms()),
                None => "–".into(),
            })
            .collect();
        let _ = writeln!(md, "| {} | {} |", blades_label(count), cells.join(" | "));
    }
    md.push('\n');
}

fn pass_table(md: &mut String, preset: &str, cases: &[&Case], bandwidth: Option<f64>) {
    let _ = writeln!(md, "### {preset}: per pass, median / p95 ms\n");
    let _ = writeln!(
        md,
        "| blades | culling | route | quality | occluders | trample | simulate | cull | blade shadows | draw | GPU frame | CPU frame | simulated blades | visible blades | of them by compute | sim+cull floor | triangles | fragments |"
    );
    let _ = writeln!(
        md,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for c in cases {
        let pair = |f: &dyn Fn(&Sample) -> f64| format!("{:.3} / {:.3}", c.median(f), c.p95(f));
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.0} | {:.0} | {:.0} | {} | {:.3e} | {:.3e} |",
            blades_label(c.blades),
            c.mode,
            c.route,
            c.quality,
            pair(&|s| s.gpu.occluders),
            pair(&|s| s.gpu.trample),
            pair(&|s| s.gpu.simulate),
            pair(&|s| s.gpu.cull),
            pair(&|s| s.gpu.shadows),
            pair(&|s| s.gpu.draw),
            pair(&|s| s.gpu.frame()),
            pair(&|s| s.cpu_ms),
            c.simulated(),
            c.visible(),
            c.splatted(),
            c.bandwidth_floor_ms(bandwidth)
                .map_or("not measured".to_string(), |ms| format!("{ms:.3}")),
            c.median(|s| s.counts.primitives as f64),
            c.median(|s| s.counts.fragments as f64),
        );
    }
    md.push('\n');
}

fn exponents(md: &mut String, cases: &[&Case]) {
    // Small counts are dominated by fixed costs; fit where the work dominates, if there is data.
    let floor = if cases.iter().filter(|c| c.blades >= 1 << 16).count() >= 2 {
        1 << 16
    } else {
        0
    };
    let mut line = format!("GPU frame time ∝ blades^k, k fitted over counts ≥ {floor}:");
    for mode in modes_of(cases.iter().copied()) {
        let points: Vec<(f64, f64)> = cases
            .iter()
            .filter(|c| c.mode == mode && c.blades >= floor)
            .map(|c| (c.blades as f64, c.frame_ms()))
            .collect();
        if let Some(k) = growth_exponent(&points) {
            let _ = write!(line, " {mode} {k:.2};");
        }
    }
    let _ = writeln!(md, "{line}\n");
}

/// results.md (`markdown`, the whole report), summary.csv (one row per case) and frames.csv (one
/// row per frame).
pub fn write_all(dir: &Path, markdown: &str, info: &RunInfo, cases: &[Case]) -> anyhow::Result<()> {
    let write = |name: &str, text: String| {
        std::fs::write(dir.join(name), text).with_context(|| format!("cannot write {}", dir.join(name).display()))
    };
    write("results.md", markdown.to_string())?;
    let mut frames = String::from(
        "preset,route,quality,blades,culling,frame,occluders_ms,simulate_ms,cull_ms,shadows_ms,draw_ms,gpu_frame_ms,cpu_ms,visible,trample_ms\n",
    );
    let mut summary = String::from(
        "device,driver,width,height,commit,case,preset,technique,route,quality,msaa,blades,culling,speed,frames,simulate_median_ms,cull_median_ms,shadows_median_ms,draw_median_ms,gpu_frame_median_ms,gpu_frame_p95_ms,gpu_frame_p99_ms,cpu_median_ms,cpu_p95_ms,visible_median,fragments_median,floor_ms,trample_median_ms,gpu_memory_mib\n",
    );
    for c in cases {
        for (i, s) in c.samples.iter().enumerate() {
            let g = s.gpu;
            let _ = writeln!(
                frames,
                "{},{},{},{},{},{i},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{},{:.5}",
                c.preset,
                c.route,
                c.quality,
                c.blades,
                c.mode,
                g.occluders,
                g.simulate,
                g.cull,
                g.shadows,
                g.draw,
                g.frame(),
                s.cpu_ms,
                s.visible,
                g.trample
            );
        }
        let _ = writeln!(
            summary,
            "\"{}\",\"{}\",{},{},{},\"{}\",{},{},{},{},{},{},{},{},{},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.5},{:.0},{:.0},{},{:.5},{:.1}",
            info.device,
            info.driver,
            info.resolution[0],
            info.resolution[1],
            info.commit,
            c.label.as_deref().unwrap_or(""),
            c.preset,
            c.technique,
            c.route,
            c.quality,
            c.msaa,
            c.blades,
            c.mode,
            c.speed,
            c.samples.len(),
            c.median(|s| s.gpu.simulate),
            c.median(|s| s.gpu.cull),
            c.median(|s| s.gpu.shadows),
            c.median(|s| s.gpu.draw),
            c.frame_ms(),
            c.p95(|s| s.gpu.frame()),
            quantile(&c.series(|s| s.gpu.frame()), 0.99),
            c.median(|s| s.cpu_ms),
            c.p95(|s| s.cpu_ms),
            c.visible(),
            c.median(|s| s.counts.fragments as f64),
            c.bandwidth_floor_ms(info.bandwidth)
                .map_or(String::new(), |ms| format!("{ms:.5}")),
            c.median(|s| s.gpu.trample),
            c.memory_mib
        );
    }
    write("frames.csv", frames)?;
    write("summary.csv", summary)?;
    write("memory.csv", memory_csv(cases))
}

/// memory.csv: each case's largest allocations, MiB, largest first (where its memory goes).
fn memory_csv(cases: &[Case]) -> String {
    let mut text = String::from("case,preset,technique,blades,culling,allocation,mib\n");
    for c in cases {
        for (name, bytes) in &c.largest_allocations {
            let _ = writeln!(
                text,
                "\"{}\",{},{},{},{},\"{}\",{:.1}",
                c.label.as_deref().unwrap_or(""),
                c.preset,
                c.technique,
                c.blades,
                c.mode,
                name.replace('"', "'"),
                *bytes as f64 / (1 << 20) as f64
            );
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_use_nearest_rank() {
        let v: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(quantile(&v, 0.5), 50.0);
        assert_eq!(quantile(&v, 0.95), 95.0);
        assert_eq!(quantile(&[3.0], 0.95), 3.0);
    }

    #[test]
    fn growth_exponent_recovers_a_power_law() {
        let points: Vec<(f64, f64)> = (10..20).map(|e| (2f64.powi(e), 3.0 * 2f64.powi(e).powf(0.8))).collect();
        assert!((growth_exponent(&points).unwrap() - 0.8).abs() < 1e-9);
        assert!(growth_exponent(&points[..1]).is_none());
    }
}
