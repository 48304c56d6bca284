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

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::SparseColMatRef;
use faer::sparse::linalg::cholesky::LltRef;
use faer::{Conj, MatMut, Par};
use nalgebra::{DMatrix, DVector, Matrix6};

use super::super::dense_cholesky::DenseCholesky;
use super::super::kept_analyses::{AnalysisKind, KeptAnalyses, KeptAnalysis};
use super::super::metric::BlockMetric;
use super::super::packed_rows::{Gram, PackedRows};
use super::super::projection::ProjectionQp;

/// Which 6x6 blocks of `H` can be nonzero, and where each lower-triangle
/// entry sits in the compressed-column value array.
struct BlockPattern {
    /// Per row, per pair of its blocks `(a, b)` with body `k >= l`:
    /// `(a, b, base)` with entry `(6 k + r, 6 l + c)` of `H` at
    /// `base[c] + r` (the positions resolved once per problem, so that an
    /// assembly does no search).
    scatter: Vec<Vec<(usize, usize, [usize; 6])>>,
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
        let mut pattern = Self {
            scatter: Vec::new(),
            neighbours,
            col_ptr,
            row_idx,
        };
        pattern.scatter = qp
            .rows
            .iter()
            .map(|row| {
                let mut pairs = Vec::new();
                for (a, (k, _)) in row.blocks.iter().enumerate() {
                    for (b, (l, _)) in row.blocks[..=a].iter().enumerate() {
                        let (a, b, k, l) = if k >= l {
                            (a, b, *k, *l)
                        } else {
                            (b, a, *l, *k)
                        };
                        let base = std::array::from_fn(|c| {
                            // Entry (6k + r, 6l + c) is at base[c] + r; on a
                            // diagonal block only r >= c is stored.
                            let first = if k == l { c } else { 0 };
                            pattern.position(k, l, first, c) - first
                        });
                        pairs.push((a, b, base));
                    }
                }
                pairs
            })
            .collect();
        pattern
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

/// The sparse symbolic analysis and the buffers that every numeric
/// factorization and solve of one problem reuses.
struct SparseFactor {
    /// The symbolic analysis, kept by the caller's store or made for this
    /// problem alone.
    analysis: Arc<KeptAnalysis>,
    /// Values of `H`'s lower triangle in the pattern's order.
    values: Vec<f64>,
    /// The same values in the order of `P H P^T`, the analysis's order
    /// applied (`super::super::kept_analyses`).
    permuted: Vec<f64>,
    /// Values of the factor `L` (empty before the first factorization).
    factor_values: Vec<f64>,
    /// Workspace of the numeric factorization and of the solves.
    workspace: MemBuffer,
}

/// A Cholesky factor of `H`.
enum Factor {
    Dense(DenseCholesky),
    Sparse,
}

/// Assembles and factors `H` for one problem; keeps the sparse symbolic
/// analysis and the value buffers across factorizations.
pub(crate) struct NewtonMatrix<'a> {
    dofs: usize,
    dense: bool,
    supernodal: bool,
    pattern: Option<BlockPattern>,
    /// The caller's store of analyses, asked on the first sparse
    /// factorization (a solve that needs none, a warm start accepted as
    /// it is, asks nothing).
    store: Option<&'a KeptAnalyses>,
    sparse: Option<SparseFactor>,
    factor: Option<Factor>,
    /// Per group of [`PackedRows`], where its blocks sit in the sparse
    /// value array (resolved on the first packed factorization).
    group_bases: Option<Vec<GroupBase>>,
}

/// Where the blocks of one group of packed rows `(k, l)`, `k > l`, sit in
/// the sparse value array: entry `(6 a + r, 6 b + c)` of block `(a, b)` at
/// `base[c] + r` (`r >= c` on a diagonal block).
struct GroupBase {
    kk: [usize; 6],
    ll: Option<[usize; 6]>,
    kl: Option<[usize; 6]>,
}

/// Why `H` could not be factored (rounding made a pivot non-positive, or
/// faer ran out of memory): the solver gives up on the problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct FactorizationFailed;

