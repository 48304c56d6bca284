//! Redundant equality rows made consistent: the part of a joint error that
//! no first-order motion can remove is left to the next linearization.
//!
//! A closed loop of joints (a four-bar linkage) locks some motions twice:
//! its equality rows `J_E dq = r` (`r = target - phi` on those rows) are
//! linearly dependent. At a configuration that satisfies every joint the
//! dependent rows agree; off it they disagree by a term of second order in
//! the error, and the linearized problem has no solution (clarabel
//! certifies primal infeasibility, Lemke's Schur elimination finds the
//! equalities inconsistent). The rows' reachable right-hand sides are the
//! range of `J_E`, which is the range of `A_EE = J_E M^-1 J_E^T`; the
//! minimum-norm correction that removes the reachable part of the error
//! solves
//!
//! ```text
//! J_E dq = P r,      P = D^-1 P_s D,
//! ```
//!
//! with `D` the Jacobi scaling of `A_EE` (`D_ii = A_ii^-1/2`, so that the
//! rank decision does not depend on masses and lengths) and `P_s` the
//! orthogonal projector onto the eigenvectors of `D A_EE D` whose
//! eigenvalues exceed [`RANK_TOLERANCE`] times the largest: `P` projects
//! onto `range(A_EE) = D^-1 range(D A_EE D)` and leaves consistent rows as
//! they are (`r = A_EE x` gives `D r = (D A_EE D)(D^-1 x)`, so `P r = r`).
//! The rank tolerance is the one Lemke's elimination uses
//! ([`crate::solver::lemke::mixed`]), so that both solvers see the same rows as
//! redundant. The step then removes every error a
//! motion can remove to first order, and the next pass linearizes again,
//! where the leftover, of second order, is smaller still: the loop closes
//! as Newton's method on the joints' manifold does.
//!
//! The eigendecomposition is dense, `O(n_E^3)`: it runs before solving
//! only where the provider says the rows may be redundant (a closed loop
//! of joints, [`crate::rows::ConstraintProvider::equalities_may_be_redundant`];
//! a tree of joints locks each body's motions once), and after a solver
//! failed on a problem with equalities; up to [`MAX_PROJECTED_EQUALITIES`]
//! rows.

use nalgebra::{DMatrix, DVector};

use crate::solver::{ProjectionQp, SolverError, lcp_matrix};

/// Eigenvalues of the scaled `A_EE` below this fraction of the largest
/// count as zero (the dependent directions): Lemke's.
pub const RANK_TOLERANCE: f64 = crate::solver::lemke::mixed::EQUALITY_RANK_TOL_REL;

/// The most equality rows whose right-hand side is projected (a dense
/// eigendecomposition of that order).
pub const MAX_PROJECTED_EQUALITIES: usize = 600;

/// `qp` with its equality rows' values moved so that `P r` replaces `r`
/// (module docs), and `|r - P r|_inf`; `None` when it has no equality row
/// or too many.
pub fn consistent_equalities(
    qp: &ProjectionQp,
) -> Result<Option<(ProjectionQp, f64)>, SolverError> {
    let n_e = qp.num_equalities;
    if n_e == 0 || n_e > MAX_PROJECTED_EQUALITIES {
        return Ok(None);
    }
    let equalities = ProjectionQp {
        rows: qp.rows[..n_e].to_vec(),
        phi: qp.phi[..n_e].to_vec(),
        target: qp.target[..n_e].to_vec(),
        num_equalities: n_e,
        cones: Vec::new(),
        ..qp.clone()
    };
    let metric = equalities.validate()?;
    let a: DMatrix<f64> = lcp_matrix(&equalities, &metric);
    // A row no body moves has A_ii = 0: unit scale (its value cannot
    // change, and the projection removes its error).
    let d = DVector::from_iterator(
        n_e,
        (0..n_e).map(|i| match a[(i, i)] {
            aii if aii > 0.0 => aii.sqrt().recip(),
            _ => 1.0,
        }),
    );
    let scaled = DMatrix::from_fn(n_e, n_e, |i, j| d[i] * a[(i, j)] * d[j]);
    let r = DVector::from_iterator(n_e, (0..n_e).map(|i| qp.target[i] - qp.phi[i]));
    let r_scaled = r.component_mul(&d);
    let eigen = scaled.symmetric_eigen();
    let largest = eigen.eigenvalues.iter().fold(0.0_f64, |m, &l| m.max(l));
    let mut projected = DVector::zeros(n_e);
    for (i, &l) in eigen.eigenvalues.iter().enumerate() {
        if l > RANK_TOLERANCE * largest {
            let v = eigen.eigenvectors.column(i);
            projected += v * v.dot(&r_scaled);
        }
    }
    let projected = projected.component_div(&d);
    let removed = (&r - &projected).amax();
    let mut out = qp.clone();
    for i in 0..n_e {
        out.phi[i] = qp.target[i] - projected[i];
    }
    Ok(Some((out, removed)))
}
