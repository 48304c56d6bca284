//! The dual active-set method (`src/solver/dual_active_set.rs`) against
//! oracles it does not share code with: the brute-force active-set
//! enumeration (nalgebra's LU on every subset of rows), clarabel at tight
//! tolerances and Lemke's pivoting, on random problems with independent,
//! redundant (random box stacks, four corners per face), duplicated and
//! infeasible rows, and friction pyramids; `Auto`'s choice of it by size;
//! and its typed outcomes.

use super::active_set_oracle::brute_force_dq;
use super::equality_rows::random_mixed;
use super::friction_cone::{pushed_column, pushed_into_the_ground};
use super::interior_point_friction::{named, tight_clarabel};
use crate::support::solver_oracle::{assert_kkt, relative_metric_distance};
use constraint_stabilization::solver::dual_active_set::{DualActiveSetFailure, MAX_DOFS};
use constraint_stabilization::solver::interior_point::InteriorPointFailure;
use constraint_stabilization::solver::{
    FailureReason, ProjectionQp, ProjectionSolution, SolverChoice, SolverError, SolverKind,
    SolverSettings, solve_projection,
};
use dev_support::solver::{StackSpec, random_stacks};

/// Agreement in `dq` (relative, `M`-norm) with the oracles: each answer is
/// certified far below it (the method is exact up to rounding, clarabel
/// runs at 1e-12), so a larger distance is a wrong answer.
const DQ_AGREEMENT_TOL: f64 = 1e-6;

fn solve_with(qp: &ProjectionQp, settings: &SolverSettings, context: &str) -> ProjectionSolution {
    solve_projection(qp, settings)
        .unwrap_or_else(|e| panic!("{context} {:?}: {e}", settings.choice))
}

/// The method's own answer (no fallback), checked by the KKT oracle.
fn dual_active_set(qp: &ProjectionQp, context: &str) -> ProjectionSolution {
    let solution = solve_with(qp, &named(SolverChoice::DualActiveSet), context);
    assert_eq!(solution.solver, SolverKind::DualActiveSet, "{context}");
    assert_kkt(qp, &solution.dq, &solution.lambda, context);
    solution
}

fn assert_close(qp: &ProjectionQp, a: &ProjectionSolution, b: &ProjectionSolution, context: &str) {
    let distance = relative_metric_distance(qp, &a.dq, &b.dq);
    assert!(distance <= DQ_AGREEMENT_TOL, "{context}: {distance:e}");
}

/// The method's answer agrees with clarabel's (tight) and Lemke's.
fn agrees_with_clarabel_and_lemke(qp: &ProjectionQp, context: &str) {
    let solution = dual_active_set(qp, context);
    for (name, settings) in [
        ("clarabel", tight_clarabel()),
        ("Lemke", named(SolverChoice::Lemke)),
    ] {
        let other = solve_with(qp, &settings, context);
        assert_close(qp, &solution, &other, &format!("{context}, {name}"));
    }
}

/// Independent random rows over two bodies (some violated, some open):
/// the answer is the brute-force enumeration's.
#[test]
fn matches_the_active_set_enumeration_on_independent_rows() {
    for inequalities in [2, 5, 8] {
        for seed in 0..20 {
            let qp = random_mixed(seed, 0, inequalities);
            let context = format!("{inequalities} rows, seed {seed}");
            let oracle = brute_force_dq(&qp).unwrap_or_else(|| panic!("{context}: no oracle"));
            let solution = dual_active_set(&qp, &context);
            let distance = relative_metric_distance(&qp, &solution.dq, &oracle);
            assert!(distance <= DQ_AGREEMENT_TOL, "{context}: {distance:e}");
        }
    }
}

/// Random box stacks with a corner row per contact corner (four per face:
/// redundant rows, a singular Delassus matrix), masses spread over up to
/// six decades: the answer is clarabel's (tight) and Lemke's.
#[test]
fn agrees_with_clarabel_and_lemke_on_redundant_stacks() {
    for rows in [8, 40, 120] {
        for mass_decades in [0.0, 3.0, 6.0] {
            for seed in 0..3 {
                let qp = random_stacks(&StackSpec {
                    rows,
                    length_scale: 1.0,
                    mass_scale: 1.0,
                    mass_decades,
                    seed,
                });
                let context = format!("{rows} rows, {mass_decades} decades, seed {seed}");
                agrees_with_clarabel_and_lemke(&qp, &context);
            }
        }
    }
}

/// Friction pyramids of pushed columns (four facets per contact, the
/// contact row implied by them: every sticking contact degenerate) agree
/// with clarabel and Lemke.
#[test]
fn agrees_with_clarabel_and_lemke_on_friction_pyramids() {
    for boxes in [2, 6, 16] {
        for seed in 0..3 {
            let qp = pushed_column(boxes, seed).pyramid().0;
            let context = format!("{boxes} boxes, seed {seed}, {} rows", qp.num_rows());
            agrees_with_clarabel_and_lemke(&qp, &context);
        }
    }
}

/// Every row listed twice (exactly dependent rows) leaves `dq` as with
/// each row once.
#[test]
fn duplicated_rows_leave_dq_unchanged() {
    for boxes in [3, 10] {
        let qp = pushed_column(boxes, 4).pyramid().0;
        let mut doubled = qp.clone();
        doubled.rows.extend(qp.rows.iter().cloned());
        doubled.phi.extend(qp.phi.iter().copied());
        doubled.target.extend(qp.target.iter().copied());
        let context = format!("{boxes} boxes doubled");
        let once = solve_with(&qp, &tight_clarabel(), &context);
        let twice = dual_active_set(&doubled, &context);
        let distance = relative_metric_distance(&qp, &once.dq, &twice.dq);
        assert!(distance <= DQ_AGREEMENT_TOL, "{context}: {distance:e}");
    }
}

