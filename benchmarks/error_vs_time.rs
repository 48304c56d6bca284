//! Error against run time, all solvers side by side (DESIGN.md section 7).
//!
//! For each scene and each `SolverChoice` (Auto, Clarabel, ClarabelDual,
//! Lemke, Pgs), the stabilizer runs with `max_passes = k` for
//! k = 1, 2, ... up to the passes it needs to resolve the scene or stall
//! (at most [`MAX_PASSES`]), all (k, solver) runs interleaved per repeat. Each run ends with a detection after its k-th pass, so
//! its `depth_after` is the deepest penetration after k passes and its
//! total time (median of `repeats` runs, fresh stabilizer each) the
//! cumulative wall time to get there. Point k = 0 is the initial depth at
//! time 0.
//!
//! The depth of each point is measured independently of the library: the
//! exact deepest penetration of the scene after the k passes (of the last
//! repeat) by brute-force separating axes (`common::sat`). A curve has
//! converged when that exact depth is at most the tolerance; the library's
//! own status and depth are kept beside it.
//!
//! Outputs in `benchmarks/results/`:
//! - `error_vs_time.csv`: scene, solver, k, status (library), time_ms,
//!   solve_ms, deepest (library), exact (separating axes);
//! - `error_vs_time.md` (with the command, the date, the commit and the
//!   load average): per scene and solver, passes and time to reach the
//!   tolerance by the exact depth, and the exact depth after 1, 2, 5, 10
//!   passes;
//! - `error_vs_time_<scene>.svg`: exact deepest penetration (log scale)
//!   against time, one line per solver. A depth of 0 (no penetration) is
//!   drawn at [`PLOT_FLOOR_FRACTION`] of the tolerance.
//!
//! Run: `cargo bench --bench error_vs_time`. `ERROR_VS_TIME_MAX_REPEATS=n`
//! caps the repeats per point (defaults: 15 on demo 100, 5 on demo 1,000,
//! 25 on the stack of 10).

mod common;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use common::sat::exact_depth;
use common::{Provenance, bench_command};
use constraint_stabilization::demo::demo_scene;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::solver::lemke::LemkeStatus;
use constraint_stabilization::solver::pgs::PgsStatus;
use constraint_stabilization::solver::{FailureReason, SolverChoice};
use constraint_stabilization::{Report, Settings, Stabilizer};
use plotters::prelude::*;

/// Largest pass count measured per solver.
const MAX_PASSES: usize = 40;
/// Depth 0 is drawn at this fraction of the tolerance on the log axis.
const PLOT_FLOOR_FRACTION: f64 = 0.1;

const SOLVERS: [(SolverChoice, &str); 5] = [
    (SolverChoice::Auto, "auto"),
    (SolverChoice::Clarabel, "clarabel"),
    (SolverChoice::ClarabelDual, "clarabel_dual"),
    (SolverChoice::Lemke, "lemke"),
    (SolverChoice::Pgs, "pgs"),
];

/// Environment variables that change what the benchmark does (or how it
/// was built).
const ENV_VARS: [&str; 3] = [
    "ERROR_VS_TIME_MAX_REPEATS",
    "RAYON_NUM_THREADS",
    "CARGO_PROFILE_RELEASE_DEBUG",
];

/// A named scene and the timing repeats per point.
struct Case {
    name: &'static str,
    scene: Scene,
    repeats: usize,
}

/// One point of a curve.
struct Point {
    passes: usize,
    status: &'static str,
    seconds: f64,
    /// Median time in the solve stage (linearization and solver).
    solve_seconds: f64,
    /// The library's deepest penetration after the k passes.
    deepest: f64,
    /// The exact deepest penetration (separating axes) of the scene after
    /// the k passes.
    exact: f64,
}

impl Point {
    /// Whether the exact depth is within the tolerance.
    fn resolved(&self, tolerance: f64) -> bool {
        self.exact <= tolerance
    }
}

/// One solver's curve on one scene.
struct Curve {
    solver: &'static str,
    points: Vec<Point>,
    /// The error that ended the curve, if any.
    error: Option<String>,
    /// Islands per solver that produced the correction, and fallbacks
    /// (failed solver attempts), over the last run.
    usage: String,
    tolerance: f64,
}

