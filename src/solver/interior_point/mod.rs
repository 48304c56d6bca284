//! A primal-dual interior-point method for the projection QP on the
//! body-space matrix, with the sparse symbolic analysis kept for the whole
//! solve.
//!
//! The problem (`super::projection`, inequality rows only) with slacks `s`:
//!
//! ```text
//! minimize 1/2 dq^T M dq   s.t.   J dq + b - s = 0,   s >= 0
//! ```
//!
//! (`b = phi - target`), multipliers `lambda >= 0` and the KKT conditions
//! `M dq = J^T lambda`, `s_i lambda_i = 0`. Mehrotra's predictor-corrector
//! (one factorization, two solves per iteration) applies Newton's method to
//! the perturbed conditions `s_i lambda_i = sigma mu`. Eliminating the
//! slacks and multipliers (`D = Lambda S^-1`)
//!
//! ```text
//! ds      = J ddq + r_p                                    (r_p = J dq + b - s)
//! dlambda = -S^-1 (r_c + Lambda ds)                        (r_c = S lambda - sigma mu + corrector)
//! (M + J^T D J) ddq = -r_d - J^T (S^-1 r_c + D r_p)        (r_d = M dq - J^T lambda)
//! ```
//!
//! leaves the body-space matrix `H = M + J^T D J` of the augmented
//! Lagrangian (`super::augmented_lagrangian`, whose assembly and sparse
//! Cholesky it shares): `6 n_bodies` unknowns instead of clarabel's KKT
//! system of `6 n_bodies + rows`, positive definite however redundant the
//! rows are (`H >= M`), and of the same pattern in every iteration: the
//! ordering and symbolic factorization are done once, each iteration costs
//! one numeric factorization and two solves.
//!
//! **Per-iteration work.** Where every row has at most two bodies (contact
//! rows, friction facets), the rows are packed (`super::packed_rows`):
//! `J^T D J` is accumulated per pair of bodies on a 12x12 matrix and
//! scattered into `H` once per pair (a box face with friction brings 20
//! rows per pair), and `J v`, `J^T v` read contiguous gradients
//! ([`InteriorPointSettings::packed_rows`]). Up to
//! [`InteriorPointSettings::dense_max_dofs`] the factor is a dense
//! Cholesky written for those sizes (`super::dense_cholesky`), above it
//! faer's supernodal sparse one.
//!
//! **Scale.** Rows are measured in the whitened distance of the most
//! violated row, `l = max_i max(0, -b_i) / g_i` with `g_i = sqrt(a_i)`,
//! `a_i = J_i M^-1 J_i^T`: the start is `s_i = g_i l max(1, b_i / (g_i l))`,
//! `lambda_i = l^2 / s_i` (each row's slack and force of order one in
//! those units, and the start centred: `s_i lambda_i = l^2` on every row),
//! so the iteration is the same whatever the masses and lengths.
//!
//! **Answer.** After every iteration the candidate `(dq, lambda)` (the
//! iterate, and `M^-1 J^T lambda` with exact stationarity) is measured by
//! the acceptance test of every solver (`super::residuals`); the solver
//! stops once it is at most
//! [`InteriorPointSettings::stop_fraction`] of the caller's tolerance: the
//! duality gap then certifies `dq` to that relative error in the `M`-norm,
//! so the answer is clarabel's polished one to that precision (the
//! minimizer is unique in `dq`). A **warm start** (multipliers of a
//! neighbouring problem) is measured first as it is, after the scaling of
//! `super::augmented_lagrangian` (the `s >= 0` that maximizes the dual along
//! it); when it passes the stop test (at the looser of the stop fraction
//! and `1e-3`, the warm finish's rounding floor being near `1e-10`) it is
//! returned with zero
//! iterations and no factorization. Else, when it is within
//! `WARM_FINISH_MAX_ACCEPTANCE` of passing, the warm finish (`warm`: the
//! method of multipliers on its active set, one factorization and a few
//! solves) tries to certify it. Otherwise the iteration starts cold: an
//! interior point cannot start from a warm start as it is (its
//! complementarity is exact), and started from one with its
//! complementarity raised to `1e-4` to `1e-2` of the cold start's it took
//! 3-21 % more iterations than cold on the loop's problems
//! (`benchmarks/results/solvers.md`).
//!
//! **Not applicable** to equality rows and friction cones (the caller
//! falls back). **Infeasible** problems make the iterates diverge, and
//! the multipliers then turn into a Farkas certificate: `lambda >= 0`
//! with `b^T lambda < 0` and `J^T lambda` small. After every iteration
//! its radius `R = -b^T lambda / ||J^T lambda||_{M^-1}` (no correction
//! shorter than `R` in the `M`-norm satisfies the rows) is measured, and
//! from [`InteriorPointSettings::infeasible_radius`] (1e6) times `l` the solver stops with
//! [`InteriorPointFailure::Infeasible`], which certifies the
//! infeasibility as clarabel's certificate does (a caller that stops on
//! certified infeasibility, as the stabilizer does for friction
//! pyramids, then drops friction without running clarabel). A
//! certificate that grows too slowly runs to the iteration limit
//! ([`InteriorPointFailure::NotConverged`]) and the caller's fallback
//! (clarabel) certifies the infeasibility.

