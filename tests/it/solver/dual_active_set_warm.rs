//! The dual active-set method's warm start
//! (`src/solver/dual_active_set/warm.rs`) on its own: started from its
//! own answer it takes no step; started from any multipliers (another
//! problem's, random ones of either sign, the wrong length, values that
//! are not finite) it ends at the cold answer, checked against clarabel
//! at 1e-12 and Lemke; a warm set of rows that hold at `dq = 0` is
//! refused and reported cold.

use super::friction_cone::pushed_column;
use super::interior_point_friction::{named, tight_clarabel};
use crate::support::proptest_config::config;
use crate::support::solver_oracle::{assert_kkt, relative_metric_distance};
use constraint_stabilization::solver::{
    ProjectionQp, ProjectionSolution, SolverChoice, SolverKind, solve_projection,
    solve_projection_warm,
};
use dev_support::solver::{StackSpec, random_stacks};
use nalgebra::DVector;
use proptest::prelude::*;

/// Agreement in `dq` (relative, `M`-norm) of a warm answer with the cold
/// one and with the oracles: each is exact up to rounding (clarabel runs
/// at 1e-12), so a larger distance is a wrong answer.
const DQ_AGREEMENT_TOL: f64 = 1e-6;

/// The method's answer from `warm`, without fallback, checked by the KKT
/// oracle.
fn warm_answer(qp: &ProjectionQp, warm: &DVector<f64>, context: &str) -> ProjectionSolution {
    let settings = named(SolverChoice::DualActiveSet);
    let solution = solve_projection_warm(qp, &settings, Some(warm))
        .unwrap_or_else(|e| panic!("{context}: {e}"));
    assert_eq!(solution.solver, SolverKind::DualActiveSet, "{context}");
    assert_kkt(qp, &solution.dq, &solution.lambda, context);
    solution
}

fn cold_answer(qp: &ProjectionQp, context: &str) -> ProjectionSolution {
    let solution = solve_projection(qp, &named(SolverChoice::DualActiveSet))
        .unwrap_or_else(|e| panic!("{context}: {e}"));
    assert_eq!(solution.solver, SolverKind::DualActiveSet, "{context}");
    solution
}

fn assert_agree(qp: &ProjectionQp, a: &DVector<f64>, b: &DVector<f64>, context: &str) {
    let distance = relative_metric_distance(qp, a, b);
    assert!(distance <= DQ_AGREEMENT_TOL, "{context}: {distance:e}");
}

/// Redundant stacks (four corner rows per face) and friction pyramids
/// (every sticking contact degenerate).
fn problems() -> Vec<(String, ProjectionQp)> {
    let mut problems = Vec::new();
    for rows in [8, 40, 120] {
        for seed in 0..2 {
            let spec = StackSpec {
                rows,
                length_scale: 1.0,
                mass_scale: 1.0,
                mass_decades: 3.0,
                seed,
            };
            problems.push((
                format!("stack of {rows} rows, seed {seed}"),
                random_stacks(&spec),
            ));
        }
    }
    for boxes in [2, 6, 16] {
        let qp = pushed_column(boxes, 1).pyramid().0;
        problems.push((format!("pyramid of {boxes} boxes"), qp));
    }
    problems
}

/// Started from its own multipliers the method takes no step, builds one
/// factor and returns the same `dq`.
#[test]
fn its_own_answer_costs_no_step() {
    for (context, qp) in problems() {
        let cold = cold_answer(&qp, &context);
        let warm = warm_answer(&qp, &cold.lambda, &context);
        assert!(warm.warm_started, "{context}");
        assert_eq!(warm.iterations, 0, "{context}");
        assert_eq!(warm.factorizations, 1, "{context}");
        assert_agree(&qp, &warm.dq, &cold.dq, &context);
    }
}

/// Started from the answer of the same rows with other right-hand sides
/// (the next pass or call of a stabilizer), it ends at the cold answer,
/// which is clarabel's and Lemke's.
#[test]
fn a_neighbouring_answer_gives_the_cold_answer() {
    for (context, qp) in problems() {
        let mut shifted = qp.clone();
        for (k, phi) in shifted.phi.iter_mut().enumerate() {
            *phi *= if k % 3 == 0 { -0.5 } else { 0.7 };
        }
        let neighbour = cold_answer(&shifted, &context);
        let warm = warm_answer(&qp, &neighbour.lambda, &context);
        let cold = cold_answer(&qp, &context);
        assert_agree(&qp, &warm.dq, &cold.dq, &context);
        for (name, settings) in [
            ("clarabel", tight_clarabel()),
            ("Lemke", named(SolverChoice::Lemke)),
        ] {
            let other = solve_projection(&qp, &settings).expect("the oracle answers");
            assert_agree(&qp, &warm.dq, &other.dq, &format!("{context}, {name}"));
        }
    }
}

/// Multipliers of the wrong length are ignored (a cold start).
#[test]
fn multipliers_of_another_length_start_cold() {
    for (context, qp) in problems() {
        let wrong = DVector::from_element(qp.num_rows() + 1, 1.0);
        let warm = warm_answer(&qp, &wrong, &context);
        let cold = cold_answer(&qp, &context);
        assert_eq!(warm.factorizations, 0, "{context}");
        assert_eq!(warm.iterations, cold.iterations, "{context}");
        assert_agree(&qp, &warm.dq, &cold.dq, &context);
    }
}

/// Multipliers only on rows that hold at `dq = 0` (a later pass's warm
/// set, module docs of `warm.rs`): the warm start is refused, the method
/// starts cold and reports so (no factor, not warm-started).
#[test]
fn a_warm_set_of_rows_that_hold_is_refused() {
    let mut tested = 0;
    for (context, qp) in problems() {
        let warm = DVector::from_fn(qp.num_rows(), |i, _| {
            if qp.phi[i] - qp.target[i] >= 0.0 {
                1.0
            } else {
                0.0
            }
        });
        if warm.iter().all(|&x| x == 0.0) {
            continue;
        }
        let answer = warm_answer(&qp, &warm, &context);
        let cold = cold_answer(&qp, &context);
        assert!(!answer.warm_started, "{context}");
        assert_eq!(answer.factorizations, 0, "{context}");
        assert_eq!(answer.iterations, cold.iterations, "{context}");
        assert_agree(&qp, &answer.dq, &cold.dq, &context);
        tested += 1;
    }
    assert!(tested > 0, "no problem has a row that holds at dq = 0");
}

proptest! {
    #![proptest_config(config(24))]

    /// Random multipliers of either sign, zeros, and values that are not
    /// finite: the cold answer.
    #[test]
    fn any_multipliers_give_the_cold_answer(
        problem in 0..9usize,
        values in proptest::collection::vec(
            prop_oneof![
                4 => -1e3..1e3f64,
                2 => Just(0.0),
                1 => 1e-12..1e-9f64,
                1 => Just(f64::INFINITY),
                1 => Just(f64::NAN),
            ],
            1..400,
        ),
    ) {
        let (context, qp) = &problems()[problem];
        let warm = DVector::from_fn(qp.num_rows(), |i, _| values[i % values.len()]);
        let answer = warm_answer(qp, &warm, context);
        let cold = cold_answer(qp, context);
        assert_agree(qp, &answer.dq, &cold.dq, context);
    }
}
