//! A stabilization call by nonlinear Gauss–Seidel: sweeps until the
//! deepest penetration and the largest joint error are within the
//! tolerance or the sweeps run out.
//!
//! Each sweep starts with a detection at the current poses (the
//! projection's: broad phase, V-Clip, exact depth); it is the measurement
//! of the configuration the previous sweep reached, so the call keeps the
//! best configuration measured (least merit, `sum (depth - tolerance)^2`
//! over the penetrations plus `sum (error - tolerance)^2` over the joints,
//! among those no deeper than the input and with no joint error beyond the
//! input's or the tolerance) without measuring anything twice, and returns
//! it: never worse than its input. Then the sweep visits the contact
//! points and the joints ([`super::contacts`]) and moves the bodies
//! ([`super::sweep`], [`super::joints`]). After the last sweep one more detection measures
//! the result.
//!
//! Status (joint errors counted with the depth): [`Status::NothingToDo`]
//! when the input is within the tolerance,
//! [`Status::Converged`] when a sweep's detection is, else
//! [`Status::PassLimit`] after `iterations` sweeps (or
//! [`Status::TimeLimit`] when [`Settings::time_budget`] is spent after a
//! sweep). [`Report::passes`] counts sweeps; each [`PassReport`] is the
//! detection at a sweep's start (no island reports: nothing is solved).

use std::time::Instant;

use nalgebra::{Isometry3, Vector3};

use super::contacts::{SweepContacts, sweep_points};
use super::sweep::{InverseMass, PushParameters, SweepBodies, SweepSummary};
use crate::Error;
use crate::broad_phase::IncrementalBroadPhase;
use crate::contact::{
    Detection, DetectionState, QueryMemo, SceneGeometry, SceneParts, WarmStartCache, detect,
};
use crate::scene::Scene;
use crate::settings::{ResolvedLengths, Settings};
use crate::stabilizer::joint_state::{joint_errors, joint_merit, largest_joint_error};
use crate::stabilizer::{PassReport, Report, Status, pass_report};
use crate::vclip::VClip;

/// The poses of a call's result and the detection made at them.
pub type MeasuredPoses = (Vec<Isometry3<f64>>, Detection);

/// What follows a sweep's detection.
enum Next {
    /// The call ends with this status.
    Stop(Status),
    /// A sweep over these contacts.
    Sweep(SweepContacts),
}

/// The best configuration measured so far.
struct Best {
    /// Sweeps done when it was measured (0: the input).
    sweeps: usize,
    merit: f64,
    poses: Vec<Isometry3<f64>>,
    detection: Detection,
}