fn main() {
    let provenance = Provenance::start(bench_command("error_vs_time", &ENV_VARS));
    let cap = common::env_cap("ERROR_VS_TIME_MAX_REPEATS");
    let cases = vec![
        Case {
            name: "demo_100",
            scene: demo_scene(100, 2026),
            repeats: 15.min(cap),
        },
        Case {
            name: "demo_1000",
            scene: demo_scene(1000, 2026),
            repeats: 5.min(cap),
        },
        Case {
            name: "stack_10",
            scene: common::box_stack(10, 1),
            repeats: 25.min(cap),
        },
    ];
    let dir = common::results_dir();
    let mut csv = String::from("scene,solver,passes,status,time_ms,solve_ms,deepest,exact\n");
    let mut md = String::from(
        "Default settings (contact manifold on) except `solver.choice`. Each point k reruns the \
         stabilizer with `max_passes = k` (fresh stabilizer, median of the repeats); time = whole \
         call; solve ms = time in the solve stage (linearization and solver) of the same runs, summed over \
         islands solved on different threads (so it can exceed the total). Depths are exact: the \
         deepest penetration over all pairs with a dynamic body by brute-force separating axes \
         (`benchmarks/common/sat.rs`) on the scene after k passes (last repeat); status and library \
         deepest are the library's report. `conv` = passes and time to reach the tolerance (1e-6 L) \
         by the exact depth, '-' if not reached within the measured passes. Machine shared and noisy: compare within a scene; each point is an \
         independent set of runs (all points of a scene interleaved per \
         repeat); noise can still put point k+1 slightly before point k on the time axis.\n",
    );
    for case in &cases {
        let curves = measure(case);
        for curve in &curves {
            for p in &curve.points {
                let _ = writeln!(
                    csv,
                    "{},{},{},{},{:.6},{:.6},{:.6e},{:.6e}",
                    case.name,
                    curve.solver,
                    p.passes,
                    p.status,
                    p.seconds * 1e3,
                    p.solve_seconds * 1e3,
                    p.deepest,
                    p.exact
                );
            }
        }
        md.push_str(&table(case, &curves));
        let svg = dir.join(format!("error_vs_time_{}.svg", case.name));
        if let Err(e) = plot(&svg, case.name, &curves) {
            eprintln!("plot {}: {e}", svg.display());
        }
    }
    let md = format!(
        "# Deepest penetration against run time, per solver\n\n{}\n\
         `error_vs_time.csv` and the `error_vs_time_*.svg` plots are from the same run.\n\n{md}",
        provenance.markdown()
    );
    std::fs::write(dir.join("error_vs_time.csv"), &csv).expect("write csv");
    std::fs::write(dir.join("error_vs_time.md"), &md).expect("write md");
    println!("{md}\nwritten to {}", dir.display());
}

