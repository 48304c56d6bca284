//! Two settings of a call: the time budget (`Settings::time_budget`,
//! status `TimeLimit`, never worse than the input) and the allowed
//! penetration (`Settings::allowed_penetration`: depths up to it accepted,
//! deeper ones brought back to about it, validated). Depths are measured
//! by the brute-force separating-axis oracle.

use crate::stabilize::support::stabilize_with;
use dev_support::sat::sat_deepest;
use dev_support::scene::{cuboid, ground, pose_bits, scene_of, unit_cube_sunk, xyzw};
use std::time::Duration;

use constraint_stabilization::SettingsError;
use constraint_stabilization::body::MassSpec;
use constraint_stabilization::{Error, Settings, Stabilizer, Status};
use nalgebra::{UnitQuaternion, Vector3};

/// A leaning stack of six cubes, each tilted 0.3 rad the other way from
/// the one below and sunk 0.3 into it: the corrections turn the cubes,
/// and the linearization of those turns needs several passes.
fn leaning_stack() -> constraint_stabilization::scene::Scene {
    let mut descs = vec![ground()];
    for k in 0..6 {
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        let tilt = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.3 * sign);
        descs.push(cuboid(
            &format!("cube {k}"),
            [0.5, 0.5, 0.5],
            [0.1 * sign, 0.4 + 0.7 * k as f64, 0.0],
            xyzw(&tilt),
            MassSpec::Mass(1.0 + k as f64),
        ));
    }
    scene_of(&descs)
}

#[test]
fn zero_budget_stops_after_the_first_pass_no_worse_than_the_input() {
    let mut full = leaning_stack();
    let (unlimited, _) = stabilize_with(&mut full, Settings::default());
    println!(
        "unlimited: {:?} after {} passes",
        unlimited.status, unlimited.passes
    );
    assert_eq!(unlimited.status, Status::Converged);
    assert!(unlimited.passes > 1, "the scene must need several passes");

    let mut scene = leaning_stack();
    let (depth_before, _) = sat_deepest(&scene);
    let settings = {
        let mut settings = Settings::default();
        settings.time_budget = Some(Duration::ZERO);
        settings
    };
    let (report, _) = stabilize_with(&mut scene, settings);
    let (depth_after, _) = sat_deepest(&scene);
    assert_eq!((report.status, report.passes), (Status::TimeLimit, 1));
    assert!(!report.status.is_resolved());
    assert!(
        depth_after <= depth_before,
        "{depth_before:e} -> {depth_after:e}"
    );
    assert!(depth_after > report.tolerance, "a penetration is left");
    assert_eq!(report.status.name(), "time_limit");
}

/// A budget that is not spent changes nothing: the same poses, bit for
/// bit, as without one (clarabel's time limit is only a limit).
#[test]
fn unspent_budget_gives_the_unlimited_answer() {
    let mut unlimited = leaning_stack();
    stabilize_with(&mut unlimited, Settings::default());
    let mut budgeted = leaning_stack();
    let settings = {
        let mut settings = Settings::default();
        settings.time_budget = Some(Duration::from_secs(3600));
        settings
    };
    let (report, _) = stabilize_with(&mut budgeted, settings);
    assert_eq!(report.status, Status::Converged);
    assert_eq!(pose_bits(&budgeted), pose_bits(&unlimited));
}

/// A zero budget is every solver's deadline from the start of the call:
/// the first pass detects, its solver stops at once, nothing moves (poses
/// bit-identical) and the call says the budget stopped it.
#[test]
fn zero_budget_stops_every_solver_and_returns_the_input() {
    let mut scene = scene_of(&[ground(), unit_cube_sunk("cube", 0.1)]);
    let before = pose_bits(&scene);
    let settings = {
        let mut settings = Settings::default();
        settings.time_budget = Some(Duration::ZERO);
        settings
    };
    let (report, _) = stabilize_with(&mut scene, settings);
    assert_eq!((report.status, report.passes), (Status::TimeLimit, 1));
    assert_eq!(pose_bits(&scene), before);
}

/// The allowed penetration of the tests: 1 mm, a thousand times the
/// default tolerance of the unit cube.
const ALLOWED: f64 = 1e-3;

fn allowing() -> Settings {
    {
        let mut settings = Settings::default();
        settings.allowed_penetration = ALLOWED;
        settings
    }
}

#[test]
fn penetration_within_the_allowed_one_is_not_touched() {
    let mut scene = scene_of(&[ground(), unit_cube_sunk("cube", 0.5 * ALLOWED)]);
    let before = pose_bits(&scene);
    let (report, _) = stabilize_with(&mut scene, allowing());
    assert_eq!(report.status, Status::NothingToDo);
    assert_eq!(pose_bits(&scene), before);
    assert_eq!(report.allowed_penetration, ALLOWED);
}

/// Sunk by 0.1, the cube is lifted to the allowed depth less the target
/// margin (exact for a translation): within the allowed depth plus the
/// tolerance, and not at zero.
#[test]
fn deeper_penetration_is_brought_back_to_the_allowed_one() {
    let mut scene = scene_of(&[ground(), unit_cube_sunk("cube", 0.1)]);
    let (report, _) = stabilize_with(&mut scene, allowing());
    let (depth, _) = sat_deepest(&scene);
    let plain_tolerance = report.tolerance - ALLOWED;
    let target = Settings::default().target_margin_relative * report.scale;
    assert_eq!(report.status, Status::Converged);
    assert!(depth <= report.tolerance, "depth {depth:e}");
    assert!(
        depth >= ALLOWED - target - plain_tolerance,
        "depth {depth:e}"
    );
}

#[test]
fn allowed_penetration_must_be_finite_and_non_negative() {
    for value in [-1e-3, f64::NAN, f64::INFINITY] {
        let settings = {
            let mut settings = Settings::default();
            settings.allowed_penetration = value;
            settings
        };
        let error = Stabilizer::new(settings).expect_err("invalid allowed penetration");
        assert!(
            matches!(
                error,
                Error::Settings(SettingsError::OutOfRange {
                    field: "allowed_penetration",
                    ..
                })
            ),
            "{value}: {error}"
        );
    }
}
