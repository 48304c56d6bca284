//! Lemke's complementary pivoting method for the LCP
//! `z >= 0, w = M z + q >= 0, z^T w = 0`, with
//! - the covering vector `d = 1` on the Jacobi-scaled problem of
//!   `super::scaling` (so every tolerance below is relative to `||M||` and
//!   `||q||` of the caller's data),
//! - the lexicographic ratio test of [`ratio`] (no cycling on degenerate
//!   problems),
//! - `n (n + 2)` multiply-adds per pivot on the condensed tableau
//!   ([`tableau`]), half of the full `B^-1 [I | -M | -d | q]` tableau's,
//!   and an LU re-solve in the final basis. Refactorizing every pivot
//!   instead (`refactor_every = 1`, `O(n^3)` each) reaches the same
//!   residuals about a hundred times slower at 100 rows (measured by
//!   `benchmarks/solvers.rs`: `benchmarks/results/solvers.md`),
//! - a pivot limit, a deadline checked before every pivot
//!   ([`LemkeSettings::deadline`], the caller's time budget), and ray
//!   termination as an outcome,
//! - a regularized retry: when the plain run fails, `M~ + eps I` for each
//!   `eps` of a growing ladder. Whatever run produced it, a `z` is returned
//!   only after its natural-map residual on the *original* (scaled,
//!   unregularized) problem is below the tolerance; the solution records
//!   the `eps` that produced it.
//!
//! When the symmetric part of `M` is positive semidefinite, `M` is
//! copositive-plus and ray termination of the plain run proves that the LCP
//! has no solution (Cottle, Pang and Stone 1992, theorem 4.4.13).
//!
//! A mixed LCP (free leading variables, `crate::solver::lcp`: the dual of
//! a projection with equality rows) is first reduced to a plain LCP by a
//! Schur complement with a pseudo-inverse of the free block ([`mixed`]);
//! inconsistent equalities end as [`LemkeStatus::InconsistentEqualities`].

pub mod mixed;
pub mod path;
pub mod ratio;
pub mod tableau;

use std::time::Instant;

use nalgebra::{DMatrix, DVector};

use super::lcp::Lcp;
use super::residuals::{lcp_natural_map, natural_map_certified, natural_map_relative};
use super::scaling::LcpScaling;
use path::{PathEnd, PathOptions, z_from_basis, z_from_tableau};
use ratio::RatioTolerances;

/// Settings of Lemke's method. All tolerances apply to the Jacobi-scaled
/// problem (unit diagonal where `M_ii > 0`, `||q~||_inf = 1`), so they are
/// relative to the caller's `M` and `q`.
#[derive(Debug, Clone, PartialEq)]
pub struct LemkeSettings {
    /// A returned `z` must have `||min(z~, w~)||_inf` below this on the
    /// scaled, unregularized problem.
    pub tol_residual: f64,
    /// Pivot elements must exceed this fraction of the column's largest
    /// magnitude.
    pub tol_pivot_rel: f64,
    /// An entering column whose entries are all below this is zero (ray).
    pub tol_zero_column: f64,
    /// Relative width within which two ratios tie.
    pub tol_tie: f64,
    /// Pivot limit per run: `max(pivot_limit_min, pivot_limit_per_row * n)`.
    pub pivot_limit_per_row: usize,
    /// See `pivot_limit_per_row`.
    pub pivot_limit_min: usize,
    /// The regularizations `eps` tried, in order, after the plain run fails
    /// (relative to the unit diagonal of the scaled problem).
    pub regularization_ladder: Vec<f64>,
    /// Refactorize the tableau from the data every this many pivots
    /// (0 = never; the final basis is always re-solved once).
    pub refactor_every: usize,
    /// A returned `z` must also have `||min(z, w)||_inf` at most this
    /// times `max(||q||_inf, ||M||_inf ||z||_inf)` on the caller's
    /// (unscaled) problem. The scaled test alone is relative to the largest
    /// scaled row: a row whose scale is small against the others can hide
    /// a violation as large as `q` (the kept fuzz input
    /// `tests/data/fuzz/lcp_solvers/crash-lemke-huge-q`;
    /// `benchmarks/results/fuzzing.md`).
    pub tol_residual_unscaled: f64,
    /// The run stops before its next pivot once this instant has passed
    /// ([`LemkeStatus::DeadlinePassed`]; no regularized retry follows);
    /// `None`: no limit. Default `None`.
    pub deadline: Option<Instant>,
}

