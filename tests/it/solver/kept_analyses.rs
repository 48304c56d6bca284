//! The store of sparse symbolic analyses (`src/solver/kept_analyses.rs`):
//! bounded, least recently used first, keyed by kind and pattern, refusing
//! invalid patterns; the body-space matrix's analysis taken from it leaves
//! the interior point's answer bit for bit what it is without a store.

use constraint_stabilization::solver::augmented_lagrangian::Start;
use constraint_stabilization::solver::interior_point::{self, InteriorPointSettings};
use constraint_stabilization::solver::kept_analyses::{
    AnalysisKind, KEPT_ANALYSES_CAPACITY, KeptAnalyses,
};
use dev_support::solver::{StackSpec, random_stacks};

/// The diagonal pattern of an `n x n` matrix.
fn diagonal(n: usize) -> (Vec<usize>, Vec<usize>) {
    ((0..=n).collect(), (0..n).collect())
}

/// Past [`KEPT_ANALYSES_CAPACITY`] patterns the least recently used goes,
/// and a pattern asked for again is moved to the front (it survives the
/// next insertions).
#[test]
fn the_kept_analyses_are_bounded_least_recently_used_first() {
    let kind = AnalysisKind::Simplicial;
    let kept = KeptAnalyses::default();
    let (first_ptr, first_idx) = diagonal(1);
    kept.analysis(kind, &first_ptr, &first_idx)
        .expect("analysed");
    for n in 2..=KEPT_ANALYSES_CAPACITY + 3 {
        let (col_ptr, row_idx) = diagonal(n);
        let analysis = kept.analysis(kind, &col_ptr, &row_idx).expect("analysed");
        assert!(analysis.fits(kind, &col_ptr, &row_idx));
        assert!(!analysis.fits(kind, &first_ptr, &first_idx));
        // The first pattern, used again after every insertion, stays.
        let again = kept
            .analysis(kind, &first_ptr, &first_idx)
            .expect("analysed");
        assert!(again.fits(kind, &first_ptr, &first_idx));
        assert_eq!(kept.len(), n.min(KEPT_ANALYSES_CAPACITY));
    }
    // Invalid patterns are refused, not kept: a row index out of range,
    // pointers that decrease, rows out of order.
    assert!(kept.analysis(kind, &[0, 1], &[3]).is_none());
    assert!(kept.analysis(kind, &[0, 5, 1], &[0]).is_none());
    assert!(kept.analysis(kind, &[0, 2, 2], &[1, 0]).is_none());
    assert_eq!(kept.len(), KEPT_ANALYSES_CAPACITY);
    kept.clear();
    assert!(kept.is_empty());
}

/// The same pattern under another kind is another analysis: a
/// supernodal one never answers for a simplicial one.
#[test]
fn the_kind_is_part_of_the_key() {
    let kept = KeptAnalyses::default();
    let (col_ptr, row_idx) = diagonal(12);
    let simplicial = kept
        .analysis(AnalysisKind::Simplicial, &col_ptr, &row_idx)
        .expect("analysed");
    let supernodal = kept
        .analysis(AnalysisKind::Supernodal, &col_ptr, &row_idx)
        .expect("analysed");
    assert!(!simplicial.fits(AnalysisKind::Supernodal, &col_ptr, &row_idx));
    assert!(supernodal.fits(AnalysisKind::Supernodal, &col_ptr, &row_idx));
    assert_eq!(kept.len(), 2);
}

/// The interior point on random stacks large enough for the sparse factor:
/// with a store its answers are those of a solve that makes its own
/// analysis, bit for bit, the store keeps one analysis per pattern (the
/// second solve of a problem finds the first's), and its size is counted.
#[test]
fn the_interior_point_takes_its_analysis_from_the_store() {
    let kept = KeptAnalyses::default();
    let settings = InteriorPointSettings::default();
    for (seed, rows) in [(1, 120), (2, 160), (3, 240)] {
        let qp = random_stacks(&StackSpec::new(rows, seed));
        assert!(qp.num_dofs() > settings.dense_max_dofs, "sparse path");
        let metric = qp.validate().expect("valid problem");
        let start = |kept| Start {
            warm: None,
            tolerance: 1e-6,
            relaxation: 1.0,
            deadline: None,
            kept,
        };
        let alone = interior_point::solve(&qp, &metric, &settings, &start(None)).expect("solved");
        let before = kept.len();
        for round in 0..2 {
            let stored = interior_point::solve(&qp, &metric, &settings, &start(Some(&kept)))
                .expect("solved");
            assert_eq!(alone.dq.as_slice(), stored.dq.as_slice(), "seed {seed}");
            assert_eq!(alone.iterations, stored.iterations);
            assert_eq!(kept.len(), before + 1, "seed {seed}, round {round}");
        }
    }
    assert!(kept.bytes() > 0);
}
