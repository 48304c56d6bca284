//! The warm finish of the interior point: certify a neighbouring
//! problem's multipliers (the previous pass's or call's) with one
//! factorization.
//!
//! With the warm start's active set `A` (the rows its correction
//! `M^-1 J^T lambda` leaves tight, within `1e-9 ||b||_inf`, or violated)
//! fixed, the method of multipliers on the
//! equality-constrained problem of `A` is
//!
//! ```text
//! (M + sum_{i in A} rho_i J_i^T J_i) dq = J_A^T (lambda_A - rho_A b_A)
//! lambda_i <- max(0, lambda_i - rho_i (b_i + J_i dq))         (i in A)
//! ```
//!
//! (`rho_i = kappa / a_i`, the augmented Lagrangian's penalties,
//! `super::super::augmented_lagrangian`): the matrix does not change, so
//! every iteration after the first factorization is one solve. When `A`
//! is the answer's active set the iteration converges to it (the dual
//! error contracts by `1 / (1 + kappa sigma)` per iteration); the
//! candidate `(M^-1 J^T lambda, lambda)` is measured by the stop test of
//! the interior point after every iteration and returned once it passes.
//! Otherwise the finish gives up after [`WARM_ITERATIONS`] and the interior
//! point starts cold: a stale warm start costs one factorization and a few
//! solves, never the answer.

use nalgebra::DVector;

use crate::solver::augmented_lagrangian::hessian::NewtonMatrix;
use crate::solver::metric::BlockMetric;
use crate::solver::outcome::Candidate;
use crate::solver::projection::ProjectionQp;
use crate::solver::projection_lcp::dq_from_lambda;
use crate::solver::residuals::{projection_residuals, row_diagonal};

/// The dimensionless penalty `kappa` (the augmented Lagrangian's default).
const WARM_PENALTY: f64 = 1e6;

/// A row that the warm start's correction leaves open by more than this
/// fraction of `||b||_inf` is not in the warm active set.
const WARM_OPEN_REL: f64 = 1e-9;

/// Multiplier iterations (solves with the one factor) before the finish
/// gives up.
pub(super) const WARM_ITERATIONS: usize = 6;

/// The certified candidate from `lambda0` (clamped, scaled), or `None`.
/// `factorizations` counts the factorization it made.
pub(super) fn warm_finish(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    newton: &mut NewtonMatrix,
    lambda0: &DVector<f64>,
    target: f64,
    factorizations: &mut usize,
) -> Option<Candidate> {
    let m = qp.num_rows();
    let b = qp.b();
    let a = row_diagonal(qp, metric);
    let rho: Vec<f64> = a
        .iter()
        .map(|&x| if x > 0.0 { WARM_PENALTY / x } else { 0.0 })
        .collect();
    let dq0 = dq_from_lambda(qp, metric, lambda0);
    let w0 = &b + qp.apply_j(&dq0);
    // The rows the warm start's correction leaves tight or violated; a row
    // it leaves open by more than rounding is inactive whatever its
    // (interior-point) multiplier.
    let open = WARM_OPEN_REL * b.amax();
    let active: Vec<bool> = (0..m).map(|i| rho[i] > 0.0 && w0[i] <= open).collect();
    if !active.iter().any(|&x| x) {
        return None;
    }
    newton.factor(qp, metric, &rho, &active).ok()?;
    *factorizations += 1;
    let mut lambda = lambda0.clone();
    for iteration in 1..=WARM_ITERATIONS {
        let rhs_rows = DVector::from_fn(m, |i, _| {
            if active[i] {
                lambda[i] - rho[i] * b[i]
            } else {
                0.0
            }
        });
        let dq = newton.solve(&qp.apply_jt(&rhs_rows))?;
        let w = &b + qp.apply_j(&dq);
        lambda = DVector::from_fn(m, |i, _| {
            if active[i] {
                (lambda[i] - rho[i] * w[i]).max(0.0)
            } else {
                0.0
            }
        });
        let stationary = dq_from_lambda(qp, metric, &lambda);
        let acceptance = projection_residuals(qp, metric, &stationary, &lambda).acceptance();
        log::trace!(
            "interior point: warm finish iteration {iteration}, acceptance {acceptance:.2e}"
        );
        if acceptance <= target {
            return Some(Candidate {
                dq: stationary,
                lambda,
                iterations: 0,
                factorizations: *factorizations,
            });
        }
        if !acceptance.is_finite() {
            return None;
        }
    }
    None
}
