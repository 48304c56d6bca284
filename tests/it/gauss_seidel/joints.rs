//! The nonlinear Gauss–Seidel baseline with joints (issue 23): each
//! locked axis relaxed as a bilateral row after the contact points of a
//! sweep. A pendulum off its fixed pivot and a ball joint pulled apart
//! are closed within the tolerance; a chain on the ground with a sunk
//! link is lifted with its joints kept, far below the input's errors but
//! (the baseline's weakness) not within the tolerance in 300 sweeps;
//! bodies outside the islands bit-identical. Joint errors are judged
//! by `dev_support::joints` (from the user poses and the anchor frames,
//! not the library's measure), depths by the separating-axis oracle of
//! `dev_support::sat`.

use constraint_stabilization::scene::Scene;
use constraint_stabilization::settings::GaussSeidelSettings;
use constraint_stabilization::{Method, Report, Settings, Stabilizer, Status};
use dev_support::joints::{
    ball_joint_pulled_apart, chain_on_ground, oracle_joint_errors, pendulum_off_pivot,
    sunk_chain_with_bystanders, worst_joint_errors,
};
use dev_support::sat::exact_depth;
use dev_support::scene::{IDENTITY_XYZW, assert_finite, assert_untouched, ground, pose_bits};

/// Sweeps allowed for a lone joint to close.
const JOINT_SWEEPS: usize = 100;

/// Sweeps allowed for the chain on the ground.
const CHAIN_SWEEPS: usize = 300;

/// Relative agreement with a closed form: the rounding of a few rows on
/// lengths of order 1.
const CLOSED_FORM_RELATIVE: f64 = 1e-12;

/// The least reduction of the chain's depth and joint errors (relative to
/// the sink) when its sweeps run out: measured 4.6e-5 and 3.4e-5.
const CHAIN_REDUCTION: f64 = 1e-3;

/// How deep the chain's sunk link is in the ground.
const SUNK: f64 = 0.02;

/// The baseline with no slop (so that a contact can be brought within the
/// tolerance) and Box2D's other defaults.
fn baseline(iterations: usize) -> Settings {
    let mut settings = Settings::default();
    settings.method = Method::GaussSeidel;
    settings.gauss_seidel = GaussSeidelSettings {
        iterations,
        slop_relative: 0.0,
        ..GaussSeidelSettings::default()
    };
    settings
}

fn run(scene: &mut Scene, settings: Settings) -> Report {
    let mut stabilizer = Stabilizer::new(settings).expect("valid settings");
    let report = stabilizer.stabilize(scene).expect("valid scene");
    assert_finite(scene);
    println!(
        "{:?} after {} sweeps: depth {:.3e} -> {:.3e}, joint error {:.3e} -> {:.3e}, tol {:.1e}",
        report.status,
        report.passes,
        report.depth_before,
        report.depth_after,
        report.joint_error_before,
        report.joint_error_after,
        report.tolerance
    );
    report
}

#[test]
fn a_pendulum_off_its_fixed_pivot_is_brought_back_to_it() {
    let mut scene = pendulum_off_pivot();
    let pivot_before = pose_bits(&scene);
    let before = oracle_joint_errors(&scene, &scene.joints()[0]);
    assert!(before.separation > 0.05, "{before:?}");
    let report = run(&mut scene, baseline(JOINT_SWEEPS));
    let after = oracle_joint_errors(&scene, &scene.joints()[0]);
    assert_eq!(report.status, Status::Converged);
    assert!(after.separation <= report.tolerance, "{after:?}");
    assert_untouched(&scene, &pivot_before, &[0]);
    // The report counts the joint as the oracle does.
    assert!((report.joint_error_before - before.linear).abs() <= CLOSED_FORM_RELATIVE);
    assert!(report.joint_error_after <= report.tolerance);
    assert_eq!(report.joints.len(), 1);
    assert!(report.joints[0].after.linear <= report.tolerance);
    assert_eq!(report.pass_reports.len(), report.passes + 1);
    let last = report.pass_reports.last().expect("a final detection");
    assert!(last.joint_error <= report.tolerance);
}