impl<'a> NewtonMatrix<'a> {
    /// The matrix of `qp`, dense when `6 n_bodies <= dense_max_dofs`; the
    /// sparse factor supernodal when `supernodal` (dense 6x6 kernels on
    /// the blocks of a body), else left to faer's flop-ratio choice.
    ///
    /// With a store `kept`, the sparse pattern's symbolic analysis is taken
    /// from it on the first factorization, or made then and kept there for
    /// the next problems of the same pattern (`super::super::kept_analyses`).
    pub(crate) fn new(
        qp: &ProjectionQp,
        dense_max_dofs: usize,
        supernodal: bool,
        kept: Option<&'a KeptAnalyses>,
    ) -> Self {
        let dofs = qp.num_dofs();
        let dense = dofs <= dense_max_dofs;
        Self {
            dofs,
            dense,
            supernodal,
            pattern: (!dense).then(|| BlockPattern::new(qp)),
            store: kept,
            sparse: None,
            factor: None,
            group_bases: None,
        }
    }

    /// Whether the dense factorization is used.
    pub(crate) fn is_dense(&self) -> bool {
        self.dense
    }

    /// Factors `H = M + sum_{i: active[i]} rho[i] J_i^T J_i`.
    pub(crate) fn factor(
        &mut self,
        qp: &ProjectionQp,
        metric: &[BlockMetric],
        rho: &[f64],
        active: &[bool],
    ) -> Result<(), FactorizationFailed> {
        self.factor = None;
        let factor = if self.dense {
            let mut h = DMatrix::zeros(self.dofs, self.dofs);
            for_each_lower_block(qp, metric, rho, active, |k, l, block| {
                let mut view = h.fixed_view_mut::<6, 6>(6 * k, 6 * l);
                view += block;
                if k != l {
                    let mut mirror = h.fixed_view_mut::<6, 6>(6 * l, 6 * k);
                    mirror += block.transpose();
                }
            });
            Factor::Dense(DenseCholesky::new(h).ok_or(FactorizationFailed)?)
        } else {
            self.sparse_factor(qp, metric, rho, active)?;
            Factor::Sparse
        };
        self.factor = Some(factor);
        Ok(())
    }

    /// Factors `H = M + J^T D J` from the packed rows (`d[i] = 0`: row
    /// `i` left out), the rows of each group accumulated on a small dense
    /// matrix first (`super::super::packed_rows`). The same matrix as
    /// [`NewtonMatrix::factor`] with `rho = d` and every row active, up to
    /// the order of the sums.
    pub(crate) fn factor_packed(
        &mut self,
        packed: &PackedRows,
        metric: &[BlockMetric],
        d: &[f64],
    ) -> Result<(), FactorizationFailed> {
        self.factor = None;
        let factor = if self.dense {
            // Only the lower triangle: the dense Cholesky reads no other.
            let grams = packed
                .groups
                .iter()
                .map(|group| packed.gram_for_lower(group, d));
            let mut h = DMatrix::zeros(self.dofs, self.dofs);
            for (k, b) in metric.iter().enumerate() {
                let mut view = h.fixed_view_mut::<6, 6>(6 * k, 6 * k);
                view += b.matrix();
            }
            for (group, gram) in packed.groups.iter().zip(grams) {
                add_gram_dense_lower(&mut h, group.bodies, &gram);
            }
            Factor::Dense(DenseCholesky::new(h).ok_or(FactorizationFailed)?)
        } else {
            self.prepare_sparse()?;
            if self.group_bases.is_none() {
                let pattern = self.pattern.as_ref().ok_or(FactorizationFailed)?;
                self.group_bases = Some(group_bases(pattern, packed));
            }
            let (Some(sparse), Some(bases)) = (self.sparse.as_mut(), self.group_bases.as_ref())
            else {
                return Err(FactorizationFailed);
            };
            let values = &mut sparse.values;
            values.fill(0.0);
            // The diagonal blocks' bases of a body's own `M_k`: those of the
            // groups' diagonal blocks are the same positions.
            let pattern = self.pattern.as_ref().ok_or(FactorizationFailed)?;
            for (k, b) in metric.iter().enumerate() {
                let block = b.matrix();
                for c in 0..6 {
                    for r in c..6 {
                        values[pattern.position(k, k, r, c)] += block[(r, c)];
                    }
                }
            }
            for (base, group) in bases.iter().zip(&packed.groups) {
                scatter_gram(values, base, &packed.gram_for_lower(group, d));
            }
            self.factor_sparse_values()?;
            Factor::Sparse
        };
        self.factor = Some(factor);
        Ok(())
    }

