//! The closed form for a single constraint.
//!
//! With one row `J` (so `A = a = J M^-1 J^T > 0`, `b = phi - target`), the
//! LCP `lambda >= 0, a lambda + b >= 0, lambda (a lambda + b) = 0` has the
//! unique solution `lambda = max(0, -b / a)`, and `dq = M^-1 J^T lambda`:
//! the constraint is met with equality along the metric gradient, or is
//! already met and nothing moves.
//!
//! An equality row (`num_equalities = 1`) has a free multiplier: the mixed
//! LCP `a lambda + b = 0` has the unique solution `lambda = -b / a` of
//! either sign (`b = 0` with `a = 0`: `lambda = 0`).

use nalgebra::DVector;

use super::metric::BlockMetric;
use super::outcome::{Candidate, FailureReason};
use super::projection::ProjectionQp;
use super::projection_lcp::dq_from_lambda;
use super::residuals::row_diagonal;

/// Solves a one-row projection QP. Fails with
/// [`FailureReason::NotApplicable`] for any other row count and with
/// [`FailureReason::Infeasible`] when the row is violated (for an equality
/// row: `b != 0`) and has a zero Jacobian (nothing can move it).
pub fn solve_single_row(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
) -> Result<Candidate, FailureReason> {
    if qp.num_rows() != 1 {
        return Err(FailureReason::NotApplicable);
    }
    let a = row_diagonal(qp, metric)[0];
    let b = qp.phi[0] - qp.target[0];
    let equality = qp.is_equality(0);
    let lambda_0 = if b == 0.0 || (b > 0.0 && !equality) {
        0.0
    } else if a > 0.0 {
        -b / a
    } else {
        return Err(FailureReason::Infeasible);
    };
    let lambda = DVector::from_element(1, lambda_0);
    let dq = dq_from_lambda(qp, metric, &lambda);
    Ok(Candidate {
        dq,
        lambda,
        iterations: 0,
        factorizations: 0,
    })
}