mod centrality;
mod step;
mod warm;

use std::time::Instant;

use nalgebra::DVector;

use super::augmented_lagrangian::Start;
use super::augmented_lagrangian::hessian::NewtonMatrix;
use super::metric::BlockMetric;
use super::outcome::Candidate;
use super::packed_rows::PackedRows;
use super::projection::ProjectionQp;
use super::projection_lcp::dq_from_lambda;
use super::residuals::{m_apply, m_inv, projection_residuals, row_diagonal};
use step::{Iterate, StepInputs, StepTaken, newton_step};

/// Settings of the interior-point solver.
#[derive(Debug, Clone, PartialEq)]
pub struct InteriorPointSettings {
    /// Iterations before giving up. Default 60.
    pub max_iter: usize,
    /// The solver stops once the acceptance measure is at most this
    /// fraction of the tolerance. Default 1e-6 (1e-12 at the default
    /// tolerance): the answers then agree with clarabel's at gap
    /// tolerance 1e-12 within 4e-7 relative in `dq` on the engine states,
    /// where at 1e-3 they were up to 1e-5 apart (as were clarabel's at its
    /// default 1e-8 from the tight ones: `benchmarks/results/solvers.md`).
    pub stop_fraction: f64,
    /// Fraction of the step to the boundary of `s, lambda >= 0` taken.
    /// Default 0.99.
    pub step_fraction: f64,
    /// Dense Cholesky of `H` up to this many entries of `dq`, sparse above
    /// (as the augmented Lagrangian's). Default 96.
    pub dense_max_dofs: usize,
    /// The sparse factor is supernodal (as the augmented Lagrangian's)
    /// rather than left to faer's flop-ratio choice. Default true.
    pub supernodal: bool,
    /// `H` is assembled from the rows grouped by body pair and `J v`,
    /// `J^T v` read packed gradients (`super::packed_rows`), where every
    /// row has at most two bodies. Default true; false: the general
    /// per-row path (the same matrices up to the order of the sums).
    pub packed_rows: bool,
    /// The Farkas radius, in units of `l` (module docs), from which the
    /// solver stops with [`InteriorPointFailure::Infeasible`]: no
    /// correction shorter than this many `l` in the `M`-norm satisfies the
    /// rows. Default [`INFEASIBLE_RADIUS_REL`] (1e6), a certificate of
    /// infeasibility in all but name; the stabilizer lowers it for friction
    /// pyramids to [`crate::Settings::friction_max_correction`] (friction
    /// that needs a correction that long cannot be honoured by any step
    /// it would take).
    pub infeasible_radius: f64,
    /// Gondzio's centrality correctors per iteration (`centrality.rs`):
    /// extra solves with the iteration's factor that lengthen the step.
    /// Default 0 (Mehrotra's predictor-corrector alone).
    pub centrality_correctors: usize,
}

impl Default for InteriorPointSettings {
    fn default() -> Self {
        Self {
            max_iter: 60,
            stop_fraction: 1e-6,
            step_fraction: 0.99,
            dense_max_dofs: 96,
            supernodal: true,
            packed_rows: true,
            infeasible_radius: INFEASIBLE_RADIUS_REL,
            centrality_correctors: 0,
        }
    }
}

/// Why the interior-point solver gave up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum InteriorPointFailure {
    /// Equality rows or friction cones, which it does not take.
    NotApplicable,
    /// The iteration limit, or iterates that are no longer finite (an
    /// infeasible problem whose certificate grows too slowly to reach
    /// `INFEASIBLE_RADIUS_REL`, or rounding).
    NotConverged,
    /// A Cholesky factorization of `H` failed, or an iterate was not finite.
    Factorization,
    /// The deadline passed.
    Deadline,
    /// The iterates' multipliers are a Farkas certificate (module docs):
    /// no correction within `INFEASIBLE_RADIUS_REL` (1e6) times `l` of
    /// zero (in the `M`-norm) satisfies the rows.
    Infeasible,
}

