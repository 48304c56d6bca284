//! Solver comparison on contact-like projection QPs (random stacks of boxes
//! with redundant corner contacts, see `tests/solver_support`): time and
//! residual for each solver, side by side, at 1, 10, 100, 500 and 1000
//! constraints. Writes `target/solver-bench/solvers.csv` and `.md` and
//! prints the Markdown table.
//!
//! `cargo bench --bench solvers` (all sizes), or with a list of sizes:
//! `cargo bench --bench solvers -- 10 100`.
//!
//! Timing: each (size, seed, solver) is run once to warm up, then repeated
//! until `MIN_TOTAL_S` of run time or `MAX_REPS` runs; the median is
//! reported, and the table shows the median over seeds. Residual: the worst
//! relative residual of `ProjectionResiduals` (natural map,
//! complementarity, primal infeasibility, stationarity), measured by the
//! same code for every solver. The LCP solvers (Lemke, PGS, clarabel dual)
//! need `A = J M^-1 J^T`: its assembly is timed separately (`build A`) and
//! included in their times.

#[path = "../tests/solver_support/mod.rs"]
mod solver_support;

use std::fmt::Write as _;
use std::time::Instant;

use constraint_stabilization::solver::clarabel_qp::{ClarabelSettings, dual, primal};
use constraint_stabilization::solver::lemke::{self, LemkeSettings};
use constraint_stabilization::solver::metric::BlockMetric;
use constraint_stabilization::solver::outcome::Candidate;
use constraint_stabilization::solver::pgs::{self, PgsSettings, PgsStatus};
use constraint_stabilization::solver::projection_lcp::{dq_from_lambda, projection_to_lcp};
use constraint_stabilization::solver::residuals::projection_residuals;
use constraint_stabilization::solver::{Lcp, ProjectionQp};
use solver_support::{StackSpec, random_stacks};

const SIZES: [usize; 5] = [1, 10, 100, 500, 1000];
const SEEDS: u64 = 3;
const MIN_TOTAL_S: f64 = 0.3;
const MAX_REPS: usize = 30;
/// The O(n^3)-per-pivot variant is only run up to this size (at 100 rows it
/// is already two orders of magnitude slower).
const REFACTOR_MAX_N: usize = 100;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Method {
    BuildA,
    ClarabelPrimal,
    ClarabelDual,
    Lemke,
    LemkeRefactorEvery,
    Pgs,
}

const METHODS: [Method; 6] = [
    Method::BuildA,
    Method::ClarabelPrimal,
    Method::ClarabelDual,
    Method::Lemke,
    Method::LemkeRefactorEvery,
    Method::Pgs,
];

impl Method {
    fn name(self) -> &'static str {
        match self {
            Method::BuildA => "build A",
            Method::ClarabelPrimal => "clarabel primal",
            Method::ClarabelDual => "clarabel dual",
            Method::Lemke => "lemke",
            Method::LemkeRefactorEvery => "lemke (LU every pivot)",
            Method::Pgs => "pgs (1000 sweeps)",
        }
    }
}

/// One measurement.
struct Row {
    n: usize,
    seed: u64,
    method: Method,
    time_s: f64,
    residual: Option<f64>,
    iterations: usize,
    status: String,
}

struct Problem {
    qp: ProjectionQp,
    metric: Vec<BlockMetric>,
}

/// A failure: its text, and the residual the solver reached in its own
/// measure when it says (PGS at its sweep limit).
type Failure = (String, Option<f64>);

/// One run.
fn run_once(p: &Problem, method: Method) -> Result<Candidate, Failure> {
    let lcp = || -> Lcp { projection_to_lcp(&p.qp, &p.metric).expect("finite data") };
    let from_lambda = |z, iterations| Candidate {
        dq: dq_from_lambda(&p.qp, &p.metric, &z),
        lambda: z,
        iterations,
    };
    match method {
        Method::BuildA => {
            let a = lcp();
            Ok(Candidate {
                dq: Default::default(),
                lambda: a.q().clone(),
                iterations: 0,
            })
        }
        Method::ClarabelPrimal => primal::solve(&p.qp, &p.metric, &ClarabelSettings::default())
            .map_err(|e| (e.to_string(), None)),
        Method::ClarabelDual => dual::solve_lcp_unchecked(&lcp(), &ClarabelSettings::default())
            .map(|s| from_lambda(s.z, s.iterations))
            .map_err(|e| (e.to_string(), None)),
        Method::Lemke | Method::LemkeRefactorEvery => {
            let refactor_every = usize::from(method == Method::LemkeRefactorEvery);
            lemke::solve(
                &lcp(),
                &LemkeSettings {
                    refactor_every,
                    ..LemkeSettings::default()
                },
            )
            .map(|s| from_lambda(s.z, s.pivots))
            .map_err(|f| (format!("{:?}", f.status), None))
        }
        Method::Pgs => pgs::solve(&lcp(), &PgsSettings::default())
            .map(|s| from_lambda(s.z, s.sweeps))
            .map_err(|s| match s {
                PgsStatus::MaxSweeps { residual } => ("sweep limit".to_string(), Some(residual)),
                other => (format!("{other:?}"), None),
            }),
    }
}

