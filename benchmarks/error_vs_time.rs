//! Error against run time: this library side by side with what engines
//! and users do instead (issue 13).
//!
//! For every scene of [`families`] and every configuration of
//! [`methods`] (the library's solvers over pass limits and tolerances,
//! nonlinear Gauss–Seidel position correction, settling by simulation),
//! the run's wall time (median of the repeats, every configuration of a
//! scene interleaved per repeat, the round starting at another configuration
//! each repeat), the exact deepest remaining penetration
//! (brute-force separating axes, `dev_support::sat`, not the library's own
//! measure), the mass-weighted displacement and the largest motion of a
//! body ([`motion`]), the passes, sweeps or steps done, and whether
//! velocities were changed. [`summary`] turns them into the goals' figures;
//! [`plots`] draws them.
//!
//! Outputs in `benchmarks/results/` (`error_vs_time_quick*` with
//! `--quick`): `error_vs_time.csv` (every point), `error_vs_time.md`
//! (parameters, goals, tables), `error_vs_time_<family>.svg` (remaining
//! penetration against time, log-log, a panel per size) and
//! `error_vs_time_scaling.svg` (time against body count, log-log, fitted
//! exponents).
//!
//! Run: `cargo bench --features rapier --bench error_vs_time` (without
//! `rapier`, settling by simulation is left out and the report says so).
//! `-- --quick`: one small scene per family, one repeat, a few points per
//! line (about a minute; `.ci/run` runs it so that the harness cannot
//! rot). `-- --only TEXT`: the scenes whose name contains TEXT.

mod common;
#[path = "error_vs_time/families.rs"]
mod families;
#[path = "error_vs_time/gauss_seidel.rs"]
mod gauss_seidel;
#[path = "error_vs_time/methods.rs"]
mod methods;
#[path = "error_vs_time/motion.rs"]
mod motion;
#[path = "error_vs_time/plots.rs"]
mod plots;
#[path = "error_vs_time/settle.rs"]
mod settle;
#[path = "error_vs_time/summary.rs"]
mod summary;

use common::{Provenance, bench_command};
use constraint_stabilization::solver::{SolverChoice, SolverSettings};
use constraint_stabilization::stabilizer::scene_scale;
use dev_support::sat::exact_depth;
use families::Case;
use indicatif::{ProgressBar, ProgressStyle};
use methods::{Config, Kind, RunPoint};

/// A configuration whose first run takes longer than this (seconds) is
/// not repeated; a solver whose probing call (default tolerance, unlimited
/// passes) takes longer gets that one point, no pass or tolerance line
/// (Lemke's dense tableau on the engine bins' 700-row islands).
const SLOW_RUN_SECONDS: f64 = 3.0;
/// Forced Lemke is measured on a scene only when `auto`'s largest island
/// has at most this many times the rows up to which `auto` itself uses
/// Lemke: beyond, a single call took minutes (a dense tableau of 1,000
/// rows and more, `n^3` per solve).
const LEMKE_ROWS_FACTOR: usize = 4;
/// Repeats per configuration on scenes of at most [`SMALL_SCENE`] bodies.
const REPEATS_SMALL: usize = 5;
/// Repeats on larger scenes.
const REPEATS_LARGE: usize = 3;
/// Scenes with at most this many bodies count as small.
const SMALL_SCENE: usize = 200;

/// Environment variables that change what the benchmark does.
const ENV_VARS: [&str; 2] = ["RAYON_NUM_THREADS", "CARGO_PROFILE_RELEASE_DEBUG"];

/// One measured point.
#[derive(Debug, Clone)]
pub struct Point {
    pub line: String,
    pub parameter: String,
    /// Passes, sweeps or steps done.
    pub iterations: usize,
    pub status: String,
    /// Median wall time of the repeats (seconds).
    pub seconds: f64,
    pub repeats: usize,
    /// Exact deepest penetration after the run (last repeat).
    pub exact: f64,
    pub motion: motion::Motion,
    /// Whether the method changed velocities (settling does).
    pub velocities_changed: bool,
    /// Rows of every island solved, summed (library runs; 0 otherwise).
    pub rows_solved: usize,
}

/// Everything measured on one scene.
pub struct Measured {
    pub family: &'static str,
    pub name: String,
    pub size: f64,
    pub bodies: usize,
    /// The library's default tolerance on this scene (absolute).
    pub tolerance: f64,
    pub initial: f64,
    pub points: Vec<Point>,
    /// Configurations that failed, with the error.
    pub errors: Vec<(String, String)>,
}

