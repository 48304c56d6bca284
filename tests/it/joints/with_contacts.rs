//! Joints and contacts removed together, judged by oracles the library
//! did not write: joint errors from the user poses
//! (`dev_support::joints`) and the separating-axis depth
//! (`dev_support::sat`). Chains, a chain on a table, a closed loop whose
//! rows are redundant (clarabel and Lemke agree on `dq`).

use constraint_stabilization::body::MassSpec;
use constraint_stabilization::joints::{Joint, JointKind};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::solver::{CrossCheckOutcome, SolverKind};
use constraint_stabilization::{Report, Settings, Stabilizer, Status};
use dev_support::joints::{revolute_chain, sunk_chain_with_bystanders, worst_joint_errors};
use dev_support::sat::exact_depth;
use dev_support::scene::{IDENTITY_XYZW, assert_untouched, cuboid, pose_bits};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};

/// Agreement of clarabel and Lemke on `dq` (relative, mass-weighted): the
/// acceptance tolerance of both answers.
const SOLVERS_AGREE: f64 = 1e-6;

fn hinge_about_z() -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -std::f64::consts::FRAC_PI_2)
}

fn run(scene: &mut Scene, settings: Settings) -> Report {
    let mut stabilizer = Stabilizer::new(settings).expect("valid settings");
    let report = stabilizer.stabilize(scene).expect("valid scene");
    assert_eq!(
        report.status,
        Status::Converged,
        "{:?}: {:?}",
        report.status,
        report.islands_left
    );
    report
}

fn assert_within_tolerance(scene: &Scene, report: &Report) {
    let (linear, angular) = worst_joint_errors(scene);
    assert!(linear <= report.tolerance, "joint separation {linear:e}");
    assert!(
        angular <= report.tolerance / report.scale,
        "joint misalignment {angular:e} rad"
    );
    let depth = exact_depth(scene, report.tolerance);
    assert!(depth.resolved(), "depth {:e}", depth.deepest);
}

#[test]
fn a_chain_on_a_table_with_a_sunk_link_is_lifted_with_every_joint_kept() {
    let (mut scene, untouched) = sunk_chain_with_bystanders(0.02);
    let before = pose_bits(&scene);
    assert!(exact_depth(&scene, 1e-6).deepest > 0.019);
    let report = run(&mut scene, Settings::default());
    assert_within_tolerance(&scene, &report);
    assert_untouched(&scene, &before, &untouched);
    // The lift spread along the chain: the sunk link's neighbours rose.
    assert!(report.bodies_moved >= 3, "{}", report.bodies_moved);
}

#[test]
fn a_chain_of_fifty_links_stretched_by_one_percent_converges_in_five_passes() {
    let mut scene = stretched_chain(50);
    let (stretch, _) = worst_joint_errors(&scene);
    assert!(stretch > 1e-3, "{stretch}");
    let report = run(&mut scene, Settings::default());
    assert!(report.passes <= 5, "{} passes", report.passes);
    assert_within_tolerance(&scene, &report);
}

/// A planar four-bar linkage of bars hinged about z to a fixed base: a
/// closed loop whose joint rows are redundant (each hinge locks the
/// out-of-plane motions that the others lock too).
fn four_bar() -> Scene {
    let mut scene = Scene::new();
    let base = scene
        .add_body(cuboid(
            "base",
            [0.1, 0.1, 0.1],
            [1.0, -1.0, 0.0],
            IDENTITY_XYZW,
            MassSpec::Fixed,
        ))
        .unwrap();
    let bar = |scene: &mut Scene, name: &str, half: [f64; 3], at: [f64; 3], mass: f64| {
        scene
            .add_body(cuboid(name, half, at, IDENTITY_XYZW, MassSpec::Mass(mass)))
            .unwrap()
    };
    let crank = bar(
        &mut scene,
        "crank",
        [0.05, 0.45, 0.05],
        [0.0, 0.5, 0.0],
        1.0,
    );
    let coupler = bar(
        &mut scene,
        "coupler",
        [0.9, 0.05, 0.05],
        [1.0, 1.0, 0.0],
        2.0,
    );
    let rocker = bar(
        &mut scene,
        "rocker",
        [0.05, 0.45, 0.05],
        [2.0, 0.5, 0.0],
        1.5,
    );
    let hinge = |a: usize, b: usize, at_a: [f64; 3], at_b: [f64; 3]| Joint {
        name: format!("hinge {a}-{b}"),
        kind: JointKind::Revolute { limit: None },
        body_a: a,
        body_b: b,
        frame_a: Isometry3::from_parts(Vector3::from(at_a).into(), hinge_about_z()),
        frame_b: Isometry3::from_parts(Vector3::from(at_b).into(), hinge_about_z()),
    };
    for joint in [
        hinge(base, crank, [-1.0, 1.0, 0.0], [0.0, -0.5, 0.0]),
        hinge(crank, coupler, [0.0, 0.5, 0.0], [-1.0, 0.0, 0.0]),
        hinge(coupler, rocker, [1.0, 0.0, 0.0], [0.0, 0.5, 0.0]),
        hinge(base, rocker, [1.0, 1.0, 0.0], [0.0, -0.5, 0.0]),
    ] {
        scene.add_joint(joint).unwrap();
    }
    scene
}

