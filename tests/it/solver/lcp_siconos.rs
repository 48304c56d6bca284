//! Lemke, PGS and clarabel (dual QP form) on the Siconos LCP test problems
//! of `tests/data/siconos` (copied there from the Siconos test suite). The
//! oracle is the README of that folder: which problems are PSD, and their
//! solutions (found there by enumerating complementary bases). Residuals
//! are recomputed here from the file's `M` and `q`, independently of the
//! library's residual code.

use crate::support::siconos::{self, known_solution};
use crate::support::solver_oracle::{LCP_TOL as TOL, lcp_residuals};
use constraint_stabilization::io::read_lcp_file;
use constraint_stabilization::solver::FailureReason;
use constraint_stabilization::solver::Lcp;
use constraint_stabilization::solver::clarabel_qp::{ClarabelSettings, dual};
use constraint_stabilization::solver::lemke::{self, LemkeSettings, LemkeStatus};
use constraint_stabilization::solver::pgs::{self, PgsSettings, PgsStatus};
use nalgebra::{DMatrix, DVector};

fn load(name: &str) -> Lcp {
    read_lcp_file(siconos::path(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The README's natural map, `z >= 0`, `w >= 0` and `z . w`, all from the
/// file's `M` and `q` (the worst, relative to `max(1, ||q||_inf)`).
fn residual(lcp: &Lcp, z: &DVector<f64>) -> f64 {
    lcp_residuals(lcp.m(), lcp.q(), z).worst()
}

fn lemke_solve(name: &str) -> lemke::LemkeSolution {
    let lcp = load(name);
    let sol =
        lemke::solve(&lcp, &LemkeSettings::default()).unwrap_or_else(|f| panic!("{name}: {f:?}"));
    let r = residual(&lcp, &sol.z);
    assert!(r <= TOL, "{name}: residual {r:e}");
    assert!(sol.z.iter().all(|&x| x >= 0.0), "{name}: z = {}", sol.z);
    sol
}

fn assert_close(name: &str, z: &DVector<f64>, expected: &[f64]) {
    siconos::assert_close(name, z.as_slice(), expected, TOL);
}

#[test]
fn cps_2_reads_column_major() {
    let lcp = load("lcp_CPS_2.dat");
    let m = DMatrix::from_row_slice(3, 3, &[0.0, -1.0, 2.0, 2.0, 0.0, -2.0, -1.0, 1.0, 0.0]);
    assert_eq!(lcp.m(), &m);
    assert_eq!(lcp.q().as_slice(), &[-3.0, 6.0, -1.0]);
}

/// Every PSD problem of the README with a known unique solution.
#[test]
fn lemke_solves_psd_problems_with_known_solutions() {
    let known = [
        "lcp_CPS_4.dat",
        "lcp_CPS_4bis.dat",
        "lcp_CPS_5.dat",
        "lcp_deudeu.dat",
        "lcp_exp_murty.dat",
        "lcp_exp_murty2.dat",
        "lcp_inf_sol_perturbed.dat",
        "lcp_ortiz.dat",
        "lcp_trivial.dat",
    ];
    for name in known {
        assert!(load(name).is_psd(), "{name} is PSD per the README");
        let sol = lemke_solve(name);
        let expected = known_solution(name).expect("listed in the README");
        assert_close(name, &sol.z, &expected);
        assert_eq!(sol.regularization, None, "{name}");
    }
}

/// PSD problems whose solution is not unique or not listed: any `z` with a
/// small residual is right.
#[test]
fn lemke_solves_psd_problems_without_unique_solution() {
    for name in ["lcp_CPS_1.dat", "lcp_mmc.dat"] {
        assert!(load(name).is_psd(), "{name}");
        lemke_solve(name);
    }
    let z = lemke_solve("lcp_CPS_1.dat").z;
    assert!(
        (z[0] + z[1] - 1.0).abs() <= TOL,
        "CPS_1: z on the segment z1 + z2 = 1, got {z}"
    );
}

#[test]
fn non_psd_problems_match_the_readme() {
    assert!(!load("lcp_CPS_2.dat").is_psd());
    assert_close("CPS_2", &lemke_solve("lcp_CPS_2.dat").z, &[0.0, 1.0, 3.0]);
    assert_close(
        "Pang",
        &lemke_solve("lcp_Pang_isolated_sol.dat").z,
        &[1.0, 0.0, 0.0],
    );
}

#[test]
fn pang_perturbed_reports_no_solution() {
    let lcp = load("lcp_Pang_isolated_sol_perturbed.dat");
    let failure = lemke::solve(&lcp, &LemkeSettings::default()).expect_err("no solution exists");
    assert_eq!(failure.status, LemkeStatus::Ray);
    // The regularized retries were tried, and none passed the check.
    assert_eq!(
        failure.attempts.len(),
        1 + LemkeSettings::default().regularization_ladder.len()
    );
    assert!(failure.attempts.iter().all(|a| a.failure.is_some()));
}

/// CPS_3 is a bimatrix game: `M >= 0` with a zero diagonal and `q < 0`.
/// After the first pivot (z0 enters, some `w_r` leaves) `z_r` enters with
/// column `-M[:, r] <= 0`: a ray for *any* covering vector. Lemke's method
/// is not guaranteed on non-copositive-plus matrices; it must say so rather
/// than return a wrong `z` (Lemke-Howson would solve it).
#[test]
fn bimatrix_game_ends_on_a_ray() {
    let lcp = load("lcp_CPS_3.dat");
    assert!(!lcp.is_psd());
    let failure = lemke::solve(&lcp, &LemkeSettings::default()).expect_err("documented ray");
    assert_eq!(failure.status, LemkeStatus::Ray);
    assert_eq!(failure.attempts[0].pivots, 1);
}

/// Murty's problem makes Lemke's method take `2^n` pivots (Murty 1978):
/// with n = 6, 64 for exp_murty2, far below the pivot limit.
#[test]
fn murty_exponential_problems_within_pivot_limit() {
    let settings = LemkeSettings::default();
    for name in ["lcp_exp_murty.dat", "lcp_exp_murty2.dat"] {
        let sol = lemke_solve(name);
        let limit = settings
            .pivot_limit_min
            .max(settings.pivot_limit_per_row * 6);
        assert!(sol.pivots < limit, "{name}: {} pivots", sol.pivots);
    }
    assert_eq!(lemke_solve("lcp_exp_murty2.dat").pivots, 64);
}

/// Not PSD, so Lemke's method is not guaranteed: recorded here, both are
/// solved (enum_fails in 8 pivots, tobenna, n = 40, in 127) to a residual
/// checked against the file's data. A change of pivoting rule that loses
/// either shows up here.
#[test]
fn enum_fails_and_tobenna_are_solved_by_lemke() {
    for (name, pivots) in [("lcp_enum_fails.dat", 8), ("lcp_tobenna.dat", 127)] {
        let lcp = load(name);
        assert!(!lcp.is_psd(), "{name}");
        let sol = lemke_solve(name);
        assert_eq!(sol.pivots, pivots, "{name}");
        assert_eq!(sol.regularization, None, "{name}");
    }
}

#[test]
fn clarabel_dual_solves_the_symmetric_psd_problems() {
    for name in [
        "lcp_CPS_1.dat",
        "lcp_CPS_5.dat",
        "lcp_deudeu.dat",
        "lcp_mmc.dat",
        "lcp_trivial.dat",
    ] {
        let lcp = load(name);
        let sol = dual::solve_lcp(&lcp, &ClarabelSettings::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let r = residual(&lcp, &sol.z);
        assert!(r <= TOL, "{name}: residual {r:e}");
    }
    let deudeu = dual::solve_lcp(&load("lcp_deudeu.dat"), &ClarabelSettings::default()).unwrap();
    assert_close("deudeu", &deudeu.z, &[4.0 / 3.0, 7.0 / 3.0]);
}

#[test]
fn clarabel_dual_refuses_nonsymmetric_problems() {
    for name in ["lcp_CPS_2.dat", "lcp_exp_murty.dat", "lcp_ortiz.dat"] {
        let err = dual::solve_lcp(&load(name), &ClarabelSettings::default()).unwrap_err();
        assert_eq!(err, FailureReason::NotApplicable, "{name}");
    }
}

#[test]
fn pgs_on_the_positive_definite_problems() {
    for name in ["lcp_deudeu.dat", "lcp_mmc.dat", "lcp_trivial.dat"] {
        let lcp = load(name);
        let sol =
            pgs::solve(&lcp, &PgsSettings::default()).unwrap_or_else(|e| panic!("{name}: {e:?}"));
        assert!(residual(&lcp, &sol.z) <= TOL, "{name}");
    }
    // mmc needs hundreds of sweeps: a cap of 10 is reported, not hidden.
    let capped = PgsSettings {
        max_sweeps: 10,
        ..PgsSettings::default()
    };
    match pgs::solve(&load("lcp_mmc.dat"), &capped) {
        Err(PgsStatus::MaxSweeps { residual }) => assert!(residual > TOL),
        other => panic!("expected MaxSweeps, got {other:?}"),
    }
    // A zero diagonal cannot be divided by.
    assert_eq!(
        pgs::solve(&load("lcp_CPS_2.dat"), &PgsSettings::default()).unwrap_err(),
        PgsStatus::NonPositiveDiagonal { row: 0 }
    );
}
