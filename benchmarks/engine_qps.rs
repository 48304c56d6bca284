//! The solvers on the projection QPs of real calls: every engine state of
//! `tests/data/engine` is stabilized once with the default settings while
//! the QPs handed to the solver are recorded
//! (`constraint_stabilization::solver::recorder`); the frictionless ones
//! (with `--friction`, the pyramids of the calls with friction)
//! of at least `--min-rows` rows (default 161, above Lemke's range) are
//! then solved again by each variant, the variants interleaved (one run of
//! each per round, `--rounds` rounds, default 7), cold (no warm start).
//! Per state: the median time of each variant summed over the state's QPs
//! (the solve of one call), its ratio to clarabel's, and the largest
//! difference in `dq` from clarabel's polished answer, `||dq - dq_ref||_M /
//! ||dq_ref||_M`, over the QPs; the answering solver, iterations and
//! factorizations are summed over the QPs.
//!
//! `cargo bench --bench engine_qps --features serde -- [--only TEXT]
//! [--min-rows N] [--max-dofs N] [--friction] [--rounds N]
//! [--variants a,b,...]`
//!
//! `--max-dofs N`: only the QPs of at most `N` entries of `dq`;
//! `--friction`: the calls with the engine's friction coefficient on every
//! body (as `engine_friction`; their QPs are the friction pyramids, every
//! call clears the coefficients a file carries otherwise).
//!
//! With `--rapier SCENE` (built with `--features rapier,serde`) the QPs
//! are instead those of the `--worst K` slowest calls (default 1) of
//! `--steps N` steps (default 300) of a `with_and_without` scene
//! (`pile_200`, `pyramid_55`, `thrown_box`, ...) with the bridge's default
//! settings, every QP of each call (frictional pyramids and velocity
//! projections included; `--min-rows` defaults to 2 there), one table row
//! per call and variant, after a line with the call's stage times. With
//! `ENGINE_QPS_AROUND_MEDIAN=1` the `--worst K` calls are instead the `K`
//! around the median call (a typical call rather than the slowest).
//!
//! With `ENGINE_QPS_PER_QP=1`, one line per QP on stderr: its entries of
//! `dq`, rows, rows violated at `dq = 0`, and each variant's median time
//! (ms) and iterations, in `--variants` order.
//!
//! With `ENGINE_QPS_ANSWERS=1`, per QP on stderr the reference's and each
//! variant's `||dq||_M` and smallest slack `min_i (J dq + b)_i`: which
//! answer is the smaller feasible one where two differ.
//!
//! Variants: `clarabel` (the reference: the default settings with
//! `SolverChoice::Clarabel`), `al` (the augmented Lagrangian, named),
//! `auto` (the default `Auto`), `auto_no_das` (`Auto` without the dual
//! active-set method), `das`, `ip`, `lemke` (named), and those listed in
//! [`variants`].

mod common;
#[cfg(feature = "rapier")]
mod engine_qps_loop;

use std::time::Instant;

use constraint_stabilization::Settings;
use constraint_stabilization::solver::recorder::{self, RecordedQp};
use constraint_stabilization::solver::{
    ProjectionSolution, SolverChoice, SolverSettings, solve_projection_warm,
};
use nalgebra::DVector;

struct Args {
    only: Option<String>,
    min_rows: Option<usize>,
    max_dofs: Option<usize>,
    friction: bool,
    rapier: Option<String>,
    steps: usize,
    worst: usize,
    rounds: usize,
    variants: Vec<String>,
}

fn parse() -> Args {
    let mut args = Args {
        only: None,
        min_rows: None,
        max_dofs: None,
        friction: false,
        rapier: None,
        steps: 300,
        worst: 1,
        rounds: 7,
        variants: vec!["clarabel".into(), "al".into()],
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        match a.as_str() {
            "--only" => args.only = it.next(),
            "--min-rows" => args.min_rows = it.next().and_then(|v| v.parse().ok()),
            "--max-dofs" => args.max_dofs = it.next().and_then(|v| v.parse().ok()),
            "--friction" => args.friction = true,
            "--rapier" => args.rapier = it.next(),
            "--steps" => args.steps = it.next().and_then(|v| v.parse().ok()).unwrap_or(300),
            "--worst" => args.worst = it.next().and_then(|v| v.parse().ok()).unwrap_or(1),
            "--rounds" => args.rounds = it.next().and_then(|v| v.parse().ok()).unwrap_or(7),
            "--variants" => {
                args.variants = it
                    .next()
                    .unwrap_or_default()
                    .split(',')
                    .map(String::from)
                    .collect()
            }
            _ => {}
        }
    }
    args
}

