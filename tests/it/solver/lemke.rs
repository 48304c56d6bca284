//! Lemke's method on small cases and against brute-force enumeration of
//! complementary bases. Every `z` is judged by `w = M z + q`, `z >= 0`,
//! `w >= 0`, `z . w = 0` recomputed here from `M` and `q`
//! (`crate::support::solver_oracle`), never by the solver's own residual.

use crate::support::proptest_config;
use crate::support::solver_oracle::{LCP_TOL, assert_lcp_solved, lcp_residuals};
use constraint_stabilization::solver::Lcp;
use constraint_stabilization::solver::lemke::{self, LemkeSettings, LemkeStatus};
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;

/// Residual allowed on the small hand-made problems (entries of order one,
/// a few pivots): a few roundings.
const SMALL_PROBLEM_TOL: f64 = 1e-14;
/// The enumeration keeps a basis whose system is solved to this, and whose
/// `z`, `w` are nonnegative to this; Lemke's `z` must match it as closely
/// (entries of order one: `M` has eigenvalues >= 0.1, `|q| <= 1`).
const ENUMERATION_TOL: f64 = 1e-9;
/// Agreement of Lemke's `w` with the enumerated one on singular problems,
/// where `z` is not unique (only `w` is): `M z` recomputed from two
/// different `z`, each to `ENUMERATION_TOL`.
const W_AGREEMENT_TOL: f64 = 1e-8;

fn lcp(n: usize, m: &[f64], q: &[f64]) -> Lcp {
    Lcp::new(DMatrix::from_row_slice(n, n, m), DVector::from_row_slice(q)).unwrap()
}

#[test]
fn one_by_one() {
    let sol = lemke::solve(&lcp(1, &[2.0], &[-3.0]), &LemkeSettings::default()).unwrap();
    assert!((sol.z[0] - 1.5).abs() < SMALL_PROBLEM_TOL);
    // z0 enters (w leaves), then z enters (z0 leaves).
    assert_eq!(sol.pivots, 2);
    // M = 0, q < 0: z0 can never leave; no solution.
    let failure = lemke::solve(&lcp(1, &[0.0], &[-1.0]), &LemkeSettings::default()).unwrap_err();
    assert_eq!(failure.status, LemkeStatus::Ray);
}

#[test]
fn nonnegative_q_is_solved_without_pivots() {
    let sol = lemke::solve(
        &lcp(2, &[1.0, -5.0, 3.0, 0.0], &[0.0, 2.0]),
        &LemkeSettings::default(),
    )
    .unwrap();
    assert_eq!(sol.pivots, 0);
    assert_eq!(sol.z.as_slice(), &[0.0, 0.0]);
}

/// `q` with zeros next to negative entries: the first ratio test ties on
/// the degenerate rows; the lexicographic rule must still terminate with a
/// solution (z = (0, 1, 0): the zero rows stay at zero).
#[test]
fn degenerate_start_with_zero_entries_in_q() {
    let m = [2.0, 1.0, 0.0, 1.0, 2.0, 1.0, 0.0, 1.0, 2.0];
    let m_dense = DMatrix::from_row_slice(3, 3, &m);
    let q = DVector::from_row_slice(&[0.0, -2.0, 0.0]);
    let sol = lemke::solve(&lcp(3, &m, q.as_slice()), &LemkeSettings::default()).unwrap();
    assert_lcp_solved(&m_dense, &q, &sol.z, SMALL_PROBLEM_TOL, "zeros in q");
    assert!((&sol.z - DVector::from_row_slice(&[0.0, 1.0, 0.0])).amax() < SMALL_PROBLEM_TOL);
    // Several equal negative entries: a tie in the first step.
    let q = DVector::from_row_slice(&[-1.0, -1.0, -1.0]);
    let sol = lemke::solve(&lcp(3, &m, q.as_slice()), &LemkeSettings::default()).unwrap();
    assert_lcp_solved(&m_dense, &q, &sol.z, SMALL_PROBLEM_TOL, "tie");
}

