//! Projected Gauss-Seidel: converges on symmetric positive definite
//! problems (to Lemke's solution, the unique one), reports when it does not.

use crate::support::proptest_config;
use constraint_stabilization::solver::Lcp;
use constraint_stabilization::solver::lemke::{self, LemkeSettings};
use constraint_stabilization::solver::pgs::{self, PgsSettings, PgsStatus};
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;

/// `M = B B^T + 0.5 I`: symmetric positive definite, condition number at
/// most about `1 + 2 n`.
fn spd_lcp() -> impl Strategy<Value = Lcp> {
    (1usize..=12).prop_flat_map(|n| {
        (
            prop::collection::vec(-1.0..1.0f64, n * n),
            prop::collection::vec(-1.0..1.0f64, n),
        )
            .prop_map(move |(b, q)| {
                let b = DMatrix::from_row_slice(n, n, &b);
                let m = &b * b.transpose() + DMatrix::identity(n, n) * 0.5;
                Lcp::new(m, DVector::from_vec(q)).unwrap()
            })
    })
}

proptest! {
    #![proptest_config(proptest_config::config(100))]
    #[test]
    fn pgs_converges_on_spd_problems(lcp in spd_lcp()) {
        let settings = PgsSettings { max_sweeps: 100_000, ..PgsSettings::default() };
        let sol = pgs::solve(&lcp, &settings).unwrap();
        prop_assert!(sol.residual <= 1e-9);
        let exact = lemke::solve(&lcp, &LemkeSettings::default()).unwrap();
        // Positive definite: the solution is unique; the distance to it is
        // bounded by the residual times the condition number.
        prop_assert!((&sol.z - &exact.z).amax() <= 1e-7 * exact.z.amax().max(1.0));
    }
}

#[test]
fn sweep_limit_is_reported() {
    // Ill-conditioned SPD, eigenvalues 2 and 1e-6, both unknowns positive
    // at the solution: PGS contracts by about (1 - 1e-6)^2 per sweep.
    let m = DMatrix::from_row_slice(2, 2, &[1.0, 0.999999, 0.999999, 1.0]);
    let lcp = Lcp::new(m, DVector::from_row_slice(&[-1.0, -1.0])).unwrap();
    let status = pgs::solve(
        &lcp,
        &PgsSettings {
            max_sweeps: 50,
            ..PgsSettings::default()
        },
    )
    .unwrap_err();
    let PgsStatus::MaxSweeps { residual } = status else {
        panic!("{status:?}")
    };
    assert!(residual > 1e-9 && residual.is_finite());
}

#[test]
fn non_positive_diagonal_is_refused() {
    let lcp = Lcp::new(
        DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, -1.0]),
        DVector::from_row_slice(&[-1.0, -1.0]),
    )
    .unwrap();
    assert_eq!(
        pgs::solve(&lcp, &PgsSettings::default()).unwrap_err(),
        PgsStatus::NonPositiveDiagonal { row: 1 }
    );
}