#[test]
fn a_four_bar_linkage_converges_and_clarabel_and_lemke_agree_on_the_correction() {
    for solver in [SolverKind::Clarabel, SolverKind::Lemke] {
        let mut scene = four_bar();
        let coupler = 2;
        let tilt = UnitQuaternion::from_scaled_axis(Vector3::new(0.3, 0.2, 1.0).normalize() * 0.05);
        let t = *scene.bodies()[coupler].translation_user() + Vector3::new(0.02, 0.03, -0.01);
        scene.bodies_mut()[coupler]
            .set_user_pose(t, dev_support::scene::xyzw(&tilt))
            .unwrap();
        let mut settings = Settings::default();
        settings.solver.cross_check = true;
        settings.solver.choice = match solver {
            SolverKind::Lemke => constraint_stabilization::solver::SolverChoice::Lemke,
            _ => constraint_stabilization::solver::SolverChoice::Clarabel,
        };
        let report = run(&mut scene, settings);
        assert_within_tolerance(&scene, &report);
        let mut compared = 0;
        for island in report.pass_reports.iter().flat_map(|p| &p.solved) {
            assert_eq!(island.solver, Some(solver));
            let check = island.cross_check.as_ref().expect("cross-check asked for");
            match &check.outcome {
                CrossCheckOutcome::Compared { differences, .. } => {
                    assert!(differences.dq_rel <= SOLVERS_AGREE, "{differences:?}");
                    compared += 1;
                }
                CrossCheckOutcome::ReferenceFailed(reason) => {
                    panic!("{:?} failed on the four-bar: {reason}", check.reference)
                }
            }
        }
        assert!(compared >= 1);
    }
}

/// A stretched chain of `links` links (every link moved out by 1 %).
fn stretched_chain(links: usize) -> Scene {
    let mut scene = revolute_chain(links, 0.1, 1.0, [0.0, 0.0, 0.0]);
    for body in 1..scene.len() {
        let t = *scene.bodies()[body].translation_user();
        scene.bodies_mut()[body]
            .set_user_pose(Vector3::new(t.x * 1.01, t.y, t.z), IDENTITY_XYZW)
            .unwrap();
    }
    scene
}

/// The stabilizer keeps the joints' sparse analysis for its next calls
/// (in the report, with its size); a call that reuses it moves every body
/// to the bits of a fresh stabilizer's call, and removing bodies frees it.
#[test]
fn the_kept_analysis_is_reported_changes_no_pose_and_goes_with_bodies() {
    let input = stretched_chain(20);
    let mut stabilizer = Stabilizer::new(Settings::default()).expect("valid settings");
    let mut first = input.clone();
    let report = stabilizer.stabilize(&mut first).expect("valid scene");
    assert_eq!(report.status, Status::Converged);
    let (count, bytes) = report.kept_analyses;
    assert!(count >= 1 && bytes > 0, "{:?}", report.kept_analyses);
    assert_eq!(stabilizer.kept_analyses(), report.kept_analyses);
    // The same input again: the kept analysis is used, the poses are a
    // fresh stabilizer's to the bit.
    let mut again = input.clone();
    let report = stabilizer.stabilize(&mut again).expect("valid scene");
    assert_eq!(report.status, Status::Converged);
    assert_eq!(report.kept_analyses.0, count, "no new pattern");
    assert_eq!(pose_bits(&again), pose_bits(&first));
    stabilizer
        .remove_bodies(&mut again, &[5])
        .expect("an index in range");
    assert_eq!(stabilizer.kept_analyses(), (0, 0));
}