/// The method alone (no fallback) fails on `qp` with `failure`; returns
/// the failure's reason for further checks.
fn fails_alone(qp: &ProjectionQp, failure: DualActiveSetFailure, context: &str) -> FailureReason {
    let Err(SolverError::AllSolversFailed(alone)) =
        solve_projection(qp, &named(SolverChoice::DualActiveSet))
    else {
        panic!("{context}: answered");
    };
    assert_eq!(
        alone[0].reason,
        FailureReason::DualActiveSet(failure),
        "{context}"
    );
    alone[0].reason.clone()
}

/// A body wedged by a push that misses its cone's pyramid has no answer:
/// the method fails typed (its certificate, at a rounding tolerance, is
/// not taken as one), and with `stop_on_infeasible` the chain goes on to
/// the interior point, which certifies it and ends the chain.
#[test]
fn a_wedged_pyramid_fails_typed_and_the_chain_certifies() {
    let qp = pushed_into_the_ground(2.0, 1.0, 0.3, 1e-3).pyramid().0;
    let reason = fails_alone(&qp, DualActiveSetFailure::Infeasible, "a wedged body");
    assert!(!reason.certifies_infeasibility());
    let chain = SolverSettings {
        choice: SolverChoice::DualActiveSet,
        stop_on_infeasible: true,
        ..SolverSettings::default()
    };
    let Err(SolverError::AllSolversFailed(fallbacks)) = solve_projection(&qp, &chain) else {
        panic!("a wedged body was solved");
    };
    let reasons: Vec<&FailureReason> = fallbacks.iter().map(|f| &f.reason).collect();
    assert_eq!(
        reasons,
        [
            &FailureReason::DualActiveSet(DualActiveSetFailure::Infeasible),
            &FailureReason::InteriorPoint(InteriorPointFailure::Infeasible),
        ]
    );
}

/// An island above its size limit, named: `NotApplicable` (no dense
/// matrices of that size are made), and the chain answers.
#[test]
fn a_large_island_named_goes_down_the_chain() {
    let qp = random_stacks(&StackSpec::new(600, 2));
    assert!(qp.num_dofs() > MAX_DOFS, "{} entries", qp.num_dofs());
    fails_alone(&qp, DualActiveSetFailure::NotApplicable, "a large island");
    let chain = SolverSettings {
        choice: SolverChoice::DualActiveSet,
        ..SolverSettings::default()
    };
    let solution = solve_with(&qp, &chain, "a stack of 600 rows");
    assert_eq!(solution.solver, SolverKind::InteriorPoint);
}

/// Equality rows are not its problem: `NotApplicable`, and under `Auto`
/// such a problem goes elsewhere.
#[test]
fn equality_rows_are_not_applicable() {
    let qp = random_mixed(3, 2, 4);
    fails_alone(&qp, DualActiveSetFailure::NotApplicable, "equality rows");
    let auto = solve_with(&qp, &SolverSettings::default(), "auto");
    assert_ne!(auto.solver, SolverKind::DualActiveSet);
}

/// `Auto` takes it for up to `DEFAULT_AUTO_DUAL_ACTIVE_SET_MAX_DOFS`
/// entries of `dq` whatever the rows, above that where the rows violated
/// at `dq = 0` are at most the entries (up to
/// `auto_dual_active_set_violated_max_dofs` entries), else the interior
/// point; each answer agrees with clarabel's.
#[test]
fn auto_takes_it_by_size() {
    let settings = SolverSettings::default();
    let frictionless = |boxes: usize| {
        let mut qp = pushed_column(boxes, 1);
        qp.cones.clear();
        qp
    };
    let pyramid = |boxes: usize| pushed_column(boxes, 1).pyramid().0;
    let cases = [
        // Three boxes: 18 entries, a few rows.
        (frictionless(3), SolverKind::DualActiveSet),
        // Six boxes' pyramids: 36 entries, more rows.
        (pyramid(6), SolverKind::DualActiveSet),
        // Six boxes without friction: 36 entries, fewer rows.
        (frictionless(6), SolverKind::DualActiveSet),
        // Thirty boxes without friction: 180 entries, fewer rows violated.
        (frictionless(30), SolverKind::DualActiveSet),
        // Thirty boxes' pyramids: 180 entries, more rows violated.
        (pyramid(30), SolverKind::InteriorPoint),
    ];
    for (qp, expected) in cases {
        let context = format!("{} entries, {} rows", qp.num_dofs(), qp.num_rows());
        let solution = solve_with(&qp, &settings, &context);
        assert_eq!(solution.solver, expected, "{context}");
        let clarabel = solve_with(&qp, &tight_clarabel(), &context);
        assert_close(&qp, &solution, &clarabel, &context);
    }
    // The rule above 132 entries is its setting's: below the column's
    // entries (or 0), the rules by rows take it (Lemke: fewer than 41 rows).
    let column = frictionless(30);
    for violated_max_dofs in [0, column.num_dofs() - 1] {
        let bounded = SolverSettings {
            auto_dual_active_set_violated_max_dofs: violated_max_dofs,
            ..SolverSettings::default()
        };
        let context = format!("violated rule up to {violated_max_dofs} entries");
        let solution = solve_with(&column, &bounded, &context);
        assert_eq!(solution.solver, SolverKind::Lemke, "{context}");
    }
}
