//! The study's plots: relative RMSE against seconds and against spp, log–log, one line per
//! configuration with its band over seeds, and plain Monte Carlo's 1/√N slope; as SVG and PNG
//! (text drawn with the embedded DejaVu Sans, so no system fonts are needed).

use super::report::Summary;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;
use stratapt_scene::{SamplerKind, Strategy};

/// Plot size in pixels, and the width of the legend column on its right.
const SIZE: (u32, u32) = (1100, 680);
const LEGEND_WIDTH: u32 = 250;

/// Which axis the errors are plotted against.
#[derive(Clone, Copy)]
pub enum Axis {
    Seconds,
    Spp,
}

impl Axis {
    fn label(self) -> &'static str {
        match self {
            Self::Seconds => "render time (s)",
            Self::Spp => "samples per pixel",
        }
    }
}

/// Write `stem.svg` and `stem.png` in `dir`.
pub fn write(
    dir: &Path,
    stem: &str,
    title: &str,
    axis: Axis,
    summaries: &[Summary],
) -> anyhow::Result<()> {
    static FONT: Once = Once::new();
    FONT.call_once(|| {
        // DejaVu Sans is a valid font: registration cannot fail.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        draw(root, title, axis, summaries).map_err(|e| anyhow::anyhow!("{stem}.svg: {e}"))?;
    }
    super::write_atomically(&dir.join(format!("{stem}.svg")), svg.as_bytes())?;
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        draw(root, title, axis, summaries).map_err(|e| anyhow::anyhow!("{stem}.png: {e}"))?;
    }
    use image::ImageEncoder as _;
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(&rgb, SIZE.0, SIZE.1, image::ExtendedColorType::Rgb8)
        .map_err(|e| anyhow::anyhow!("{stem}.png: {e}"))?;
    super::write_atomically(&dir.join(format!("{stem}.png")), &png)
}

/// (x, mean relative RMSE, lowest and highest over seeds) per level with an error.
fn points(summary: &Summary, axis: Axis) -> Vec<(f64, f64, f64, f64)> {
    summary
        .levels
        .iter()
        .filter(|l| l.relmse > 0.0)
        .map(|l| {
            let x = match axis {
                Axis::Seconds => l.seconds.max(1e-6),
                Axis::Spp => l.spp as f64,
            };
            let (lo, hi) = l.rel_rmse_range;
            (x, l.relmse.sqrt(), lo.max(l.relmse.sqrt() * 1e-3), hi)
        })
        .collect()
}

