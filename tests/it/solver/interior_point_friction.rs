//! The interior point on friction pyramids (issue 21's frictional calls):
//! the pyramids of random pushed columns, small (dense `H`) and large
//! (sparse `H`), against clarabel and Lemke; the packed rows against the
//! general path; `Auto` with the interior point from a row count; and the
//! typed outcomes of infeasible and degenerate rows.
//!
//! The oracles are other solvers (clarabel at tight tolerances, Lemke's
//! exact pivoting) and the KKT conditions of the answer, never the
//! interior point's own residuals.

use super::friction_cone::{pushed_column, pushed_into_the_ground};
use crate::support::solver_oracle::{assert_kkt, relative_metric_distance};
use constraint_stabilization::settings::DEFAULT_FRICTION_MAX_CORRECTION;
use constraint_stabilization::solver::clarabel_qp::ClarabelFailure;
use constraint_stabilization::solver::interior_point::InteriorPointFailure;
use constraint_stabilization::solver::{
    FailureReason, ProjectionQp, ProjectionSolution, SolverChoice, SolverError, SolverKind,
    SolverSettings, solve_projection,
};
use constraint_stabilization::{Error, Settings, SettingsError, Stabilizer};

/// Agreement in `dq` (relative, M-norm) of the interior point with Lemke
/// and with clarabel at gap and feasibility tolerances 1e-12: each is
/// certified to far below this (the interior point's duality gap to 1e-12
/// of the energy), so a larger distance is a wrong answer.
const DQ_AGREEMENT_TOL: f64 = 1e-6;

/// Agreement of the packed rows with the general path: the same iteration
/// on the same matrices up to the order of the sums.
const PACKED_AGREEMENT_TOL: f64 = 1e-9;

/// The pyramid (four facets per cone, linear rows only) of a pushed
/// column of `boxes` boxes.
fn pyramid(boxes: usize, seed: u64) -> ProjectionQp {
    pushed_column(boxes, seed).pyramid().0
}

fn solve_with(qp: &ProjectionQp, settings: &SolverSettings) -> ProjectionSolution {
    solve_projection(qp, settings).unwrap_or_else(|e| panic!("{:?}: {e}", settings.choice))
}

/// `choice` alone, no fallback (also the dual active-set tests').
pub(super) fn named(choice: SolverChoice) -> SolverSettings {
    SolverSettings {
        choice,
        fall_back: false,
        ..SolverSettings::default()
    }
}

/// clarabel at gap and feasibility tolerances 1e-12, the chain after it.
pub(super) fn tight_clarabel() -> SolverSettings {
    let mut settings = named(SolverChoice::Clarabel);
    settings.clarabel.tol_gap = 1e-12;
    settings.clarabel.tol_feas = 1e-12;
    settings.fall_back = true;
    settings
}

/// Pyramids of 2 to 40 boxes (about 34 to 680 rows; `H` dense up to 16
/// boxes, sparse above), three seeds each: the interior point, followed by
/// the fallback chain, answers each; its answer passes the KKT oracle and
/// agrees with clarabel and (up to [`LEMKE_MAX_BOXES`]) Lemke (the interior point's answer passes the
/// KKT oracle too; clarabel's default answer is certified to 1e-6 only).
/// The interior point answers itself all but at most [`IP_MAY_FAIL`] of
/// them: on the pushed columns of 40 boxes, seeds 1 and 2, its iterates
/// stall at the boundary for about 40 iterations (steps of 1e-3 to 1e-2)
/// and the iteration limit stops it; clarabel then answers.
#[test]
fn agrees_with_clarabel_and_lemke_on_friction_pyramids() {
    let mut answered_by_ip = 0;
    let mut problems = 0;
    let ip_then_the_chain = SolverSettings {
        choice: SolverChoice::InteriorPoint,
        ..SolverSettings::default()
    };
    for boxes in [2, 6, 16, 40] {
        for seed in 0..3 {
            let qp = pyramid(boxes, seed);
            let context = format!("{boxes} boxes, seed {seed}, {} rows", qp.num_rows());
            let ip = solve_with(&qp, &ip_then_the_chain);
            problems += 1;
            answered_by_ip += usize::from(ip.solver == SolverKind::InteriorPoint);
            if ip.solver == SolverKind::InteriorPoint {
                assert_kkt(&qp, &ip.dq, &ip.lambda, &context);
            }
            let mut references = vec![("clarabel", solve_with(&qp, &tight_clarabel()))];
            if boxes <= LEMKE_MAX_BOXES {
                references.push(("Lemke", solve_with(&qp, &named(SolverChoice::Lemke))));
            }
            for (name, other) in &references {
                let distance = relative_metric_distance(&qp, &ip.dq, &other.dq);
                assert!(
                    distance <= DQ_AGREEMENT_TOL,
                    "{context}: {distance:e} from {name}"
                );
            }
        }
    }
    assert!(
        answered_by_ip + IP_MAY_FAIL >= problems,
        "the interior point answered {answered_by_ip} of {problems}"
    );
}

