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

/// The rows touching each body, grouped by body (rows ascending within a
/// body): entry `p` in `start[k]..start[k + 1]` is row `row[p]` with
/// `J_ik = g[p]` and `M_k^-1 J_ik^T = u[p]`.
pub(crate) struct Incidence {
    pub(crate) start: Vec<usize>,
    pub(crate) row: Vec<usize>,
    pub(crate) g: Vec<Vector6<f64>>,
    pub(crate) u: Vec<Vector6<f64>>,
}

impl Incidence {
    pub(crate) fn of(qp: &ProjectionQp, metric: &[BlockMetric]) -> Self {
        let mut start = vec![0; metric.len() + 1];
        for row in &qp.rows {
            for (k, _) in &row.blocks {
                start[*k + 1] += 1;
            }
        }
        for k in 0..metric.len() {
            start[k + 1] += start[k];
        }
        let total = start[metric.len()];
        let mut next = start.clone();
        let (mut row, mut g, mut u) = (
            vec![0; total],
            vec![Vector6::zeros(); total],
            vec![Vector6::zeros(); total],
        );
        for (i, jacobian_row) in qp.rows.iter().enumerate() {
            for (k, block) in &jacobian_row.blocks {
                let p = next[*k];
                next[*k] += 1;
                row[p] = i;
                g[p] = *block;
                u[p] = metric[*k].apply_inv(block);
            }
        }
        Self { start, row, g, u }
    }

    /// The entries of body `k`.
    pub(crate) fn of_body(&self, k: usize) -> std::ops::Range<usize> {
        self.start[k]..self.start[k + 1]
    }
}

/// Calls `add(i, j, v)` for every term `v = J_ik M_k^-1 J_jk^T` of
/// `A_ij` (module docs), once per unordered pair of rows `{i, j}` (`i ==
/// j` included) and body `k` they share: `A_ij` is the sum of the terms of
/// `(i, j)` and `(j, i)`.
pub(crate) fn for_each_delassus_term(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    mut add: impl FnMut(usize, usize, f64),
) {
    let incidence = Incidence::of(qp, metric);
    for k in 0..metric.len() {
        let entries = incidence.of_body(k);
        for x in entries.clone() {
            let (i, u_i) = (incidence.row[x], incidence.u[x]);
            for y in x..entries.end {
                add(i, incidence.row[y], incidence.g[y].dot(&u_i));
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