/// The curves of every solver on one scene.
///
/// A first run per solver with `max_passes = MAX_PASSES` gives the number of
/// passes `K_s` it needs (or the error that ends its curve). Then every
/// repeat runs every (k, solver) with `k <= K_s`, interleaved, so that the
/// machine's load drifts over all points alike (grouping the repeats of one
/// k together made whole columns of points early or late).
fn measure(case: &Case) -> Vec<Curve> {
    let mut curves: Vec<Curve> = SOLVERS
        .iter()
        .map(|&(_, name)| Curve {
            solver: name,
            points: Vec::new(),
            error: None,
            usage: String::new(),
            tolerance: 0.0,
        })
        .collect();
    let passes_needed: Vec<usize> = SOLVERS
        .iter()
        .zip(&mut curves)
        .map(
            |(&(choice, _), curve)| match run(&case.scene, choice, MAX_PASSES) {
                Ok((report, _)) => report.passes.max(1),
                Err(e) => {
                    curve.error = Some(e);
                    0
                }
            },
        )
        .collect();
    let k_max = passes_needed.iter().copied().max().unwrap_or(0);
    // times[s][k - 1]: (total, solve) seconds of each repeat.
    let mut times: Vec<Vec<Vec<(f64, f64)>>> = passes_needed
        .iter()
        .map(|&n| vec![Vec::with_capacity(case.repeats); n])
        .collect();
    let mut last: Vec<Vec<Option<(Report, Scene)>>> = passes_needed
        .iter()
        .map(|&n| (0..n).map(|_| None).collect())
        .collect();
    for _ in 0..case.repeats {
        for k in 1..=k_max {
            for (s, &(choice, _)) in SOLVERS.iter().enumerate() {
                if k > passes_needed[s] || curves[s].error.is_some() {
                    continue;
                }
                match run(&case.scene, choice, k) {
                    Ok((report, scene)) => {
                        times[s][k - 1].push((report.times.total, report.times.solve));
                        last[s][k - 1] = Some((report, scene));
                    }
                    Err(e) => curves[s].error = Some(e),
                }
            }
        }
    }
    for (s, curve) in curves.iter_mut().enumerate() {
        for (k_times, run) in times[s].iter().zip(last[s].iter_mut()) {
            let Some((report, scene)) = run.take() else {
                break;
            };
            let total: Vec<f64> = k_times.iter().map(|t| t.0).collect();
            let solve: Vec<f64> = k_times.iter().map(|t| t.1).collect();
            if curve.points.is_empty() {
                let initial = exact_depth(&case.scene, report.tolerance).deepest;
                curve.tolerance = report.tolerance;
                curve.points.push(Point {
                    passes: 0,
                    status: "initial",
                    seconds: 0.0,
                    solve_seconds: 0.0,
                    deepest: report.depth_before,
                    exact: initial,
                });
            }
            curve.usage = solver_usage(&report);
            curve.points.push(Point {
                passes: report.passes,
                status: report.status.name(),
                seconds: common::median(&total),
                solve_seconds: common::median(&solve),
                deepest: report.depth_after,
                exact: exact_depth(&scene, report.tolerance).deepest,
            });
        }
        log_curve(case.name, curve);
    }
    curves
}

/// One call with `max_passes = k`, fresh stabilizer: the report and the
/// stabilized scene.
fn run(scene: &Scene, choice: SolverChoice, k: usize) -> Result<(Report, Scene), String> {
    let mut settings = Settings::default();
    settings.solver.choice = choice;
    settings.max_passes = k;
    let mut work = scene.clone();
    let mut stabilizer = Stabilizer::new(settings).map_err(|e| e.to_string())?;
    let report = stabilizer.stabilize(&mut work).map_err(|e| e.to_string())?;
    Ok((report, work))
}

