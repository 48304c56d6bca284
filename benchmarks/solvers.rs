//! Solver comparison on contact-like projection QPs (random stacks of boxes
//! with redundant corner contacts, see `dev_support::solver`): time and
//! residual for each solver, side by side, at 1, 10, 100, 500 and 1000
//! constraints. Writes `benchmarks/results/solvers.md` (with the command,
//! the date, the commit, the load average and the seeds; in place of the
//! file's part before its first `## ` section, keeping the sections) and
//! `benchmarks/results/solvers.csv`, and prints the Markdown table.
//!
//! `cargo bench --bench solvers` (all sizes), or with a list of sizes:
//! `cargo bench --bench solvers -- 10 100`.
//!
//! Timing: for each (size, seed), every solver is run once to warm up, then
//! the solvers are run in alternation, one run each per round, for at least
//! `MIN_ROUNDS` rounds and until the rounds have taken `ROUND_BUDGET_S`, at
//! most `MAX_ROUNDS`; the median per solver is reported, and the table shows
//! the median over seeds. On a shared machine the load then weighs on every
//! solver alike. Residual: the worst
//! relative residual of `ProjectionResiduals` (natural map,
//! complementarity, primal infeasibility, stationarity), measured by the
//! same code for every solver. The LCP solvers (Lemke, PGS, clarabel dual)
//! need `A = J M^-1 J^T`: its assembly is timed separately (`build A`) and
//! included in their times.

mod common;

use std::fmt::Write as _;
use std::time::Instant;

use common::{Provenance, bench_command, results_dir};
use constraint_stabilization::solver::BlockMetric;
use constraint_stabilization::solver::Candidate;
use constraint_stabilization::solver::augmented_lagrangian::{
    self, AugmentedLagrangianSettings, Start,
};
use constraint_stabilization::solver::clarabel_qp::{ClarabelSettings, dual, primal};
use constraint_stabilization::solver::dual_active_set;
use constraint_stabilization::solver::interior_point::{self, InteriorPointSettings};
use constraint_stabilization::solver::lemke::{self, LemkeSettings};
use constraint_stabilization::solver::pgs::{self, PgsSettings, PgsStatus};
use constraint_stabilization::solver::residuals::projection_residuals;
use constraint_stabilization::solver::{Lcp, ProjectionQp};
use constraint_stabilization::solver::{dq_from_lambda, projection_to_lcp};
use dev_support::solver::{StackSpec, random_stacks};
use nalgebra::DVector;

const SIZES: [usize; 5] = [1, 10, 100, 500, 1000];
const SEEDS: u64 = 3;
/// The generator's seed of problem `seed` (0..SEEDS).
const SEED_BASE: u64 = 100;
const MIN_ROUNDS: usize = 5;
const ROUND_BUDGET_S: f64 = 2.0;
const MAX_ROUNDS: usize = 30;
/// The O(n^3)-per-pivot variant is only run up to this size (at 100 rows it
/// is already two orders of magnitude slower).
const REFACTOR_MAX_N: usize = 100;
/// The dual active-set method (dense in its active rows, `O(|A|^2)` per
/// step, and refusing more than 600 entries of `dq`) is only run up to
/// this size (about 75 boxes, 450 entries of `dq`).
const DUAL_ACTIVE_SET_MAX_N: usize = 300;

/// The augmented Lagrangian with a dense `H` is only run up to this size
/// (at 1,000 rows one solve takes seconds).
const DENSE_H_MAX_N: usize = 300;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Method {
    BuildA,
    ClarabelPrimal,
    ClarabelDual,
    Lemke,
    LemkeRefactorEvery,
    Pgs,
    AugmentedLagrangianDense,
    AugmentedLagrangianSparse,
    AugmentedLagrangianWarm,
    InteriorPoint,
    InteriorPointWarm,
    DualActiveSet,
}

const METHODS: [Method; 12] = [
    Method::BuildA,
    Method::DualActiveSet,
    Method::InteriorPoint,
    Method::InteriorPointWarm,
    Method::AugmentedLagrangianDense,
    Method::AugmentedLagrangianSparse,
    Method::AugmentedLagrangianWarm,
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
            Method::AugmentedLagrangianDense => "augmented Lagrangian, dense H",
            Method::AugmentedLagrangianSparse => "augmented Lagrangian, sparse H",
            Method::AugmentedLagrangianWarm => "augmented Lagrangian, warm",
            Method::InteriorPoint => "interior point",
            Method::InteriorPointWarm => "interior point, warm",
            Method::DualActiveSet => "dual active set",
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
    /// The multipliers of the same problem with every `phi` scaled by
    /// [`WARM_PHI_SCALE`] (a neighbouring problem, as between two passes).
    warm: DVector<f64>,
}