/// Refactorizing the tableau from the data every pivot follows the same
/// path (same pivots) and reaches the same solution as the O(n^2) updates.
#[test]
fn refactorizing_every_pivot_changes_nothing_on_a_well_posed_problem() {
    let lcp = lcp(
        3,
        &[4.0, 1.0, 0.0, 1.0, 3.0, 1.0, 0.0, 1.0, 2.0],
        &[-1.0, -2.0, -1.0],
    );
    let a = lemke::solve(&lcp, &LemkeSettings::default()).unwrap();
    let b = lemke::solve(
        &lcp,
        &LemkeSettings {
            refactor_every: 1,
            ..LemkeSettings::default()
        },
    )
    .unwrap();
    assert_eq!(a.pivots, b.pivots);
    assert_lcp_solved(lcp.m(), lcp.q(), &a.z, SMALL_PROBLEM_TOL, "updated tableau");
    assert_lcp_solved(
        lcp.m(),
        lcp.q(),
        &b.z,
        SMALL_PROBLEM_TOL,
        "refactorized tableau",
    );
    assert!((a.z - b.z).amax() < SMALL_PROBLEM_TOL);
}

/// All solutions of a small LCP by enumerating the `2^n` complementary
/// bases: `z_S = -M_SS^-1 q_S`, `z = 0` elsewhere, kept when `z >= 0` and
/// `w >= 0` (to a tolerance). A basis whose system is not solved to the
/// tolerance, or whose solution is so large that the rounding of `M z`
/// exceeds it (`M_SS` singular: LU returns garbage of size 1/u), is skipped.
fn enumerate(m: &DMatrix<f64>, q: &DVector<f64>) -> Vec<DVector<f64>> {
    let n = q.len();
    let mut solutions = Vec::new();
    for mask in 0u32..(1 << n) {
        let s: Vec<usize> = (0..n).filter(|i| mask & (1 << i) != 0).collect();
        if s.is_empty() {
            if q.iter().all(|&x| x >= 0.0) {
                solutions.push(DVector::zeros(n));
            }
            continue;
        }
        let m_ss = DMatrix::from_fn(s.len(), s.len(), |a, b| m[(s[a], s[b])]);
        let q_s = DVector::from_fn(s.len(), |a, _| -q[s[a]]);
        let Some(z_s) = m_ss.clone().lu().solve(&q_s) else {
            continue;
        };
        // Rounding in M_SS z_S, of size u |M_SS| |z_S|, must stay below the
        // tolerance too, or a lucky cancellation certifies garbage.
        let rounding = (m_ss.abs() * z_s.abs()).amax() * f64::EPSILON * n as f64;
        if (&m_ss * &z_s - &q_s).amax() > ENUMERATION_TOL || rounding > ENUMERATION_TOL {
            continue;
        }
        let mut z = DVector::zeros(n);
        for (a, &i) in s.iter().enumerate() {
            z[i] = z_s[a];
        }
        let w = m * &z + q;
        if z.iter().chain(w.iter()).all(|&x| x >= -ENUMERATION_TOL) {
            solutions.push(z);
        }
    }
    solutions
}

/// Random positive definite `M = B B^T + K + c I` (`K` skew) has a unique
/// solution: Lemke's must be it.
fn pd_lcp() -> impl Strategy<Value = (DMatrix<f64>, DVector<f64>)> {
    (2usize..=6).prop_flat_map(|n| {
        (
            prop::collection::vec(-1.0..1.0f64, n * n),
            prop::collection::vec(-1.0..1.0f64, n * n),
            prop::collection::vec(-1.0..1.0f64, n),
        )
            .prop_map(move |(b, k, q)| {
                let b = DMatrix::from_row_slice(n, n, &b);
                let k = DMatrix::from_row_slice(n, n, &k);
                let m = &b * b.transpose() + (&k - k.transpose()) + DMatrix::identity(n, n) * 0.1;
                (m, DVector::from_vec(q))
            })
    })
}

proptest! {
    #![proptest_config(proptest_config::config(200))]
    #[test]
    fn lemke_matches_enumeration((m, q) in pd_lcp()) {
        let solutions = enumerate(&m, &q);
        prop_assert_eq!(solutions.len(), 1);
        let lcp = Lcp::new(m.clone(), q.clone()).unwrap();
        let sol = lemke::solve(&lcp, &LemkeSettings::default()).unwrap();
        prop_assert!((&sol.z - &solutions[0]).amax() < ENUMERATION_TOL, "lemke {} enum {}", sol.z, solutions[0]);
        let r = lcp_residuals(&m, &q, &sol.z);
        prop_assert!(r.worst() <= LCP_TOL, "{:?}", r);
    }
}