    /// The symbolic analysis of the sparse pattern, once.
    fn prepare_sparse(&mut self) -> Result<(), FactorizationFailed> {
        if self.sparse.is_some() {
            return Ok(());
        }
        let pattern = self.pattern.as_ref().ok_or(FactorizationFailed)?;
        let kind = analysis_kind(self.supernodal);
        let analysis = match self.store {
            Some(store) => store.analysis(kind, &pattern.col_ptr, &pattern.row_idx),
            None => KeptAnalysis::new(kind, &pattern.col_ptr, &pattern.row_idx).map(Arc::new),
        }
        .ok_or(FactorizationFailed)?;
        self.sparse = Some(SparseFactor::buffers(analysis, pattern.row_idx.len())?);
        Ok(())
    }

    /// The numeric factorization of the assembled sparse values.
    fn factor_sparse_values(&mut self) -> Result<(), FactorizationFailed> {
        let Some(sparse) = self.sparse.as_mut() else {
            return Err(FactorizationFailed);
        };
        sparse
            .analysis
            .permute_values(&sparse.values, &mut sparse.permuted);
        let matrix = SparseColMatRef::new(sparse.analysis.permuted_pattern(), &sparse.permuted);
        let stack = MemStack::new(&mut sparse.workspace);
        sparse
            .analysis
            .symbolic()
            .factorize_numeric_llt(
                &mut sparse.factor_values,
                matrix,
                sparse.analysis.permuted_side(),
                LltRegularization::default(),
                Par::Seq,
                stack,
                Default::default(),
            )
            .map(|_| ())
            .map_err(|_| FactorizationFailed)
    }

    fn sparse_factor(
        &mut self,
        qp: &ProjectionQp,
        metric: &[BlockMetric],
        rho: &[f64],
        active: &[bool],
    ) -> Result<(), FactorizationFailed> {
        // `new` builds the pattern whenever the matrix is sparse.
        self.prepare_sparse()?;
        let (Some(pattern), Some(sparse)) = (self.pattern.as_ref(), self.sparse.as_mut()) else {
            return Err(FactorizationFailed);
        };
        sparse.values.fill(0.0);
        let values = &mut sparse.values;
        for (k, b) in metric.iter().enumerate() {
            let block = b.matrix();
            for c in 0..6 {
                for r in c..6 {
                    values[pattern.position(k, k, r, c)] += block[(r, c)];
                }
            }
        }
        for (i, row) in qp.rows.iter().enumerate() {
            if !active[i] || rho[i] == 0.0 {
                continue;
            }
            for &(a, b, base) in &pattern.scatter[i] {
                let (k, gk) = &row.blocks[a];
                let (l, gl) = &row.blocks[b];
                let diagonal = k == l;
                for c in 0..6 {
                    let weight = rho[i] * gl[c];
                    let first = if diagonal { c } else { 0 };
                    for r in first..6 {
                        values[base[c] + r] += weight * gk[r];
                    }
                }
            }
        }
        self.factor_sparse_values()
    }

    /// `H^-1 rhs` with the current factor (`None` before a factorization).
    pub(crate) fn solve(&mut self, rhs: &DVector<f64>) -> Option<DVector<f64>> {
        match self.factor.as_ref()? {
            Factor::Dense(chol) => Some(chol.solve(rhs)),
            Factor::Sparse => {
                let sparse = self.sparse.as_mut()?;
                // `H x = rhs` as `(P H P^T) (P x) = P rhs`.
                let order = sparse.analysis.order();
                let mut x_permuted: Vec<f64> = order.iter().map(|&i| rhs[i]).collect();
                let n = x_permuted.len();
                let llt = LltRef::new(sparse.analysis.symbolic(), &sparse.factor_values);
                llt.solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(&mut x_permuted, n, 1),
                    Par::Seq,
                    MemStack::new(&mut sparse.workspace),
                );
                let mut x = DVector::zeros(n);
                for (&i, value) in order.iter().zip(x_permuted) {
                    x[i] = value;
                }
                Some(x)
            }
        }
    }
}