/// Corrects `scene` by nonlinear Gauss–Seidel sweeps
/// ([`crate::stabilizer::Method::GaussSeidel`]); returns the report (its
/// displacement, bodies moved and total time are the caller's) and the
/// result's poses with their detection.
pub fn run(
    scene: &mut Scene,
    settings: &Settings,
    lengths: &ResolvedLengths,
    cache: &mut WarmStartCache,
    start: Instant,
    observer: &mut dyn FnMut(&PassReport),
) -> Result<(Report, MeasuredPoses), Error> {
    let gauss_seidel = settings.gauss_seidel;
    let parameters = PushParameters {
        baumgarte: gauss_seidel.baumgarte,
        slop: lengths.gauss_seidel_slop,
        max_correction: lengths.gauss_seidel_max_correction,
    };
    let vclip = VClip::new(settings.vclip);
    let parts = SceneParts::of(scene);
    let mut bodies = sweep_bodies(scene);
    let input = InputPoses::of(scene);
    let mut report = Report::new(lengths);
    let mut memo = QueryMemo::default();
    let mut broad_phase = IncrementalBroadPhase::new();
    let mut best: Option<Best> = None;
    // The contacts of the first sweep, kept when they are detected once.
    let mut stored: Option<SweepContacts> = None;
    loop {
        if let Some(contacts) = stored
            .as_ref()
            .filter(|_| report.passes < gauss_seidel.iterations && !budget_spent(settings, start))
        {
            let solve_start = Instant::now();
            let summary = bodies.sweep(&contacts.points, &contacts.joints, parameters);
            report.times.solve += solve_start.elapsed().as_secs_f64();
            report.passes += 1;
            log::debug!(
                "gauss-seidel sweep {} on the stored points: {} visited, {} pushed; {} joint rows, {} relaxed",
                report.passes,
                summary.visited,
                summary.pushed,
                summary.joint_rows,
                summary.joint_relaxed
            );
            if !summary.moved() {
                // Nothing moved: further sweeps would repeat this one.
                stored = None;
            }
            continue;
        }
        // The scene follows the sweeps before each detection (its broad
        // phase reads the bodies' poses), not after every stored sweep.
        write_poses(scene, &bodies.poses)?;
        let part_poses = parts.poses(&bodies.poses);
        let geometry = SceneGeometry {
            parts: &parts,
            poses: &part_poses,
        };
        let state = DetectionState {
            broad_phase: &mut broad_phase,
            cache,
            memo: &mut memo,
            certificates: None,
            kept_pairs: &[],
        };
        let detection = detect(scene, geometry, state, &vclip, lengths)?;
        report.record_detection(&detection);
        let joints = joint_errors(scene)?;
        let mut pass = pass_report(&detection, lengths.tolerance);
        pass.joint_error = largest_joint_error(&joints, lengths.scale);
        if report.passes == 0 {
            // The input's, as the stabilizer measures it again after the call.
            report.joint_error_before = pass.joint_error;
        }
        let solve_start = Instant::now();
        let next = match stop_status(&report, &pass, settings, start) {
            Some(status) => Next::Stop(status),
            None => Next::Sweep(sweep_points(
                scene,
                geometry,
                &bodies.poses,
                &detection,
                &joints,
                lengths,
                settings,
            )?),
        };
        let measured = Measured {
            joint_error: pass.joint_error,
            merit: Report::merit(&detection.penetrations, report.tolerance)
                + joint_merit(&joints, lengths.scale, report.tolerance),
            detection,
        };
        keep_if_best(&mut best, &report, &bodies.poses, measured);
        let contacts = match next {
            Next::Sweep(contacts) => contacts,
            Next::Stop(status) => {
                log::debug!(
                    "gauss-seidel stop: deepest penetration {:.3e}, largest joint error {:.3e}, tolerance {:.1e}: {}",
                    pass.deepest,
                    pass.joint_error,
                    lengths.tolerance,
                    status.name()
                );
                report.pass_reports.push(pass);
                report.status = status;
                break;
            }
        };
        pass.islands = contacts.islands;
        let summary = bodies.sweep(&contacts.points, &contacts.joints, parameters);
        if !gauss_seidel.detect_every_sweep {
            stored = Some(contacts);
        }
        report.times.solve += solve_start.elapsed().as_secs_f64();
        report.passes += 1;
        log_sweep(report.passes, &pass, &summary, start);
        observer(&pass);
        report.pass_reports.push(pass);
    }
    // `keep_if_best` keeps the first detection it is given, and every
    // run of the loop gives it one: `best` is set.
    let best = best.expect("the input's detection is kept");
    finish(scene, report, best, &input)
}

/// The poses of the bodies before the call: COM poses, and the user poses
/// they were computed from (so that a body put back is bit-identical).
struct InputPoses {
    com: Vec<Isometry3<f64>>,
    user: Vec<(Vector3<f64>, [f64; 4])>,
}

impl InputPoses {
    fn of(scene: &Scene) -> Self {
        InputPoses {
            com: scene.bodies().iter().map(|b| *b.com_pose()).collect(),
            user: scene
                .bodies()
                .iter()
                .map(|b| (*b.translation_user(), b.rotation_user_xyzw()))
                .collect(),
        }
    }
}

/// The status that ends the call after a sweep's detection (`pass`, with
/// its joint error), if any: the deepest penetration and the largest joint
/// error within the tolerance, out of sweeps, or out of time.
fn stop_status(
    report: &Report,
    pass: &PassReport,
    settings: &Settings,
    start: Instant,
) -> Option<Status> {
    Status::after_detection(
        pass.deepest.max(pass.joint_error),
        report.tolerance,
        report.passes,
        settings.gauss_seidel.iterations,
        || budget_spent(settings, start),
    )
}

/// Whether the time budget is spent.
fn budget_spent(settings: &Settings, start: Instant) -> bool {
    settings
        .time_budget
        .is_some_and(|budget| start.elapsed() >= budget)
}