/// Solves `qp` (module docs). `Candidate::iterations` counts interior-point
/// iterations, `Candidate::factorizations` numeric factorizations of `H`.
pub fn solve(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    settings: &InteriorPointSettings,
    start: &Start<'_>,
) -> Result<Candidate, InteriorPointFailure> {
    if qp.num_equalities > 0 || !qp.cones.is_empty() {
        return Err(InteriorPointFailure::NotApplicable);
    }
    let own_target = settings.stop_fraction * start.tolerance;
    let target = match start.relaxation > 1.0 {
        true => (own_target * start.relaxation)
            .min(crate::solver::PRECISION_STOP_CAP * start.tolerance)
            .max(own_target),
        false => own_target,
    };
    log::trace!(
        "interior point: stop target {target:.2e} (relaxation {:.2e})",
        start.relaxation
    );
    let mut newton =
        NewtonMatrix::new(qp, settings.dense_max_dofs, settings.supernodal, start.kept);
    let mut factorizations = 0;
    if let Some(warm) = start.warm {
        // The method of multipliers of the warm finish has a rounding floor
        // near 1e-10 (random stacks): a warm start is accepted at the
        // rounding-floor fraction of the tolerance.
        let warm_target = target.max(ROUNDING_FLOOR_FRACTION * start.tolerance);
        match warm_candidate(qp, metric, warm, warm_target) {
            Ok(candidate) => {
                log::trace!("interior point: warm start accepted as it is");
                return Ok(candidate);
            }
            // The warm finish only where the warm start is nearly the
            // answer: from a far one it fails and costs a factorization.
            Err((scaled, acceptance)) if acceptance <= WARM_FINISH_MAX_ACCEPTANCE => {
                if let Some(candidate) = warm::warm_finish(
                    qp,
                    metric,
                    &mut newton,
                    &scaled,
                    warm_target,
                    &mut factorizations,
                ) {
                    log::trace!("interior point: warm start certified by the warm finish");
                    return Ok(candidate);
                }
            }
            Err((_, acceptance)) => {
                log::trace!(
                    "interior point: warm start too far for the warm finish (acceptance {acceptance:.2e})"
                );
            }
        }
    }
    let m = qp.num_rows();
    let b = qp.b();
    let a = row_diagonal(qp, metric);
    let g: Vec<f64> = a.iter().map(|&x| x.sqrt()).collect();
    // The whitened distance of the most violated row (module docs); the
    // caller only solves problems with a violated row, but a problem with
    // none starts at the scale of its nearest row.
    let mut l = (0..m)
        .filter(|&i| g[i] > 0.0)
        .map(|i| (-b[i]).max(0.0) / g[i])
        .fold(0.0, f64::max);
    if l <= 0.0 {
        l = (0..m)
            .filter(|&i| g[i] > 0.0)
            .map(|i| b[i].abs() / g[i])
            .fold(0.0, f64::max);
    }
    if !(l > 0.0 && l.is_finite()) {
        return Err(InteriorPointFailure::NotApplicable);
    }
    // Rows no body moves hold (the caller rejected them otherwise): they
    // stay out with a zero multiplier.
    let moved: Vec<bool> = g.iter().map(|&x| x > 0.0 && x.is_finite()).collect();
    let mut it = Iterate {
        dq: DVector::zeros(qp.num_dofs()),
        s: DVector::from_fn(m, |i, _| {
            if moved[i] {
                g[i] * l * (b[i] / (g[i] * l)).max(1.0)
            } else {
                1.0
            }
        }),
        lambda: DVector::from_fn(m, |i, _| {
            if moved[i] {
                l / (g[i] * (b[i] / (g[i] * l)).max(1.0))
            } else {
                0.0
            }
        }),
        jt_lambda: None,
    };
    let packed = settings.packed_rows.then(|| PackedRows::new(qp)).flatten();
    let mut best: Option<(Candidate, f64)> = None;
    for iteration in 1..=settings.max_iter {
        if start.deadline.is_some_and(|d| Instant::now() >= d) {
            return Err(InteriorPointFailure::Deadline);
        }
        let inputs = StepInputs {
            qp,
            metric,
            b: &b,
            moved: &moved,
            a: &a,
            packed: packed.as_ref(),
        };
        let StepTaken { gap, clamped } = newton_step(
            &inputs,
            &mut newton,
            &mut it,
            settings.step_fraction,
            settings.centrality_correctors,
        )?;
        factorizations += 1;
        // Weights clamped after an answer at the rounding floor: the
        // iterates only degrade from here (on a bin of 160 boxes with
        // friction they wandered 38 more iterations to the limit and the
        // best candidate, already at hand, answered).
        let floor = ROUNDING_FLOOR_FRACTION * start.tolerance;
        if clamped && best.as_ref().is_some_and(|(_, b)| *b <= floor) {
            log::trace!(
                "interior point: factorization clamped at iteration {iteration} after an answer at the rounding floor"
            );
            break;
        }
        let radius = farkas_radius(&inputs, &g, &mut it) / l;
        log::trace!(
            "interior point: iteration {iteration}, gap {:.2e} l^2, Farkas radius {radius:.2e} l",
            gap / (l * l)
        );
        if radius >= settings.infeasible_radius {
            log::trace!("interior point: infeasibility certified at iteration {iteration}");
            return Err(InteriorPointFailure::Infeasible);
        }
        // The acceptance test costs several products with `J`: it is only
        // measured once the complementarity gap, relative to the energy
        // scale `l^2`, is small enough for it to pass.
        if gap > CHECK_GAP_REL * l * l && iteration < settings.max_iter {
            continue;
        }
        let (candidate, acceptance) = best_candidate(qp, metric, &it, iteration, factorizations);
        log::trace!("interior point: iteration {iteration}, acceptance {acceptance:.2e}");
        if best.as_ref().is_none_or(|(_, b)| acceptance < *b) {
            best = Some((candidate, acceptance));
        }
        if acceptance <= target {
            break;
        }
    }
    // The iteration can stall at the rounding floor short of a very small
    // target: the best candidate within the tolerance's stop fraction of
    // the default answers then.
    match best {
        Some((candidate, acceptance))
            if acceptance <= target.max(ROUNDING_FLOOR_FRACTION * start.tolerance) =>
        {
            log::trace!(
                "interior point: answered after {} iterations, acceptance {acceptance:.2e} ({})",
                candidate.iterations,
                if newton.is_dense() { "dense" } else { "sparse" }
            );
            Ok(candidate)
        }
        _ => Err(InteriorPointFailure::NotConverged),
    }
}

