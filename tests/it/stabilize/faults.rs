//! Solver faults forced through the settings: clarabel with one
//! interior-point iteration, Lemke with a pivot limit of one, PGS with one
//! sweep. With one solver broken the fallback chain must reach an answer
//! (the scene converges, judged by brute-force separating axes) and every
//! island's report must name the broken solver and why it failed. With all
//! three broken, an island of several rows cannot be solved: the call must
//! say so (`Status::Unsolved`, the island named in `islands_left` with the
//! three failures in order), keep that island's poses bit for bit, and keep
//! the progress of an island the closed form (one row, no solver to break)
//! solved in the same call.

use crate::stabilize::extreme::{assert_converged, run, stack};
use constraint_stabilization::body::{BodyDesc, MassSpec};
use constraint_stabilization::error::SolverError;
use constraint_stabilization::solver::clarabel_qp::ClarabelFailure;
use constraint_stabilization::solver::lemke::LemkeStatus;
use constraint_stabilization::solver::pgs::PgsStatus;
use constraint_stabilization::solver::{FailureReason, SolverChoice, SolverKind};
use constraint_stabilization::stabilizer::IslandOutcome;
use constraint_stabilization::{Error, Settings, Status};
use dev_support::sat::sat_depth;
use dev_support::scene::{IDENTITY_XYZW, assert_untouched, cuboid, pose_bits, scene_of, xyzw};
use nalgebra::{UnitQuaternion, Vector3};

/// Settings with the given solvers broken, and the dual active-set method
/// out of `Auto`'s choice (so that the islands here go to Lemke first, as
/// the tests follow the chain from there).
fn broken(clarabel: bool, lemke: bool, pgs: bool) -> Settings {
    let mut settings = Settings::default();
    let solver = &mut settings.solver;
    solver.auto_dual_active_set_max_dofs = 0;
    solver.auto_dual_active_set_violated_max_dofs = 0;
    if clarabel {
        solver.clarabel.max_iter = 1;
    }
    if lemke {
        solver.lemke.pivot_limit_per_row = 0;
        solver.lemke.pivot_limit_min = 1;
    }
    if pgs {
        solver.pgs.max_sweeps = 1;
    }
    settings
}

/// A stack of three boxes on the ground, sunk 1 % into each other: islands
/// of many rows (four per face contact), no closed form.
fn three_boxes() -> Vec<BodyDesc> {
    stack(&[1.0, 2.0, 3.0].map(MassSpec::Mass), 0.01)
}

/// Whether `reason` is the failure the broken `kind` must give.
fn is_forced_failure(kind: SolverKind, reason: &FailureReason) -> bool {
    match (kind, reason) {
        (SolverKind::Clarabel, FailureReason::Clarabel(ClarabelFailure::MaxIterations)) => true,
        (SolverKind::Lemke, FailureReason::Lemke(LemkeStatus::PivotLimit)) => true,
        (SolverKind::Pgs, FailureReason::Pgs(PgsStatus::MaxSweeps { .. })) => true,
        // A solver stopped early may also return an answer that our
        // residual check rejects.
        (_, FailureReason::ResidualTooLarge { .. }) => true,
        _ => false,
    }
}

#[test]
fn one_broken_solver_falls_back_and_the_report_says_why() {
    let cases = [
        (
            SolverChoice::Clarabel,
            SolverKind::Clarabel,
            broken(true, false, false),
        ),
        (
            SolverChoice::Lemke,
            SolverKind::Lemke,
            broken(false, true, false),
        ),
        (
            SolverChoice::Pgs,
            SolverKind::Pgs,
            broken(false, false, true),
        ),
    ];
    for (choice, kind, mut settings) in cases {
        settings.solver.choice = choice;
        let label = format!("{kind:?} broken");
        let run = run(&label, &three_boxes(), settings);
        assert_converged(&label, &run, 4);
        let islands: Vec<_> = run
            .report
            .pass_reports
            .iter()
            .flat_map(|p| &p.solved)
            .collect();
        assert!(!islands.is_empty());
        for island in islands {
            let first = island.fallbacks.first();
            println!(
                "{label}: solved by {:?}, first failure {first:?}",
                island.solver
            );
            let first = first.unwrap_or_else(|| panic!("{label}: no fallback reported"));
            assert_eq!(first.solver, kind, "{label}");
            assert!(
                is_forced_failure(kind, &first.reason),
                "{label}: {:?}",
                first.reason
            );
            assert!(island.solver.is_some_and(|s| s != kind), "{label}");
        }
    }
}

#[test]
fn every_solver_broken_leaves_the_island_unsolved_and_keeps_other_progress() {
    // A box far away with one corner sunk into its own fixed block: one
    // row, solved in closed form. The stack needs a real solver.
    let turned = UnitQuaternion::from_scaled_axis(Vector3::new(0.5, 0.3, 0.2));
    let mut descs = three_boxes();
    let far = 100.0;
    descs.push(cuboid(
        "block",
        [1.0, 0.5, 1.0],
        [far, -0.5, 0.0],
        IDENTITY_XYZW,
        MassSpec::Fixed,
    ));
    let corner = descs.len();
    let lowest_y = [-0.5, 0.5]
        .iter()
        .flat_map(|x| [-0.5, 0.5].map(|y| (*x, y)))
        .flat_map(|(x, y)| [-0.5, 0.5].map(|z| (turned * Vector3::new(x, y, z)).y))
        .fold(f64::INFINITY, f64::min);
    descs.push(cuboid(
        "corner",
        [0.5; 3],
        [far, -lowest_y - 0.01, 0.0],
        xyzw(&turned),
        MassSpec::Mass(1.0),
    ));
    let before = pose_bits(&scene_of(&descs));
    let run = run("all broken", &descs, broken(true, true, true));
    assert_eq!(run.report.status, Status::Unsolved);
    assert_eq!(
        run.report.islands_left.len(),
        1,
        "{:?}",
        run.report.islands_left
    );
    let left = &run.report.islands_left[0];
    assert_eq!(left.bodies, vec![1, 2, 3]);
    let IslandOutcome::Failed(Error::Solver(SolverError::AllSolversFailed(failures))) =
        &left.outcome
    else {
        panic!("unexpected outcome {:?}", left.outcome);
    };
    let solvers: Vec<_> = failures.iter().map(|f| f.solver).collect();
    assert_eq!(
        solvers,
        [SolverKind::Lemke, SolverKind::Clarabel, SolverKind::Pgs]
    );
    for failure in failures {
        assert!(
            is_forced_failure(failure.solver, &failure.reason),
            "{failure:?}"
        );
    }
    assert_untouched(&run.scene, &before, &[0, 1, 2, 3, 4]);
    // The closed-form island kept its progress.
    assert!(sat_depth(&run.scene, 4, corner) <= run.report.tolerance);
    assert!(run.depth_after <= run.depth_before);
}
