//! The joints of a scene as the call sees them: their body pairs for the
//! islands, their errors at the scene's poses for the stop rule and the
//! report, and each island's joints for its provider.

use crate::Error;
use crate::broad_phase::BodyPair;
use crate::contact::{Detection, Island, islands_with_joints};
use crate::joints::{IslandJoints, JointErrors, island_joints::JointBody};
use crate::scene::Scene;
use crate::settings::ResolvedLengths;

use super::report::JointReport;

/// The body pair of every joint of `scene`, in joint order (the smaller
/// index first).
pub(crate) fn joint_pairs(scene: &Scene) -> Vec<BodyPair> {
    scene
        .joints()
        .iter()
        .map(|joint| BodyPair {
            body_a: joint.body_a.min(joint.body_b),
            body_b: joint.body_a.max(joint.body_b),
        })
        .collect()
}

/// The islands of `detection`'s active pairs and `scene`'s joints that
/// have a penetration or a joint error (`joints`, at the detection's
/// poses) beyond the tolerance, in island order, and the number of
/// islands in all.
pub(crate) fn violated_islands(
    scene: &Scene,
    detection: &Detection,
    joints: &[JointErrors],
    lengths: &ResolvedLengths,
) -> Result<(Vec<Island>, usize), Error> {
    let all_islands = islands_with_joints(
        &scene.fixed_flags(),
        &detection.active_bodies,
        &joint_pairs(scene),
    )?;
    let count = all_islands.len();
    let joint_violated = |j: &usize| joints[*j].largest(lengths.scale) > lengths.tolerance;
    let violated = all_islands
        .into_iter()
        .filter(|island| {
            detection.island_penetrates(island, lengths.tolerance)
                || island.joints.iter().any(joint_violated)
        })
        .collect();
    Ok((violated, count))
}

/// The errors of every joint at the scene's poses.
pub(crate) fn joint_errors(scene: &Scene) -> Result<Vec<JointErrors>, Error> {
    scene
        .joints()
        .iter()
        .map(|joint| {
            let (a, b) = (scene.body(joint.body_a)?, scene.body(joint.body_b)?);
            Ok(JointErrors::in_scene(joint, a, b))
        })
        .collect()
}

/// The largest joint error in length units (angles times `scale`).
pub(crate) fn largest_joint_error(errors: &[JointErrors], scale: f64) -> f64 {
    errors.iter().fold(0.0, |m, e| m.max(e.largest(scale)))
}

/// The joints' part of the merit: `sum (error - tolerance)^2` over the
/// joints whose largest error (length units, angles times `scale`)
/// exceeds the tolerance, as [`super::Report::merit`] counts penetrations.
pub(crate) fn joint_merit(errors: &[JointErrors], scale: f64, tolerance: f64) -> f64 {
    errors
        .iter()
        .map(|e| (e.largest(scale) - tolerance).max(0.0).powi(2))
        .sum()
}

/// One report line per joint, from its errors before and after the call.
pub(crate) fn joint_reports(
    scene: &Scene,
    before: &[JointErrors],
    after: &[JointErrors],
) -> Vec<JointReport> {
    scene
        .joints()
        .iter()
        .zip(before.iter().zip(after))
        .enumerate()
        .map(|(index, (joint, (before, after)))| JointReport {
            index,
            name: joint.name.clone(),
            kind: joint.kind.name(),
            body_a: joint.body_a,
            body_b: joint.body_b,
            before: *before,
            after: *after,
        })
        .collect()
}

/// The joints `indices` of `scene` for an island whose configuration holds
/// `moving` (ascending scene indices); every other body is held where it
/// is.
pub(crate) fn island_joints(
    scene: &Scene,
    indices: &[usize],
    moving: &[usize],
    scale: f64,
    margin: f64,
) -> Result<IslandJoints, Error> {
    let mut joints = Vec::with_capacity(indices.len());
    for &index in indices {
        let joint = scene.joints()[index].clone();
        let end = |body: usize| -> Result<JointBody, Error> {
            let b = scene.body(body)?;
            Ok(JointBody {
                slot: moving.binary_search(&body).ok(),
                com_pose: *b.com_pose(),
                com_offset: *b.com_offset(),
            })
        };
        let ends = [end(joint.body_a)?, end(joint.body_b)?];
        joints.push((index, joint, ends));
    }
    Ok(IslandJoints::new(joints, scale, margin))
}
