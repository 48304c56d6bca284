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

/// A kept analysis factors `P A P^T` in its own order (the order applied
/// once, `KeptAnalysis::permute_values`): for random sparse symmetric
/// positive definite matrices (a star around index 0, which AMD orders
/// last, and random couplings), of every kind, the factor's solve
/// through the order equals nalgebra's dense Cholesky solve of `A` within
/// rounding.
#[test]
fn the_permuted_factor_solves_the_original_matrix() {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::cholesky::llt::factor::LltRegularization;
    use faer::sparse::SparseColMatRef;
    use faer::sparse::linalg::cholesky::LltRef;
    use faer::{Conj, MatMut, Par};
    use nalgebra::{DMatrix, DVector};
    use rand::{Rng, SeedableRng};

    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    for n in [5usize, 12, 30] {
        for kind in [
            AnalysisKind::Simplicial,
            AnalysisKind::Supernodal,
            AnalysisKind::Auto,
        ] {
            // The diagonal, a star around index 0 and random couplings.
            let mut dense = DMatrix::<f64>::zeros(n, n);
            for i in 0..n {
                for j in 0..i {
                    if j == 0 || rng.random_bool(0.2) {
                        let v: f64 = rng.random_range(-1.0..1.0);
                        dense[(i, j)] = v;
                        dense[(j, i)] = v;
                    }
                }
            }
            for i in 0..n {
                dense[(i, i)] = n as f64 + 1.0;
            }
            let mut col_ptr = vec![0];
            let mut row_idx = Vec::new();
            let mut values = Vec::new();
            for j in 0..n {
                for i in j..n {
                    if i == j || dense[(i, j)] != 0.0 {
                        row_idx.push(i);
                        values.push(dense[(i, j)]);
                    }
                }
                col_ptr.push(row_idx.len());
            }
            let kept = KeptAnalyses::default();
            let analysis = kept.analysis(kind, &col_ptr, &row_idx).expect("analysed");
            let order = analysis.order();
            let mut sorted = order.to_vec();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..n).collect::<Vec<_>>(), "a permutation");
            assert_ne!(order[0], 0, "the star's centre is not eliminated first");
            let mut permuted = vec![0.0; values.len()];
            analysis.permute_values(&values, &mut permuted);
            let symbolic = analysis.symbolic();
            let mut l_values = vec![0.0; symbolic.len_val()];
            let scratch = symbolic
                .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
                .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
            let mut workspace = MemBuffer::try_new(scratch).expect("memory");
            symbolic
                .factorize_numeric_llt(
                    &mut l_values,
                    SparseColMatRef::new(analysis.permuted_pattern(), &permuted),
                    analysis.permuted_side(),
                    LltRegularization::default(),
                    Par::Seq,
                    MemStack::new(&mut workspace),
                    Default::default(),
                )
                .expect("positive definite");
            let rhs = DVector::from_fn(n, |_, _| rng.random_range(-1.0..1.0));
            let mut x_permuted: Vec<f64> = order.iter().map(|&i| rhs[i]).collect();
            LltRef::new(symbolic, &l_values).solve_in_place_with_conj(
                Conj::No,
                MatMut::from_column_major_slice_mut(&mut x_permuted, n, 1),
                Par::Seq,
                MemStack::new(&mut workspace),
            );
            let mut x = DVector::zeros(n);
            for (&i, v) in order.iter().zip(x_permuted) {
                x[i] = v;
            }
            let expected = dense.clone().cholesky().expect("spd").solve(&rhs);
            let error = (&x - &expected).amax() / expected.amax();
            assert!(error < 1e-12, "n {n} {kind:?}: relative error {error:.2e}");
        }
    }
}
