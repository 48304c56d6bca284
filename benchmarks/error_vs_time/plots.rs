//! The SVG plots (plotters): per family, a work-precision diagram per
//! scene (exact remaining penetration against wall time, log-log, one line
//! per method; the initial depth and the tolerance as grey lines), and the
//! time against body count of the families with several sizes (log-log,
//! the fitted exponent in the legend).

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::summary::{self, DEFAULT_LINE};
use crate::{Measured, common};

/// Depth 0 (no penetration) is drawn at this fraction of the tolerance.
const FLOOR_FRACTION: f64 = 0.1;
/// Panel size in pixels.
const PANEL: (u32, u32) = (520, 380);
/// Most panels per row.
const COLUMNS: usize = 3;

/// The lines drawn, with their colours (others are in the CSV only).
const DRAWN: [(&str, RGBColor); 9] = [
    ("auto passes", BLACK),
    ("auto tol", RGBColor(120, 120, 120)),
    ("clarabel passes", BLUE),
    ("lemke passes", GREEN),
    ("pgs passes", CYAN),
    ("gs_box2d", RGBColor(230, 140, 0)),
    ("gs_tuned", RED),
    ("gs_tuned_redetect", RGBColor(150, 0, 0)),
    ("settle", MAGENTA),
];

/// Draws every plot; returns the errors (a plot that fails is skipped).
pub fn draw(dir: &Path, stem: &str, measured: &[Measured]) -> Vec<String> {
    let mut errors = Vec::new();
    let mut families: Vec<&str> = Vec::new();
    for m in measured {
        if !families.contains(&m.family) {
            families.push(m.family);
        }
    }
    for family in families {
        let scenes: Vec<&Measured> = measured.iter().filter(|m| m.family == family).collect();
        let path = dir.join(format!("{stem}_{family}.svg"));
        if let Err(e) = family_plot(&path, family, &scenes) {
            errors.push(format!("{}: {e}", path.display()));
        }
    }
    let path = dir.join(format!("{stem}_scaling.svg"));
    if let Err(e) = scaling_plot(&path, measured) {
        errors.push(format!("{}: {e}", path.display()));
    }
    errors
}

type PlotResult = Result<(), Box<dyn std::error::Error>>;

/// A line to draw: its label, colour and points.
type Drawn<L> = (L, RGBColor, Vec<(f64, f64)>);

/// Height of the title band (pixels).
const TITLE_HEIGHT: u32 = 40;

/// A white SVG of `rows x columns` panels under `title` (with the commit
/// and the date); returns the area below the title.
fn titled_grid<'a>(
    path: &'a Path,
    title: &str,
    (rows, columns): (usize, usize),
) -> Result<DrawingArea<SVGBackend<'a>, Shift>, Box<dyn std::error::Error>> {
    let size = (
        PANEL.0 * columns as u32,
        PANEL.1 * rows as u32 + TITLE_HEIGHT,
    );
    let root = SVGBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE)?;
    let title = format!(
        "{title} ({}, {})",
        common::git_commit(),
        &common::utc_now()[..10]
    );
    Ok(root.titled(&title, ("sans-serif", 20))?)
}

fn family_plot(path: &Path, family: &str, scenes: &[&Measured]) -> PlotResult {
    let columns = scenes.len().clamp(1, COLUMNS);
    let rows = scenes.len().div_ceil(columns).max(1);
    let title = format!("{family}: exact remaining penetration vs wall time");
    let root = titled_grid(path, &title, (rows, columns))?;
    let panels = root.split_evenly((rows, columns));
    for (k, (panel, m)) in panels.iter().zip(scenes).enumerate() {
        panel_plot(panel, m, k == 0)?;
    }
    root.present()?;
    Ok(())
}

