//! Sparse symbolic analyses kept across solves while their pattern holds.
//!
//! The symbolic part of a sparse Cholesky factorization (the AMD ordering,
//! the elimination tree and the supernodes of `A = L L^T`) depends on the
//! matrix's pattern alone. The equality block `A_EE = J_E M^-1 J_E^T` of a
//! scene's joints (`super::equality_elimination`) has the same pattern in
//! every pass of a call, in the velocity projection after it and in the
//! next calls: its entries follow the joint graph, not the poses. The
//! body-space matrix `H = M + J^T D J` of the interior point and the
//! augmented Lagrangian (`super::augmented_lagrangian::hessian`) follows
//! the pairs of bodies that share a row: the same in the passes of a call
//! while an island's contacts keep their pairs, and in the next calls of a
//! scene at rest. Each analysis is made once and kept here, keyed by the
//! pattern itself (column pointers and row indices of the lower triangle,
//! compared entry by entry) and by its [`AnalysisKind`]: a kept analysis is
//! used only for exactly the pattern and kind it was made for, so it cannot
//! change an answer, only skip work.
//!
//! **The order applied once.** faer's numeric factorization under an
//! ordering `P` first copies the matrix into `P A P^T`, computing every
//! entry's permuted place again at every factorization (8 % of a call on
//! the Bullet pyramid, whose 21 interior-point iterations each factor).
//! A kept analysis therefore holds the AMD order `P`, the pattern of
//! `P A P^T` (lower triangle, sorted columns) and, for each entry of the
//! caller's pattern, its place in that one (`value_map`); the symbolic
//! analysis is made on the permuted pattern under the identity order
//! (the same elimination tree, supernodes and fill, since faer analyses
//! `P A P^T` either way). A factorization then gathers the values once
//! ([`KeptAnalysis::permute_values`]) and a solve permutes its right-hand
//! side in and out ([`KeptAnalysis::order`]): `A x = b` is
//! `(P A P^T) (P x) = P b`.
//!
//! **Owner and size.** A [`crate::Stabilizer`] owns one store for its calls
//! (its islands, solved on several threads, share it behind a mutex); the
//! store keeps at most [`KEPT_ANALYSES_CAPACITY`] patterns, the most
//! recently used first, reports its size ([`KeptAnalyses::len`],
//! [`KeptAnalyses::bytes`]; `Report::kept_analyses`) and is emptied when
//! bodies are removed through the stabilizer. A solve without a store
//! makes its analysis and drops it.

use std::sync::{Arc, Mutex, PoisonError};

use faer::Side;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};

/// Patterns kept at most: a scene has a few joint islands whose patterns
/// repeat (each island's, and the velocity projection's of the same
/// joints) and a few large islands solved on the body-space matrix; the
/// least recently used goes first.
pub const KEPT_ANALYSES_CAPACITY: usize = 16;

/// How faer lays out the factor: column by column (simplicial), by dense
/// blocks of columns with the same structure (supernodal), or faer's own
/// choice by the ratio of flops to nonzeros.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AnalysisKind {
    /// Column by column (the equality block, banded or tree-like).
    Simplicial,
    /// Dense blocks (a body's 6 columns and those that share its pattern).
    Supernodal,
    /// faer's choice.
    Auto,
}

impl AnalysisKind {
    fn threshold(self) -> SupernodalThreshold {
        match self {
            AnalysisKind::Simplicial => SupernodalThreshold::FORCE_SIMPLICIAL,
            AnalysisKind::Supernodal => SupernodalThreshold::FORCE_SUPERNODAL,
            AnalysisKind::Auto => SupernodalThreshold::AUTO,
        }
    }
}

/// A symbolic analysis of a symmetric matrix's lower triangle under an AMD
/// order `P`, made on the pattern of `P A P^T` (module docs), and the
/// pattern and kind it was made for.
#[derive(Debug)]
pub struct KeptAnalysis {
    kind: AnalysisKind,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// `order[i]`: the caller's index of row and column `i` of `P A P^T`.
    order: Vec<usize>,
    /// `value_map[p]`: the place in `P A P^T`'s values of the caller's
    /// value `p`.
    value_map: Vec<usize>,
    /// Column pointers and row indices of `P A P^T`'s triangle `side`.
    permuted_col_ptr: Vec<usize>,
    permuted_row_idx: Vec<usize>,
    /// The triangle of `P A P^T` stored: the one faer's factorization of
    /// this analysis reads.
    side: Side,
    /// The analysis of `P A P^T` under the identity order.
    symbolic: SymbolicCholesky<usize>,
}