/// The poses and inverse masses of the scene's bodies.
fn sweep_bodies(scene: &Scene) -> SweepBodies {
    SweepBodies {
        poses: scene.bodies().iter().map(|b| *b.com_pose()).collect(),
        inverse_masses: scene
            .bodies()
            .iter()
            .map(|b| {
                b.mass().map(|m| InverseMass {
                    mass: 1.0 / m.mass,
                    inertia_body: m.inverse_inertia_body,
                })
            })
            .collect(),
    }
}

/// A configuration as a sweep's detection measured it.
struct Measured {
    /// The largest joint error (length units).
    joint_error: f64,
    /// Penetrations' and joints' merit together.
    merit: f64,
    detection: Detection,
}

/// Makes `measured` (at `poses`) the best if it is no deeper than the
/// input, has no joint error beyond the input's or the tolerance, and has
/// a smaller merit than the best so far (the first one is the input's,
/// kept whatever it is): the stabilizer's own test of a result worse than
/// its input.
fn keep_if_best(
    best: &mut Option<Best>,
    report: &Report,
    poses: &[Isometry3<f64>],
    measured: Measured,
) {
    let better = match best {
        None => true,
        Some(kept) => {
            measured.detection.deepest <= report.depth_before
                && measured.joint_error <= report.joint_error_before.max(report.tolerance)
                && measured.merit < kept.merit
        }
    };
    if better {
        *best = Some(Best {
            sweeps: report.passes,
            merit: measured.merit,
            poses: poses.to_vec(),
            detection: measured.detection,
        });
    }
}

/// Moves every body whose pose changed to its pose in `poses`.
fn write_poses(scene: &mut Scene, poses: &[Isometry3<f64>]) -> Result<(), Error> {
    for (body, pose) in scene.bodies_mut().iter_mut().zip(poses) {
        if body.com_pose() != pose {
            body.set_com_pose(*pose)?;
        }
    }
    Ok(())
}

/// Moves every body whose pose differs from `poses` to it: a body sent back
/// to its input pose gets its input user pose back, bit for bit (as the
/// stabilizer's own restore does); a body at its pose is not touched.
fn restore_poses(
    scene: &mut Scene,
    poses: &[Isometry3<f64>],
    input: &InputPoses,
) -> Result<(), Error> {
    for (i, (body, pose)) in scene.bodies_mut().iter_mut().zip(poses).enumerate() {
        if body.com_pose() == pose {
            continue;
        }
        if *pose == input.com[i] {
            let (translation, rotation_xyzw) = input.user[i];
            body.set_user_pose(translation, rotation_xyzw)?;
        } else {
            body.set_com_pose(*pose)?;
        }
    }
    Ok(())
}

/// Puts the best configuration in the scene when a later sweep was worse,
/// and makes the report's depth after its depth.
fn finish(
    scene: &mut Scene,
    mut report: Report,
    best: Best,
    input: &InputPoses,
) -> Result<(Report, MeasuredPoses), Error> {
    if best.sweeps < report.passes {
        log::debug!(
            "gauss-seidel: the configuration after sweep {} (merit {:.3e}) is kept, the last one was worse",
            best.sweeps,
            best.merit
        );
        restore_poses(scene, &best.poses, input)?;
        report.depth_after = best.detection.deepest;
        report.penetrations_after = best.detection.penetrations.clone();
        report.restored_input = best.sweeps == 0;
    }
    Ok((report, (best.poses, best.detection)))
}

/// The debug line of a sweep.
fn log_sweep(number: usize, pass: &PassReport, summary: &SweepSummary, start: Instant) {
    log::debug!(
        "gauss-seidel sweep {number}: {} active pairs, {} penetrating, deepest {:.3e}, joint error {:.3e}; \
         {} points visited, {} pushed, least separation {:.3e}; {} joint rows, {} relaxed, largest met {:.3e}; \
         {:.3} ms so far",
        pass.active_pairs,
        pass.penetrating_pairs,
        pass.deepest,
        pass.joint_error,
        summary.visited,
        summary.pushed,
        summary.min_separation,
        summary.joint_rows,
        summary.joint_relaxed,
        summary.joint_error,
        start.elapsed().as_secs_f64() * 1e3
    );
}
