//! Scale invariance at the extremes: one scene (a stack of three boxes and
//! a turned box sunk into the ground and against the stack) at scales 1e-4
//! and 1e4 must take the same passes and end at the poses of scale 1
//! multiplied by the scale; offset by 1e5 from the origin it must take the
//! same passes and end at the same poses plus the offset, to the rounding
//! of the offset. Scales 1e-3 and 1e3 are in `scenes`.
//!
//! `where_f64_runs_out` stabilizes the scene at larger offsets and more
//! extreme scales and prints what happens (`-- --nocapture`); it asserts
//! only what must hold everywhere (no NaN; never deeper than the input by
//! the library's measure; at scales, a converged status backed by the
//! oracle), not where convergence stops. Far from the origin the oracle
//! and the library round world vertices differently, so there only the
//! library's own measure is asserted.

use crate::stabilize::extreme::{Run, assert_converged, run, run_unchecked, stack};
use constraint_stabilization::body::{BodyDesc, MassSpec};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Settings, Status};
use dev_support::scene::{cuboid, scaled, xyzw};
use nalgebra::{UnitQuaternion, Vector3};

/// Relative agreement of a scaled run with the reference (rounding only:
/// the stabilizer works in units of the scene's scale).
const SCALE_AGREEMENT: f64 = 1e-6;

/// Offset of the whole scene in `scene_far_from_the_origin`.
const OFFSET: f64 = 1e5;

/// Agreement of the offset run with the reference, in units of the
/// offset's rounding (`OFFSET * f64::EPSILON`, 1.5e-11 at 1e5): every
/// position carries that error, and the passes amplify it by the
/// conditioning of the contacts.
const OFFSET_ROUNDINGS: f64 = 1e4;

fn scene() -> Vec<BodyDesc> {
    let turned = UnitQuaternion::from_scaled_axis(Vector3::new(0.2, 0.4, 0.1));
    let mut descs = stack(&[MassSpec::Density(1.0); 3], 0.01);
    descs.push(cuboid(
        "turned",
        [0.3, 0.2, 0.25],
        [0.75, 0.25, 0.1],
        xyzw(&turned),
        MassSpec::Density(2.0),
    ));
    descs
}

fn offset(desc: &BodyDesc, by: f64) -> BodyDesc {
    let mut desc = desc.clone();
    desc.translation += Vector3::repeat(by);
    desc
}

#[test]
fn scales_1e_minus_4_and_1e4_scale_the_answer() {
    let reference = run("scale 1", &scene(), Settings::default());
    assert_converged("scale 1", &reference, 10);
    for s in [1e-4, 1e4] {
        let label = format!("scale {s:e}");
        let descs: Vec<_> = scene().iter().map(|d| scaled(d, s)).collect();
        let run = run(&label, &descs, Settings::default());
        assert_converged(&label, &run, 10);
        assert_eq!(run.report.passes, reference.report.passes, "{label}");
        for (a, b) in reference.scene.bodies().iter().zip(run.scene.bodies()) {
            let dt = (b.translation_user() / s - a.translation_user()).norm();
            let angle = a.user_pose().rotation.angle_to(&b.user_pose().rotation);
            assert!(
                dt <= SCALE_AGREEMENT && angle <= SCALE_AGREEMENT,
                "{label}: {} differs by {dt:e} (scaled back), {angle:e} rad",
                a.name()
            );
        }
    }
}

#[test]
fn scene_far_from_the_origin() {
    let reference = run("offset 0", &scene(), Settings::default());
    let descs: Vec<_> = scene().iter().map(|d| offset(d, OFFSET)).collect();
    let label = format!("offset {OFFSET:e}");
    let run = run(&label, &descs, Settings::default());
    assert_converged(&label, &run, 10);
    assert_eq!(run.report.passes, reference.report.passes);
    let allowed = OFFSET_ROUNDINGS * OFFSET * f64::EPSILON;
    for (a, b) in reference.scene.bodies().iter().zip(run.scene.bodies()) {
        let dt = (b.translation_user() - Vector3::repeat(OFFSET) - a.translation_user()).norm();
        let angle = a.user_pose().rotation.angle_to(&b.user_pose().rotation);
        println!("{}: differs by {dt:e}, {angle:e} rad", a.name());
        assert!(
            dt <= allowed && angle <= allowed,
            "{}: differs by {dt:e}, {angle:e} rad (allowed {allowed:e})",
            a.name()
        );
    }
}

#[test]
fn where_f64_runs_out() {
    let tolerance = Settings::default().tolerance_relative;
    for by in [1e9, 1e11, 1e12, 1e13, 1e14] {
        let descs: Vec<_> = scene().iter().map(|d| offset(d, by)).collect();
        let run = run_unchecked(&format!("offset {by:e}"), &descs, Settings::default());
        assert!(run.report.depth_after <= run.report.depth_before);
        let rounding = by * f64::EPSILON;
        println!("  position rounding {rounding:.1e}, tolerance {tolerance:.1e} of the scale");
    }
    for s in [
        1e-10, 1e-15, 1e-20, 1e-25, 1e-30, 1e20, 1e30, 1e35, 1e40, 1e45,
    ] {
        let descs: Vec<_> = scene().iter().map(|d| scaled(d, s)).collect();
        // Beyond the geometry's range the bodies are rejected (a typed
        // error, `GeometryError::CoordinatesOutOfRange`).
        let mut rejected = Scene::new();
        if let Some(error) = descs
            .iter()
            .find_map(|d| rejected.add_body(d.clone()).err())
        {
            println!("scale {s:e}: rejected: {error}");
            continue;
        }
        check_resolved_status(&run(&format!("scale {s:e}"), &descs, Settings::default()));
    }
}

/// A resolved status must be true by the oracle.
fn check_resolved_status(run: &Run) {
    if run.report.status == Status::Converged {
        assert!(run.depth_after <= run.report.tolerance * (1.0 + SCALE_AGREEMENT));
    }
}