/// The solver settings of a named variant.
fn variant(name: &str) -> SolverSettings {
    let mut s = Settings::default().solver;
    match name {
        "clarabel" => s.choice = SolverChoice::Clarabel,
        "auto" => {}
        "al" => s.choice = SolverChoice::AugmentedLagrangian,
        "al_inexact" => {
            s.choice = SolverChoice::AugmentedLagrangian;
            s.augmented_lagrangian.exact_only = false;
        }
        "ip" => s.choice = SolverChoice::InteriorPoint,
        "das" => s.choice = SolverChoice::DualActiveSet,
        "lemke" => s.choice = SolverChoice::Lemke,
        "auto_no_das" => s.auto_dual_active_set_max_dofs = 0,
        "ip_sparse" => {
            s.choice = SolverChoice::InteriorPoint;
            s.interior_point.dense_max_dofs = 0;
        }
        "ip_unpacked" => {
            s.choice = SolverChoice::InteriorPoint;
            s.interior_point.packed_rows = false;
        }
        "ip_simplicial" => {
            s.choice = SolverChoice::InteriorPoint;
            s.interior_point.supernodal = false;
        }
        "clarabel_nopolish" => {
            s.choice = SolverChoice::Clarabel;
            s.clarabel.polish_above = s.tol_residual;
        }
        other => {
            if !extra_variant(other, &mut s) {
                panic!("no variant named {other}")
            }
        }
    }
    s.fall_back = true;
    s
}

/// Variants of the solvers under study (filled in as they are built).
fn extra_variant(name: &str, s: &mut SolverSettings) -> bool {
    // `clarabel_tight:G`: clarabel with gap and feasibility tolerances `G`.
    if let Some(gap) = name
        .strip_prefix("clarabel_tight:")
        .and_then(|f| f.parse().ok())
    {
        s.choice = SolverChoice::Clarabel;
        s.clarabel.tol_gap = gap;
        s.clarabel.tol_feas = gap;
        return true;
    }
    // `auto_ip:N`: `Auto` with the interior point from `N` rows.
    if let Some(rows) = name.strip_prefix("auto_ip:").and_then(|f| f.parse().ok()) {
        s.auto_interior_point_min_rows = rows;
        return true;
    }
    // `ipf:F`: the interior point taking `F` of the step to the boundary.
    if let Some(fraction) = name.strip_prefix("ipf:").and_then(|f| f.parse().ok()) {
        s.choice = SolverChoice::InteriorPoint;
        s.interior_point.step_fraction = fraction;
        return true;
    }
    // `ipc:N`: the interior point with `N` centrality correctors.
    if let Some(count) = name.strip_prefix("ipc:").and_then(|f| f.parse().ok()) {
        s.choice = SolverChoice::InteriorPoint;
        s.interior_point.centrality_correctors = count;
        return true;
    }
    // `ip:F`: the interior point stopping at `F` times the tolerance.
    if let Some(fraction) = name.strip_prefix("ip:").and_then(|f| f.parse().ok()) {
        s.choice = SolverChoice::InteriorPoint;
        s.interior_point.stop_fraction = fraction;
        return true;
    }
    false
}

fn m_norm(qp: &constraint_stabilization::solver::ProjectionQp, dq: &DVector<f64>) -> f64 {
    let mut total = 0.0;
    for (k, body) in qp.bodies.iter().enumerate() {
        let lin = dq.fixed_rows::<3>(6 * k);
        let ang = dq.fixed_rows::<3>(6 * k + 3);
        total += body.mass * lin.norm_squared() + ang.dot(&(body.inertia_world * ang));
    }
    total.sqrt()
}

struct Outcome {
    time: f64,
    solution: Option<ProjectionSolution>,
}

