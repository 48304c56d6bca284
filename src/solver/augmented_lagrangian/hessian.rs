//! The Newton matrix `H = M + sum_{i in A} rho_i J_i^T J_i` of the
//! augmented Lagrangian (module docs of [`super`]), assembled per 6x6 body
//! block and factored by Cholesky: dense (nalgebra) up to
//! [`super::AugmentedLagrangianSettings::dense_max_dofs`] entries of `dq`,
//! sparse (faer's supernodal/simplicial `L L^T` with an AMD ordering)
//! above.
//!
//! The sparse pattern is that of `M + sum_i J_i^T J_i` over **every** row,
//! active or not: the pattern is then fixed for the whole solve, the
//! symbolic analysis (ordering, elimination tree, supernodes) is done once,
//! and a change of the active set costs one numeric factorization. An
//! inactive row's blocks are stored as exact zeros.

use faer::linalg::solvers::SolveCore;
use faer::sparse::linalg::solvers::{Llt as SparseLlt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Side};
use nalgebra::{DMatrix, DVector, Matrix6};

use super::super::metric::BlockMetric;
use super::super::projection::ProjectionQp;

/// Which 6x6 blocks of `H` can be nonzero, and where each lower-triangle
/// entry sits in the compressed-column value array.
struct BlockPattern {
    /// `neighbours[l]`: the bodies `k > l` that share a row with `l`,
    /// ascending.
    neighbours: Vec<Vec<usize>>,
    /// Column pointers of the lower triangle (length `6 n_bodies + 1`).
    col_ptr: Vec<usize>,
    /// Row indices, column by column.
    row_idx: Vec<usize>,
}

impl BlockPattern {
    fn new(qp: &ProjectionQp) -> Self {
        let n_bodies = qp.bodies.len();
        let mut neighbours = vec![Vec::new(); n_bodies];
        for row in &qp.rows {
            for (a, (k, _)) in row.blocks.iter().enumerate() {
                for (l, _) in &row.blocks[..a] {
                    let (hi, lo) = if k > l { (*k, *l) } else { (*l, *k) };
                    neighbours[lo].push(hi);
                }
            }
        }
        for list in &mut neighbours {
            list.sort_unstable();
            list.dedup();
        }
        let mut col_ptr = Vec::with_capacity(6 * n_bodies + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for (l, list) in neighbours.iter().enumerate() {
            for c in 0..6 {
                row_idx.extend(6 * l + c..6 * l + 6);
                for k in list {
                    row_idx.extend(6 * k..6 * k + 6);
                }
                col_ptr.push(row_idx.len());
            }
        }
        Self {
            neighbours,
            col_ptr,
            row_idx,
        }
    }

    /// Position of entry `(6 k + r, 6 l + c)`, `k >= l` (and `r >= c` when
    /// `k == l`), in the value array.
    fn position(&self, k: usize, l: usize, r: usize, c: usize) -> usize {
        let start = self.col_ptr[6 * l + c];
        if k == l {
            return start + r - c;
        }
        // Every coupled pair was recorded in `new`: the search succeeds.
        let slot = self.neighbours[l].binary_search(&k).unwrap_or_default();
        start + (6 - c) + 6 * slot + r
    }
}

/// A Cholesky factor of `H`.
enum Factor {
    Dense(nalgebra::Cholesky<f64, nalgebra::Dyn>),
    Sparse(SparseLlt<usize, f64>),
}

/// Assembles and factors `H` for one problem; keeps the sparse symbolic
/// analysis across factorizations.
pub(super) struct NewtonMatrix {
    dofs: usize,
    dense: bool,
    pattern: Option<BlockPattern>,
    symbolic: Option<SymbolicLlt<usize>>,
    factor: Option<Factor>,
}

/// Why `H` could not be factored (rounding made a pivot non-positive, or
/// faer ran out of memory): the solver gives up on the problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct FactorizationFailed;

impl NewtonMatrix {
    /// The matrix of `qp`, dense when `6 n_bodies <= dense_max_dofs`.
    pub(super) fn new(qp: &ProjectionQp, dense_max_dofs: usize) -> Self {
        let dofs = qp.num_dofs();
        let dense = dofs <= dense_max_dofs;
        Self {
            dofs,
            dense,
            pattern: (!dense).then(|| BlockPattern::new(qp)),
            symbolic: None,
            factor: None,
        }
    }

