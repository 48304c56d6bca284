//! The dense Cholesky of the small body-space matrices
//! (`solver::dense_cholesky`) against nalgebra's on random symmetric
//! positive definite matrices of the sizes it serves (6 to 96), and its
//! refusal of matrices that are not positive definite.

use constraint_stabilization::solver::dense_cholesky::DenseCholesky;
use nalgebra::{DMatrix, DVector};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Relative agreement of two backward-stable solves of a system with
/// condition number below about 1e4: rounding of order `n u kappa`.
const SOLVE_AGREEMENT_TOL: f64 = 1e-9;

/// `B B^T + n I` (well conditioned), `B` uniform in [-1, 1].
fn random_spd(n: usize, rng: &mut ChaCha8Rng) -> DMatrix<f64> {
    let b = DMatrix::from_fn(n, n, |_, _| rng.random_range(-1.0..1.0));
    &b * b.transpose() + DMatrix::identity(n, n) * n as f64
}

#[test]
fn solves_as_nalgebra_on_random_spd_matrices() {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    for n in [6, 12, 36, 96] {
        for _ in 0..3 {
            let h = random_spd(n, &mut rng);
            let rhs = DVector::from_fn(n, |_, _| rng.random_range(-1.0..1.0));
            let ours = DenseCholesky::new(h.clone()).expect("positive definite");
            let theirs = h.clone().cholesky().expect("positive definite");
            let x = ours.solve(&rhs);
            let y = theirs.solve(&rhs);
            let relative = (&x - &y).norm() / y.norm();
            assert!(relative <= SOLVE_AGREEMENT_TOL, "n = {n}: {relative:e}");
            let residual = (&h * &x - &rhs).norm() / rhs.norm();
            assert!(
                residual <= SOLVE_AGREEMENT_TOL,
                "n = {n}: residual {residual:e}"
            );
        }
    }
}

/// Only the lower triangle is read: garbage above the diagonal changes
/// nothing.
#[test]
fn reads_the_lower_triangle_only() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let h = random_spd(18, &mut rng);
    let mut upper_garbage = h.clone();
    for c in 1..18 {
        for r in 0..c {
            upper_garbage[(r, c)] = f64::NAN;
        }
    }
    let rhs = DVector::from_element(18, 1.0);
    let x = DenseCholesky::new(h).expect("spd").solve(&rhs);
    let y = DenseCholesky::new(upper_garbage).expect("spd").solve(&rhs);
    assert_eq!(x, y);
}

/// An indefinite, a singular, a NaN and a non-square matrix are refused.
#[test]
fn refuses_what_is_not_positive_definite() {
    let mut indefinite = DMatrix::identity(4, 4);
    indefinite[(2, 2)] = -1.0;
    let singular = DMatrix::from_element(3, 3, 1.0);
    let mut nan = DMatrix::identity(3, 3);
    nan[(1, 1)] = f64::NAN;
    for (name, h) in [
        ("indefinite", indefinite),
        ("singular", singular),
        ("NaN", nan),
        ("non-square", DMatrix::zeros(2, 3)),
    ] {
        assert!(DenseCholesky::new(h).is_none(), "{name}");
    }
}