fn panel_plot(area: &DrawingArea<SVGBackend, Shift>, m: &Measured, legend: bool) -> PlotResult {
    let floor = FLOOR_FRACTION * m.tolerance;
    let drawn: Vec<Drawn<&str>> = DRAWN
        .iter()
        .map(|&(line, color)| {
            let points = summary::line_points(m, line)
                .iter()
                .map(|p| (p.seconds * 1e3, p.exact.max(floor)))
                .filter(|(t, _)| *t > 0.0)
                .collect();
            (line, color, points)
        })
        .filter(|(_, _, points): &(_, _, Vec<_>)| !points.is_empty())
        .collect();
    let all = || drawn.iter().flat_map(|(_, _, p)| p.iter());
    let t_min = all().map(|p| p.0).fold(f64::INFINITY, f64::min);
    let t_max = all().map(|p| p.0).fold(0.0, f64::max);
    if !(t_min.is_finite() && t_max > 0.0) {
        return Ok(());
    }
    let y_max = all().map(|p| p.1).fold(m.initial.max(floor), f64::max) * 3.0;
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("{} ({} bodies)", m.name, m.bodies),
            ("sans-serif", 16),
        )
        .margin(8)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(
            (t_min * 0.5..t_max * 2.0).log_scale(),
            (floor * 0.5..y_max).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("wall time (ms)")
        .y_desc("exact deepest penetration")
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()?;
    for level in [m.tolerance, m.initial.max(floor)] {
        chart.draw_series(LineSeries::new(
            [(t_min * 0.5, level), (t_max * 2.0, level)],
            ShapeStyle::from(&BLACK.mix(0.25)),
        ))?;
    }
    for (line, color, points) in drawn {
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 2, color.filled())))?;
        let series = chart.draw_series(LineSeries::new(points, color.stroke_width(2)))?;
        if legend {
            series
                .label(line)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], color));
        }
    }
    if legend {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 11))
            .draw()?;
    }
    Ok(())
}

fn scaling_plot(path: &Path, measured: &[Measured]) -> PlotResult {
    let families: Vec<&str> = ["stack", "pyramid", "pile"]
        .into_iter()
        .filter(|f| summary::family_times(measured, f, DEFAULT_LINE.0, DEFAULT_LINE.1).len() >= 2)
        .collect();
    if families.is_empty() {
        return Ok(());
    }
    let root = titled_grid(
        path,
        "time against body count, log-log",
        (1, families.len()),
    )?;
    let panels = root.split_evenly((1, families.len()));
    let series: [(&str, &str, &str, RGBColor); 3] = [
        ("auto, default", DEFAULT_LINE.0, DEFAULT_LINE.1, BLACK),
        (
            "gs_tuned_redetect, 1 sweep",
            "gs_tuned_redetect",
            "sweeps=1",
            RED,
        ),
        ("settle, 1 step", "settle", "steps=1", MAGENTA),
    ];
    for (panel, family) in panels.iter().zip(families) {
        let lines: Vec<Drawn<String>> = series
            .iter()
            .map(|&(name, line, parameter, color)| {
                let points: Vec<(f64, f64)> =
                    summary::family_times(measured, family, line, parameter)
                        .into_iter()
                        .map(|(n, t)| (n, t * 1e3))
                        .collect();
                let k = summary::fitted_exponent(&points);
                (format!("{name}: k = {k:.2}"), color, points)
            })
            .filter(|(_, _, p)| !p.is_empty())
            .collect();
        let all = || lines.iter().flat_map(|(_, _, p)| p.iter());
        let (n_min, n_max) = all().fold((f64::INFINITY, 0.0_f64), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
        let (t_min, t_max) = all().fold((f64::INFINITY, 0.0_f64), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
        let mut chart = ChartBuilder::on(panel)
            .caption(family, ("sans-serif", 16))
            .margin(8)
            .x_label_area_size(35)
            .y_label_area_size(55)
            .build_cartesian_2d(
                (n_min * 0.7..n_max * 1.4).log_scale(),
                (t_min * 0.5..t_max * 2.0).log_scale(),
            )?;
        chart
            .configure_mesh()
            .x_desc("bodies")
            .y_desc("wall time (ms)")
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .draw()?;
        for (label, color, points) in lines {
            chart
                .draw_series(LineSeries::new(points, color.stroke_width(2)))?
                .label(label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], color));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 11))
            .draw()?;
    }
    root.present()?;
    Ok(())
}
