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
//! **Owner and size.** A [`crate::Stabilizer`] owns one store for its calls
//! (its islands, solved on several threads, share it behind a mutex); the
//! store keeps at most [`KEPT_ANALYSES_CAPACITY`] patterns, the most
//! recently used first, reports its size ([`KeptAnalyses::len`],
//! [`KeptAnalyses::bytes`]; `Report::kept_analyses`) and is emptied when
//! bodies are removed through the stabilizer. A solve without a store
//! makes its analysis and drops it.

use std::sync::{Arc, Mutex, PoisonError};

use faer::Side;
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
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
/// order, and the pattern and kind it was made for.
#[derive(Debug)]
pub struct KeptAnalysis {
    kind: AnalysisKind,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
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
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: kind.threshold(),
            ..Default::default()
        };
        let symbolic =
            factorize_symbolic_cholesky(pattern, Side::Lower, SymmetricOrdering::Amd, params)
                .ok()?;
        Some(Self {
            kind,
            col_ptr: col_ptr.to_vec(),
            row_idx: row_idx.to_vec(),
            symbolic,
        })
    }

    /// Whether this analysis was made for exactly this kind and pattern.
    pub fn fits(&self, kind: AnalysisKind, col_ptr: &[usize], row_idx: &[usize]) -> bool {
        self.kind == kind && self.col_ptr == col_ptr && self.row_idx == row_idx
    }

    /// The analysis.
    pub fn symbolic(&self) -> &SymbolicCholesky<usize> {
        &self.symbolic
    }

    /// Bytes held: the pattern's indices and the factor's structure (one
    /// index per stored entry of `L`, one per column).
    pub fn bytes(&self) -> usize {
        let indices = self.col_ptr.len()
            + self.row_idx.len()
            + self.symbolic.len_val()
            + self.symbolic.nrows();
        indices * std::mem::size_of::<usize>()
    }
}

/// Whether `col_ptr`, `row_idx` compress an `n x n` pattern as faer reads
/// it: pointers from 0 to `row_idx.len()`, never decreasing, rows strictly
/// ascending within a column and below `n`.
fn valid_pattern(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> bool {
    // The pointers first: every slice below is then within `row_idx`.
    col_ptr.first() == Some(&0)
        && col_ptr.last() == Some(&row_idx.len())
        && col_ptr.windows(2).all(|w| w[0] <= w[1])
        && col_ptr.windows(2).all(|w| {
            let column = &row_idx[w[0]..w[1]];
            column.windows(2).all(|r| r[0] < r[1]) && column.iter().all(|&r| r < n)
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