/// One solve; warm-started from the recorded warm start when `warm`.
fn run(p: &RecordedQp, s: &SolverSettings, warm: bool) -> Outcome {
    let warm = if warm { p.warm.as_ref() } else { None };
    let start = Instant::now();
    let solution = solve_projection_warm(&p.qp, s, warm).ok();
    Outcome {
        time: start.elapsed().as_secs_f64(),
        solution,
    }
}

fn main() {
    let _ = env_logger::try_init();
    let args = parse();
    println!(
        "| state | QP rows | variant | solve ms (median) | / clarabel | max dq diff (M, rel) | worst acceptance | answered by | iterations | factorizations |"
    );
    println!("|---|---|---|---:|---:|---:|---:|---|---:|---:|");
    if let Some(scene) = &args.rapier {
        loop_cases(&args, scene);
        return;
    }
    let min_rows = args.min_rows.unwrap_or(161);
    for (name, scene) in common::engine_states() {
        if args
            .only
            .as_ref()
            .is_some_and(|o| !name.contains(o.as_str()))
        {
            continue;
        }
        let mu = args.friction.then(|| common::engine_friction(&name));
        let mut work = common::with_friction(scene.clone(), mu);
        let mut stabilizer =
            constraint_stabilization::Stabilizer::new(Settings::default()).expect("settings");
        recorder::start();
        let _ = stabilizer.stabilize(&mut work);
        let max_dofs = args.max_dofs.unwrap_or(usize::MAX);
        let qps: Vec<RecordedQp> = recorder::stop()
            .into_iter()
            .filter(|p| {
                p.qp.cones.is_empty() && p.qp.num_rows() >= min_rows && p.qp.num_dofs() <= max_dofs
            })
            .collect();
        compare(&args, &name, &qps);
    }
}

/// The slowest calls of a Rapier loop (`--rapier`), each compared.
#[cfg(feature = "rapier")]
fn loop_cases(args: &Args, scene: &str) {
    let min_rows = args.min_rows.unwrap_or(2);
    for call in engine_qps_loop::worst_calls(scene, args.steps, args.worst, |_| {}) {
        let in_solver: f64 = call.qps.iter().map(|p| p.seconds).sum();
        // Per answering solver: QPs, rows and milliseconds.
        let mut by_solver: Vec<(String, usize, usize, f64)> = Vec::new();
        for p in &call.qps {
            let solver = p.solver.map_or("failed".into(), |k| format!("{k:?}"));
            match by_solver.iter_mut().find(|(s, ..)| *s == solver) {
                Some(entry) => {
                    entry.1 += 1;
                    entry.2 += p.qp.num_rows();
                    entry.3 += 1e3 * p.seconds;
                }
                None => by_solver.push((solver, 1, p.qp.num_rows(), 1e3 * p.seconds)),
            }
        }
        let solved: Vec<String> = by_solver
            .iter()
            .map(|(s, n, rows, ms)| format!("{s}: {n} QPs, {rows} rows, {ms:.2} ms"))
            .collect();
        println!(
            "\n{scene} step {}: call {:.2} ms, {:.2} ms in the solver ({}); last stabilizer run: {} passes, narrow phase {:.2} ms, solve stage {:.2} ms, line search {:.2} ms, total {:.2} ms\n",
            call.step,
            call.call_ms,
            1e3 * in_solver,
            solved.join(", "),
            call.passes,
            call.narrow_ms,
            call.solve_ms,
            call.line_search_ms,
            call.stabilizer_ms,
        );
        let qps: Vec<RecordedQp> = call
            .qps
            .into_iter()
            .filter(|p| p.qp.num_rows() >= min_rows)
            .collect();
        compare(args, &format!("{scene}@{}", call.step), &qps);
    }
}

#[cfg(not(feature = "rapier"))]
fn loop_cases(_: &Args, _: &str) {
    eprintln!("--rapier needs --features rapier,serde");
}