/// The neighbouring problem of the warm start: `phi` times this.
const WARM_PHI_SCALE: f64 = 0.9;

/// The acceptance tolerance of `solve_projection` (its default).
const ACCEPTANCE_TOL: f64 = 1e-6;

/// Runs the augmented Lagrangian with dense or sparse `H`, from `warm`.
fn augmented_lagrangian(
    p: &Problem,
    dense_max_dofs: usize,
    warm: Option<&DVector<f64>>,
) -> Result<Candidate, Failure> {
    let settings = AugmentedLagrangianSettings {
        dense_max_dofs,
        ..AugmentedLagrangianSettings::default()
    };
    let start = Start {
        warm,
        tolerance: ACCEPTANCE_TOL,
        relaxation: 1.0,
        deadline: None,
        kept: None,
    };
    augmented_lagrangian::solve(&p.qp, &p.metric, &settings, &start)
        .map_err(|e| (format!("{e:?}"), None))
}

/// Runs the interior point on the body-space matrix, from `warm`.
fn interior_point(p: &Problem, warm: Option<&DVector<f64>>) -> Result<Candidate, Failure> {
    let start = Start {
        warm,
        tolerance: ACCEPTANCE_TOL,
        relaxation: 1.0,
        deadline: None,
        kept: None,
    };
    interior_point::solve(&p.qp, &p.metric, &InteriorPointSettings::default(), &start)
        .map_err(|e| (format!("{e:?}"), None))
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
        factorizations: 0,
    };
    match method {
        Method::AugmentedLagrangianDense => augmented_lagrangian(p, usize::MAX, None),
        Method::AugmentedLagrangianSparse => augmented_lagrangian(p, 0, None),
        Method::AugmentedLagrangianWarm => augmented_lagrangian(
            p,
            AugmentedLagrangianSettings::default().dense_max_dofs,
            Some(&p.warm),
        ),
        Method::InteriorPoint => interior_point(p, None),
        Method::InteriorPointWarm => interior_point(p, Some(&p.warm)),
        Method::DualActiveSet => {
            dual_active_set::solve(&p.qp, &p.metric, ACCEPTANCE_TOL, None, None)
                .map_err(|e| (format!("{e:?}"), None))
        }
        Method::BuildA => {
            let a = lcp();
            Ok(Candidate {
                dq: Default::default(),
                lambda: a.q().clone(),
                iterations: 0,
                factorizations: 0,
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

/// Times every method of `methods` on `p`, interleaved (see the module
/// doc): one row per method.
fn measure_interleaved(p: &Problem, n: usize, seed: u64, methods: &[Method]) -> Vec<Row> {
    let first: Vec<_> = methods.iter().map(|&m| run_once(p, m)).collect();
    let mut times = vec![Vec::new(); methods.len()];
    let mut total = 0.0;
    while times[0].len() < MAX_ROUNDS && (times[0].len() < MIN_ROUNDS || total < ROUND_BUDGET_S) {
        for (&method, times) in methods.iter().zip(&mut times) {
            let start = Instant::now();
            let out = run_once(p, method);
            let t = start.elapsed().as_secs_f64();
            std::hint::black_box(out.is_ok());
            times.push(t);
            total += t;
        }
    }
    methods
        .iter()
        .zip(first)
        .zip(times)
        .map(|((&method, first), times)| row(p, n, seed, method, &first, times))
        .collect()
}

fn row(
    p: &Problem,
    n: usize,
    seed: u64,
    method: Method,
    first: &Result<Candidate, Failure>,
    times: Vec<f64>,
) -> Row {
    let time_s = median(times);
    let (residual, iterations, status) = match (first, method) {
        (Ok(_), Method::BuildA) => (None, 0, "ok".to_string()),
        (Ok(c), _) => {
            let residuals = projection_residuals(&p.qp, &p.metric, &c.dq, &c.lambda);
            (
                Some(residuals.worst()),
                c.iterations,
                if residuals.acceptance() <= ACCEPTANCE_TOL {
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

/// The multipliers of `qp` with `phi` scaled by [`WARM_PHI_SCALE`]
/// (solved cold by the augmented Lagrangian).
fn neighbour_multipliers(qp: &ProjectionQp, metric: &[BlockMetric]) -> DVector<f64> {
    let mut neighbour = qp.clone();
    for phi in &mut neighbour.phi {
        *phi *= WARM_PHI_SCALE;
    }
    let p = Problem {
        qp: neighbour,
        metric: metric.to_vec(),
        warm: DVector::zeros(0),
    };
    augmented_lagrangian(&p, usize::MAX, None)
        .map(|c| c.lambda)
        .unwrap_or_else(|_| DVector::zeros(qp.num_rows()))
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
    let provenance = Provenance::start(bench_command("solvers", &[]));
    let mut rows = Vec::new();
    let mut csv = String::from("n,seed,method,time_s,residual,iterations,status\n");
    for &n in &sizes {
        for seed in 0..SEEDS {
            let qp = random_stacks(&StackSpec::new(n, SEED_BASE + seed));
            let metric = qp.validate().expect("valid generated problem");
            let warm = neighbour_multipliers(&qp, &metric);
            let p = Problem { qp, metric, warm };
            let methods: Vec<Method> = METHODS
                .into_iter()
                .filter(|&m| m != Method::LemkeRefactorEvery || n <= REFACTOR_MAX_N)
                .filter(|&m| m != Method::AugmentedLagrangianDense || n <= DENSE_H_MAX_N)
                .filter(|&m| m != Method::DualActiveSet || n <= DUAL_ACTIVE_SET_MAX_N)
                .collect();
            for row in measure_interleaved(&p, n, seed, &methods) {
                let _ = writeln!(
                    csv,
                    "{},{},{},{:.6e},{},{},{}",
                    row.n,
                    SEED_BASE + row.seed,
                    row.method.name(),
                    row.time_s,
                    row.residual.map_or(String::new(), |r| format!("{r:.3e}")),
                    row.iterations,
                    row.status.replace(',', ";")
                );
                eprintln!(
                    "n {n} seed {} {:<24} {:>10.3} ms  {}",
                    SEED_BASE + seed,
                    row.method.name(),
                    row.time_s * 1e3,
                    row.status
                );
                rows.push(row);
            }
        }
    }
    let table = markdown(&rows, &sizes);
    println!("{table}");
    let md = format!(
        "# Solvers on contact-like projection QPs\n\n{}\n\
         Problems: `random_stacks(&StackSpec::new(n, seed))` \
         (`dev_support::solver`, random box stacks with redundant corner \
         rows), seeds {SEED_BASE} to {} for each n. For each (n, seed) every \
         solver runs once to warm up, then the solvers run in alternation, one \
         run each per round, at least {MIN_ROUNDS} rounds and until the rounds \
         have taken {ROUND_BUDGET_S} s, at most {MAX_ROUNDS}; time = median \
         over the seeds of the median per seed. The LCP solvers' times include \
         the assembly of `A = J M^-1 J^T` (`build A`). Residual: the worst \
         relative residual of `ProjectionResiduals` (natural map, \
         complementarity, primal infeasibility, stationarity), the same code \
         for every solver; solved = the acceptance test of \
         `solve_projection` passed (`ProjectionResiduals::acceptance` at most \
         1e-6). The augmented Lagrangian runs with a dense and with a sparse \
         Cholesky of `H`, and warm-started from the multipliers of the same \
         problem with every `phi` scaled by 0.9 (as between two passes); so \
         does the interior point on the body-space matrix \
         (`solver::interior_point`). The dual active-set method \
         (`solver::dual_active_set`, dense in its active rows) runs up to \
         {DUAL_ACTIVE_SET_MAX_N} rows. Every run is in `solvers.csv`.\n\n{table}",
        provenance.markdown(),
        SEED_BASE + SEEDS - 1,
    );
    let dir = results_dir();
    std::fs::write(dir.join("solvers.csv"), csv).expect("write solvers.csv");
    common::write_keeping_sections(&dir.join("solvers.md"), &md);
    println!("written to {}", dir.join("solvers.md").display());
}