impl SparseFactor {
    /// The buffers of the numeric factorizations and solves for the
    /// symbolic analysis `analysis` of a pattern of `nonzeros` entries.
    fn buffers(analysis: Arc<KeptAnalysis>, nonzeros: usize) -> Result<Self, FactorizationFailed> {
        let symbolic = analysis.symbolic();
        let workspace_size = symbolic
            .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        let workspace = MemBuffer::try_new(workspace_size).map_err(|_| FactorizationFailed)?;
        Ok(Self {
            factor_values: vec![0.0; symbolic.len_val()],
            values: vec![0.0; nonzeros],
            permuted: vec![0.0; nonzeros],
            analysis,
            workspace,
        })
    }
}

/// The layout of the sparse factor: supernodal (dense 6x6 kernels on the
/// blocks of a body) or left to faer's flop-ratio choice.
fn analysis_kind(supernodal: bool) -> AnalysisKind {
    if supernodal {
        AnalysisKind::Supernodal
    } else {
        AnalysisKind::Auto
    }
}

/// Calls `add(k, l, block)` for the 6x6 blocks `(k, l)`, `k >= l`, of `H`:
/// `M_k` on the diagonal, then `rho_i g_k g_l^T` of every active row over
/// bodies `k` and `l` (a block may come several times: the caller adds).
fn for_each_lower_block(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    rho: &[f64],
    active: &[bool],
    mut add: impl FnMut(usize, usize, &Matrix6<f64>),
) {
    for (k, b) in metric.iter().enumerate() {
        add(k, k, &b.matrix());
    }
    for ((row, &r), _) in qp.rows.iter().zip(rho).zip(active).filter(|(_, a)| **a) {
        for (a, (k, gk)) in row.blocks.iter().enumerate() {
            for (l, gl) in &row.blocks[..=a] {
                if k >= l {
                    add(*k, *l, &(gk * gl.transpose() * r));
                } else {
                    add(*l, *k, &(gl * gk.transpose() * r));
                }
            }
        }
    }
}

/// Adds a group's Gram matrix ([`PackedRows::gram_for_lower`]) to the
/// lower triangle of the dense `h`: its diagonal blocks (upper parts zero)
/// and the block `(k, l)`, `k > l`; the mirror block `(l, k)` is left out.
fn add_gram_dense_lower(h: &mut DMatrix<f64>, bodies: (usize, Option<usize>), gram: &Gram) {
    let k = bodies.0;
    let mut kk = h.fixed_view_mut::<6, 6>(6 * k, 6 * k);
    kk += gram.fixed_view::<6, 6>(0, 0);
    if let Some(l) = bodies.1 {
        let mut ll = h.fixed_view_mut::<6, 6>(6 * l, 6 * l);
        ll += gram.fixed_view::<6, 6>(6, 6);
        // `k > l`: the block `(k, l)` lies below the diagonal.
        let mut kl = h.fixed_view_mut::<6, 6>(6 * k, 6 * l);
        kl += gram.fixed_view::<6, 6>(0, 6);
    }
}

/// The value-array bases of every group's blocks ([`GroupBase`]).
fn group_bases(pattern: &BlockPattern, packed: &PackedRows) -> Vec<GroupBase> {
    let diagonal = |k: usize| std::array::from_fn(|c| pattern.position(k, k, c, c) - c);
    packed
        .groups
        .iter()
        .map(|group| {
            let (k, l) = group.bodies;
            GroupBase {
                kk: diagonal(k),
                ll: l.map(diagonal),
                kl: l.map(|l| std::array::from_fn(|c| pattern.position(k, l, 0, c))),
            }
        })
        .collect()
}

/// Adds a group's Gram matrix (the entries of
/// [`PackedRows::gram_for_lower`]) to the sparse lower triangle.
fn scatter_gram(values: &mut [f64], base: &GroupBase, gram: &Gram) {
    for c in 0..6 {
        for r in c..6 {
            values[base.kk[c] + r] += gram[(r, c)];
        }
    }
    if let (Some(ll), Some(kl)) = (base.ll, base.kl) {
        for c in 0..6 {
            for r in c..6 {
                values[ll[c] + r] += gram[(6 + r, 6 + c)];
            }
            for r in 0..6 {
                values[kl[c] + r] += gram[(r, 6 + c)];
            }
        }
    }
}