#[test]
fn a_ball_joint_pulled_apart_closes_in_one_sweep_in_the_ratio_of_the_masses() {
    // The anchors lie on the line of the centres: the x row moves the
    // cubes along x only, by -C / k with k = 1/m_a + 1/m_b, in the ratio
    // of the masses; the y and z rows are 0 and move nothing.
    let (m_a, m_b, d) = (1.0, 3.0, 0.04);
    let mut scene = ball_joint_pulled_apart(m_a, m_b, d);
    let report = run(&mut scene, baseline(JOINT_SWEEPS));
    assert_eq!(report.status, Status::Converged);
    assert_eq!(report.passes, 1);
    let errors = oracle_joint_errors(&scene, &scene.joints()[0]);
    assert!(errors.separation <= report.tolerance, "{errors:?}");
    let moved_a = scene.bodies()[0].translation_user().x;
    let moved_b = scene.bodies()[1].translation_user().x - (1.0 + d);
    let expected_a = d * m_b / (m_a + m_b);
    let expected_b = -d * m_a / (m_a + m_b);
    assert!(
        (moved_a - expected_a).abs() <= CLOSED_FORM_RELATIVE * d,
        "{moved_a} against {expected_a}"
    );
    assert!(
        (moved_b - expected_b).abs() <= CLOSED_FORM_RELATIVE * d,
        "{moved_b} against {expected_b}"
    );
    for body in scene.bodies() {
        assert_eq!(body.rotation_user_xyzw(), IDENTITY_XYZW, "{}", body.name());
    }
}

/// The largest oracle joint error in length units (angles times `scale`).
fn oracle_joint_error(scene: &Scene, scale: f64) -> f64 {
    let (linear, angular) = worst_joint_errors(scene);
    linear.max(angular * scale)
}

#[test]
fn a_chain_on_the_ground_with_a_sunk_link_is_lifted_with_its_joints_kept() {
    let (mut scene, untouched) = sunk_chain_with_bystanders(SUNK);
    let before = pose_bits(&scene);
    let depth_before = exact_depth(&scene, 1e-6).deepest;
    assert!(depth_before > 0.9 * SUNK, "{depth_before}");
    let report = run(&mut scene, baseline(CHAIN_SWEEPS));
    let depth = exact_depth(&scene, report.tolerance);
    let joint_error = oracle_joint_error(&scene, report.scale);
    println!(
        "chain: exact depth {:.3e}, oracle joint error {joint_error:.3e}, {} moved",
        depth.deepest, report.bodies_moved
    );
    assert_untouched(&scene, &before, &untouched);
    // The baseline's known weakness: the contacts and the joints pull
    // against each other one row at a time, and the error falls only
    // linearly (measured when this was written: 300 sweeps leave the
    // depth at 9.1e-7 and the joints at 6.7e-7, tolerance 1.9e-7, where
    // the projection converges in a few passes). What it guarantees: a
    // converged call is within the tolerance; otherwise the sweeps run
    // out with both errors far below the input's and never above it.
    match report.status {
        Status::Converged => {
            assert!(depth.resolved(), "depth {:e}", depth.deepest);
            assert!(
                joint_error <= report.tolerance,
                "joint error {joint_error:e}"
            );
        }
        status => {
            assert_eq!(status, Status::PassLimit);
            assert_eq!(report.passes, CHAIN_SWEEPS);
            assert!(
                depth.deepest <= CHAIN_REDUCTION * depth_before,
                "depth {:e}",
                depth.deepest
            );
            assert!(
                joint_error <= CHAIN_REDUCTION * SUNK,
                "joint error {joint_error:e}"
            );
        }
    }
    assert!(!report.restored_input);
    assert!(report.depth_after <= report.depth_before);
    assert!(report.joint_error_after <= report.joint_error_before.max(report.tolerance));
    // The lift spread along the chain through the joints.
    assert!(report.bodies_moved >= 3, "{}", report.bodies_moved);
}

#[test]
fn a_jointed_scene_within_the_tolerance_is_not_touched() {
    let mut scene = Scene::new();
    scene.add_body(ground()).expect("valid ground");
    chain_on_ground(&mut scene, 4, usize::MAX, 0.0);
    let before = pose_bits(&scene);
    let report = run(&mut scene, baseline(JOINT_SWEEPS));
    assert_eq!(report.status, Status::NothingToDo);
    assert_eq!(pose_bits(&scene), before);
}
