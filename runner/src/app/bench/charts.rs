//! The benchmark's charts (plotters, drawn into memory and saved as PNG): frame time
//! against blade count per configuration, pass times against blade count, and what
//! each configuration costs at the largest count.

use super::stats::{Point, Spread};
use crate::cli::BenchConfig;
use anyhow::{Result, anyhow};
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

/// Chart size in pixels.
const SIZE: (u32, u32) = (1000, 640);

/// Registers the font plotters draws text with: egui's Ubuntu Light, already in the
/// binary, so charts need no system fonts.
fn register_font() {
    static FONT: Once = Once::new();
    FONT.call_once(|| {
        let font = epaint_default_fonts::UBUNTU_LIGHT;
        if plotters::style::register_font("sans-serif", FontStyle::Normal, font).is_err() {
            log::warn!("charts: the built-in font did not load; labels may be missing");
        }
    });
}

/// Draws into an RGB buffer with `draw`, then writes it to `path` as PNG.
fn save(
    path: &Path,
    draw: impl FnOnce(&DrawingArea<BitMapBackend, plotters::coord::Shift>) -> Result<()>,
) -> Result<()> {
    register_font();
    let mut pixels = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        draw(&root)?;
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    crate::files::save_png(path, &pixels, SIZE, image::ColorType::Rgb8)?;
    Ok(())
}

/// The points of `config`, by blade count.
fn series(points: &[Point], config: BenchConfig) -> Vec<&Point> {
    points.iter().filter(|p| p.config == config).collect()
}

/// A log-log chart of `value` against blade count, one line per configuration.
fn log_log(path: &Path, title: &str, lines: &[(String, Vec<(f64, f64)>)]) -> Result<()> {
    let all: Vec<(f64, f64)> = lines.iter().flat_map(|(_, l)| l.iter().copied()).collect();
    if all.is_empty() {
        return Ok(());
    }
    let fold = |f: fn(f64, f64) -> f64, pick: fn(&(f64, f64)) -> f64, start| {
        all.iter().map(pick).fold(start, f)
    };
    let (x0, x1) = (
        fold(f64::min, |p| p.0, f64::MAX),
        fold(f64::max, |p| p.0, 0.0),
    );
    let (y0, y1) = (
        fold(f64::min, |p| p.1, f64::MAX),
        fold(f64::max, |p| p.1, 0.0),
    );
    save(path, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 26))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(72)
            .build_cartesian_2d(
                (x0 * 0.8..x1 * 1.25).log_scale(),
                (y0.max(1e-4) * 0.8..y1 * 1.25).log_scale(),
            )
            .map_err(|e| anyhow!("{e}"))?;
        chart
            .configure_mesh()
            .x_desc("blades")
            .y_desc("ms (median)")
            .x_label_formatter(&|x| format!("{x:.0}"))
            .y_label_formatter(&|y| format!("{y}"))
            .label_style(("sans-serif", 16))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        for (i, (name, line)) in lines.iter().enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            chart
                .draw_series(LineSeries::new(
                    line.iter().copied(),
                    colour.stroke_width(2),
                ))
                .map_err(|e| anyhow!("{e}"))?
                .label(name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
            chart
                .draw_series(line.iter().map(|&p| Circle::new(p, 3, colour.filled())))
                .map_err(|e| anyhow!("{e}"))?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 16))
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        Ok(())
    })
}

/// GPU frame time per configuration at the largest blade count, as bars.
fn bars(path: &Path, points: &[Point]) -> Result<()> {
    let Some(largest) = points.iter().map(|p| p.blades).max() else {
        return Ok(());
    };
    let bars: Vec<(String, Spread, f64)> = points
        .iter()
        .filter(|p| p.blades == largest)
        .map(|p| (format!("{:?}", p.config), p.gpu, p.drawn))
        .collect();
    let top = bars.iter().map(|b| b.1.p95).fold(0.0, f64::max) * 1.2;
    let n = bars.len();
    save(path, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!("GPU frame at {largest} blades: median (bar), p95 (line), drawn"),
                ("sans-serif", 24),
            )
            .margin(16)
            .x_label_area_size(60)
            .y_label_area_size(72)
            .build_cartesian_2d(0f64..n as f64, 0f64..top.max(1e-3))
            .map_err(|e| anyhow!("{e}"))?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(0)
            .y_desc("ms")
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        for (i, (name, gpu, drawn)) in bars.iter().enumerate() {
            let x = i as f64;
            let colour = Palette99::pick(i).to_rgba();
            chart
                .draw_series([Rectangle::new(
                    [(x + 0.15, 0.0), (x + 0.85, gpu.median)],
                    colour.filled(),
                )])
                .map_err(|e| anyhow!("{e}"))?;
            chart
                .draw_series([PathElement::new(
                    vec![(x + 0.15, gpu.p95), (x + 0.85, gpu.p95)],
                    BLACK,
                )])
                .map_err(|e| anyhow!("{e}"))?;
            chart
                .draw_series([Text::new(
                    format!("{name}: {:.2} ms, {drawn:.0} drawn", gpu.median),
                    (x + 0.15, gpu.p95 + top * 0.02),
                    ("sans-serif", 13),
                )])
                .map_err(|e| anyhow!("{e}"))?;
        }
        Ok(())
    })
}

/// Writes `<stem>_frame.png`, `<stem>_passes.png` and `<stem>_configs.png` next to
/// the CSV at `csv`; returns their paths.
pub fn write(csv: &Path, title: &str, points: &[Point]) -> Result<Vec<std::path::PathBuf>> {
    let stem = csv.with_extension("");
    let path = |suffix: &str| {
        let mut p = stem.clone().into_os_string();
        p.push(suffix);
        std::path::PathBuf::from(p)
    };
    let line = |config, value: fn(&Point) -> f64| -> Vec<(f64, f64)> {
        series(points, config)
            .iter()
            .map(|p| (f64::from(p.blades), value(p)))
            .collect()
    };
    let frames: Vec<_> = BenchConfig::ALL
        .iter()
        .map(|&c| (format!("{c:?}"), line(c, |p| p.gpu.median)))
        .filter(|(_, l)| !l.is_empty())
        .collect();
    let frame_png = path("_frame.png");
    log_log(&frame_png, &format!("GPU frame time, {title}"), &frames)?;
    let mut passes = Vec::new();
    for config in [BenchConfig::None, BenchConfig::CullsLod] {
        passes.push((
            format!("grass, {config:?}"),
            line(config, |p| p.grass.median),
        ));
        passes.push((
            format!("simulate+cull, {config:?}"),
            line(config, |p| p.simulate_cull.median),
        ));
    }
    passes.retain(|(_, l)| !l.is_empty());
    let passes_png = path("_passes.png");
    log_log(&passes_png, &format!("Pass times, {title}"), &passes)?;
    let configs_png = path("_configs.png");
    bars(&configs_png, points)?;
    Ok(vec![frame_png, passes_png, configs_png])
}