fn main() {
    let common::BenchArgs { quick, only } = common::BenchArgs::parse();
    let features = if cfg!(feature = "rapier") {
        " --features rapier"
    } else {
        ""
    };
    let provenance = Provenance::start(bench_command(
        &format!("error_vs_time{features}"),
        &ENV_VARS,
    ));
    let mut cases = families::cases(quick);
    if let Some(text) = &only {
        cases.retain(|c| c.name.contains(text.as_str()));
    }
    let progress = ProgressBar::new(cases.len() as u64);
    progress.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut measured = Vec::with_capacity(cases.len());
    for case in &cases {
        progress.set_message(format!("{} ({} bodies)", case.name, case.scene.len()));
        let m = measure(case, quick);
        // A hidden bar (no terminal, as in CI) prints nothing: say it on
        // standard error instead.
        if progress.is_hidden() {
            eprintln!("{}", summary::one_line(&m));
        } else {
            progress.println(summary::one_line(&m));
        }
        measured.push(m);
        progress.inc(1);
    }
    progress.finish_and_clear();
    let dir = common::results_dir();
    let stem = if quick {
        "error_vs_time_quick"
    } else {
        "error_vs_time"
    };
    let md = summary::markdown(&measured, &provenance, quick);
    std::fs::write(dir.join(format!("{stem}.csv")), summary::csv(&measured)).expect("write csv");
    std::fs::write(dir.join(format!("{stem}.md")), &md).expect("write md");
    for error in plots::draw(&dir, stem, &measured) {
        eprintln!("plot: {error}");
    }
    println!("{md}\nwritten to {}", dir.display());
}

/// Every configuration of one scene, measured.
fn measure(case: &Case, quick: bool) -> Measured {
    let tolerance = methods::DEFAULT_TOLERANCE * scene_scale(&case.scene);
    let mut measured = Measured {
        family: case.family,
        name: case.name.clone(),
        size: case.size,
        bodies: case.scene.len(),
        tolerance,
        initial: exact_depth(&case.scene, tolerance).deepest,
        points: Vec::new(),
        errors: Vec::new(),
    };
    let (configs, probed) = plan(case, quick, &mut measured.errors);
    let checkpoints: &[usize] = if quick {
        &methods::STEPS_QUICK
    } else {
        &methods::STEPS
    };
    let repeats = if quick {
        1
    } else if case.scene.len() <= SMALL_SCENE {
        REPEATS_SMALL
    } else {
        REPEATS_LARGE
    };
    // times[c][p]: the seconds of point p of configuration c per repeat;
    // last[c]: the points of its last run.
    let mut times: Vec<Vec<Vec<f64>>> = vec![Vec::new(); configs.len()];
    let mut last: Vec<Option<Vec<RunPoint>>> = (0..configs.len()).map(|_| None).collect();
    let mut skip = vec![false; configs.len()];
    for (c, probe) in probed.into_iter().enumerate() {
        if let Some(points) = probe {
            times[c] = points.iter().map(|p| vec![p.seconds]).collect();
            last[c] = Some(points);
            skip[c] = true;
        }
    }
    let count = configs.len();
    for repeat in 0..repeats {
        // Each repeat starts the round at another configuration, so that no
        // configuration always runs first (or right after a given other).
        let first = repeat * count / repeats.max(1);
        for k in 0..count {
            let c = (first + k) % count;
            let config = &configs[c];
            if skip[c] {
                continue;
            }
            match methods::run(&case.scene, config, checkpoints) {
                Ok(points) => {
                    times[c].resize(points.len(), Vec::new());
                    for (t, p) in times[c].iter_mut().zip(&points) {
                        t.push(p.seconds);
                    }
                    let slowest = points.iter().map(|p| p.seconds).fold(0.0, f64::max);
                    if repeat == 0 && slowest > SLOW_RUN_SECONDS {
                        skip[c] = true;
                    }
                    last[c] = Some(points);
                }
                Err(e) => {
                    measured.errors.push((label(config), e));
                    skip[c] = true;
                }
            }
        }
    }
    for (c, config) in configs.iter().enumerate() {
        let Some(points) = last[c].take() else {
            continue;
        };
        for (p, run) in points.into_iter().enumerate() {
            let parameter = if matches!(config.kind, Kind::Settle) {
                run.parameter.clone()
            } else {
                config.parameter.clone()
            };
            measured.points.push(Point {
                line: config.line.clone(),
                parameter,
                iterations: run.iterations,
                status: run.status,
                seconds: common::median(&times[c][p]),
                repeats: times[c][p].len(),
                exact: exact_depth(&run.scene, tolerance).deepest,
                motion: motion::motion(&case.scene, &run.scene),
                velocities_changed: matches!(config.kind, Kind::Settle),
                rows_solved: run.rows_solved,
            });
        }
    }
    measured
}