/// Lemke is a reference up to this many boxes (272 rows); on the 680 rows
/// of 40 boxes its tableau's rounding leaves residuals of 1e-6.
const LEMKE_MAX_BOXES: usize = 16;

/// Pyramids of [`agrees_with_clarabel_and_lemke_on_friction_pyramids`]
/// the interior point may leave to its fallback (measured: two of twelve).
const IP_MAY_FAIL: usize = 2;

/// The packed rows and the general per-row path take the same iterations
/// to the same answer, dense and sparse.
#[test]
fn packed_rows_agree_with_the_general_path() {
    for boxes in [3, 30] {
        let qp = pyramid(boxes, 5);
        let packed = solve_with(&qp, &named(SolverChoice::InteriorPoint));
        let mut settings = named(SolverChoice::InteriorPoint);
        settings.interior_point.packed_rows = false;
        let general = solve_with(&qp, &settings);
        assert_eq!(packed.iterations, general.iterations, "{boxes} boxes");
        let distance = relative_metric_distance(&qp, &packed.dq, &general.dq);
        assert!(
            distance <= PACKED_AGREEMENT_TOL,
            "{boxes} boxes: {distance:e}"
        );
    }
}

/// Under `Auto` with the interior point from `N` rows (and the dual
/// active-set method off), a pyramid of at least `N` rows goes to it and a
/// smaller one to Lemke, and both answers
/// agree with Lemke's.
#[test]
fn auto_takes_the_interior_point_from_its_row_count() {
    let settings = SolverSettings {
        auto_interior_point_min_rows: 41,
        auto_dual_active_set_max_dofs: 0,
        auto_dual_active_set_violated_max_dofs: 0,
        ..SolverSettings::default()
    };
    for (boxes, expected) in [(2, SolverKind::Lemke), (6, SolverKind::InteriorPoint)] {
        let qp = pyramid(boxes, 9);
        let solution = solve_with(&qp, &settings);
        assert_eq!(solution.solver, expected, "{} rows", qp.num_rows());
        let lemke = solve_with(&qp, &named(SolverChoice::Lemke));
        let distance = relative_metric_distance(&qp, &solution.dq, &lemke.dq);
        assert!(distance <= DQ_AGREEMENT_TOL, "{boxes} boxes: {distance:e}");
    }
}

/// A body wedged by a push that misses its cone's pyramid has no answer:
/// the interior point certifies the infeasibility itself (its Farkas
/// certificate), the chain stops there, and clarabel, asked on its own,
/// certifies it too.
#[test]
fn a_wedged_pyramid_fails_typed_and_clarabel_certifies() {
    let qp = pushed_into_the_ground(2.0, 1.0, 0.3, 1e-3).pyramid().0;
    let settings = SolverSettings {
        choice: SolverChoice::InteriorPoint,
        stop_on_infeasible: true,
        ..SolverSettings::default()
    };
    let Err(SolverError::AllSolversFailed(fallbacks)) = solve_projection(&qp, &settings) else {
        panic!("a wedged body was solved");
    };
    assert_eq!(
        fallbacks[0].reason,
        FailureReason::InteriorPoint(InteriorPointFailure::Infeasible)
    );
    assert_eq!(fallbacks.len(), 1, "the chain went on after a certificate");
    let Err(SolverError::AllSolversFailed(clarabel)) =
        solve_projection(&qp, &named(SolverChoice::Clarabel))
    else {
        panic!("clarabel solved a wedged body");
    };
    assert_eq!(
        clarabel[0].reason,
        FailureReason::Clarabel(ClarabelFailure::PrimalInfeasible)
    );
}

