//! From the projection QP to its dual LCP, without forming `M^-1` densely.
//!
//! ```text
//! A = J M^-1 J^T,   b = phi - target,   dq = M^-1 J^T lambda
//! ```
//!
//! (a mixed LCP when the problem has equality rows: their multipliers are
//! free, `super::lcp`).
//!
//! `M` is block diagonal, so `A_ij = sum_k J_ik M_k^-1 J_jk^T` over the bodies
//! `k` that rows `i` and `j` share. The sum runs body by body over the rows
//! incident to that body: `O(sum_k deg_k^2)` 6-vector dot products, where
//! `deg_k` is the number of rows touching body `k`.

use nalgebra::{DMatrix, DVector, Vector6};

use super::error::SolverError;
use super::lcp::Lcp;
use super::metric::BlockMetric;
use super::projection::ProjectionQp;
use super::residuals::m_inv;

/// A row touching a body: `(row index, J_ik, M_k^-1 J_ik^T)`.
type Incidence = (usize, Vector6<f64>, Vector6<f64>);

/// Calls `add(i, j, v)` for every term `v = J_ik M_k^-1 J_jk^T` of
/// `A_ij` (module docs), once per unordered pair of rows `{i, j}` (`i ==
/// j` included) and body `k` they share: `A_ij` is the sum of the terms of
/// `(i, j)` and `(j, i)`.
pub(crate) fn for_each_delassus_term(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    mut add: impl FnMut(usize, usize, f64),
) {
    // incident[k] = rows touching body k, with J_ik and M_k^-1 J_ik^T.
    let mut incident: Vec<Vec<Incidence>> = vec![Vec::new(); metric.len()];
    for (i, row) in qp.rows.iter().enumerate() {
        for (k, g) in &row.blocks {
            incident[*k].push((i, *g, metric[*k].apply_inv(g)));
        }
    }
    for rows in &incident {
        for (x, (i, _, u_i)) in rows.iter().enumerate() {
            for (j, g_j, _) in &rows[x..] {
                add(*i, *j, g_j.dot(u_i));
            }
        }
    }
}

/// `A = J M^-1 J^T` (dense, symmetric).
pub fn lcp_matrix(qp: &ProjectionQp, metric: &[BlockMetric]) -> DMatrix<f64> {
    let n = qp.num_rows();
    let mut a = DMatrix::zeros(n, n);
    for_each_delassus_term(qp, metric, |i, j, v| {
        a[(i, j)] += v;
        if i != j {
            a[(j, i)] += v;
        }
    });
    a
}

/// The dual LCP `(A, b)` of a validated projection QP: mixed, with one
/// free variable per equality row (`super::lcp`).
pub fn projection_to_lcp(qp: &ProjectionQp, metric: &[BlockMetric]) -> Result<Lcp, SolverError> {
    Lcp::mixed(lcp_matrix(qp, metric), qp.b(), qp.num_equalities)
}

/// `dq = M^-1 J^T lambda`.
pub fn dq_from_lambda(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    lambda: &DVector<f64>,
) -> DVector<f64> {
    m_inv(metric, &qp.apply_jt(lambda))
}