/// A tick label: 3 significant digits, in exponent form below 0.001 or from 10 000.
fn short(v: f64) -> String {
    if v != 0.0 && !(1e-3..1e4).contains(&v.abs()) {
        format!("{v:.0e}")
    } else {
        let text = format!("{v:.3}");
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// Colour of a strategy's lines (the same in every plot).
fn strategy_color(strategy: Strategy) -> RGBColor {
    match strategy {
        Strategy::Uniform => RGBColor(140, 140, 140),
        Strategy::Cosine => RGBColor(230, 159, 0),
        Strategy::Bsdf => RGBColor(0, 158, 115),
        Strategy::Light => RGBColor(86, 180, 233),
        Strategy::Mis => RGBColor(213, 94, 0),
    }
}

/// Line width of a sampler's lines: the better stratified, the bolder.
fn sampler_width(sampler: SamplerKind) -> u32 {
    match sampler {
        SamplerKind::Independent => 1,
        SamplerKind::Stratified => 2,
        SamplerKind::Sobol => 3,
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    axis: Axis,
    summaries: &[Summary],
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let (area, legend) = root.split_horizontally(SIZE.0 - LEGEND_WIDTH);
    let all: Vec<Vec<(f64, f64, f64, f64)>> = summaries.iter().map(|s| points(s, axis)).collect();
    let flat: Vec<&(f64, f64, f64, f64)> = all.iter().flatten().collect();
    if flat.is_empty() {
        return Ok(());
    }
    let fold = |f: fn(f64, f64) -> f64, init: f64, pick: fn(&(f64, f64, f64, f64)) -> f64| {
        flat.iter().map(|p| pick(p)).fold(init, f)
    };
    let (x0, x1) = (
        fold(f64::min, f64::INFINITY, |p| p.0),
        fold(f64::max, 0.0, |p| p.0),
    );
    let (y0, y1) = (
        fold(f64::min, f64::INFINITY, |p| p.2.min(p.1)),
        fold(f64::max, 0.0, |p| p.3.max(p.1)),
    );
    let mut chart = ChartBuilder::on(&area)
        .caption(title, ("sans-serif", 20))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(
            (x0 / 1.3..x1 * 1.3).log_scale(),
            (y0 / 1.5..y1 * 1.5).log_scale(),
        )
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(axis.label())
        .y_desc("relative RMSE  √relMSE")
        .x_labels(10)
        .y_labels(10)
        .light_line_style(WHITE.mix(0.0))
        .y_label_formatter(&|v| short(*v))
        .x_label_formatter(&|v| short(*v))
        .draw()
        .map_err(err)?;
    // Plain Monte Carlo's rate, through the first point of the worst configuration.
    if let Some(worst) = all
        .iter()
        .filter(|p| !p.is_empty())
        .max_by(|a, b| a[0].1.total_cmp(&b[0].1))
    {
        let (ax, ay) = (worst[0].0, worst[0].1);
        let line: Vec<(f64, f64)> = [x0, x1]
            .iter()
            .map(|&x| (x, ay * (x / ax).powf(-0.5)))
            .collect();
        chart
            .draw_series(LineSeries::new(line, BLACK.stroke_width(1)))
            .map_err(err)?;
    }
    for (summary, pts) in summaries.iter().zip(&all) {
        let color = strategy_color(summary.strategy);
        let width = sampler_width(summary.sampler);
        chart
            .draw_series(LineSeries::new(
                pts.iter().map(|p| (p.0, p.1)),
                color.stroke_width(width),
            ))
            .map_err(err)?;
        // The band over seeds: lowest to highest error at each level.
        chart
            .draw_series(
                pts.iter()
                    .map(|p| PathElement::new(vec![(p.0, p.2), (p.0, p.3)], color.stroke_width(1))),
            )
            .map_err(err)?;
        chart
            .draw_series(
                pts.iter()
                    .map(|p| Circle::new((p.0, p.1), 1 + width, color.filled())),
            )
            .map_err(err)?;
    }
    // ---- The legend, beside the chart: best configuration first -----------------------------
    let font = ("sans-serif", 13).into_font();
    let mut y = 40;
    legend
        .draw(&Text::new(
            "sampler / strategy (by efficiency)",
            (4, y - 22),
            font.clone(),
        ))
        .map_err(err)?;
    legend
        .draw(&PathElement::new(
            vec![(6, y), (30, y)],
            BLACK.stroke_width(1),
        ))
        .map_err(err)?;
    legend
        .draw(&Text::new(
            "1/√N (plain Monte Carlo)",
            (36, y - 7),
            font.clone(),
        ))
        .map_err(err)?;
    for summary in summaries {
        y += 20;
        let color = strategy_color(summary.strategy);
        let width = sampler_width(summary.sampler);
        legend
            .draw(&PathElement::new(
                vec![(6, y), (30, y)],
                color.stroke_width(width),
            ))
            .map_err(err)?;
        legend
            .draw(&Circle::new((18, y), 1 + width, color.filled()))
            .map_err(err)?;
        legend
            .draw(&Text::new(
                format!("{} / {}", summary.sampler, summary.strategy),
                (36, y - 7),
                font.clone(),
            ))
            .map_err(err)?;
    }
    y += 30;
    for line in [
        "colour: strategy",
        "line width: sampler",
        "(independent thin,",
        " stratified, sobol bold)",
        "bars: range over seeds",
    ] {
        legend
            .draw(&Text::new(line, (6, y), font.clone()))
            .map_err(err)?;
        y += 18;
    }
    root.present().map_err(err)?;
    Ok(())
}