impl KeptAnalysis {
    /// The analysis of the square pattern `col_ptr`, `row_idx` (lower
    /// triangle, compressed by columns, rows ascending); `None` when the
    /// pattern is invalid or faer fails (out of memory).
    pub fn new(kind: AnalysisKind, col_ptr: &[usize], row_idx: &[usize]) -> Option<Self> {
        let n = col_ptr.len().checked_sub(1)?;
        if !valid_pattern(n, col_ptr, row_idx) {
            return None;
        }
        // Checked above: faer's own check cannot fail.
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
        let (order, inverse) = amd_order(pattern)?;
        // faer analyses a pattern under the identity order as its upper
        // triangle; its supernodal factorization reads the lower one, its
        // simplicial one the upper (either other side costs a copy).
        let upper = permute_pattern(col_ptr, row_idx, &inverse, Side::Upper);
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: kind.threshold(),
            ..Default::default()
        };
        let symbolic = factorize_symbolic_cholesky(
            SymbolicSparseColMatRef::new_checked(n, n, &upper.col_ptr, None, &upper.row_idx),
            Side::Upper,
            SymmetricOrdering::Identity,
            params,
        )
        .ok()?;
        let (permuted, side) = match symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(_) => (
                permute_pattern(col_ptr, row_idx, &inverse, Side::Lower),
                Side::Lower,
            ),
            SymbolicCholeskyRaw::Simplicial(_) => (upper, Side::Upper),
        };
        Some(Self {
            kind,
            col_ptr: col_ptr.to_vec(),
            row_idx: row_idx.to_vec(),
            order,
            value_map: permuted.value_map,
            permuted_col_ptr: permuted.col_ptr,
            permuted_row_idx: permuted.row_idx,
            side,
            symbolic,
        })
    }

    /// Whether this analysis was made for exactly this kind and pattern.
    pub fn fits(&self, kind: AnalysisKind, col_ptr: &[usize], row_idx: &[usize]) -> bool {
        self.kind == kind && self.col_ptr == col_ptr && self.row_idx == row_idx
    }

    /// The analysis of `P A P^T` (module docs), under the identity order:
    /// factor the values of [`KeptAnalysis::permuted_pattern`] (from
    /// [`KeptAnalysis::permute_values`]) with it.
    pub fn symbolic(&self) -> &SymbolicCholesky<usize> {
        &self.symbolic
    }

    /// `order[i]`: the caller's index of row and column `i` of `P A P^T`
    /// (`(P x)_i = x_order[i]`).
    pub fn order(&self) -> &[usize] {
        &self.order
    }

    /// The triangle of `P A P^T` that [`KeptAnalysis::permuted_pattern`]
    /// holds, as faer's factorization is told.
    pub fn permuted_side(&self) -> Side {
        self.side
    }

    /// The pattern of `P A P^T`'s triangle [`KeptAnalysis::permuted_side`].
    pub fn permuted_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        let n = self.order.len();
        SymbolicSparseColMatRef::new_checked(
            n,
            n,
            &self.permuted_col_ptr,
            None,
            &self.permuted_row_idx,
        )
    }

    /// Writes the values of `P A P^T` into `permuted` from the caller's
    /// values of `A` (both as long as the pattern's entries).
    pub fn permute_values(&self, values: &[f64], permuted: &mut [f64]) {
        for (&value, &place) in values.iter().zip(&self.value_map) {
            permuted[place] = value;
        }
    }

    /// Bytes held: the pattern's indices (the caller's and the permuted
    /// one, with the map between them and the order) and the factor's
    /// structure (one index per stored entry of `L`, one per column).
    pub fn bytes(&self) -> usize {
        let indices = 2 * (self.col_ptr.len() + self.row_idx.len())
            + self.value_map.len()
            + self.order.len()
            + self.symbolic.len_val()
            + self.symbolic.nrows();
        indices * std::mem::size_of::<usize>()
    }
}

/// faer's approximate minimum degree order of the pattern of `A + A^T`
/// (here a triangle's pattern, mirrored): `(order, inverse)`,
/// `order[i]` the original index placed at `i`; `None` when faer fails
/// (out of memory, or an index overflow).
fn amd_order(pattern: SymbolicSparseColMatRef<'_, usize>) -> Option<(Vec<usize>, Vec<usize>)> {
    let n = pattern.nrows();
    let scratch = amd::order_maybe_unsorted_scratch::<usize>(n, pattern.compute_nnz());
    let mut workspace = MemBuffer::try_new(scratch).ok()?;
    let mut order = vec![0usize; n];
    let mut inverse = vec![0usize; n];
    amd::order_maybe_unsorted(
        &mut order,
        &mut inverse,
        pattern,
        amd::Control::default(),
        MemStack::new(&mut workspace),
    )
    .ok()?;
    Some((order, inverse))
}

/// A triangle of `P A P^T` and where each entry of `A` goes.
struct PermutedPattern {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    value_map: Vec<usize>,
}