/// Every facet listed twice (the multipliers split anyhow between the
/// copies: the rows are degenerate) leaves `dq` as with each row once.
#[test]
fn duplicated_facets_leave_dq_unchanged() {
    for boxes in [4, 24] {
        let qp = pyramid(boxes, 2);
        let mut doubled = qp.clone();
        doubled.rows.extend(qp.rows.iter().cloned());
        doubled.phi.extend(qp.phi.iter().copied());
        doubled.target.extend(qp.target.iter().copied());
        let once = solve_with(&qp, &tight_clarabel());
        let twice = solve_with(&doubled, &named(SolverChoice::InteriorPoint));
        assert_eq!(twice.solver, SolverKind::InteriorPoint);
        let distance = relative_metric_distance(&qp, &once.dq, &twice.dq);
        assert!(distance <= DQ_AGREEMENT_TOL, "{boxes} boxes: {distance:e}");
    }
}

/// The stabilizer's radius for friction
/// (`Settings::friction_max_correction`, 1e4 `l`) gives up no feasible
/// pyramid: on every pushed column the interior point at that radius,
/// stopping on certificates as the stabilizer does, either answers (as
/// clarabel does) or leaves the problem to the chain for another reason
/// than infeasibility; the wedged body still stops at the certificate.
#[test]
fn the_friction_radius_gives_up_no_feasible_pyramid() {
    let mut settings = SolverSettings {
        choice: SolverChoice::InteriorPoint,
        stop_on_infeasible: true,
        ..SolverSettings::default()
    };
    settings.interior_point.infeasible_radius = DEFAULT_FRICTION_MAX_CORRECTION;
    for boxes in [2, 6, 16, 40] {
        for seed in 0..3 {
            let qp = pyramid(boxes, seed);
            let context = format!("{boxes} boxes, seed {seed}");
            let answer = solve_projection(&qp, &settings)
                .unwrap_or_else(|e| panic!("{context}: given up: {e}"));
            assert!(
                answer
                    .fallbacks
                    .iter()
                    .all(|f| !f.reason.certifies_infeasibility()),
                "{context}: {:?}",
                answer.fallbacks
            );
            let reference = solve_with(&qp, &tight_clarabel());
            let distance = relative_metric_distance(&qp, &answer.dq, &reference.dq);
            assert!(distance <= DQ_AGREEMENT_TOL, "{context}: {distance:e}");
        }
    }
    let wedged = pushed_into_the_ground(2.0, 1.0, 0.3, 1e-3).pyramid().0;
    let Err(SolverError::AllSolversFailed(fallbacks)) = solve_projection(&wedged, &settings) else {
        panic!("a wedged body was solved");
    };
    assert_eq!(
        fallbacks[0].reason,
        FailureReason::InteriorPoint(InteriorPointFailure::Infeasible)
    );
}

/// Both radii are checked where the settings enter: zero, negative, NaN
/// or infinite is a typed error naming the field, never a solver that
/// stops at once or never.
#[test]
fn the_radii_must_be_finite_and_positive() {
    for value in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let mut friction = Settings::default();
        friction.friction_max_correction = value;
        let mut interior_point = Settings::default();
        interior_point.solver.interior_point.infeasible_radius = value;
        for (settings, field) in [
            (friction, "friction_max_correction"),
            (interior_point, "solver.interior_point.infeasible_radius"),
        ] {
            match Stabilizer::new(settings) {
                Err(Error::Settings(SettingsError::OutOfRange { field: f, .. })) => {
                    assert_eq!(f, field, "{value}")
                }
                other => panic!("{field} = {value}: {:?}", other.err()),
            }
        }
    }
}
