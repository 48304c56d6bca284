//! A joint's constraints relaxed one at a time in a sweep, as bilateral
//! rows (issue 23): the position-level nonlinear Gauss–Seidel of Box2D
//! v2.4's joints (`b2RevoluteJoint::SolvePositionConstraints` and its
//! siblings), in 3D, one scalar row at a time.
//!
//! At each visit the joint's anchor frames are computed at the current
//! poses and each constraint of [`JointConstraint::of`] (the locked axes,
//! then the limits) is linearized there ([`JointConstraint::linearize`]):
//! value `e`, gradient blocks `g_a`, `g_b` in the `[dx; dtheta]` world
//! convention, angles times the scene scale `L` (length units). The row's
//! error `C` and its relaxation are
//!
//! ```text
//! equality (locked axis):  C = e                                    (no slop, no cap)
//! limit (e >= 0):          C = clamp(e + slop, -max_correction, 0)
//! k      = g_a^T M_a^-1 g_a + g_b^T M_b^-1 g_b,   M^-1 = diag(I/m, I_world^-1)
//! lambda = -C / k   (k > 0; no clamp on lambda: bilateral for an equality)
//! (dx, dtheta)_a = lambda M_a^-1 g_a,   (dx, dtheta)_b = lambda M_b^-1 g_b
//! ```
//!
//! applied at once (`x += dx`, `R = exp(dtheta) R`), before the next row is
//! linearized. To first order the row's value moves by `lambda k = -C`: an
//! equality is removed whole, a violated limit is brought back to `-slop`.
//! A fixed end has no term in `k` and does not move.
//!
//! **Choices, against Box2D.** Box2D corrects a joint's point-to-point and
//! weld errors whole, without Baumgarte factor, slop or cap (v2.4), and
//! its angle limits with `b2_angularSlop` and `b2_maxAngularCorrection`;
//! here the equalities are corrected whole too, and every limit (travel
//! or angle, both in length units) takes the contact's slop and cap
//! (`b2_linearSlop`, `b2_maxLinearCorrection`, times `L`) without the
//! Baumgarte factor. Box2D solves a joint's point constraint as one 2x2
//! (3x3 in 3D) block; here each locked axis is its own scalar row, as the
//! projection's rows are. The joints are visited after the contact points
//! in each sweep, as Box2D's position iterations do
//! (`contactSolver.SolvePositionConstraints()`, then every joint's).

use nalgebra::Vector3;

use super::sweep::{PushParameters, Row, SweepBodies, SweepSummary};
use crate::Error;
use crate::joints::{AnchorFrames, Joint, JointConstraint};
use crate::scene::Scene;

/// A joint of a sweep: its bodies' centre-of-mass offsets and its
/// constraints.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepJoint {
    /// Scene index of the joint.
    pub index: usize,
    /// The joint.
    pub joint: Joint,
    /// Centre of mass of body `a`, `b` in its user frame.
    pub offsets: [Vector3<f64>; 2],
    /// The joint's constraints, one relaxed row each.
    pub constraints: Vec<JointConstraint>,
    /// The length that turns angles into lengths (`L`).
    pub scale: f64,
}

impl SweepJoint {
    /// Joint `index` of `scene`, angles measured by `scale`.
    pub fn of(scene: &Scene, index: usize, scale: f64) -> Result<Self, Error> {
        let joint =
            scene
                .joints()
                .get(index)
                .cloned()
                .ok_or(crate::scene::SceneError::NoSuchJoint {
                    index,
                    len: scene.joints().len(),
                })?;
        let offsets = [
            *scene.body(joint.body_a)?.com_offset(),
            *scene.body(joint.body_b)?.com_offset(),
        ];
        Ok(SweepJoint {
            index,
            constraints: JointConstraint::of(&joint),
            joint,
            offsets,
            scale,
        })
    }
}

impl SweepBodies {
    /// Relaxes the constraints of `joint` in order (module docs), counting
    /// them in `summary`.
    pub(super) fn relax_joint(
        &mut self,
        joint: &SweepJoint,
        parameters: PushParameters,
        summary: &mut SweepSummary,
    ) {
        let (a, b) = (joint.joint.body_a, joint.joint.body_b);
        for constraint in &joint.constraints {
            let frames = AnchorFrames::at(
                &joint.joint,
                &self.poses[a],
                &joint.offsets[0],
                &self.poses[b],
                &joint.offsets[1],
            );
            let linearized = constraint.linearize(&frames, joint.scale);
            let value = linearized.value;
            let (c, error) = if constraint.is_equality() {
                (value, value.abs())
            } else {
                let c = (value + parameters.slop).clamp(-parameters.max_correction, 0.0);
                (c, (-value).max(0.0))
            };
            summary.joint_rows += 1;
            summary.joint_error = summary.joint_error.max(error);
            let row = Row {
                body_a: a,
                body_b: b,
                grad_a: linearized.grad_a,
                grad_b: linearized.grad_b,
            };
            summary.joint_relaxed += usize::from(self.relax(&row, c));
        }
    }
}