/// The acceptance test is measured once the complementarity gap
/// `sum_i s_i lambda_i` is at most this times `l^2` (the energy of the
/// most violated row alone; module docs).
const CHECK_GAP_REL: f64 = 1e-8;

/// The interior point stops with [`InteriorPointFailure::Infeasible`] once
/// its multipliers prove that no correction within this many `l` (the
/// whitened distance of the most violated row, module docs) of zero
/// satisfies the rows (a correction a million times the most violated
/// row's: no step would ever take it). On the MuJoCo hull pile with its
/// friction (1,235 pyramid rows, wedged) the radius grows from 10 to 6e8
/// `l` at the tenth iteration, where the iterates break down and used to
/// run on to the limit of 60 before clarabel certified the
/// infeasibility; on seven wedged pyramids of the Rapier loop (55-165
/// rows) likewise, each confirmed by clarabel. Over 5,036 solves that
/// converged in the loop the largest radius was 191 `l`. A certificate
/// that grows slowly (the MuJoCo bin of 160 boxes with its friction: 15 %
/// per iteration, 2.5e5 `l` at the limit) is left to clarabel at this
/// radius, and stops at the stabilizer's radius for friction, 1e4 `l`
/// (`crate::Settings::friction_max_correction`), after about 32.
/// The measurement (one product with `J^T` per iteration) costs about 2 %
/// of the interior point's time on the engine states' QPs of 41 rows and
/// more (120.4 against 122.7 ms summed, medians of four interleaved runs).
pub const INFEASIBLE_RADIUS_REL: f64 = 1e6;

/// The radius of the Farkas certificate of `lambda >= 0` (negative parts
/// ignored) for the rows `J dq + b >= 0`:
///
/// ```text
/// R = -b^T lambda / ||J^T lambda||_{M^-1}      (0 unless b^T lambda < 0)
/// ```
///
/// For every `dq`, `lambda^T (J dq + b)` is at most
/// `||J^T lambda||_{M^-1} ||dq||_M + b^T lambda`,
/// which is negative when `||dq||_M < R`: some row is then
/// violated, so every correction that satisfies the rows is longer than
/// `R`. The norm is taken no smaller than the rounding of the sum that
/// forms it (`m` epsilons of `sum_i lambda_i g_i`, `g_i = ||J_i||_{M^-1}`),
/// so that rounding cannot make a certificate.
fn farkas_radius(inputs: &StepInputs, g: &[f64], it: &mut Iterate) -> f64 {
    let lambda = it.lambda.map(|x| x.max(0.0));
    let beta = inputs.b.dot(&lambda);
    if beta.is_nan() || beta >= 0.0 {
        return 0.0;
    }
    // ||J^T lambda||_{M^-1}^2 = f^T M^-1 f with f = J^T lambda. The
    // iterate's multipliers are positive (the step stays inside the
    // boundary), so `f` is the iterate's own `J^T lambda`, which the next
    // step's stationarity residual reuses; `J^T` skips zero multipliers,
    // so a zero of either sign gives the same `f`.
    let clamped = it.lambda.iter().any(|&x| x < 0.0);
    let clamped_force;
    let force = if clamped {
        clamped_force = inputs.apply_jt(&lambda);
        &clamped_force
    } else {
        it.jt_lambda(inputs)
    };
    let norm = force.dot(&m_inv(inputs.metric, force)).max(0.0).sqrt();
    let magnitude: f64 = lambda.iter().zip(g).map(|(l, g)| l * g).sum();
    let rounding = f64::EPSILON * lambda.len() as f64 * magnitude;
    let radius = -beta / norm.max(rounding);
    if radius.is_finite() { radius } else { 0.0 }
}