fn label(config: &Config) -> String {
    format!("{} {}", config.line, config.parameter)
}

/// The configurations of one scene, and beside each the points already
/// measured for it (a slow solver's probe, see [`SLOW_RUN_SECONDS`]). The
/// library's pass lines end at the passes each solver needs at the
/// default tolerance (one probing call per solver finds it; a solver whose
/// probe fails gets no line).
fn plan(
    case: &Case,
    quick: bool,
    errors: &mut Vec<(String, String)>,
) -> (Vec<Config>, Vec<Option<Vec<RunPoint>>>) {
    let (pass_limits, tolerances, iterations): (&[usize], &[f64], &[usize]) = if quick {
        (
            &methods::PASS_LIMITS_QUICK,
            &methods::TOLERANCES_QUICK,
            &methods::ITERATIONS_QUICK,
        )
    } else {
        (
            &methods::PASS_LIMITS,
            &methods::TOLERANCES,
            &methods::ITERATIONS,
        )
    };
    let default_passes = constraint_stabilization::Settings::default().max_passes;
    let mut configs = Vec::new();
    let mut probed = Vec::new();
    // Rows of the largest island of `auto`'s probe (the first solver).
    let mut auto_rows = 0;
    let lemke_limit = SolverSettings::default().auto_lemke_max_rows;
    for &(solver, name) in &methods::SOLVERS {
        if solver == SolverChoice::Lemke && auto_rows > LEMKE_ROWS_FACTOR * lemke_limit {
            errors.push((
                format!("{name} lines"),
                format!(
                    "not measured: islands of {auto_rows} rows, over {LEMKE_ROWS_FACTOR} times the \
                     {lemke_limit} up to which auto uses Lemke (dense tableau, n^3)"
                ),
            ));
            continue;
        }
        let probe = Config {
            line: format!("{name} passes"),
            parameter: "passes=all".into(),
            kind: Kind::Library {
                solver,
                tolerance_relative: methods::DEFAULT_TOLERANCE,
                max_passes: default_passes,
            },
        };
        let points = match methods::run(&case.scene, &probe, &[]) {
            Ok(points) => points,
            Err(e) => {
                errors.push((label(&probe), e));
                continue;
            }
        };
        let needed = points.first().map_or(0, |p| p.iterations);
        if solver == SolverChoice::Auto {
            auto_rows = points.first().map_or(0, |p| p.largest_island_rows);
        }
        if points.iter().any(|p| p.seconds > SLOW_RUN_SECONDS) {
            errors.push((
                format!("{name} lines"),
                format!("not measured: its call took more than {SLOW_RUN_SECONDS} s"),
            ));
            configs.push(probe);
            probed.resize_with(configs.len() - 1, || None);
            probed.push(Some(points));
            continue;
        }
        for &k in pass_limits.iter().filter(|&&k| k < needed) {
            configs.push(Config {
                line: format!("{name} passes"),
                parameter: format!("passes={k}"),
                kind: Kind::Library {
                    solver,
                    tolerance_relative: methods::DEFAULT_TOLERANCE,
                    max_passes: k,
                },
            });
        }
        configs.push(probe);
        // Tolerance lines for `auto` only: the other solvers' would double
        // the run (see the module doc).
        let tolerances = if solver == SolverChoice::Auto {
            tolerances
        } else {
            &[]
        };
        for &tolerance in tolerances
            .iter()
            .filter(|&&t| t != methods::DEFAULT_TOLERANCE)
        {
            configs.push(Config {
                line: format!("{name} tol"),
                parameter: format!("tol={tolerance:.0e}"),
                kind: Kind::Library {
                    solver,
                    tolerance_relative: tolerance,
                    max_passes: default_passes,
                },
            });
        }
    }
    for preset in &methods::GAUSS_SEIDEL_PRESETS {
        for &n in iterations {
            configs.push(Config {
                line: preset.name.into(),
                parameter: format!("sweeps={n}"),
                kind: Kind::GaussSeidel {
                    preset: *preset,
                    iterations: n,
                },
            });
        }
    }
    configs.push(Config {
        line: "settle".into(),
        parameter: "steps".into(),
        kind: Kind::Settle,
    });
    probed.resize_with(configs.len(), || None);
    (configs, probed)
}
