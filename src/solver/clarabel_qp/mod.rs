//! clarabel (Goulart and Chen 2024, an interior-point solver) on the two QP
//! forms of the projection problem.
//!
//! clarabel solves `min 1/2 x^T P x + c^T x  s.t.  A x + s = b, s in K` and
//! returns the primal `x`, the slack `s` and the dual `z in K*`. Both forms
//! here use the nonnegative cone `K = R^m_+`, the primal form with a zero
//! cone `{0}` before it for equality rows and three-dimensional
//! second-order cones after it for friction cones:
//! - [`primal`]: `x` is the (rescaled) correction `dq`, one cone row per
//!   constraint and three per friction cone ([`cone`]); `lambda` is read
//!   from the dual `z`.
//! - [`dual`]: `x` is `lambda` of the LCP, `P = A = J M^-1 J^T` dense.
//!
//! Every status is mapped: `Solved` and `AlmostSolved` hand their point to
//! our own residual check (the caller's); every other status is a
//! [`ClarabelFailure`].

pub mod cone;
pub mod dual;
pub mod polish;
pub mod primal;

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};

/// Settings passed to clarabel. The problems handed to clarabel are scaled
/// to unit size first (see [`primal`] and [`dual`]), so these absolute
/// tolerances act as relative ones on the caller's data.
#[derive(Debug, Clone, PartialEq)]
pub struct ClarabelSettings {
    /// Interior-point iteration limit (clarabel's default is 200).
    pub max_iter: u32,
    /// Wall-clock limit in seconds (infinite by default).
    pub time_limit: f64,
    /// Duality-gap tolerance, absolute and relative, on the scaled problem
    /// (clarabel's default). Default 1e-8: the interior point's answer
    /// then passes the projection's acceptance test (1e-6) by two orders of
    /// magnitude (largest acceptance measure 1.1e-8 over 126 random stacks
    /// of 10 to 2,000 rows and every engine state,
    /// `benchmarks/results/polish.md`).
    pub tol_gap: f64,
    /// Primal and dual feasibility tolerance on the scaled problem.
    pub tol_feas: f64,
    /// The primal form polishes its interior point by active-set steps
    /// ([`polish`]; up to six factorizations of the KKT system) and keeps
    /// the better point when the point's acceptance measure
    /// ([`crate::solver::ProjectionResiduals::acceptance`]) is above this.
    /// Default 0: always, which gives `dq` to rounding (about 1e-15
    /// relative) rather than to the gap (about 1e-8), for comparisons
    /// between solvers. The stabilizer's default
    /// ([`crate::Settings::default`]) is the acceptance tolerance: polish
    /// only an answer that would be rejected. Measured, the unpolished
    /// answer passed the acceptance test on every problem of 126 random
    /// stacks and of the engine states, and the polish cost 13 % of
    /// clarabel's time on the stacks (`benchmarks/results/polish.md`);
    /// stacks with mass ratios of 1e8 need it.
    pub polish_above: f64,
}

impl Default for ClarabelSettings {
    fn default() -> Self {
        Self {
            max_iter: 200,
            time_limit: f64::INFINITY,
            tol_gap: 1e-8,
            tol_feas: 1e-8,
            polish_above: 0.0,
        }
    }
}

impl ClarabelSettings {
    fn to_clarabel(&self) -> DefaultSettings<f64> {
        DefaultSettings {
            max_iter: self.max_iter,
            time_limit: self.time_limit,
            verbose: false,
            tol_gap_abs: self.tol_gap,
            tol_gap_rel: self.tol_gap,
            tol_feas: self.tol_feas,
            ..DefaultSettings::default()
        }
    }
}

/// A clarabel outcome other than (almost) solved: one variant per status,
/// plus a setup failure (clarabel rejected the data).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum ClarabelFailure {
    /// clarabel rejected the problem data or settings at setup.
    Setup(String),
    /// The solver did not run.
    Unsolved,
    /// Certificate that the constraints cannot all hold.
    PrimalInfeasible,
    /// Certificate that the objective is unbounded below.
    DualInfeasible,
    /// Primal infeasibility at reduced accuracy.
    AlmostPrimalInfeasible,
    /// Dual infeasibility at reduced accuracy.
    AlmostDualInfeasible,
    /// Iteration limit.
    MaxIterations,
    /// Time limit.
    MaxTime,
    /// Numerical error (a factorization failed).
    NumericalError,
    /// Stalled.
    InsufficientProgress,
    /// Stopped by a user callback.
    CallbackTerminated,
}

/// Accuracy clarabel claims for a point it returns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClarabelAccuracy {
    /// `Solved`: full tolerances met.
    Solved,
    /// `AlmostSolved`: reduced tolerances met.
    AlmostSolved,
}

/// Maps a clarabel status: a returned point, or the typed failure.
pub fn map_status(status: SolverStatus) -> Result<ClarabelAccuracy, ClarabelFailure> {
    match status {
        SolverStatus::Solved => Ok(ClarabelAccuracy::Solved),
        SolverStatus::AlmostSolved => Ok(ClarabelAccuracy::AlmostSolved),
        SolverStatus::Unsolved => Err(ClarabelFailure::Unsolved),
        SolverStatus::PrimalInfeasible => Err(ClarabelFailure::PrimalInfeasible),
        SolverStatus::DualInfeasible => Err(ClarabelFailure::DualInfeasible),
        SolverStatus::AlmostPrimalInfeasible => Err(ClarabelFailure::AlmostPrimalInfeasible),
        SolverStatus::AlmostDualInfeasible => Err(ClarabelFailure::AlmostDualInfeasible),
        SolverStatus::MaxIterations => Err(ClarabelFailure::MaxIterations),
        SolverStatus::MaxTime => Err(ClarabelFailure::MaxTime),
        SolverStatus::NumericalError => Err(ClarabelFailure::NumericalError),
        SolverStatus::InsufficientProgress => Err(ClarabelFailure::InsufficientProgress),
        SolverStatus::CallbackTerminated => Err(ClarabelFailure::CallbackTerminated),
    }
}