fn measure(p: &Problem, n: usize, seed: u64, method: Method) -> Row {
    let first = run_once(p, method);
    let mut times = Vec::new();
    let mut total = 0.0;
    while times.len() < MAX_REPS && (total < MIN_TOTAL_S || times.is_empty()) {
        let start = Instant::now();
        let out = run_once(p, method);
        let t = start.elapsed().as_secs_f64();
        std::hint::black_box(out.is_ok());
        times.push(t);
        total += t;
    }
    times.sort_by(f64::total_cmp);
    let time_s = times[times.len() / 2];
    let (residual, iterations, status) = match (&first, method) {
        (Ok(_), Method::BuildA) => (None, 0, "ok".to_string()),
        (Ok(c), _) => {
            let r = projection_residuals(&p.qp, &p.metric, &c.dq, &c.lambda).worst();
            (
                Some(r),
                c.iterations,
                if r <= 1e-9 {
                    "solved".into()
                } else {
                    "inaccurate".into()
                },
            )
        }
        (Err((e, Some(own))), Method::Pgs) => (
            None,
            PgsSettings::default().max_sweeps,
            format!("{e} (residual {own:.0e}, own measure)"),
        ),
        (Err((e, _)), _) => (None, 0, e.clone()),
    };
    Row {
        n,
        seed,
        method,
        time_s,
        residual,
        iterations,
        status,
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        f64::NAN
    } else {
        v[v.len() / 2]
    }
}

fn markdown(rows: &[Row], sizes: &[usize]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "| n | method | time (ms, median) | worst residual (max over seeds) | iterations / pivots | solved | failures |"
    );
    let _ = writeln!(out, "|---:|---|---:|---:|---:|---:|---|");
    for &n in sizes {
        for method in METHODS {
            let sel: Vec<&Row> = rows
                .iter()
                .filter(|r| r.n == n && r.method == method)
                .collect();
            if sel.is_empty() {
                continue;
            }
            let t = median(sel.iter().map(|r| r.time_s).collect()) * 1e3;
            let res = sel
                .iter()
                .filter_map(|r| r.residual)
                .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.max(x))));
            let it = median(sel.iter().map(|r| r.iterations as f64).collect());
            let solved = sel.iter().filter(|r| r.status == "solved").count();
            let res_text = res.map_or("-".to_string(), |r| format!("{r:.1e}"));
            let solved_text = if method == Method::BuildA {
                "-".to_string()
            } else {
                format!("{solved}/{}", sel.len())
            };
            let failures: Vec<&str> = sel
                .iter()
                .filter(|r| r.status != "solved" && r.status != "ok")
                .map(|r| r.status.as_str())
                .collect();
            let _ = writeln!(
                out,
                "| {n} | {} | {t:.3} | {res_text} | {it:.0} | {solved_text} | {} |",
                method.name(),
                failures.join("; ")
            );
        }
    }
    out
}

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let sizes: Vec<usize> = if args.is_empty() {
        SIZES.to_vec()
    } else {
        args
    };
    let mut rows = Vec::new();
    let mut csv = String::from("n,seed,method,time_s,residual,iterations,status\n");
    for &n in &sizes {
        for seed in 0..SEEDS {
            let qp = random_stacks(&StackSpec::new(n, 100 + seed));
            let metric = qp.validate().expect("valid generated problem");
            let p = Problem { qp, metric };
            for method in METHODS {
                if method == Method::LemkeRefactorEvery && n > REFACTOR_MAX_N {
                    continue;
                }
                let row = measure(&p, n, seed, method);
                let _ = writeln!(
                    csv,
                    "{},{},{},{:.6e},{},{},{}",
                    row.n,
                    row.seed,
                    row.method.name(),
                    row.time_s,
                    row.residual.map_or(String::new(), |r| format!("{r:.3e}")),
                    row.iterations,
                    row.status.replace(',', ";")
                );
                eprintln!(
                    "n {n} seed {seed} {:<24} {:>10.3} ms  {}",
                    method.name(),
                    row.time_s * 1e3,
                    row.status
                );
                rows.push(row);
            }
        }
    }
    let md = markdown(&rows, &sizes);
    println!("{md}");
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/target/solver-bench");
    if std::fs::create_dir_all(dir).is_ok() {
        let _ = std::fs::write(format!("{dir}/solvers.csv"), csv);
        let _ = std::fs::write(format!("{dir}/solvers.md"), md);
    }
}
