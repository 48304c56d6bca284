//! The rows of a projection QP packed for the inner loops of the
//! body-space solvers: each row's one or two bodies and their twelve
//! gradient entries stored contiguously, and the rows grouped by the pair
//! of bodies they couple.
//!
//! With row `i` over bodies `k > l` written as `g_i = [g_ik; g_il]` (twelve
//! entries; six and `l` absent for a row of one body), the weighted Gram
//! matrix of a group `P` of rows with the same bodies is
//!
//! ```text
//! G_P = sum_{i in P} d_i g_i g_i^T          (12 x 12, or 6 x 6)
//! ```
//!
//! and `J^T D J` is the sum of the `G_P` placed at the blocks `(k, k)`,
//! `(l, l)`, `(k, l)` and `(l, k)`: the accumulation runs on a small
//! fixed-size matrix (vectorized rank-one updates), and each group is
//! scattered into `H` once instead of each row (a contact pair of a box
//! face with friction has 20 rows). `J dq` and `J^T lambda` read the packed
//! gradients without indexing the rows' block lists.
//!
//! Rows over more than two bodies are not packed ([`PackedRows::new`]
//! returns `None`; the callers keep the general path).

use nalgebra::{DVector, SMatrix, SVector, Vector6};

use super::projection::ProjectionQp;

/// Twelve gradient entries: the first body's six, then the second's.
pub(crate) type Gradient = SVector<f64, 12>;

/// The weighted Gram matrix of a group of rows.
pub(crate) type Gram = SMatrix<f64, 12, 12>;

/// The rows of a QP with at most two bodies each, packed (module docs).
#[derive(Debug, Clone)]
pub(crate) struct PackedRows {
    /// Per row: the first body (the larger index) and the second (`None`
    /// for a row of one body).
    pub bodies: Vec<(usize, Option<usize>)>,
    /// Per row: the gradients `[g_k; g_l]` (the second half zero for a
    /// row of one body).
    pub gradients: Vec<Gradient>,
    /// Groups of rows with the same bodies: the bodies and the rows.
    pub groups: Vec<RowGroup>,
    dofs: usize,
}

/// Rows coupling the same bodies.
#[derive(Debug, Clone)]
pub(crate) struct RowGroup {
    /// The first body (larger index) and the second, as in
    /// [`PackedRows::bodies`].
    pub bodies: (usize, Option<usize>),
    /// The rows, ascending.
    pub rows: Vec<usize>,
}

impl PackedRows {
    /// The packed rows of `qp`, or `None` when a row has more than two
    /// bodies or one body twice.
    pub(crate) fn new(qp: &ProjectionQp) -> Option<Self> {
        let m = qp.num_rows();
        let mut bodies = Vec::with_capacity(m);
        let mut gradients = Vec::with_capacity(m);
        for row in &qp.rows {
            let mut g = Gradient::zeros();
            let pair = match row.blocks.as_slice() {
                [] => (0, None),
                [(k, gk)] => {
                    g.fixed_rows_mut::<6>(0).copy_from(gk);
                    (*k, None)
                }
                [(a, ga), (b, gb)] if a != b => {
                    let (k, gk, l, gl) = if a > b {
                        (*a, ga, *b, gb)
                    } else {
                        (*b, gb, *a, ga)
                    };
                    g.fixed_rows_mut::<6>(0).copy_from(gk);
                    g.fixed_rows_mut::<6>(6).copy_from(gl);
                    (k, Some(l))
                }
                _ => return None,
            };
            bodies.push(pair);
            gradients.push(g);
        }
        let mut order: Vec<usize> = (0..m).filter(|&i| !qp.rows[i].blocks.is_empty()).collect();
        order.sort_by_key(|&i| (bodies[i], i));
        let mut groups: Vec<RowGroup> = Vec::new();
        for i in order {
            match groups.last_mut() {
                Some(group) if group.bodies == bodies[i] => group.rows.push(i),
                _ => groups.push(RowGroup {
                    bodies: bodies[i],
                    rows: vec![i],
                }),
            }
        }
        Some(Self {
            bodies,
            gradients,
            groups,
            dofs: qp.num_dofs(),
        })
    }