/// Entry `(i, j)`, `i >= j`, of `A` (lower triangle, compressed by
/// columns) is entry `(max, min)` of `(inverse[i], inverse[j])` in the
/// lower triangle of `P A P^T`, `(min, max)` in its upper one: counted per
/// new column, placed, and each new column's rows sorted with the map
/// following them.
fn permute_pattern(
    col_ptr: &[usize],
    row_idx: &[usize],
    inverse: &[usize],
    side: Side,
) -> PermutedPattern {
    let n = inverse.len();
    let entry = |p: usize, j: usize| {
        let (a, b) = (inverse[row_idx[p]], inverse[j]);
        match side {
            Side::Lower => (a.max(b), a.min(b)),
            Side::Upper => (a.min(b), a.max(b)),
        }
    };
    let columns = || (0..n).flat_map(|j| (col_ptr[j]..col_ptr[j + 1]).map(move |p| (p, j)));
    let mut counts = vec![0usize; n + 1];
    for (p, j) in columns() {
        counts[entry(p, j).1 + 1] += 1;
    }
    for c in 0..n {
        counts[c + 1] += counts[c];
    }
    let new_col_ptr = counts.clone();
    let mut next = counts;
    // (new row, original position) per new place, then sorted per column.
    let mut placed = vec![(0usize, 0usize); row_idx.len()];
    for (p, j) in columns() {
        let (r, c) = entry(p, j);
        placed[next[c]] = (r, p);
        next[c] += 1;
    }
    for c in 0..n {
        placed[new_col_ptr[c]..new_col_ptr[c + 1]].sort_unstable();
    }
    let mut value_map = vec![0usize; row_idx.len()];
    for (place, &(_, p)) in placed.iter().enumerate() {
        value_map[p] = place;
    }
    PermutedPattern {
        col_ptr: new_col_ptr,
        row_idx: placed.into_iter().map(|(r, _)| r).collect(),
        value_map,
    }
}

/// Whether `col_ptr`, `row_idx` compress the lower triangle of an `n x n`
/// pattern as faer reads it: pointers from 0 to `row_idx.len()`, never
/// decreasing, rows strictly ascending within a column, from the column's
/// own index and below `n`.
fn valid_pattern(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> bool {
    // The pointers first: every slice below is then within `row_idx`.
    col_ptr.first() == Some(&0)
        && col_ptr.last() == Some(&row_idx.len())
        && col_ptr.windows(2).all(|w| w[0] <= w[1])
        && col_ptr.windows(2).enumerate().all(|(c, w)| {
            let column = &row_idx[w[0]..w[1]];
            column.windows(2).all(|r| r[0] < r[1]) && column.iter().all(|&r| c <= r && r < n)
        })
}

/// The analyses a stabilizer keeps (module docs). Cloning shares the kept
/// analyses (they are immutable); the clones then keep their own lists.
#[derive(Debug, Default)]
pub struct KeptAnalyses {
    /// Most recently used first.
    entries: Mutex<Vec<Arc<KeptAnalysis>>>,
}

impl Clone for KeptAnalyses {
    fn clone(&self) -> Self {
        Self {
            entries: Mutex::new(self.lock().clone()),
        }
    }
}

impl KeptAnalyses {
    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<Arc<KeptAnalysis>>> {
        // A panic while the list was held leaves it a valid list: the
        // poison is only a flag.
        self.entries.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The analysis of this kind and pattern: the kept one (moved to the
    /// front), else a new one, kept. `None` when the analysis fails.
    pub fn analysis(
        &self,
        kind: AnalysisKind,
        col_ptr: &[usize],
        row_idx: &[usize],
    ) -> Option<Arc<KeptAnalysis>> {
        {
            let mut entries = self.lock();
            if let Some(at) = entries.iter().position(|e| e.fits(kind, col_ptr, row_idx)) {
                let kept = entries.remove(at);
                entries.insert(0, Arc::clone(&kept));
                return Some(kept);
            }
        }
        // Made outside the lock: another thread's islands go on meanwhile.
        let made = Arc::new(KeptAnalysis::new(kind, col_ptr, row_idx)?);
        let mut entries = self.lock();
        if !entries.iter().any(|e| e.fits(kind, col_ptr, row_idx)) {
            entries.insert(0, Arc::clone(&made));
            entries.truncate(KEPT_ANALYSES_CAPACITY);
        }
        Some(made)
    }

    /// Number of kept analyses.
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    /// Whether nothing is kept.
    pub fn is_empty(&self) -> bool {
        self.lock().is_empty()
    }

    /// Bytes held by the kept analyses ([`KeptAnalysis::bytes`]).
    pub fn bytes(&self) -> usize {
        self.lock().iter().map(|e| e.bytes()).sum()
    }

    /// Drops every kept analysis.
    pub fn clear(&self) {
        self.lock().clear();
    }
}
