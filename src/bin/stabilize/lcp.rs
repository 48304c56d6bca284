//! `stabilize lcp FILE.dat [--solver lemke|clarabel|pgs]`: solve one LCP
//! file and print one JSON object to stdout:
//!
//! ```text
//! { "solver", "status", "z", "w", "residual", "pivots" | "iterations", "time_s", ... }
//! ```
//!
//! `status` is `"solved"` when the solver succeeded *and* the natural-map
//! residual `||min(z, w)||_inf / max(1, ||q||_inf)` is at most
//! [`LCP_FILE_TOL`]; otherwise it names the failure, `z`, `w` and
//! `residual` are null (no unchecked answer is printed) and the exit code
//! is 1. A file that cannot be read, and a solver that does not apply to
//! the problem (clarabel on a matrix that is not symmetric positive
//! semidefinite, PGS on a non-positive diagonal), exit with 2 and a message
//! on stderr.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::{Args, ValueEnum};
use constraint_stabilization::io::read_lcp_file;
use constraint_stabilization::solver::FailureReason;
use constraint_stabilization::solver::Lcp;
use constraint_stabilization::solver::clarabel_qp::{ClarabelSettings, dual};
use constraint_stabilization::solver::lemke::{self, LemkeSettings, LemkeStatus};
use constraint_stabilization::solver::pgs::{self, PgsSettings, PgsStatus};
use constraint_stabilization::solver::residuals::lcp_natural_map;
use nalgebra::DVector;
use serde_json::{Value, json};

/// The acceptance threshold of `tests/data/siconos/README.md`.
pub const LCP_FILE_TOL: f64 = 1e-9;