/// Solves `qps` with every variant, interleaved, and prints a row per
/// variant.
fn compare(args: &Args, name: &str, qps: &[RecordedQp]) {
    if qps.is_empty() {
        return;
    }
    // `NAME+warm`: variant NAME warm-started as in the recorded call.
    let settings: Vec<(SolverSettings, bool)> = args
        .variants
        .iter()
        .map(|v| match v.strip_suffix("+warm") {
            Some(name) => (variant(name), true),
            None => (variant(v), false),
        })
        .collect();
    let reference = variant(&std::env::var("ENGINE_QPS_REFERENCE").unwrap_or("clarabel".into()));
    let reference: Vec<Option<DVector<f64>>> = qps
        .iter()
        .map(|p| run(p, &reference, false).solution.map(|s| s.dq))
        .collect();
    // times[variant][qp][round]
    let mut times = vec![vec![Vec::new(); qps.len()]; settings.len()];
    let mut last: Vec<Vec<Option<ProjectionSolution>>> =
        vec![vec![None; qps.len()]; settings.len()];
    for _ in 0..args.rounds {
        for (q, p) in qps.iter().enumerate() {
            for (v, (s, warm)) in settings.iter().enumerate() {
                let outcome = run(p, s, *warm);
                times[v][q].push(outcome.time);
                last[v][q] = outcome.solution;
            }
        }
    }
    let rows: String = if qps.len() <= 4 {
        qps.iter()
            .map(|p| p.qp.num_rows().to_string())
            .collect::<Vec<_>>()
            .join("+")
    } else {
        let total: usize = qps.iter().map(|p| p.qp.num_rows()).sum();
        let largest = qps.iter().map(|p| p.qp.num_rows()).max().unwrap_or(0);
        format!("{} QPs, {total} rows, largest {largest}", qps.len())
    };
    if std::env::var("ENGINE_QPS_PER_QP").is_ok() {
        for (q, p) in qps.iter().enumerate() {
            let medians: Vec<String> = (0..settings.len())
                .map(|v| format!("{:.4}", 1e3 * common::median(&times[v][q])))
                .collect();
            let violated = p.qp.b().iter().filter(|&&b| b < 0.0).count();
            let steps: Vec<String> = (0..settings.len())
                .map(|v| last[v][q].as_ref().map_or(0, |s| s.iterations).to_string())
                .collect();
            eprintln!(
                "per-qp {name} dofs {} rows {} violated {violated} ms {} iterations {}",
                p.qp.num_dofs(),
                p.qp.num_rows(),
                medians.join(" "),
                steps.join(" ")
            );
        }
    }
    if std::env::var("ENGINE_QPS_ANSWERS").is_ok() {
        for (q, p) in qps.iter().enumerate() {
            let b = p.qp.b();
            let describe = |dq: &DVector<f64>| {
                let s = p.qp.apply_j(dq) + &b;
                let min_slack = s.iter().cloned().fold(f64::INFINITY, f64::min);
                format!(
                    "norm {:.12e} min slack {:.3e}",
                    m_norm(&p.qp, dq),
                    min_slack
                )
            };
            if let Some(r) = &reference[q] {
                eprintln!("answers {name} qp {q} reference {}", describe(r));
            }
            for (v, vname) in args.variants.iter().enumerate() {
                if let Some(sol) = &last[v][q] {
                    eprintln!("answers {name} qp {q} {vname} {}", describe(&sol.dq));
                }
            }
        }
    }
    let clarabel_time: f64 = times[0].iter().map(|t| common::median(t)).sum();
    for (v, vname) in args.variants.iter().enumerate() {
        let time: f64 = times[v].iter().map(|t| common::median(t)).sum();
        let mut diff: f64 = 0.0;
        let mut worst_acceptance: f64 = 0.0;
        let mut answered = Vec::new();
        let (mut iterations, mut factorizations) = (0, 0);
        for (q, p) in qps.iter().enumerate() {
            match (&last[v][q], &reference[q]) {
                (Some(sol), Some(r)) => {
                    let d = m_norm(&p.qp, &(&sol.dq - r)) / m_norm(&p.qp, r).max(f64::MIN_POSITIVE);
                    diff = diff.max(d);
                    worst_acceptance = worst_acceptance.max(sol.residuals.acceptance());
                    answered.push(format!("{:?}", sol.solver));
                    iterations += sol.iterations;
                    factorizations += sol.factorizations;
                }
                _ => answered.push("failed".into()),
            }
        }
        println!(
            "| {name} | {rows} | {vname} | {:.2} | {:.2} | {diff:.1e} | {worst_acceptance:.1e} | {} | {iterations} | {factorizations} |",
            1e3 * time,
            time / clarabel_time,
            answered.join(",")
        );
    }
}