#[test]
fn empty_problem() {
    let lcp = Lcp::new(DMatrix::zeros(0, 0), DVector::zeros(0)).unwrap();
    let sol = lemke::solve(&lcp, &LemkeSettings::default()).unwrap();
    assert_eq!(sol.z.len(), 0);
    assert_eq!(sol.pivots, 0);
}

/// Symmetric PSD and singular: `M = B B^T` with `B` of rank `r < n`. A
/// solution exists or not (enumeration decides); when it does, `w` is the
/// same for every solution (the gradient of a convex QP is constant on its
/// solution set), so Lemke's `w` must equal the enumerated one.
fn singular_psd_lcp() -> impl Strategy<Value = (DMatrix<f64>, DVector<f64>)> {
    (2usize..=6, 1usize..=3).prop_flat_map(|(n, r)| {
        (
            prop::collection::vec(-1.0..1.0f64, n * r),
            prop::collection::vec(-1.0..1.0f64, n),
        )
            .prop_map(move |(b, q)| {
                let b = DMatrix::from_row_slice(n, r, &b);
                (&b * b.transpose(), DVector::from_vec(q))
            })
    })
}

proptest! {
    #![proptest_config(proptest_config::config(200))]
    #[test]
    fn lemke_on_singular_psd_matches_enumeration((m, q) in singular_psd_lcp()) {
        let solutions = enumerate(&m, &q);
        let lcp = Lcp::new(m.clone(), q.clone()).unwrap();
        match lemke::solve(&lcp, &LemkeSettings::default()) {
            Ok(sol) => {
                prop_assert!(!solutions.is_empty(), "lemke found {} where enumeration found none", sol.z);
                let r = lcp_residuals(&m, &q, &sol.z);
                prop_assert!(r.worst() <= LCP_TOL, "{:?}", r);
                let w = &m * &sol.z + &q;
                let w_enum = &m * &solutions[0] + &q;
                prop_assert!((&w - &w_enum).amax() < W_AGREEMENT_TOL, "w {} vs {}", w, w_enum);
            }
            Err(f) => {
                prop_assert!(solutions.is_empty(), "lemke {:?} but enumeration found {}", f.status, solutions[0]);
                prop_assert_eq!(f.status, LemkeStatus::Ray);
            }
        }
    }
}

/// Regression: `M = b b^T` (rank one), `q = (0, -0.685)` has no solution
/// (`w_1 = b_1 t >= 0` needs `t = b.z >= 0`, `w_2 = b_2 t + q_2 >= 0` needs
/// `t <= -0.85`). The plain run ends on a ray; the run on `M + 1e-10 I`
/// "solves" it with `z ~ 1e15`, whose computed `w` looked complementary in
/// the scaled problem by cancellation. The check now includes the rounding
/// of `w`, so every retry is rejected.
#[test]
fn regularized_retry_never_returns_a_huge_z() {
    let m = DMatrix::from_column_slice(
        2,
        2,
        &[
            0.27013412104566353,
            -0.4179152553767884,
            -0.4179152553767884,
            0.6465423916111764,
        ],
    );
    let q = DVector::from_column_slice(&[0.0, -0.6849893387354267]);
    let failure = lemke::solve(&Lcp::new(m, q).unwrap(), &LemkeSettings::default()).unwrap_err();
    assert_eq!(failure.status, LemkeStatus::Ray);
    assert!(failure.attempts.iter().all(|a| a.failure.is_some()));
}

/// The LCP oracle can fail: a solution passes; a negative `z`, a negative
/// `w` and a complementary pair both positive are each caught.
#[test]
fn lcp_oracle_rejects_wrong_answers() {
    let m = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
    let q = DVector::from_row_slice(&[-3.0, 1.0]);
    // w = (0, 2.5) at z = (1.5, 0).
    let check = |z: &[f64]| lcp_residuals(&m, &q, &DVector::from_row_slice(z));
    assert!(check(&[1.5, 0.0]).worst() <= SMALL_PROBLEM_TOL);
    assert!(check(&[1.5, -0.1]).infeasibility > LCP_TOL);
    assert!(check(&[1.4, 0.0]).infeasibility > LCP_TOL);
    assert!(check(&[1.5, 0.1]).complementarity > LCP_TOL);
}
