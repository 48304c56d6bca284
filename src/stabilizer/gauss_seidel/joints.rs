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
    joint: Joint,
    /// Centre of mass of body `a`, `b` in its user frame.
    offsets: [Vector3<f64>; 2],
    constraints: Vec<JointConstraint>,
    /// The length that turns angles into lengths (`L`).
    scale: f64,
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

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry3, Matrix3};

    use super::*;
    use crate::joints::{JointAxes, JointKind, JointLimits};
    use crate::stabilizer::gauss_seidel::sweep::InverseMass;

    /// Rounding of one relaxation on lengths of order 1.
    const ROUNDING: f64 = 1e-15;

    /// A fixed body at the origin and a unit-mass, unit-inertia body at
    /// `(travel, 0, 0)` on a slider along x (every rotation and the y, z
    /// translations locked) whose travel is limited to `[0, 0.5]`, the
    /// anchors at the centres of mass.
    fn slider(travel: f64) -> (SweepBodies, SweepJoint) {
        let joint = Joint {
            name: "slider".into(),
            kind: JointKind::Generic {
                locked: JointAxes {
                    linear: [false, true, true],
                    angular: [true; 3],
                },
                limits: JointLimits {
                    linear: [Some([0.0, 0.5]), None, None],
                    ..JointLimits::NONE
                },
            },
            body_a: 0,
            body_b: 1,
            frame_a: Isometry3::identity(),
            frame_b: Isometry3::identity(),
        };
        let bodies = SweepBodies {
            poses: vec![
                Isometry3::identity(),
                Isometry3::translation(travel, 0.0, 0.0),
            ],
            inverse_masses: vec![
                None,
                Some(InverseMass {
                    mass: 1.0,
                    inertia_body: Matrix3::identity(),
                }),
            ],
        };
        let sweep_joint = SweepJoint {
            index: 0,
            constraints: JointConstraint::of(&joint),
            joint,
            offsets: [Vector3::zeros(); 2],
            scale: 1.0,
        };
        (bodies, sweep_joint)
    }

    fn parameters(slop: f64, max_correction: f64) -> PushParameters {
        PushParameters {
            baumgarte: 0.2,
            slop,
            max_correction,
        }
    }

    #[test]
    fn a_limit_is_a_unilateral_row_with_the_slop_and_the_cap() {
        // Travel 0.8 beyond the maximum 0.5: `k = 1`, the slider returns
        // to the limit (no Baumgarte factor), or by the cap; the equalities
        // are 0 and move nothing; the fixed body stays put.
        let cases = [
            (0.0, f64::INFINITY, 0.5),
            (0.0, 0.1, 0.7),
            (0.01, f64::INFINITY, 0.51),
        ];
        for (slop, cap, expected) in cases {
            let (mut bodies, joint) = slider(0.8);
            let mut summary = bodies.sweep(&[], &[joint], parameters(slop, cap));
            let x = bodies.poses[1].translation.vector;
            assert!((x.x - expected).abs() < ROUNDING, "{slop} {cap}: {x}");
            assert_eq!(x.yz(), nalgebra::Vector2::zeros());
            assert_eq!(bodies.poses[1].rotation, Isometry3::identity().rotation);
            assert_eq!(bodies.poses[0], Isometry3::identity());
            assert_eq!(summary.joint_relaxed, 1);
            assert!((summary.joint_error - 0.3).abs() < ROUNDING);
            // Within the limit nothing moves.
            let (mut inside, joint) = slider(0.3);
            summary = inside.sweep(&[], &[joint], parameters(slop, cap));
            assert!(!summary.moved());
            assert_eq!(inside.poses[1], Isometry3::translation(0.3, 0.0, 0.0));
        }
    }

    #[test]
    fn an_equality_is_removed_whole_whatever_its_sign() {
        // Off the slider's axis by -0.2 along y: the bilateral y row moves
        // the body back by +0.2, with no slop and no cap.
        for offset in [-0.2, 0.2] {
            let (mut bodies, joint) = slider(0.3);
            bodies.poses[1].translation.vector.y = offset;
            bodies.sweep(&[], &[joint], parameters(0.01, 0.05));
            let y = bodies.poses[1].translation.vector.y;
            assert!(y.abs() < ROUNDING, "{offset}: {y}");
        }
    }
}