/// The warm finish is tried only from a warm start whose acceptance
/// measure is at most this. In the Rapier loop of the pile of 200 the
/// previous call's multipliers measure 4e-6 to 1e6 (median 1): the finish
/// certified none of 2,866 and cost a factorization and six solves per
/// island, a fifth of the interior point's time
/// (`benchmarks/results/solvers.md`, "The interior point's warm start in
/// the loop"). An unchanged problem's warm start passes as it is.
const WARM_FINISH_MAX_ACCEPTANCE: f64 = 1e-6;

/// An answer whose acceptance measure is at most this fraction of the
/// tolerance is returned when the iteration limit stops a smaller
/// [`InteriorPointSettings::stop_fraction`].
const ROUNDING_FLOOR_FRACTION: f64 = 1e-3;

/// The better of the iterate and its multipliers' `M^-1 J^T lambda`, by
/// the acceptance measure (NaN counts as infinite).
fn best_candidate(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    it: &Iterate,
    iterations: usize,
    factorizations: usize,
) -> (Candidate, f64) {
    let lambda = it.lambda.map(|x| x.max(0.0));
    let stationary = dq_from_lambda(qp, metric, &lambda);
    let measure = |dq: &DVector<f64>| {
        let a = projection_residuals(qp, metric, dq, &lambda).acceptance();
        if a.is_nan() { f64::INFINITY } else { a }
    };
    let (from_iterate, from_lambda) = (measure(&it.dq), measure(&stationary));
    let (dq, acceptance) = if from_lambda <= from_iterate {
        (stationary, from_lambda)
    } else {
        (it.dq.clone(), from_iterate)
    };
    (
        Candidate {
            dq,
            lambda,
            iterations,
            factorizations,
        },
        acceptance,
    )
}

/// The warm start as it is, then scaled (module docs): the first that
/// passes the stop test at `target`; else the multipliers the warm finish
/// would start from (scaled when the scale is defined) with their
/// acceptance measure (NaN counts as infinite).
fn warm_candidate(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    warm: &DVector<f64>,
    target: f64,
) -> Result<Candidate, (DVector<f64>, f64)> {
    let lambda = DVector::from_fn(qp.num_rows(), |i, _| {
        warm.get(i)
            .copied()
            .filter(|x| x.is_finite())
            .unwrap_or(0.0)
            .max(0.0)
    });
    let dq = dq_from_lambda(qp, metric, &lambda);
    let measure = |dq: &DVector<f64>, lambda: &DVector<f64>| {
        let a = projection_residuals(qp, metric, dq, lambda).acceptance();
        if a.is_nan() { f64::INFINITY } else { a }
    };
    let candidate = |dq: DVector<f64>, lambda: DVector<f64>| Candidate {
        dq,
        lambda,
        iterations: 0,
        factorizations: 0,
    };
    let acceptance = measure(&dq, &lambda);
    if acceptance <= target {
        return Ok(candidate(dq, lambda));
    }
    // The scale that maximizes the dual along the warm start:
    // s = -b^T lambda / lambda^T J M^-1 J^T lambda.
    let curvature = dq.dot(&m_apply(metric, &dq));
    let scale = -qp.b().dot(&lambda) / curvature;
    if !(scale.is_finite() && scale > 0.0 && curvature > 0.0) {
        return Err((lambda, acceptance));
    }
    let (dq, lambda) = (dq * scale, lambda * scale);
    let acceptance = measure(&dq, &lambda);
    if acceptance <= target {
        return Ok(candidate(dq, lambda));
    }
    Err((lambda, acceptance))
}
