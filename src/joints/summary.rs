//! A joint's errors in the units a user reads: the anchor points'
//! separation along locked axes (length), the misalignment of locked
//! rotations (radians), and how far a limit is exceeded.

use super::constraints::AnchorFrames;
use super::model::Joint;
use crate::body::Body;

/// The errors of one joint at some poses.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointErrors {
    /// Norm of `p` over the locked linear axes (length units): for a
    /// joint that locks every translation, the distance between the anchor
    /// points.
    pub linear: f64,
    /// Misalignment of the locked rotations, radians: the relative
    /// rotation's angle when all three are locked, the angle between the
    /// free axes of the two frames when one is free (a hinge), the locked
    /// component of the relative rotation vector when two are free.
    pub angular: f64,
    /// How far a travel limit is exceeded (length units; 0 within every
    /// limit).
    pub travel_limit: f64,
    /// How far an angle limit is exceeded (radians; 0 within every limit).
    pub angle_limit: f64,
}

impl JointErrors {
    /// The errors of `joint` with its anchor frames at `frames`.
    pub fn at(joint: &Joint, frames: &AnchorFrames) -> Self {
        let locked = joint.kind.locked_axes();
        let limits = joint.kind.limits();
        let p = frames.relative_position();
        let linear = (0..3)
            .filter(|&k| locked.linear[k])
            .map(|k| p[k] * p[k])
            .sum::<f64>()
            .sqrt();
        let phi = frames.relative_rotation();
        let locked_angular = (0..3).filter(|&k| locked.angular[k]).count();
        let single_free = locked.single_free_angular();
        let angular = match (locked_angular, single_free) {
            (3, _) => phi.norm(),
            (_, Some(free)) => frames.axis_misalignment(free),
            _ => (0..3)
                .filter(|&k| locked.angular[k])
                .map(|k| phi[k] * phi[k])
                .sum::<f64>()
                .sqrt(),
        };
        let excess = |value: f64, [min, max]: [f64; 2]| (min - value).max(value - max).max(0.0);
        let (mut travel_limit, mut angle_limit) = (0.0_f64, 0.0_f64);
        for k in 0..3 {
            if let Some(range) = limits.linear[k] {
                travel_limit = travel_limit.max(excess(p[k], range));
            }
            if let Some(range) = limits.angular[k] {
                angle_limit = angle_limit.max(excess(frames.hinge_angle(k), range));
            }
        }
        JointErrors {
            linear,
            angular,
            travel_limit,
            angle_limit,
        }
    }

    /// The errors of `joint` between `body_a` and `body_b` at their poses.
    pub fn in_scene(joint: &Joint, body_a: &Body, body_b: &Body) -> Self {
        let frames = AnchorFrames::at(
            joint,
            body_a.com_pose(),
            body_a.com_offset(),
            body_b.com_pose(),
            body_b.com_offset(),
        );
        JointErrors::at(joint, &frames)
    }

    /// The largest error in length units, angles measured by `scale`.
    pub fn largest(&self, scale: f64) -> f64 {
        let lengths = self.linear.max(self.travel_limit);
        lengths.max(scale * self.angular.max(self.angle_limit))
    }
}