    /// `J dq` into `out` (length the rows). Each row's value is the
    /// sequential sum of its twelve (or six) products from zero, as
    /// nalgebra's `dot` sums vectors of six.
    pub(crate) fn apply_j_into(&self, dq: &DVector<f64>, out: &mut DVector<f64>) {
        let (dq_blocks, _) = dq.as_slice().as_chunks::<6>();
        let out = out.as_mut_slice();
        for ((value, &(k, l)), g) in out.iter_mut().zip(&self.bodies).zip(&self.gradients) {
            let (halves, _) = g.as_slice().as_chunks::<6>();
            let mut sum = dot6(&halves[0], &dq_blocks[k]);
            if let Some(l) = l {
                sum += dot6(&halves[1], &dq_blocks[l]);
            }
            *value = sum;
        }
    }

    /// `J dq`.
    pub(crate) fn apply_j(&self, dq: &DVector<f64>) -> DVector<f64> {
        let mut out = DVector::zeros(self.bodies.len());
        self.apply_j_into(dq, &mut out);
        out
    }

    /// `J^T lambda`: `out_k += lambda_i g_ik` row by row.
    pub(crate) fn apply_jt(&self, lambda: &DVector<f64>) -> DVector<f64> {
        let mut out = DVector::zeros(self.dofs);
        let (blocks, _) = out.as_mut_slice().as_chunks_mut::<6>();
        let rows = self.bodies.iter().zip(&self.gradients);
        for ((&(k, l), g), &x) in rows.zip(lambda.as_slice()) {
            if x == 0.0 {
                continue;
            }
            let (halves, _) = g.as_slice().as_chunks::<6>();
            axpy6(x, &halves[0], &mut blocks[k]);
            if let Some(l) = l {
                axpy6(x, &halves[1], &mut blocks[l]);
            }
        }
        out
    }

    /// The entries of the weighted Gram matrix `sum_i d_i g_i g_i^T` of a
    /// group that the lower triangle of `H` takes. For two bodies: the
    /// lower triangles of its diagonal blocks and its upper-right block
    /// `(k, l)`, 78 of the 144 (the others stay zero), each entry `(j, k)`
    /// accumulating `(d_i g_ik) g_ij` row by row (nalgebra's `syger` and
    /// `ger`). For one body: its whole 6x6 block in the top-left corner
    /// ([`PackedRows::one_body_gram`]).
    pub(crate) fn gram_for_lower(&self, group: &RowGroup, d: &[f64]) -> Gram {
        if group.bodies.1.is_none() {
            let mut gram = Gram::zeros();
            gram.fixed_view_mut::<6, 6>(0, 0)
                .copy_from(&self.one_body_gram(group, d));
            return gram;
        }
        let mut gram = Gram::zeros();
        for &i in &group.rows {
            if d[i] == 0.0 {
                continue;
            }
            let g = &self.gradients[i];
            let (first, second) = (g.fixed_rows::<6>(0), g.fixed_rows::<6>(6));
            gram.fixed_view_mut::<6, 6>(0, 0)
                .syger(d[i], &first, &first, 1.0);
            gram.fixed_view_mut::<6, 6>(0, 6)
                .ger(d[i], &first, &second, 1.0);
            gram.fixed_view_mut::<6, 6>(6, 6)
                .syger(d[i], &second, &second, 1.0);
        }
        gram
    }

    /// The weighted Gram matrix `sum_i d_i g_ik g_ik^T` of a group of one
    /// body `k` (module docs).
    fn one_body_gram(&self, group: &RowGroup, d: &[f64]) -> SMatrix<f64, 6, 6> {
        let mut gram = SMatrix::<f64, 6, 6>::zeros();
        for &i in &group.rows {
            if d[i] != 0.0 {
                let g: Vector6<f64> = self.gradients[i].fixed_rows::<6>(0).into_owned();
                gram.ger(d[i], &g, &g, 1.0);
            }
        }
        gram
    }
}

/// `sum_t a_t b_t`, summed in order from zero.
fn dot6(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    a.iter().zip(b).fold(0.0, |sum, (x, y)| sum + x * y)
}

/// `y += x a`.
fn axpy6(x: f64, a: &[f64; 6], y: &mut [f64; 6]) {
    for (y, a) in y.iter_mut().zip(a) {
        *y += x * a;
    }
}