/// Arguments of `stabilize lcp`.
#[derive(Debug, Args)]
pub struct LcpArgs {
    /// The LCP file.
    file: PathBuf,
    /// The solver.
    #[arg(long, value_enum, default_value_t = LcpSolver::Lemke)]
    solver: LcpSolver,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum LcpSolver {
    Lemke,
    Clarabel,
    Pgs,
}

/// What a solver produced.
struct Outcome {
    /// `Ok(z)` or the failure's status string.
    result: Result<DVector<f64>, String>,
    /// `("pivots" | "iterations", count)`.
    count: (&'static str, usize),
    /// Solver-specific fields.
    extra: Vec<(&'static str, Value)>,
}

/// Runs the subcommand.
pub fn run(args: &LcpArgs) -> ExitCode {
    let lcp = match read_lcp_file(&args.file) {
        Ok(lcp) => lcp,
        Err(e) => return usage_error(&format!("{}: {e}", args.file.display())),
    };
    if let Err(message) = applicable(&lcp, args.solver) {
        return usage_error(&message);
    }
    let start = Instant::now();
    let outcome = solve(&lcp, args.solver);
    let time_s = start.elapsed().as_secs_f64();
    report(&lcp, args.solver, outcome, time_s)
}

fn usage_error(message: &str) -> ExitCode {
    eprintln!("stabilize lcp: {message}");
    ExitCode::from(2)
}

fn applicable(lcp: &Lcp, solver: LcpSolver) -> Result<(), String> {
    match solver {
        LcpSolver::Clarabel if !lcp.is_symmetric_psd() => Err(
            "clarabel applies only where M is symmetric positive semidefinite (the LCP is then a convex QP); \
             this M is not: use --solver lemke"
                .into(),
        ),
        LcpSolver::Pgs => match lcp.m().diagonal().iter().position(|&d| d <= 0.0) {
            Some(row) => Err(format!("PGS needs a positive diagonal; M[{row}][{row}] is not: use --solver lemke")),
            None => Ok(()),
        },
        _ => Ok(()),
    }
}

fn solve(lcp: &Lcp, solver: LcpSolver) -> Outcome {
    match solver {
        LcpSolver::Lemke => solve_lemke(lcp),
        LcpSolver::Clarabel => solve_clarabel(lcp),
        LcpSolver::Pgs => solve_pgs(lcp),
    }
}

fn solve_lemke(lcp: &Lcp) -> Outcome {
    match lemke::solve(lcp, &LemkeSettings::default()) {
        Ok(s) => Outcome {
            result: Ok(s.z),
            count: ("pivots", s.pivots),
            extra: vec![("regularization", json!(s.regularization))],
        },
        Err(f) => {
            let status = match f.status {
                LemkeStatus::Ray => "ray_termination",
                LemkeStatus::PivotLimit => "pivot_limit",
                LemkeStatus::Inaccurate { .. } => "inaccurate",
                LemkeStatus::InconsistentEqualities { .. } => "inconsistent_equalities",
                LemkeStatus::DeadlinePassed => "deadline_passed",
            };
            Outcome {
                result: Err(status.into()),
                count: ("pivots", f.pivots),
                extra: vec![("attempts", json!(f.attempts.len()))],
            }
        }
    }
}

fn solve_clarabel(lcp: &Lcp) -> Outcome {
    match dual::solve_lcp(lcp, &ClarabelSettings::default()) {
        Ok(s) => Outcome {
            result: Ok(s.z),
            count: ("iterations", s.iterations),
            extra: Vec::new(),
        },
        Err(reason) => {
            let status = match reason {
                FailureReason::Clarabel(c) => format!("clarabel_{}", snake(&format!("{c:?}"))),
                other => snake(&format!("{other:?}")),
            };
            Outcome {
                result: Err(status),
                count: ("iterations", 0),
                extra: Vec::new(),
            }
        }
    }
}

fn solve_pgs(lcp: &Lcp) -> Outcome {
    match pgs::solve(lcp, &PgsSettings::default()) {
        Ok(s) => Outcome {
            result: Ok(s.z),
            count: ("iterations", s.sweeps),
            extra: Vec::new(),
        },
        Err(status) => {
            let (name, sweeps) = match status {
                PgsStatus::MaxSweeps { .. } => {
                    ("max_iterations", PgsSettings::default().max_sweeps)
                }
                PgsStatus::Diverged { sweeps } => ("diverged", sweeps),
                PgsStatus::DeadlinePassed { sweeps } => ("deadline_passed", sweeps),
                PgsStatus::NonPositiveDiagonal { .. } => ("non_positive_diagonal", 0),
            };
            Outcome {
                result: Err(name.into()),
                count: ("iterations", sweeps),
                extra: Vec::new(),
            }
        }
    }
}

/// `CamelCase` (up to the first parenthesis or brace) to `snake_case`.
fn snake(debug: &str) -> String {
    let head = debug.split(['(', ' ', '{']).next().unwrap_or(debug);
    let mut out = String::new();
    for (i, c) in head.chars().enumerate() {
        if c.is_uppercase() && i > 0 {
            out.push('_');
        }
        out.extend(c.to_lowercase());
    }
    out
}

fn report(lcp: &Lcp, solver: LcpSolver, outcome: Outcome, time_s: f64) -> ExitCode {
    let solver_name = format!("{solver:?}").to_lowercase();
    let mut object = json!({ "solver": solver_name, "time_s": time_s });
    let (status, z, w, residual) = match outcome.result {
        Ok(z) => {
            let w = lcp.w(&z);
            let residual = lcp_natural_map(&z, &w, lcp.q(), lcp.free());
            let status = if residual <= LCP_FILE_TOL {
                "solved".to_string()
            } else {
                "inaccurate".to_string()
            };
            (
                status,
                json!(z.as_slice()),
                json!(w.as_slice()),
                json!(residual),
            )
        }
        Err(status) => (status, Value::Null, Value::Null, Value::Null),
    };
    let solved = status == "solved";
    // A JSON object literal always yields `Value::Object`.
    if let Some(map) = object.as_object_mut() {
        map.insert("status".into(), json!(status));
        map.insert("z".into(), if solved { z } else { Value::Null });
        map.insert("w".into(), if solved { w } else { Value::Null });
        map.insert("residual".into(), residual);
        map.insert(outcome.count.0.into(), json!(outcome.count.1));
        for (key, value) in outcome.extra {
            map.insert(key.into(), value);
        }
    }
    println!("{object}");
    if solved {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
