//! One call on every engine state with its engine's friction, side by side
//! with the frictionless call (issue 21, "With friction").
//!
//! For each engine state in `tests/data/engine/*.json`, the coefficient
//! its engine uses for two default bodies is written on every body
//! (`Body::set_friction`; a pair's coefficient is the mean of its bodies',
//! so the pair gets that coefficient): Bullet 0.5 x 0.5 = 0.25 (Bullet
//! multiplies the two bodies' coefficients), MuJoCo 1.0 (its default,
//! combined by the maximum), Rapier 0.5 (its default, combined by the
//! mean). Seven calls per repeat, interleaved and rotated in order:
//! frictionless (every body's coefficient cleared, also those a file
//! carries: `rp08_mixed_pile` has Rapier's 0.5 on its bodies), then
//! friction as the pyramid (the default model) and as the cone, each with
//! the three ways its rows enter the problem (`Settings::friction_rows`:
//! the pyramid's facets in place of their row, `implied`, the default;
//! generated as needed; all rows, the Rapier bridge's default); each on a
//! fresh copy of the scene, with
//! a fresh stabilizer and the default settings otherwise.
//! Time: the median over the repeats.
//!
//! Quality (from the first repeat, the call being deterministic): status,
//! passes, the islands solved without friction (`friction_dropped`), the
//! solvers that answered and those that failed before them, and the exact
//! deepest penetration after the call by the brute-force separating axes
//! (`dev_support::sat::sat_deepest`) against the call's tolerance.
//!
//! Outputs `benchmarks/results/engine_friction.md` (`--quick`:
//! `engine_friction_quick.md`).
//!
//! Run: `cargo bench --features serde --bench engine_friction`
//! (`-- --quick`: one repeat; `-- --only STEM`: the states whose stem
//! contains STEM). The environment variable `ENGINE_FRICTION_IP_MIN_ROWS`
//! sets `Auto`'s `auto_interior_point_min_rows` in every call.

mod common;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::time::Instant;

use constraint_stabilization::scene::Scene;
use constraint_stabilization::{FrictionModel, FrictionRows, Report, Settings, Stabilizer};

/// Repeats per state (`--quick`: 1).
const REPEATS: usize = 9;
/// The calls compared: label, friction model (`None`: frictionless) and
/// how its rows enter the problem (`Settings::friction_rows`). The labels
/// name the rows' way; `default` marks the default settings' call (the
/// pyramid with `Implied`), `bridge's default` the Rapier bridge's way
/// (the pyramid with `All`).
const CALLS: [(&str, Option<FrictionModel>, FrictionRows); 7] = [
    ("frictionless", None, FrictionRows::Implied),
    (
        "pyramid, implied (default)",
        Some(FrictionModel::Pyramid),
        FrictionRows::Implied,
    ),
    (
        "cone, implied",
        Some(FrictionModel::Cone),
        FrictionRows::Implied,
    ),
    (
        "pyramid, generated",
        Some(FrictionModel::Pyramid),
        FrictionRows::Generated,
    ),
    (
        "cone, generated",
        Some(FrictionModel::Cone),
        FrictionRows::Generated,
    ),
    (
        "pyramid, all rows (bridge's default)",
        Some(FrictionModel::Pyramid),
        FrictionRows::All,
    ),
    (
        "cone, all rows",
        Some(FrictionModel::Cone),
        FrictionRows::All,
    ),
];

/// One call's quality and time.
struct Call {
    report: Result<Report, String>,
    exact_after: f64,
    seconds: Vec<f64>,
}

