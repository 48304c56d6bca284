use constraint_stabilization::internals::stabilizer::gauss_seidel::sweep::{
    PushParameters, SweepBodies,
};
use constraint_stabilization::joints::{Joint, JointConstraint};
use nalgebra::Vector3;
use nalgebra::{Isometry3, Matrix3};

use constraint_stabilization::internals::stabilizer::gauss_seidel::joints::*;
use constraint_stabilization::internals::stabilizer::gauss_seidel::sweep::InverseMass;
use constraint_stabilization::joints::{JointAxes, JointKind, JointLimits};

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
