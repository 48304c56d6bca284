//! Levenberg–Marquardt damping of the equality rows: a joint's step stays
//! where its linearization holds, and redundant rows stay solvable.
//!
//! The equality rows `e + J_E dq = 0` of a jointed island are solved by a
//! Newton step. Where a joint error can be removed to first order only by a
//! motion with a tiny lever (a chain of nearly collinear links closing a
//! gap along itself: a link turned by `theta` moves its far anchor along
//! the chain by `theta` times a lever that vanishes as the links line up),
//! the minimum-norm step turns light bodies far (`theta = e / lever`) and
//! its second-order error `r theta^2 / 2` exceeds the error it removes: the
//! line search cuts the step again and again and the passes converge
//! linearly, or not at all. Levenberg–Marquardt damping turns the rows
//! soft by a slack `s` with weight `1 / mu`,
//!
//! ```text
//! minimize 1/2 dq^T M dq + 1/(2 mu) |s|^2   subject to   e + J_E dq - s = 0,
//! ```
//!
//! with one weight per row (`1 / mu_k`), whose dual matrix is
//! `A_EE + diag(mu)` (`A_EE = J_E M^-1 J_E^T`): directions of `A_EE` with
//! eigenvalues small against the rows' `mu_k` (tiny levers, and
//! redundant rows with eigenvalue 0) are damped, the others solved as
//! before. With Marquardt's scaling by the diagonal,
//!
//! ```text
//! mu_k = nu (|e|_inf / L) (A_EE)_kk
//! ```
//!
//! (`nu` = [`crate::Settings::equality_damping`], `L` the scene's length
//! scale; the diagonal makes the damping independent of each row's units
//! and of how easily its bodies move: a hinge's alignment row, which a
//! light bar's cheap twist moves easily, is not damped by the same `mu`
//! as its anchor rows) the damping vanishes with the error, as in the
//! Levenberg–Marquardt method of Fan and Yuan ("On the quadratic
//! convergence of the Levenberg–Marquardt method without nonsingularity
//! assumption", Computing 74, 2005: `mu = |F|^delta`, `delta` in `[1, 2]`,
//! converges quadratically under a local error bound even where the
//! Jacobian is singular). A step along a well-conditioned direction
//! removes the fraction `a / (a + mu)` of its error, nearly all of it; the
//! next pass removes the rest, in the same direction (a ball joint's
//! mass-weighted split is kept exactly).
//!
//! The slacks are carried by pseudo-bodies appended to the QP, so every
//! solver solves the damped problem unchanged: slack `k` is the `x`
//! translation of pseudo-body `n + k`, of mass `1 / mu_k`, with `-1` in
//! row `k`'s Jacobian. The pseudo-bodies' part of `dq` is dropped.

use nalgebra::{Matrix3, Vector6};

use crate::solver::{BlockMetric, BodyMetric, ProjectionQp, SolverError};

/// `qp` with its equality rows damped (module docs) and the largest
/// `mu_k`; `None` when it has no equality row, `nu` is 0, or the rows
/// already hold exactly.
pub fn damped_equalities(
    qp: &ProjectionQp,
    nu: f64,
    scale: f64,
) -> Result<Option<(ProjectionQp, f64)>, SolverError> {
    let n_e = qp.num_equalities;
    if n_e == 0 || nu <= 0.0 {
        return Ok(None);
    }
    let error = (0..n_e)
        .map(|k| (qp.phi[k] - qp.target[k]).abs())
        .fold(0.0, f64::max);
    let metric: Vec<BlockMetric> = qp.validate()?;
    let diagonal = |k: usize| -> f64 {
        qp.rows[k]
            .blocks
            .iter()
            .map(|(body, g)| g.dot(&metric[*body].apply_inv(g)))
            .sum()
    };
    let relative = nu * error / scale;
    let mu: Vec<f64> = (0..n_e).map(|k| relative * diagonal(k)).collect();
    if !mu.iter().all(|m| *m > 0.0 && m.is_finite()) {
        return Ok(None);
    }
    let mut damped = qp.clone();
    let first = qp.bodies.len();
    damped.bodies.extend(mu.iter().map(|m| BodyMetric {
        mass: 1.0 / m,
        inertia_world: Matrix3::identity() / *m,
    }));
    let slack = Vector6::new(-1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for k in 0..n_e {
        damped.rows[k].blocks.push((first + k, slack));
    }
    Ok(Some((damped, mu.iter().copied().fold(0.0, f64::max))))
}
