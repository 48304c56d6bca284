//! The solvers on the body-space matrix, the augmented Lagrangian and the
//! interior point, against clarabel and Lemke on random contact-like
//! stacks (redundant coplanar rows, singular `A`), on degenerate rows (a
//! row listed twice) and on infeasible rows, and their warm starts: zero
//! iterations on an unchanged problem, the same answer as a cold solve on
//! a changed one.

use crate::support::solver_oracle::{assert_kkt, relative_metric_distance};
use constraint_stabilization::solver::augmented_lagrangian::AugmentedLagrangianFailure;
use constraint_stabilization::solver::interior_point::InteriorPointFailure;
use constraint_stabilization::solver::{
    FailureReason, ProjectionQp, ProjectionSolution, SolverChoice, SolverError, SolverKind,
    SolverSettings, solve_projection, solve_projection_warm,
};
use dev_support::solver::{StackSpec, random_stacks};
use nalgebra::DVector;

/// Agreement of the solvers' `dq` with clarabel's and Lemke's, relative in
/// the M-norm: the augmented Lagrangian's answers are certified exact (the
/// exact finish verifies the KKT conditions to 1e-9 of the correction), the
/// interior point's by a duality gap of 1e-12 of the energy.
const DQ_AGREEMENT_TOL: f64 = 1e-8;

/// The solvers on the body-space matrix, named as a choice, with the kind
/// that must answer.
const BODY_SPACE: [(SolverChoice, SolverKind); 2] = [
    (
        SolverChoice::AugmentedLagrangian,
        SolverKind::AugmentedLagrangian,
    ),
    (SolverChoice::InteriorPoint, SolverKind::InteriorPoint),
];

/// Factorizations a warm start that is already the answer may cost: none
/// for the augmented Lagrangian (its multipliers are checked as they
/// are), one for the interior point (its multipliers are interior, spread
/// over every row: its warm finish certifies them with one factorization
/// of the warm active set, `solver/interior_point/warm.rs`).
fn max_warm_factorizations(choice: SolverChoice) -> usize {
    usize::from(choice == SolverChoice::InteriorPoint)
}

fn settings(choice: SolverChoice) -> SolverSettings {
    SolverSettings {
        choice,
        fall_back: false,
        ..SolverSettings::default()
    }
}

fn solve(qp: &ProjectionQp, choice: SolverChoice) -> ProjectionSolution {
    solve_projection(qp, &settings(choice)).unwrap_or_else(|e| panic!("{choice:?}: {e}"))
}

/// Random stacks from 10 to about 250 rows (dense and sparse Newton
/// matrices), at unit and extreme scales: each solver on the body-space
/// matrix answers every one itself, passes the KKT oracle, and agrees with
/// clarabel and (up to Lemke's size) with Lemke.
#[test]
fn agrees_with_clarabel_and_lemke_on_random_stacks() {
    for (choice, kind) in BODY_SPACE {
        agrees_on_random_stacks(choice, kind);
    }
}

fn agrees_on_random_stacks(choice: SolverChoice, kind: SolverKind) {
    let scales = [(1.0, 1.0, 2.0), (1e-3, 1e3, 4.0)];
    for rows in [10, 60, 250] {
        for (length_scale, mass_scale, mass_decades) in scales {
            for seed in 0..2 {
                let spec = StackSpec {
                    length_scale,
                    mass_scale,
                    mass_decades,
                    ..StackSpec::new(rows, seed)
                };
                let qp = random_stacks(&spec);
                let context = format!("{choice:?}, {spec:?}");
                let ours = solve(&qp, choice);
                assert_eq!(ours.solver, kind, "{context}");
                assert!(
                    ours.factorizations >= 1,
                    "{context}: cold solve factored nothing"
                );
                assert_kkt(&qp, &ours.dq, &ours.lambda, &context);
                let mut references = vec![SolverChoice::Clarabel];
                if rows <= SolverSettings::default().auto_lemke_max_rows {
                    references.push(SolverChoice::Lemke);
                }
                for reference in references {
                    let theirs = solve(&qp, reference);
                    let distance = relative_metric_distance(&qp, &ours.dq, &theirs.dq);
                    assert!(
                        distance <= DQ_AGREEMENT_TOL,
                        "{context}: {distance:e} from {reference:?}"
                    );
                }
            }
        }
    }
}

