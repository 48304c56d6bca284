//! Shared checks of the stiff, extreme and infeasible scene tests
//! (`stiff`, `deep`, `infeasible`): run one
//! call and judge it by the brute-force separating-axis oracle
//! (`dev_support::sat::sat_deepest`), which the library did not write.
//!
//! Every run checks what must hold whatever the scene: no NaN, the exact
//! deepest penetration after the call equals the report's (to
//! [`DEPTH_AGREEMENT`] of the scene's scale) and is never above the input's,
//! and the merit of the report never rises. The tests then assert the
//! status and, where it is known in closed form, the motion.
#![allow(dead_code)]

use crate::stabilize::support::describe;
use constraint_stabilization::body::{BodyDesc, MassSpec};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Report, Settings, Stabilizer, Status};
use dev_support::sat::sat_deepest;
use dev_support::scene::{IDENTITY_XYZW, assert_finite, cuboid, ground, scene_of};
use nalgebra::Vector3;

/// The report's deepest penetration and the oracle's agree to this
/// fraction of the scene's length scale (both are exact depths; they
/// differ by rounding of world vertices only).
pub const DEPTH_AGREEMENT: f64 = 1e-9;

/// A body's motion agrees with its closed form to this fraction of that
/// motion (as in `scenes`).
pub const RELATIVE_MOTION: f64 = 0.01;

/// One call and what the oracle says of it.
pub struct Run {
    /// The scene before the call.
    pub input: Scene,
    /// The scene after the call.
    pub scene: Scene,
    /// The call's report.
    pub report: Report,
    /// Exact deepest penetration before the call (oracle).
    pub depth_before: f64,
    /// Exact deepest penetration after the call (oracle).
    pub depth_after: f64,
}

/// Builds the scene, stabilizes it with `settings`, prints one line, and
/// checks the properties of the module docs.
pub fn run(label: &str, descs: &[BodyDesc], settings: Settings) -> Run {
    let run = run_unchecked(label, descs, settings);
    check_run(label, &run.report, run.depth_before, run.depth_after);
    run
}

/// [`run`] without the oracle's checks (no NaN is still checked): for
/// measurements where rounding makes the oracle and the library disagree.
pub fn run_unchecked(label: &str, descs: &[BodyDesc], settings: Settings) -> Run {
    let input = scene_of(descs);
    let mut scene = input.clone();
    let (depth_before, _) = sat_deepest(&scene);
    let report = run_scene(label, &mut scene, settings);
    let (depth_after, _) = sat_deepest(&scene);
    println!(
        "{}; oracle depth {depth_before:.3e} -> {depth_after:.3e}",
        describe(label, &report, depth_after)
    );
    Run {
        input,
        scene,
        report,
        depth_before,
        depth_after,
    }
}

/// One call with `settings`; panics on an error (the scenes are valid
/// input) and on a non-finite pose.
pub fn run_scene(label: &str, scene: &mut Scene, settings: Settings) -> Report {
    let mut stabilizer = Stabilizer::new(settings).expect("valid settings");
    let report = stabilizer
        .stabilize(scene)
        .unwrap_or_else(|e| panic!("{label}: the call failed: {e}"));
    assert_finite(scene);
    report
}

/// The properties every run must have (module docs).
pub fn check_run(label: &str, report: &Report, depth_before: f64, depth_after: f64) {
    let slack = DEPTH_AGREEMENT * report.scale;
    assert!(
        (report.depth_after.max(0.0) - depth_after).abs() <= slack,
        "{label}: report says depth {:e} after, oracle {depth_after:e}",
        report.depth_after
    );
    assert!(
        depth_after <= depth_before + slack,
        "{label}: deeper after ({depth_after:e}) than before ({depth_before:e})"
    );
    let merit = |p| Report::merit(p, report.tolerance);
    assert!(
        merit(&report.penetrations_after) <= merit(&report.penetrations_before),
        "{label}: the merit rose"
    );
}

/// Asserts that the call converged: status, and the oracle's depth within
/// the tolerance.
pub fn assert_converged(label: &str, run: &Run, max_passes: usize) {
    assert_eq!(run.report.status, Status::Converged, "{label}");
    assert!(
        run.depth_after <= run.report.tolerance,
        "{label}: exact depth {:e} above the tolerance {:e}",
        run.depth_after,
        run.report.tolerance
    );
    assert!(
        run.report.passes <= max_passes,
        "{label}: {} passes, at most {max_passes} expected",
        run.report.passes
    );
}

/// Asserts that body `index` moved by `expected` from its input pose (to
/// [`RELATIVE_MOTION`] of the motion) without turning (beyond the angle
/// that moves its farthest point by that fraction).
pub fn assert_translated(run: &Run, index: usize, expected: Vector3<f64>) {
    let (before, body) = (&run.input.bodies()[index], &run.scene.bodies()[index]);
    let moved = body.translation_user() - before.translation_user();
    let allowed = RELATIVE_MOTION * expected.norm();
    assert!(
        (moved - expected).norm() <= allowed,
        "{}: moved {moved:?}, expected {expected:?}",
        body.name()
    );
    let turned = body
        .user_pose()
        .rotation
        .angle_to(&before.user_pose().rotation);
    assert!(
        turned <= allowed / body.polyhedron().expect("a convex body").scale(),
        "{}: turned by {turned:e} rad",
        body.name()
    );
}

/// The target margin of the default settings at the run's scale.
pub fn target_margin(run: &Run) -> f64 {
    Settings::default().target_margin_relative * run.report.scale
}

/// Unit boxes stacked on the ground, one per mass, each sunk by `overlap`
/// into the one below (the lowest into the ground).
pub fn stack(masses: &[MassSpec], overlap: f64) -> Vec<BodyDesc> {
    let mut descs = vec![ground()];
    for (k, &mass) in masses.iter().enumerate() {
        let at = [0.0, stack_height(k, overlap), 0.0];
        descs.push(cuboid(
            &format!("box{k}"),
            [0.5; 3],
            at,
            IDENTITY_XYZW,
            mass,
        ));
    }
    descs
}

/// Height of box `k` of [`stack`].
pub fn stack_height(k: usize, overlap: f64) -> f64 {
    0.5 - overlap + k as f64 * (1.0 - overlap)
}
