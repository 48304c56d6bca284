//! `SolverSettings::deadline` (the call's time budget inside a pass): a
//! solver asked to run after it stops with the typed outcome
//! `FailureReason::DeadlinePassed` (Lemke before a pivot, PGS before a
//! sweep, clarabel by its time limit, the augmented Lagrangian before a
//! Newton step, the dual active-set method before a step or while its
//! warm start is built) and ends the fallback chain; the `O(1)` closed form still
//! answers. No timing is asserted: the deadline is already past.

use std::time::Instant;

use constraint_stabilization::solver::lemke::{self, LemkeSettings, LemkeStatus};
use constraint_stabilization::solver::pgs::{self, PgsSettings, PgsStatus};
use constraint_stabilization::solver::{
    FailureReason, Fallback, SolverChoice, SolverError, SolverKind, SolverSettings,
    projection_to_lcp, solve_projection, solve_projection_warm,
};
use dev_support::solver::{StackSpec, random_stacks};

/// Settings whose deadline has passed (the instant of the call: `now >=
/// deadline` holds at every later check).
fn past_deadline(choice: SolverChoice) -> SolverSettings {
    SolverSettings {
        choice,
        deadline: Some(Instant::now()),
        ..SolverSettings::default()
    }
}

#[test]
fn every_solver_stops_when_its_deadline_has_passed_and_ends_the_chain() {
    let qp = random_stacks(&StackSpec::new(40, 7));
    for (choice, kind) in [
        (SolverChoice::Clarabel, SolverKind::Clarabel),
        (SolverChoice::ClarabelDual, SolverKind::ClarabelDual),
        (SolverChoice::Lemke, SolverKind::Lemke),
        (SolverChoice::Pgs, SolverKind::Pgs),
        (
            SolverChoice::AugmentedLagrangian,
            SolverKind::AugmentedLagrangian,
        ),
        (SolverChoice::DualActiveSet, SolverKind::DualActiveSet),
        (SolverChoice::Auto, SolverKind::DualActiveSet),
    ] {
        let result = solve_projection(&qp, &past_deadline(choice));
        let Err(SolverError::AllSolversFailed(fallbacks)) = result else {
            panic!("{choice:?}: {result:?}");
        };
        // The first solver stopped and no fallback ran after it.
        assert_eq!(
            fallbacks,
            vec![Fallback {
                solver: kind,
                reason: FailureReason::DeadlinePassed
            }],
            "{choice:?}"
        );
    }
    // Without a deadline the same problem is solved.
    let answer = solve_projection(&qp, &SolverSettings::default()).expect("solved");
    // Warm-started from that answer (which its warm start would return
    // with no step), the method still stops.
    let past = past_deadline(SolverChoice::DualActiveSet);
    let result = solve_projection_warm(&qp, &past, Some(&answer.lambda));
    let Err(SolverError::AllSolversFailed(fallbacks)) = result else {
        panic!("warm: {result:?}");
    };
    assert_eq!(
        fallbacks,
        vec![Fallback {
            solver: SolverKind::DualActiveSet,
            reason: FailureReason::DeadlinePassed
        }]
    );
}

#[test]
fn lemke_and_pgs_stop_before_their_first_pivot_or_sweep() {
    let qp = random_stacks(&StackSpec::new(30, 3));
    let metric = qp.validate().expect("a valid problem");
    let lcp = projection_to_lcp(&qp, &metric).expect("an LCP");
    let deadline = Some(Instant::now());
    let failure = lemke::solve(
        &lcp,
        &LemkeSettings {
            deadline,
            ..LemkeSettings::default()
        },
    )
    .expect_err("stopped");
    assert_eq!(failure.status, LemkeStatus::DeadlinePassed);
    assert_eq!((failure.pivots, failure.attempts.len()), (0, 1));
    let status = pgs::solve(
        &lcp,
        &PgsSettings {
            deadline,
            ..PgsSettings::default()
        },
    )
    .expect_err("stopped");
    assert_eq!(status, PgsStatus::DeadlinePassed { sweeps: 0 });
}

#[test]
fn the_closed_form_of_one_row_still_answers_after_the_deadline() {
    let qp = random_stacks(&StackSpec::new(1, 5));
    assert_eq!(qp.num_rows(), 1);
    let solution = solve_projection(&qp, &past_deadline(SolverChoice::Auto)).expect("solved");
    assert_eq!(solution.solver, SolverKind::ClosedForm);
    assert!(solution.residuals.acceptance() <= SolverSettings::default().tol_residual);
}

/// The case: the MuJoCo bin of 160 boxes with MuJoCo's friction
/// (`mu = 1` on every body) under a budget of one millisecond, far less
/// than one pass: the call ends with `TimeLimit` and is never worse than
/// its input by the exact depth (brute-force separating axes).
#[test]
fn a_tiny_budget_on_a_big_scene_stops_at_the_time_limit_never_worse() {
    use constraint_stabilization::{Settings, Stabilizer, Status};
    use std::time::Duration;
    let (_, mut scene) = crate::support::engine_states::engine_states()
        .into_iter()
        .find(|(stem, _)| stem == "mj01_box_bin")
        .expect("the MuJoCo box bin");
    for body in 0..scene.bodies().len() {
        let body = scene.body_mut(body).expect("a body of the scene");
        body.set_friction(Some(1.0)).expect("a valid coefficient");
    }
    let (depth_before, _) = dev_support::sat::sat_deepest(&scene);
    let mut settings = Settings::default();
    settings.time_budget = Some(Duration::from_millis(1));
    let mut stabilizer = Stabilizer::new(settings).expect("valid settings");
    let report = stabilizer.stabilize(&mut scene).expect("a valid scene");
    assert_eq!(report.status, Status::TimeLimit);
    let (depth_after, _) = dev_support::sat::sat_deepest(&scene);
    assert!(
        depth_after <= depth_before,
        "{depth_before:e} -> {depth_after:e}"
    );
}
