//! Rapier's joints read into scene joints.
//!
//! An impulse joint (`ImpulseJointSet`) is a [`GenericJoint`]: two local
//! frames, one in each rigid body's frame `B`, and masks of locked and
//! limited axes in those frames, exactly the library's
//! [`JointKind::Generic`]. The scene body of a rigid body is placed by its
//! collider frame `U = B P` (a compound's by `B`, `P` the identity), so a
//! joint frame `F` (body frame) is `P^-1 F` in the scene body's frame.
//!
//! | Rapier | scene |
//! |---|---|
//! | enabled impulse joint with locked axes, between bodies in the scene | a generic joint with the same locked axes and the limits of its free axes |
//! | a limit on an axis the library cannot limit (an angular limit where more than one rotation is free; a limit on a locked axis) | the joint without that limit, listed in [`JointReadReport::limits_ignored`] |
//! | a joint with coupled axes (a rope joint), or locking nothing (a spring joint) | skipped: not a bilateral lock |
//! | a disabled joint | skipped |
//! | a joint to a body with no collider in the scene (a fixed anchor without collider, a body skipped for its shape) | skipped, naming the body |
//! | a multibody joint | skipped: reduced coordinates keep it exact by construction |
//!
//! Motors and softness are the engine's dynamics, not constraints on
//! positions: they are not read.

use std::collections::HashMap;

use nalgebra::Isometry3;
use rapier3d::dynamics::{
    GenericJoint, ImpulseJointHandle, ImpulseJointSet, JointAxesMask, JointEnabled,
    MultibodyJointHandle, MultibodyJointSet, RigidBodyHandle,
};

use super::body_map::BodyMap;
use super::convert::pose_to_f64;
use crate::joints::{Joint, JointAxes, JointKind, JointLimits};

/// A Rapier joint, by its handle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RapierJoint {
    /// In the `ImpulseJointSet`.
    Impulse(ImpulseJointHandle),
    /// In the `MultibodyJointSet`.
    Multibody(MultibodyJointHandle),
}

/// Why a joint is not in the scene.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum JointSkipReason {
    /// A multibody joint: reduced coordinates, exact by construction.
    Multibody,
    /// Disabled, by the user or by a disabled body.
    Disabled,
    /// Coupled axes (a rope joint) or no locked axis (a spring joint): no
    /// bilateral lock to keep.
    NotALock,
    /// One of its bodies has no collider in the scene.
    BodyNotInScene(RigidBodyHandle),
    /// Both of its bodies are fixed in the scene (static, or held still
    /// as asleep by the bridge in this call): a correction moves neither,
    /// so the joint has nothing to keep.
    BothBodiesFixed,
    /// The scene rejected it (the message says why).
    Invalid(String),
}

/// A joint that is not in the scene.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SkippedJoint {
    /// The joint.
    pub joint: RapierJoint,
    /// Why.
    pub reason: JointSkipReason,
}

/// How the joints were read.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct JointReadReport {
    /// Joints in the scene.
    pub read: usize,
    /// Joints not in the scene, and why.
    pub skipped: Vec<SkippedJoint>,
    /// Limits not kept (joint, axis index `0..6`: linear x, y, z, angular
    /// x, y, z), the joint itself kept.
    pub limits_ignored: Vec<(ImpulseJointHandle, usize)>,
}

/// The scene joints of `impulse_joints`, each with its handle, in the
/// set's order, and what was skipped; `multibody_joints` are listed as
/// skipped.
pub(crate) fn read_joints(
    impulse_joints: &ImpulseJointSet,
    multibody_joints: &MultibodyJointSet,
    map: &BodyMap,
) -> (Vec<(ImpulseJointHandle, Joint)>, JointReadReport) {
    let mut report = JointReadReport::default();
    // The scene body of every mapped rigid body (its first collider's for
    // a fixed body with several).
    let mut scene_body: HashMap<RigidBodyHandle, usize> = HashMap::new();
    for (index, entry) in map.entries().iter().enumerate() {
        if let Some(body) = entry.body {
            scene_body.entry(body).or_insert(index);
        }
    }
    let mut joints = Vec::new();
    for (handle, joint) in impulse_joints.iter() {
        let skip = |reason| SkippedJoint {
            joint: RapierJoint::Impulse(handle),
            reason,
        };
        let data = &joint.data;
        if data.enabled != JointEnabled::Enabled {
            report.skipped.push(skip(JointSkipReason::Disabled));
            continue;
        }
        if !data.coupled_axes.is_empty() || data.locked_axes.is_empty() {
            report.skipped.push(skip(JointSkipReason::NotALock));
            continue;
        }
        let ends = [joint.body1(), joint.body2()].map(|b| scene_body.get(&b).copied().ok_or(b));
        let (a, b) = match ends {
            [Ok(a), Ok(b)] => (a, b),
            [Err(missing), _] | [_, Err(missing)] => {
                report
                    .skipped
                    .push(skip(JointSkipReason::BodyNotInScene(missing)));
                continue;
            }
        };
        let frame_in_scene_body = |index: usize, frame| {
            let in_body = map
                .entry(index)
                .map_or_else(Isometry3::identity, |e| e.collider_in_body);
            in_body.inverse() * pose_to_f64(frame)
        };
        let (locked, limits, ignored) = axes_of(data);
        report
            .limits_ignored
            .extend(ignored.into_iter().map(|axis| (handle, axis)));
        joints.push((
            handle,
            Joint {
                name: format!("joint {}", handle.0.into_raw_parts().0),
                kind: JointKind::Generic { locked, limits },
                body_a: a,
                body_b: b,
                frame_a: frame_in_scene_body(a, &data.local_frame1),
                frame_b: frame_in_scene_body(b, &data.local_frame2),
            },
        ));
    }
    for (handle, ..) in multibody_joints.iter() {
        report.skipped.push(SkippedJoint {
            joint: RapierJoint::Multibody(handle),
            reason: JointSkipReason::Multibody,
        });
    }
    (joints, report)
}

/// The locked axes and the limits the library keeps, and the axes whose
/// limits it drops.
fn axes_of(data: &GenericJoint) -> (JointAxes, JointLimits, Vec<usize>) {
    const MASKS: [JointAxesMask; 6] = [
        JointAxesMask::LIN_X,
        JointAxesMask::LIN_Y,
        JointAxesMask::LIN_Z,
        JointAxesMask::ANG_X,
        JointAxesMask::ANG_Y,
        JointAxesMask::ANG_Z,
    ];
    let mut locked = JointAxes::default();
    for (axis, mask) in MASKS.iter().enumerate() {
        let is_locked = data.locked_axes.contains(*mask);
        match axis {
            0..3 => locked.linear[axis] = is_locked,
            _ => locked.angular[axis - 3] = is_locked,
        }
    }
    let single_free = locked.single_free_angular();
    let mut limits = JointLimits::NONE;
    let mut ignored = Vec::new();
    for (axis, mask) in MASKS.iter().enumerate() {
        if !data.limit_axes.contains(*mask) {
            continue;
        }
        let l = &data.limits[axis];
        let range = [f64::from(l.min), f64::from(l.max)];
        let usable = range[0] <= range[1] && !data.locked_axes.contains(*mask);
        match axis {
            0..3 if usable => limits.linear[axis] = Some(range),
            3.. if usable && single_free == Some(axis - 3) => {
                limits.angular[axis - 3] = Some(range)
            }
            _ => ignored.push(axis),
        }
    }
    (locked, limits, ignored)
}
