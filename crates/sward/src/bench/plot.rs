//! Bench plots as PNG: GPU frame time against blade count per culling mode (log-log), and the
//! per-pass split (simulate, cull, draw) stacked, for each preset.

use std::path::Path;

use anyhow::{anyhow, Context as _};
use plotters::prelude::*;

use super::report::{modes_of, setups, Case};

const SIZE: (u32, u32) = (960, 600);

pub fn write_all(dir: &Path, cases: &[Case]) -> anyhow::Result<()> {
    let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular());
    for setup in setups(cases) {
        let of: Vec<&Case> = cases.iter().filter(|c| c.setup() == setup).collect();
        let file = of[0].setup_file_name();
        let preset = setup.as_str();
        save(&dir.join(format!("frame-time-{file}.png")), |area| {
            frame_time(area, preset, &of)
        })?;
        save(&dir.join(format!("passes-{file}.png")), |area| {
            passes(area, preset, &of)
        })?;
    }
    Ok(())
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// Draw into an RGB buffer with `draw`, then encode it with `image`.
fn save(path: &Path, draw: impl FnOnce(&Area) -> anyhow::Result<()>) -> anyhow::Result<()> {
    let mut pixels = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let area = BitMapBackend::with_buffer(&mut pixels, SIZE).into_drawing_area();
        area.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        draw(&area)?;
        area.present().map_err(|e| anyhow!("{e}"))?;
    }
    let image = image::RgbImage::from_raw(SIZE.0, SIZE.1, pixels).context("plot buffer size")?;
    image
        .save(path)
        .with_context(|| format!("cannot write {}", path.display()))
}

/// The series legend, top left, the same on every plot.
fn legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| anyhow!("{e}"))
}

fn range_of(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if lo > hi {
        (1.0, 10.0)
    } else {
        (lo.max(1e-4) * 0.8, hi.max(lo * 1.01) * 1.25)
    }
}

fn frame_time(area: &Area, preset: &str, cases: &[&Case]) -> anyhow::Result<()> {
    let (x0, x1) = range_of(cases.iter().map(|c| c.blades as f64));
    let (y0, y1) = range_of(cases.iter().map(|c| c.frame_ms()));
    let mut chart = ChartBuilder::on(area)
        .caption(format!("{preset}: GPU frame time vs blades"), ("sans-serif", 24))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(|e| anyhow!("{e}"))?;
    chart
        .configure_mesh()
        .x_desc("blades")
        .y_desc("ms (median)")
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    let modes = modes_of(cases.iter().copied());
    for (i, mode) in modes.iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        let points: Vec<(f64, f64)> = cases
            .iter()
            .filter(|c| c.mode == *mode)
            .map(|c| (c.blades as f64, c.frame_ms()))
            .collect();
        chart
            .draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))
            .map_err(|e| anyhow!("{e}"))?
            .label(*mode)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
        chart
            .draw_series(points.iter().map(|p| Circle::new(*p, 3, color.filled())))
            .map_err(|e| anyhow!("{e}"))?;
    }
    legend(&mut chart)?;
    Ok(())
}

fn passes(area: &Area, preset: &str, cases: &[&Case]) -> anyhow::Result<()> {
    let mode = if cases.iter().any(|c| c.mode == "all") {
        "all"
    } else {
        cases.first().map_or("all", |c| c.mode)
    };
    let of: Vec<&&Case> = cases.iter().filter(|c| c.mode == mode).collect();
    let (x0, x1) = range_of(of.iter().map(|c| c.blades as f64));
    let top = of.iter().map(|c| c.frame_ms()).fold(0.0, f64::max).max(1e-3) * 1.15;
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("{preset}: time per pass, culling {mode} (stacked)"),
            ("sans-serif", 24),
        )
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d((x0..x1).log_scale(), 0.0..top)
        .map_err(|e| anyhow!("{e}"))?;
    chart
        .configure_mesh()
        .x_desc("blades")
        .y_desc("ms (median)")
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    type Layer = fn(&Case) -> f64;
    let layers: [(&str, Layer, RGBColor); 3] = [
        ("draw", |c| c.median(|s| s.gpu.frame()), RGBColor(90, 160, 90)),
        (
            "cull",
            |c| c.median(|s| s.gpu.simulate + s.gpu.cull),
            RGBColor(220, 170, 60),
        ),
        ("simulate", |c| c.median(|s| s.gpu.simulate), RGBColor(70, 110, 200)),
    ];
    for (name, top_of, color) in layers {
        let points: Vec<(f64, f64)> = of.iter().map(|c| (c.blades as f64, top_of(c))).collect();
        chart
            .draw_series(AreaSeries::new(points, 0.0, color.mix(0.85)).border_style(color))
            .map_err(|e| anyhow!("{e}"))?
            .label(name)
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], color.filled()));
    }
    legend(&mut chart)?;
    Ok(())
}