/// What a clarabel run returns when it reports (almost) solved.
#[derive(Debug, Clone, PartialEq)]
pub struct ClarabelPoint {
    /// Primal variables.
    pub x: Vec<f64>,
    /// Dual variables of the cone rows.
    pub z: Vec<f64>,
    /// Slacks `s = b - A x` of the cone rows.
    pub s: Vec<f64>,
    /// Interior-point iterations.
    pub iterations: usize,
    /// Claimed accuracy.
    pub accuracy: ClarabelAccuracy,
}

/// One clarabel solve of `min 1/2 x^T P x + c^T x, A x + s = b, s >= 0`.
pub(crate) fn run(
    p: &CscMatrix<f64>,
    c: &[f64],
    a: &CscMatrix<f64>,
    b: &[f64],
    settings: &ClarabelSettings,
) -> Result<ClarabelPoint, ClarabelFailure> {
    run_with_cones(p, c, a, b, ConeLayout::nonnegative(b.len()), settings)
}

/// How the entries of `s` in `A x + s = b` are constrained, in order: the
/// first `zero` are `= 0` (equality rows), the next `nonnegative` are
/// `>= 0`, the next `3 * second_order` form three-dimensional second-order
/// cones `s_0 >= |(s_1, s_2)|`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ConeLayout {
    /// Entries in clarabel's `ZeroConeT`.
    pub zero: usize,
    /// Entries in the `NonnegativeConeT`.
    pub nonnegative: usize,
    /// Number of `SecondOrderConeT(3)`.
    pub second_order: usize,
}

impl ConeLayout {
    /// Nonnegative entries only.
    pub(crate) fn nonnegative(nonnegative: usize) -> Self {
        Self {
            zero: 0,
            nonnegative,
            second_order: 0,
        }
    }

    /// clarabel's cones, empty blocks left out (a nonnegative cone of
    /// size 0 stands for a problem without any row, as before equality
    /// rows existed).
    fn cones(&self) -> Vec<SupportedConeT<f64>> {
        let mut cones = Vec::with_capacity(2 + self.second_order);
        if self.zero > 0 {
            cones.push(SupportedConeT::ZeroConeT(self.zero));
        }
        if self.nonnegative > 0 || (self.second_order == 0 && self.zero == 0) {
            cones.push(SupportedConeT::NonnegativeConeT(self.nonnegative));
        }
        cones.extend((0..self.second_order).map(|_| SupportedConeT::SecondOrderConeT(3)));
        cones
    }
}

/// One clarabel solve of `min 1/2 x^T P x + c^T x, A x + s = b` with `s`
/// in the cones of `layout`.
pub(crate) fn run_with_cones(
    p: &CscMatrix<f64>,
    c: &[f64],
    a: &CscMatrix<f64>,
    b: &[f64],
    layout: ConeLayout,
    settings: &ClarabelSettings,
) -> Result<ClarabelPoint, ClarabelFailure> {
    let cones = layout.cones();
    let mut solver = DefaultSolver::new(p, c, a, b, &cones, settings.to_clarabel())
        .map_err(|e| ClarabelFailure::Setup(e.to_string()))?;
    solver.solve();
    let solution = &solver.solution;
    log::trace!(
        "clarabel: status {:?} after {} iterations, r_prim {:.2e}, r_dual {:.2e}",
        solution.status,
        solution.iterations,
        solution.r_prim,
        solution.r_dual
    );
    let accuracy = map_status(solution.status)?;
    Ok(ClarabelPoint {
        x: solution.x.clone(),
        z: solution.z.clone(),
        s: solution.s.clone(),
        iterations: solution.iterations as usize,
        accuracy,
    })
}

/// Assembles a CSC matrix from `(row, col, value)` triplets; duplicates are
/// summed, exact zeros dropped.
pub(crate) fn csc_from_triplets(
    rows: usize,
    cols: usize,
    mut triplets: Vec<(usize, usize, f64)>,
) -> CscMatrix<f64> {
    triplets.sort_by_key(|&(r, c, _)| (c, r));
    let mut colptr = vec![0usize; cols + 1];
    let mut rowval = Vec::with_capacity(triplets.len());
    let mut nzval: Vec<f64> = Vec::with_capacity(triplets.len());
    let mut last: Option<(usize, usize)> = None;
    for (r, c, v) in triplets {
        if last == Some((r, c)) {
            if let Some(tail) = nzval.last_mut() {
                *tail += v;
            }
            continue;
        }
        if v == 0.0 {
            continue;
        }
        rowval.push(r);
        nzval.push(v);
        colptr[c + 1] += 1;
        last = Some((r, c));
    }
    for c in 0..cols {
        colptr[c + 1] += colptr[c];
    }
    CscMatrix::new(rows, cols, colptr, rowval, nzval)
}