/// A problem with every row listed twice (the multipliers split anyhow
/// between the copies): the same `dq` as the problem with each row once.
#[test]
fn duplicated_rows_leave_dq_unchanged() {
    let qp = random_stacks(&StackSpec::new(40, 7));
    let mut doubled = qp.clone();
    doubled.rows.extend(qp.rows.iter().cloned());
    doubled.phi.extend(qp.phi.iter().copied());
    doubled.target.extend(qp.target.iter().copied());
    let once = solve(&qp, SolverChoice::Clarabel);
    for (choice, _) in BODY_SPACE {
        let twice = solve(&doubled, choice);
        let distance = relative_metric_distance(&qp, &once.dq, &twice.dq);
        assert!(distance <= DQ_AGREEMENT_TOL, "{choice:?}: {distance:e}");
    }
}

/// Two opposite rows on one body that both ask to move it the same way
/// (`x >= 1` and `-x >= 1`): no correction satisfies both. The augmented
/// Lagrangian stops at its iteration limit with a typed failure and
/// clarabel then certifies the infeasibility, as after any other first
/// solver; the interior point certifies it itself (its Farkas
/// certificate), the chain stops there, and clarabel asked on its own
/// certifies it too.
#[test]
fn infeasible_rows_fail_typed_and_clarabel_certifies() {
    let mut qp = random_stacks(&StackSpec::new(20, 3));
    let mut opposite = qp.rows[0].clone();
    for (_, g) in &mut opposite.blocks {
        *g = -*g;
    }
    qp.rows.push(opposite);
    qp.phi.push(qp.phi[0]);
    qp.target.push(qp.target[0]);
    qp.phi[0] = -1.0;
    let last = qp.phi.len() - 1;
    qp.phi[last] = -1.0;
    let expected = [
        FailureReason::AugmentedLagrangian(AugmentedLagrangianFailure::NotConverged),
        FailureReason::InteriorPoint(InteriorPointFailure::Infeasible),
    ];
    for ((choice, kind), failure) in BODY_SPACE.into_iter().zip(expected) {
        let settings = SolverSettings {
            choice,
            stop_on_infeasible: true,
            ..SolverSettings::default()
        };
        let Err(SolverError::AllSolversFailed(fallbacks)) = solve_projection(&qp, &settings) else {
            panic!("{choice:?}: an infeasible problem was solved");
        };
        let reasons: Vec<_> = fallbacks.iter().map(|f| (f.solver, &f.reason)).collect();
        assert_eq!(reasons[0], (kind, &failure));
        if failure.certifies_infeasibility() {
            assert_eq!(fallbacks.len(), 1, "the chain went on: {reasons:?}");
            let clarabel = SolverSettings {
                choice: SolverChoice::Clarabel,
                fall_back: false,
                ..SolverSettings::default()
            };
            let Err(SolverError::AllSolversFailed(alone)) = solve_projection(&qp, &clarabel) else {
                panic!("clarabel solved an infeasible problem");
            };
            assert!(alone[0].reason.certifies_infeasibility(), "{alone:?}");
        } else {
            assert_eq!(fallbacks[1].solver, SolverKind::Clarabel);
            assert!(fallbacks[1].reason.certifies_infeasibility(), "{reasons:?}");
        }
    }
}

/// Started from its own answer, each solver returns it with no iteration
/// and no factorization.
#[test]
fn warm_start_from_the_answer_costs_nothing() {
    for (choice, _) in BODY_SPACE {
        for rows in [30, 250] {
            let qp = random_stacks(&StackSpec::new(rows, 11));
            let cold = solve(&qp, choice);
            let warm = solve_projection_warm(&qp, &settings(choice), Some(&cold.lambda)).unwrap();
            assert!(warm.warm_started);
            assert_eq!(warm.iterations, 0, "{choice:?}, {rows} rows");
            assert!(
                warm.factorizations <= max_warm_factorizations(choice),
                "{choice:?}, {rows} rows: {} factorizations",
                warm.factorizations
            );
            let distance = relative_metric_distance(&qp, &warm.dq, &cold.dq);
            assert!(distance <= DQ_AGREEMENT_TOL, "{choice:?}: {distance:e}");
        }
    }
}