fn main() {
    let common::BenchArgs { quick, only } = common::BenchArgs::parse();
    let provenance = common::Provenance::start(common::bench_command(
        "engine_friction --features serde",
        &[],
    ));
    let repeats = if quick { 1 } else { REPEATS };
    let mut table = String::new();
    for (stem, scene) in common::engine_states() {
        if only.as_ref().is_some_and(|o| !stem.contains(o.as_str())) {
            continue;
        }
        let mu = common::engine_friction(&stem);
        let calls = measure(&scene, mu, repeats);
        let base = median(&calls[0].seconds);
        for ((label, _, _), call) in CALLS.iter().zip(&calls) {
            let line = row(&stem, mu, label, call, base);
            println!("{line}");
            table.push_str(&line);
            table.push('\n');
        }
    }
    let mut md = String::from("# Engine states with their engine's friction\n\n");
    md.push_str(&provenance.markdown());
    md.push_str(
        "\nOne call per state and model, interleaved (see the benchmark's module docs); \
         time = median over the repeats; `dropped` = islands solved without friction \
         (summed over passes); `exact after` = brute-force separating-axis depth after the \
         call; `solvers` = the solvers that answered (count), `failed` = the fallbacks before \
         them.\n\n\
         | state | mu | call | status | passes | dropped | exact after | tolerance | solvers | failed | ms | x frictionless |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    md.push_str(&table);
    let dir = common::results_dir();
    let name = if quick {
        "engine_friction_quick.md"
    } else {
        "engine_friction.md"
    };
    common::write_keeping_sections(&dir.join(name), &md);
    println!("written to {}", dir.join(name).display());
}

/// The calls of [`CALLS`] on `scene`, `repeats` times each,
/// interleaved with a rotating first call.
fn measure(scene: &Scene, mu: f64, repeats: usize) -> Vec<Call> {
    let mut calls: Vec<Call> = CALLS
        .iter()
        .map(|_| Call {
            report: Err("not run".into()),
            exact_after: f64::NAN,
            seconds: Vec::new(),
        })
        .collect();
    for repeat in 0..repeats {
        for k in 0..CALLS.len() {
            let index = (repeat + k) % CALLS.len();
            let (_, model, friction_rows) = CALLS[index];
            let mut copy = common::with_friction(scene.clone(), model.map(|_| mu));
            let mut settings = Settings::default();
            settings.friction_rows = friction_rows;
            if let Some(rows) = std::env::var("ENGINE_FRICTION_IP_MIN_ROWS")
                .ok()
                .and_then(|v| v.parse().ok())
            {
                settings.solver.auto_interior_point_min_rows = rows;
            }
            if let Some(model) = model {
                settings.friction_model = model;
            }
            let mut stabilizer = Stabilizer::new(settings).expect("valid settings");
            let start = Instant::now();
            let report = stabilizer.stabilize(&mut copy);
            let seconds = start.elapsed().as_secs_f64();
            let call = &mut calls[index];
            call.seconds.push(seconds);
            if repeat == 0 {
                call.exact_after = dev_support::sat::sat_deepest(&copy).0;
                call.report = report.map_err(|e| e.to_string());
            }
        }
    }
    calls
}

/// The Markdown row of one call.
fn row(stem: &str, mu: f64, label: &str, call: &Call, base: f64) -> String {
    let ms = median(&call.seconds);
    let mut line = format!("| {stem} | {mu} | {label} | ");
    match &call.report {
        Err(error) => {
            let _ = write!(line, "error: {error} | | | | | | |");
        }
        Ok(report) => {
            let islands = report.pass_reports.iter().flat_map(|p| &p.solved);
            let dropped = islands.clone().filter(|i| i.friction_dropped).count();
            let mut solvers: BTreeMap<String, usize> = BTreeMap::new();
            let mut failed: BTreeMap<String, usize> = BTreeMap::new();
            for island in islands {
                if let Some(kind) = island.solver {
                    *solvers.entry(format!("{kind:?}")).or_default() += 1;
                }
                for fallback in &island.fallbacks {
                    *failed.entry(format!("{:?}", fallback.solver)).or_default() += 1;
                }
            }
            let _ = write!(
                line,
                "{} | {} | {dropped} | {:.2e} | {:.2e} | {} | {} |",
                report.status.name(),
                report.passes,
                call.exact_after,
                report.tolerance,
                counts(&solvers),
                counts(&failed),
            );
        }
    }
    let _ = write!(line, " {:.1} | {:.2} |", ms * 1e3, ms / base);
    line
}

/// `name n, name n` (or `-`).
fn counts(map: &BTreeMap<String, usize>) -> String {
    if map.is_empty() {
        return "-".into();
    }
    map.iter()
        .map(|(k, n)| format!("{k} {n}"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN)
}