    /// Whether the dense factorization is used.
    pub(super) fn is_dense(&self) -> bool {
        self.dense
    }

    /// Factors `H = M + sum_{i: active[i]} rho[i] J_i^T J_i`.
    pub(super) fn factor(
        &mut self,
        qp: &ProjectionQp,
        metric: &[BlockMetric],
        rho: &[f64],
        active: &[bool],
    ) -> Result<(), FactorizationFailed> {
        self.factor = None;
        let blocks = lower_blocks(qp, metric, rho, active);
        let factor = if self.dense {
            let mut h = DMatrix::zeros(self.dofs, self.dofs);
            for ((k, l), block) in &blocks {
                let mut view = h.fixed_view_mut::<6, 6>(6 * k, 6 * l);
                view += block;
                if k != l {
                    let mut mirror = h.fixed_view_mut::<6, 6>(6 * l, 6 * k);
                    mirror += block.transpose();
                }
            }
            Factor::Dense(h.cholesky().ok_or(FactorizationFailed)?)
        } else {
            Factor::Sparse(self.sparse_factor(&blocks)?)
        };
        self.factor = Some(factor);
        Ok(())
    }

    fn sparse_factor(
        &mut self,
        blocks: &[((usize, usize), Matrix6<f64>)],
    ) -> Result<SparseLlt<usize, f64>, FactorizationFailed> {
        // `new` builds the pattern whenever the matrix is sparse.
        let pattern = self.pattern.as_ref().ok_or(FactorizationFailed)?;
        let mut values = vec![0.0; pattern.row_idx.len()];
        for ((k, l), block) in blocks {
            for c in 0..6 {
                let rows = if k == l { c..6 } else { 0..6 };
                for r in rows {
                    values[pattern.position(*k, *l, r, c)] += block[(r, c)];
                }
            }
        }
        let symbolic_matrix = SymbolicSparseColMatRef::new_checked(
            self.dofs,
            self.dofs,
            &pattern.col_ptr,
            None,
            &pattern.row_idx,
        );
        if self.symbolic.is_none() {
            self.symbolic = Some(
                SymbolicLlt::try_new(symbolic_matrix, Side::Lower)
                    .map_err(|_| FactorizationFailed)?,
            );
        }
        let symbolic = self.symbolic.clone().ok_or(FactorizationFailed)?;
        let matrix = SparseColMatRef::new(symbolic_matrix, &values);
        SparseLlt::try_new_with_symbolic(symbolic, matrix, Side::Lower)
            .map_err(|_| FactorizationFailed)
    }

    /// `H^-1 rhs` with the current factor (`None` before a factorization).
    pub(super) fn solve(&self, rhs: &DVector<f64>) -> Option<DVector<f64>> {
        match self.factor.as_ref()? {
            Factor::Dense(chol) => Some(chol.solve(rhs)),
            Factor::Sparse(llt) => {
                let mut x = rhs.clone();
                let n = x.len();
                llt.solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(x.as_mut_slice(), n, 1),
                );
                Some(x)
            }
        }
    }
}

/// The 6x6 blocks `(k, l)`, `k >= l`, of `H`: `M_k` on the diagonal plus
/// `rho_i g_k g_l^T` of every active row over bodies `k` and `l`.
fn lower_blocks(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    rho: &[f64],
    active: &[bool],
) -> Vec<((usize, usize), Matrix6<f64>)> {
    let mut blocks: Vec<((usize, usize), Matrix6<f64>)> = metric
        .iter()
        .enumerate()
        .map(|(k, b)| ((k, k), b.matrix()))
        .collect();
    for ((row, &r), _) in qp.rows.iter().zip(rho).zip(active).filter(|(_, a)| **a) {
        for (a, (k, gk)) in row.blocks.iter().enumerate() {
            for (l, gl) in &row.blocks[..=a] {
                let (key, block) = if k >= l {
                    ((*k, *l), gk * gl.transpose() * r)
                } else {
                    ((*l, *k), gl * gk.transpose() * r)
                };
                blocks.push((key, block));
            }
        }
    }
    blocks
}