/// "Lemke 12, ClosedForm 3; fallbacks: Pgs MaxSweeps 2" over every island
/// of a report.
fn solver_usage(report: &Report) -> String {
    let mut used: BTreeMap<String, usize> = BTreeMap::new();
    let mut failed: BTreeMap<String, usize> = BTreeMap::new();
    for island in report.pass_reports.iter().flat_map(|p| &p.solved) {
        let name = island
            .solver
            .map_or("none".to_string(), |k| format!("{k:?}"));
        *used.entry(name).or_default() += 1;
        for fallback in &island.fallbacks {
            let key = format!("{:?} {}", fallback.solver, reason_name(&fallback.reason));
            *failed.entry(key).or_default() += 1;
        }
    }
    let join = |m: &BTreeMap<String, usize>| {
        m.iter()
            .map(|(k, n)| format!("{k} {n}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    if failed.is_empty() {
        join(&used)
    } else {
        format!("{}; failed first: {}", join(&used), join(&failed))
    }
}

/// A failure reason without its numbers.
fn reason_name(reason: &FailureReason) -> String {
    match reason {
        FailureReason::NotApplicable => "not-applicable".into(),
        FailureReason::Infeasible => "infeasible".into(),
        FailureReason::Clarabel(c) => format!("{c:?}"),
        FailureReason::Lemke(LemkeStatus::Inaccurate { .. }) => "Inaccurate".into(),
        FailureReason::Lemke(status) => format!("{status:?}"),
        FailureReason::Pgs(PgsStatus::MaxSweeps { .. }) => "MaxSweeps".into(),
        FailureReason::Pgs(PgsStatus::NonPositiveDiagonal { .. }) => "NonPositiveDiagonal".into(),
        FailureReason::Pgs(PgsStatus::Diverged { .. }) => "Diverged".into(),
        FailureReason::ResidualTooLarge { .. } => "residual".into(),
    }
}

fn log_curve(scene: &str, curve: &Curve) {
    if let Some(p) = curve.points.last() {
        eprintln!(
            "{scene} {}: {} passes, {}, {:.3} ms, deepest {:.3e}, exact {:.3e}",
            curve.solver,
            p.passes,
            p.status,
            p.seconds * 1e3,
            p.deepest,
            p.exact
        );
    }
}

/// Exact depth after k passes, or '-' when the curve stopped earlier (at
/// the depth it stopped with if that is within the tolerance).
fn depth_after(curve: &Curve, k: usize) -> String {
    match curve.points.iter().find(|p| p.passes == k) {
        Some(p) => format!("{:.2e}", p.exact),
        None => match curve.points.last() {
            Some(p) if p.passes < k && p.resolved(curve.tolerance) => format!("{:.2e}", p.exact),
            _ => "-".into(),
        },
    }
}

fn table(case: &Case, curves: &[Curve]) -> String {
    let mut md = format!(
        "\n## {} ({} bodies, {} repeat(s) per point)\n\n\
         | solver | verdict (exact) | status (library) | passes | time ms | solve ms | final exact | final library | conv passes | conv ms | after 1 | after 2 | after 5 | after 10 | islands solved by |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
        case.name,
        case.scene.len(),
        case.repeats
    );
    for curve in curves {
        let Some(last) = curve.points.last() else {
            let _ = writeln!(
                md,
                "| {} | error: {} | | | | | | | | | | | | | |",
                curve.solver,
                curve.error.as_deref().unwrap_or("no point")
            );
            continue;
        };
        // The first point within the tolerance by the exact depth.
        let converged = curve
            .points
            .iter()
            .skip(1)
            .find(|p| p.resolved(curve.tolerance));
        let verdict = if last.resolved(curve.tolerance) {
            "resolved"
        } else {
            "UNRESOLVED"
        };
        let status = match &curve.error {
            Some(e) => format!("{} then error: {e}", last.status),
            None => last.status.to_string(),
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.3} | {:.3} | {:.2e} | {:.2e} | {} | {} | {} | {} | {} | {} | {} |",
            curve.solver,
            verdict,
            status,
            last.passes,
            last.seconds * 1e3,
            last.solve_seconds * 1e3,
            last.exact,
            last.deepest,
            converged.map_or("-".into(), |p| p.passes.to_string()),
            converged.map_or("-".into(), |p| format!("{:.3}", p.seconds * 1e3)),
            depth_after(curve, 1),
            depth_after(curve, 2),
            depth_after(curve, 5),
            depth_after(curve, 10),
            curve.usage,
        );
    }
    md
}

const COLORS: [RGBColor; 5] = [BLACK, RED, BLUE, GREEN, MAGENTA];

fn plot(path: &Path, title: &str, curves: &[Curve]) -> Result<(), Box<dyn std::error::Error>> {
    let tolerance = curves
        .iter()
        .map(|c| c.tolerance)
        .find(|&t| t > 0.0)
        .unwrap_or(1e-6);
    let floor = PLOT_FLOOR_FRACTION * tolerance;
    let all = || curves.iter().flat_map(|c| &c.points);
    let x_max = all().map(|p| p.seconds * 1e3).fold(0.0, f64::max).max(1e-3) * 1.05;
    let y_max = all().map(|p| p.exact).fold(floor, f64::max) * 2.0;
    let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "{title}: exact deepest penetration vs time ({}, {})",
                common::git_commit(),
                &common::utc_now()[..10]
            ),
            ("sans-serif", 22),
        )
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(75)
        .build_cartesian_2d(0.0..x_max, (floor * 0.5..y_max).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("cumulative wall time (ms)")
        .y_desc("exact deepest penetration")
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()?;
    chart.draw_series(LineSeries::new(
        [(0.0, tolerance), (x_max, tolerance)],
        ShapeStyle::from(&BLACK.mix(0.3)),
    ))?;
    for (i, curve) in curves.iter().enumerate() {
        let color = COLORS[i % COLORS.len()];
        let points: Vec<(f64, f64)> = curve
            .points
            .iter()
            .map(|p| (p.seconds * 1e3, p.exact.max(floor)))
            .collect();
        chart
            .draw_series(LineSeries::new(points, color.stroke_width(2)))?
            .label(curve.solver)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
