//! Oracles for projection QPs with equality rows, from the problem's data
//! and nalgebra's dense factorizations only (no solver, residual or `J`
//! product of the library):
//!
//! - [`brute_force_dq`]: active-set enumeration. For every subset `S` of
//!   the inequality rows, the rows `E ∪ S` are taken to hold with equality
//!   and the KKT system
//!
//!   ```text
//!   [ M     -J_A^T ] [ dq       ]   [  0   ]
//!   [ J_A    0     ] [ lambda_A ] = [ -b_A ]      (A = E ∪ S, b = phi - target)
//!   ```
//!
//!   is solved by a full-pivot LU. The answer is the one whose inequality
//!   rows all hold and whose `lambda_S` are nonnegative (`lambda_E` free):
//!   those are the KKT conditions of the convex QP, sufficient for
//!   optimality, and `dq` is unique since `M` is positive definite. The
//!   rows must be linearly independent (the KKT matrix is then nonsingular
//!   for every `S`); small problems only (`2^|I|` systems).
//! - [`minimum_norm_dq`]: equality rows only, any rank: the closed form
//!   `dq = M^-1 J^T (J M^-1 J^T)^+ (target - phi)` with an SVD
//!   pseudo-inverse.

use constraint_stabilization::solver::ProjectionQp;
use nalgebra::{DMatrix, DVector};

use crate::support::solver_oracle::apply_metric;

/// A row counts as holding when `w_i >= -FEASIBLE_TOL * ||b||_inf`, a
/// multiplier as nonnegative when `>= -FEASIBLE_TOL * max|lambda|`: far
/// below any wrong active set (whose violations are of order one in these
/// units), far above the LU's rounding on the small systems used.
pub const FEASIBLE_TOL: f64 = 1e-10;

/// Singular values of `J M^-1 J^T` below this fraction of the largest are
/// zero in [`minimum_norm_dq`] (redundant rows formed in f64 leave about
/// 1e-16).
pub const PSEUDO_INVERSE_TOL_REL: f64 = 1e-12;

/// The dense metric `M` (columns `M e_j`).
pub fn dense_metric(qp: &ProjectionQp) -> DMatrix<f64> {
    let n = 6 * qp.bodies.len();
    let mut m = DMatrix::zeros(n, n);
    for j in 0..n {
        let mut e = DVector::zeros(n);
        e[j] = 1.0;
        m.set_column(j, &apply_metric(qp, &e));
    }
    m
}

/// The dense Jacobian `J` (one row per constraint row).
pub fn dense_jacobian(qp: &ProjectionQp) -> DMatrix<f64> {
    let mut j = DMatrix::zeros(qp.rows.len(), 6 * qp.bodies.len());
    for (i, row) in qp.rows.iter().enumerate() {
        for (k, g) in &row.blocks {
            for c in 0..6 {
                j[(i, 6 * k + c)] += g[c];
            }
        }
    }
    j
}

fn b_of(qp: &ProjectionQp) -> DVector<f64> {
    DVector::from_iterator(
        qp.phi.len(),
        qp.phi.iter().zip(&qp.target).map(|(p, t)| p - t),
    )
}

/// The minimizer `dq` by active-set enumeration (module docs), or `None`
/// when no subset passes (infeasible, or dependent rows).
pub fn brute_force_dq(qp: &ProjectionQp) -> Option<DVector<f64>> {
    let (m, j, b) = (dense_metric(qp), dense_jacobian(qp), b_of(qp));
    let (dofs, rows, equalities) = (m.nrows(), j.nrows(), qp.num_equalities);
    let inequalities = rows - equalities;
    let length = b.amax().max(f64::MIN_POSITIVE);
    let mut best: Option<(f64, DVector<f64>)> = None;
    for mask in 0u32..(1 << inequalities) {
        let active: Vec<usize> = (0..rows)
            .filter(|&i| i < equalities || mask & (1 << (i - equalities)) != 0)
            .collect();
        let a = active.len();
        let mut kkt = DMatrix::zeros(dofs + a, dofs + a);
        let mut rhs = DVector::zeros(dofs + a);
        kkt.view_mut((0, 0), (dofs, dofs)).copy_from(&m);
        for (r, &i) in active.iter().enumerate() {
            for c in 0..dofs {
                kkt[(dofs + r, c)] = j[(i, c)];
                kkt[(c, dofs + r)] = -j[(i, c)];
            }
            rhs[dofs + r] = -b[i];
        }
        let Some(x) = kkt.full_piv_lu().solve(&rhs) else {
            continue;
        };
        let dq = x.rows(0, dofs).into_owned();
        let lambda = x.rows(dofs, a).into_owned();
        let w = &b + &j * &dq;
        let rows_hold = (equalities..rows).all(|i| w[i] >= -FEASIBLE_TOL * length);
        let lambda_scale = lambda.amax().max(f64::MIN_POSITIVE);
        let signs_hold = active
            .iter()
            .zip(lambda.iter())
            .all(|(&i, &l)| i < equalities || l >= -FEASIBLE_TOL * lambda_scale);
        if rows_hold && signs_hold {
            let objective = 0.5 * dq.dot(&(&m * &dq));
            if best.as_ref().is_none_or(|(f, _)| objective < *f) {
                best = Some((objective, dq));
            }
        }
    }
    best.map(|(_, dq)| dq)
}

/// `dq = M^-1 J^T (J M^-1 J^T)^+ (target - phi)` for a problem whose rows
/// are all equalities (module docs).
pub fn minimum_norm_dq(qp: &ProjectionQp) -> DVector<f64> {
    let (m, j, b) = (dense_metric(qp), dense_jacobian(qp), b_of(qp));
    // M is the block-diagonal metric of positive masses and positive
    // definite inertias of the test problems.
    let m_inv = m.try_inverse().expect("test metric is invertible");
    let a = &j * &m_inv * j.transpose();
    let svd = a.svd(true, true);
    let eps = PSEUDO_INVERSE_TOL_REL * svd.singular_values.max();
    // eps >= 0: the only error of pseudo_inverse.
    let a_pinv = svd.pseudo_inverse(eps).expect("nonnegative epsilon");
    m_inv * j.transpose() * a_pinv * (-b)
}
