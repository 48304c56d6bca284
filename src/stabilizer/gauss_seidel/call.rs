//! A stabilization call by nonlinear Gauss–Seidel: sweeps until the
//! deepest penetration is within the tolerance or the sweeps run out.
//!
//! Each sweep starts with a detection at the current poses (the
//! projection's: broad phase, V-Clip, exact depth); it is the measurement
//! of the configuration the previous sweep reached, so the call keeps the
//! best configuration measured (least merit, `sum (depth - tolerance)^2`,
//! among those no deeper than the input) without measuring anything twice,
//! and returns it: never worse than its input. Then the sweep visits the
//! contact points ([`super::contacts`]) and moves the bodies
//! ([`super::sweep`]). After the last sweep one more detection measures
//! the result.
//!
//! Status: [`Status::NothingToDo`] when the input is within the tolerance,
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
    let fixed = scene.fixed_flags();
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
            let summary = bodies.sweep(&contacts.points, parameters);
            report.times.solve += solve_start.elapsed().as_secs_f64();
            report.passes += 1;
            log::debug!(
                "gauss-seidel sweep {} on the stored points: {} visited, {} pushed",
                report.passes,
                summary.visited,
                summary.pushed
            );
            if summary.pushed == 0 {
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
        };
        let detection = detect(scene, geometry, state, &vclip, lengths)?;
        report.record_detection(&detection);
        let mut pass = pass_report(&detection, lengths.tolerance);
        let solve_start = Instant::now();
        let next = match stop_status(&report, &detection, settings, start) {
            Some(status) => Next::Stop(status),
            None => Next::Sweep(sweep_points(
                geometry,
                &bodies.poses,
                &fixed,
                &detection,
                lengths,
                settings,
            )?),
        };
        keep_if_best(&mut best, &report, &bodies.poses, detection);
        let contacts = match next {
            Next::Sweep(contacts) => contacts,
            Next::Stop(status) => {
                log::debug!(
                    "gauss-seidel stop: deepest penetration {:.3e}, tolerance {:.1e}: {}",
                    pass.deepest,
                    lengths.tolerance,
                    status.name()
                );
                report.pass_reports.push(pass);
                report.status = status;
                break;
            }
        };
        pass.islands = contacts.islands;
        let summary = bodies.sweep(&contacts.points, parameters);
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

/// The status that ends the call after a sweep's detection, if any: within
/// the tolerance, out of sweeps, or out of time.
fn stop_status(
    report: &Report,
    detection: &Detection,
    settings: &Settings,
    start: Instant,
) -> Option<Status> {
    Status::after_detection(
        detection.deepest,
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

/// Makes `detection` (at `poses`) the best if it is no deeper than the
/// input and has a smaller merit than the best so far (the first one is the
/// input's, kept whatever it is).
fn keep_if_best(
    best: &mut Option<Best>,
    report: &Report,
    poses: &[Isometry3<f64>],
    detection: Detection,
) {
    let merit = Report::merit(&detection.penetrations, report.tolerance);
    let better = match best {
        None => true,
        Some(kept) => detection.deepest <= report.depth_before && merit < kept.merit,
    };
    if better {
        *best = Some(Best {
            sweeps: report.passes,
            merit,
            poses: poses.to_vec(),
            detection,
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
        "gauss-seidel sweep {number}: {} active pairs, {} penetrating, deepest {:.3e}; \
         {} points visited, {} pushed, least separation {:.3e}, {:.3} ms so far",
        pass.active_pairs,
        pass.penetrating_pairs,
        pass.deepest,
        summary.visited,
        summary.pushed,
        summary.min_separation,
        start.elapsed().as_secs_f64() * 1e3
    );
}