impl Default for LemkeSettings {
    fn default() -> Self {
        Self {
            tol_residual: 1e-9,
            tol_pivot_rel: 1e-11,
            tol_zero_column: 1e-13,
            tol_tie: 1e-11,
            pivot_limit_per_row: 50,
            pivot_limit_min: 1000,
            regularization_ladder: vec![1e-12, 1e-10, 1e-8, 1e-6],
            refactor_every: 0,
            tol_residual_unscaled: 1e-6,
            deadline: None,
        }
    }
}

/// Why Lemke's method did not return a solution.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum LemkeStatus {
    /// Secondary ray: no solution (proved when `M` is copositive-plus).
    Ray,
    /// The pivot limit was reached.
    PivotLimit,
    /// The deadline ([`LemkeSettings::deadline`]) passed before the path
    /// ended.
    DeadlinePassed,
    /// A complementary basis was found, but its `z` misses the residual
    /// tolerance on the original problem.
    Inaccurate {
        /// Scaled natural-map residual.
        residual: f64,
    },
    /// A mixed LCP whose free rows cannot all hold: `b_E` is not in the
    /// range of `M_EE` ([`mixed`]); for a projection, equality rows that
    /// contradict each other.
    InconsistentEqualities {
        /// The part of `b_E` outside the range, relative to `|q|_inf`.
        residual: f64,
    },
}

/// One run (plain or regularized).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct LemkeAttempt {
    /// `eps` added to the scaled diagonal (0 for the plain run).
    pub regularization: f64,
    /// Pivots of this run.
    pub pivots: usize,
    /// `None` if this run produced the accepted solution.
    pub failure: Option<LemkeStatus>,
}

/// A checked solution.
#[derive(Debug, Clone, PartialEq)]
pub struct LemkeSolution {
    /// `z`: `z >= 0`, except the free leading variables of a mixed LCP.
    pub z: DVector<f64>,
    /// `w = M z + q`, recomputed on the original data.
    pub w: DVector<f64>,
    /// Total pivots over all runs.
    pub pivots: usize,
    /// `Some(eps)` when the accepted run was regularized.
    pub regularization: Option<f64>,
    /// Every run, in order.
    pub attempts: Vec<LemkeAttempt>,
    /// Natural map on the scaled problem, plus the rounding uncertainty of
    /// `w` (what was checked, see [`natural_map_certified`]).
    pub residual_scaled: f64,
    /// `||min(z, w)||_inf / max(1, ||q||_inf)` on the original data.
    pub residual: f64,
}

/// No solution: the status of the plain run and every attempt.
#[derive(Debug, Clone, PartialEq)]
pub struct LemkeFailure {
    /// Why the plain (unregularized) run failed.
    pub status: LemkeStatus,
    /// Every run, in order.
    pub attempts: Vec<LemkeAttempt>,
    /// Total pivots.
    pub pivots: usize,
}

/// The scaled problem shared by every run, and the caller's.
struct Scaled<'a> {
    scaling: LcpScaling,
    m: DMatrix<f64>,
    q: DVector<f64>,
    original_m: &'a DMatrix<f64>,
    original_q: &'a DVector<f64>,
}

/// Solves the LCP with Lemke's method, a mixed one by elimination first
/// (see the module docs).
pub fn solve(lcp: &Lcp, settings: &LemkeSettings) -> Result<LemkeSolution, LemkeFailure> {
    if lcp.free() > 0 {
        mixed::solve(lcp, settings)
    } else {
        solve_plain(lcp, settings)
    }
}

/// Lemke's method on an LCP without free variables.
fn solve_plain(lcp: &Lcp, settings: &LemkeSettings) -> Result<LemkeSolution, LemkeFailure> {
    let scaling = LcpScaling::jacobi(lcp.m(), lcp.q());
    let scaled = Scaled {
        m: scaling.scale_m(lcp.m()),
        q: scaling.scale_q(lcp.q()),
        scaling,
        original_m: lcp.m(),
        original_q: lcp.q(),
    };
    let mut attempts = Vec::new();
    let ladder = std::iter::once(0.0).chain(settings.regularization_ladder.iter().copied());
    for eps in ladder {
        let (attempt, z_scaled) = attempt(&scaled, eps, settings);
        let out_of_time = attempt.failure == Some(LemkeStatus::DeadlinePassed);
        attempts.push(attempt);
        if let Some(z_scaled) = z_scaled {
            return Ok(finish(lcp, &scaled, z_scaled, attempts));
        }
        if out_of_time {
            break;
        }
    }
    let pivots = attempts.iter().map(|a| a.pivots).sum();
    let status = attempts[0].failure.unwrap_or(LemkeStatus::Ray);
    log::debug!(
        "lemke: no solution after {} runs, {pivots} pivots: {status:?}",
        attempts.len()
    );
    Err(LemkeFailure {
        status,
        attempts,
        pivots,
    })
}