/// Warm-started from the answer of a neighbouring problem (every `phi`
/// moved by up to a fifth of its own size, as between two passes), the
/// solver gives the cold answer of the new problem; a warm start of the
/// wrong length or with non-finite entries only costs iterations.
#[test]
fn warm_start_from_a_neighbouring_problem_gives_the_cold_answer() {
    let qp = random_stacks(&StackSpec::new(120, 5));
    let before = solve(&qp, SolverChoice::AugmentedLagrangian);
    let mut moved = qp.clone();
    for (i, phi) in moved.phi.iter_mut().enumerate() {
        *phi *= 1.0 + 0.2 * ((i % 7) as f64 / 7.0 - 0.5);
    }
    let cold = solve(&moved, SolverChoice::Clarabel);
    let stale_short = DVector::from_element(3, 1.0);
    let mut stale_nan = before.lambda.clone();
    stale_nan[0] = f64::NAN;
    for (choice, kind) in BODY_SPACE {
        for warm in [&before.lambda, &stale_short, &stale_nan] {
            let sol = solve_projection_warm(&moved, &settings(choice), Some(warm)).unwrap();
            assert_eq!(sol.solver, kind);
            let distance = relative_metric_distance(&moved, &sol.dq, &cold.dq);
            assert!(distance <= DQ_AGREEMENT_TOL, "{choice:?}: {distance:e}");
        }
    }
}

/// The Newton system solved by conjugate gradients preconditioned with the
/// previous factor (when few rows change state), and the simplicial
/// sparse factor: both give clarabel's `dq` on random stacks of sparse
/// size.
#[test]
fn cg_steps_and_the_simplicial_factor_agree_with_clarabel() {
    for seed in 0..2 {
        let qp = random_stacks(&StackSpec::new(250, seed));
        let reference = solve(&qp, SolverChoice::Clarabel);
        for (rows_without_factorization, supernodal) in [(16, true), (0, false)] {
            let mut s = settings(SolverChoice::AugmentedLagrangian);
            s.augmented_lagrangian
                .max_rows_changed_without_factorization = rows_without_factorization;
            s.augmented_lagrangian.supernodal = supernodal;
            let ours = solve_projection(&qp, &s).expect("solved");
            let context =
                format!("seed {seed}, {rows_without_factorization} rows, supernodal {supernodal}");
            assert_eq!(ours.solver, SolverKind::AugmentedLagrangian, "{context}");
            assert_kkt(&qp, &ours.dq, &ours.lambda, &context);
            let distance = relative_metric_distance(&qp, &ours.dq, &reference.dq);
            assert!(distance <= DQ_AGREEMENT_TOL, "{context}: {distance:e}");
        }
    }
}

/// The multipliers of a problem whose violations are a thousand times
/// larger (a first pass against the second): scaled along the dual they
/// are this problem's answer, accepted with zero iterations.
#[test]
fn a_warm_start_of_another_size_is_scaled_to_fit() {
    let qp = random_stacks(&StackSpec::new(60, 5));
    let mut larger = qp.clone();
    for (phi, target) in larger.phi.iter_mut().zip(&larger.target) {
        *phi = target + 1e3 * (*phi - target);
    }
    let cold = solve(&qp, SolverChoice::Clarabel);
    for (choice, _) in BODY_SPACE {
        let s = settings(choice);
        let first = solve_projection(&larger, &s).expect("solved");
        let warm = solve_projection_warm(&qp, &s, Some(&first.lambda)).expect("solved");
        assert!(warm.warm_started);
        assert_eq!(warm.iterations, 0, "{choice:?}");
        assert!(
            warm.factorizations <= max_warm_factorizations(choice),
            "{choice:?}: {} factorizations",
            warm.factorizations
        );
        let distance = relative_metric_distance(&qp, &warm.dq, &cold.dq);
        assert!(distance <= DQ_AGREEMENT_TOL, "{choice:?}: {distance:e}");
    }
}