/// One run with `M~ + eps I`; returns the checked scaled `z` if accepted.
fn attempt(
    scaled: &Scaled,
    eps: f64,
    settings: &LemkeSettings,
) -> (LemkeAttempt, Option<DVector<f64>>) {
    let n = scaled.q.len();
    let m_run = if eps > 0.0 {
        &scaled.m + DMatrix::identity(n, n) * eps
    } else {
        scaled.m.clone()
    };
    let options = PathOptions {
        max_pivots: settings
            .pivot_limit_min
            .max(settings.pivot_limit_per_row * n),
        refactor_every: settings.refactor_every,
        deadline: settings.deadline,
        ratio: RatioTolerances {
            pivot_rel: settings.tol_pivot_rel,
            zero_column: settings.tol_zero_column,
            tie: settings.tol_tie,
        },
    };
    let path = path::run(&m_run, &DVector::from_element(n, 1.0), &scaled.q, &options);
    log::trace!(
        "lemke run eps={eps:e}: {:?} after {} pivots",
        path.end,
        path.pivots
    );
    let failure = match path.end {
        PathEnd::Ray => Some(LemkeStatus::Ray),
        PathEnd::PivotLimit => Some(LemkeStatus::PivotLimit),
        PathEnd::DeadlinePassed => Some(LemkeStatus::DeadlinePassed),
        PathEnd::Complementary => None,
    };
    let mut record = LemkeAttempt {
        regularization: eps,
        pivots: path.pivots,
        failure,
    };
    if failure.is_some() {
        return (record, None);
    }
    let (z, residual) = best_candidate(scaled, &path);
    let residual_unscaled = unscaled_residual(scaled, &z);
    if residual <= settings.tol_residual && residual_unscaled <= settings.tol_residual_unscaled {
        (record, Some(z))
    } else {
        let residual = residual.max(residual_unscaled);
        record.failure = Some(LemkeStatus::Inaccurate { residual });
        (record, None)
    }
}

/// [`natural_map_relative`] on the caller's problem for the scaled
/// solution `z_scaled`.
fn unscaled_residual(scaled: &Scaled, z_scaled: &DVector<f64>) -> f64 {
    let z = scaled.scaling.unscale_z(z_scaled);
    natural_map_relative(scaled.original_m, scaled.original_q, &z, 0)
}

/// The better of the tableau's `z` and the LU re-solve of the final basis
/// on the unregularized problem, each clamped to `z >= 0` and measured on
/// the unregularized scaled problem, rounding of `w` included
/// ([`natural_map_certified`]).
fn best_candidate(scaled: &Scaled, path: &path::Path) -> (DVector<f64>, f64) {
    let mut candidates = vec![z_from_tableau(&path.tableau)];
    candidates.extend(z_from_basis(&path.tableau.basis, &scaled.m, &scaled.q));
    candidates
        .into_iter()
        .map(|z| {
            let z = z.map(|x| x.max(0.0));
            let r = natural_map_certified(&scaled.m, &scaled.q, &z, 0);
            (z, r)
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or_else(|| (DVector::zeros(scaled.q.len()), f64::INFINITY))
}

fn finish(
    lcp: &Lcp,
    scaled: &Scaled,
    z_scaled: DVector<f64>,
    attempts: Vec<LemkeAttempt>,
) -> LemkeSolution {
    let residual_scaled = natural_map_certified(&scaled.m, &scaled.q, &z_scaled, 0);
    let z = scaled.scaling.unscale_z(&z_scaled);
    let w = lcp.w(&z);
    let residual = lcp_natural_map(&z, &w, lcp.q(), 0);
    let pivots = attempts.iter().map(|a| a.pivots).sum();
    let regularization = attempts
        .last()
        .map(|a| a.regularization)
        .filter(|&e| e > 0.0);
    LemkeSolution {
        z,
        w,
        pivots,
        regularization,
        attempts,
        residual_scaled,
        residual,
    }
}
