//! Every joint constraint's gradient against central finite differences of
//! its exact value, at random poses (the derivatives of
//! `src/joints/constraints.rs`, checked by differencing the values alone).

use constraint_stabilization::internals::rows::BodyState;
use constraint_stabilization::joints::{
    AnchorFrames, Joint, JointAxes, JointConstraint, JointKind, JointLimits,
};
use dev_support::random::{random_pose, random_rotation};
use nalgebra::{Isometry3, Vector3, Vector6};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Step of the central differences.
const STEP: f64 = 1e-6;
/// Agreement asked of gradient and differences (relative to the
/// gradient's size; the differences' error is about `STEP^2` times the
/// third derivative, and rounding `1e-16 / STEP`).
const AGREEMENT: f64 = 1e-6;
/// Length scale of the angular constraints.
const SCALE: f64 = 0.7;

fn joints(rng: &mut ChaCha8Rng) -> Vec<Joint> {
    let frame = |rng: &mut ChaCha8Rng| random_pose(rng, 0.5);
    let kinds = [
        JointKind::Fixed,
        JointKind::Spherical,
        JointKind::Revolute {
            limit: Some([-0.3, 0.4]),
        },
        JointKind::Prismatic {
            limit: Some([-0.1, 0.2]),
        },
        JointKind::Generic {
            locked: JointAxes {
                linear: [true, false, true],
                angular: [true, false, false],
            },
            limits: JointLimits {
                linear: [None, Some([-0.2, 0.1]), None],
                ..JointLimits::NONE
            },
        },
        JointKind::Generic {
            locked: JointAxes {
                linear: [false; 3],
                angular: [true, true, false],
            },
            limits: JointLimits {
                angular: [None, None, Some([-1.0, 1.0])],
                ..JointLimits::NONE
            },
        },
    ];
    kinds
        .into_iter()
        .map(|kind| Joint {
            name: kind.name().into(),
            kind,
            body_a: 0,
            body_b: 1,
            frame_a: frame(rng),
            frame_b: frame(rng),
        })
        .collect()
}

fn frames(joint: &Joint, states: &[BodyState; 2], offsets: &[Vector3<f64>; 2]) -> AnchorFrames {
    AnchorFrames::at(
        joint,
        &states[0].isometry(),
        &offsets[0],
        &states[1].isometry(),
        &offsets[1],
    )
}

/// `states` with body `body`'s correction entry `i` moved by `h`.
fn nudged(states: &[BodyState; 2], body: usize, i: usize, h: f64) -> [BodyState; 2] {
    let mut out = *states;
    let mut d = Vector6::zeros();
    d[i] = h;
    let dx = d.fixed_rows::<3>(0).into_owned();
    let dtheta = d.fixed_rows::<3>(3).into_owned();
    out[body] = states[body].moved(&dx, &dtheta, 1.0);
    out
}

#[test]
fn every_constraint_gradient_matches_central_differences() {
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let mut checked = 0;
    for _ in 0..20 {
        let offsets = [
            Vector3::new(rng.random_range(-0.2..0.2), 0.1, -0.05),
            Vector3::new(0.0, rng.random_range(-0.2..0.2), 0.3),
        ];
        for joint in joints(&mut rng) {
            // Poses near the joint's rest (so that the constraints are near
            // where they are used), with a random error.
            let pose_a = random_pose(&mut rng, 1.0);
            let rest_b: Isometry3<f64> = {
                let mut a = joint.frame_a;
                a.translation.vector -= offsets[0];
                let mut b = joint.frame_b;
                b.translation.vector -= offsets[1];
                pose_a * a * b.inverse()
            };
            let error = Isometry3::from_parts(
                (Vector3::new(0.05, -0.03, 0.02) * rng.random_range(0.0..1.0)).into(),
                nalgebra::UnitQuaternion::from_scaled_axis(
                    random_rotation(&mut rng).scaled_axis() * 0.1,
                ),
            );
            let pose_b = rest_b * error;
            let states = [pose_a, pose_b].map(|p| BodyState {
                position: p.translation.vector.into(),
                rotation: p.rotation,
            });
            for constraint in JointConstraint::of(&joint) {
                let lin = constraint.linearize(&frames(&joint, &states, &offsets), SCALE);
                for (body, grad) in [(0, lin.grad_a), (1, lin.grad_b)] {
                    for i in 0..6 {
                        let value = |h: f64| {
                            constraint.value(
                                &frames(&joint, &nudged(&states, body, i, h), &offsets),
                                SCALE,
                            )
                        };
                        let fd = (value(STEP) - value(-STEP)) / (2.0 * STEP);
                        let size = grad.norm().max(1.0);
                        assert!(
                            (fd - grad[i]).abs() <= AGREEMENT * size,
                            "{} {constraint:?}: body {body} entry {i}: gradient {} differences {fd}",
                            joint.name,
                            grad[i]
                        );
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(checked > 1000, "{checked}");
}

#[test]
fn a_joint_at_rest_measures_zero_and_an_offset_measures_exactly() {
    let joint = Joint {
        name: "hinge".into(),
        kind: JointKind::Revolute { limit: None },
        body_a: 0,
        body_b: 1,
        frame_a: Isometry3::translation(0.5, 0.0, 0.0),
        frame_b: Isometry3::translation(-0.5, 0.0, 0.0),
    };
    let zero = Vector3::zeros();
    let at = |b: Isometry3<f64>| AnchorFrames::at(&joint, &Isometry3::identity(), &zero, &b, &zero);
    // Hinge about x turned by 1 rad: every equality holds.
    let turned = Isometry3::translation(1.0, 0.0, 0.0)
        * nalgebra::UnitQuaternion::from_scaled_axis(Vector3::x() * 1.0);
    for c in JointConstraint::of(&joint) {
        assert!(c.value(&at(turned), SCALE).abs() < 1e-15, "{c:?}");
    }
    assert!((at(turned).hinge_angle(0) - 1.0).abs() < 1e-15);
    // Pulled 3 cm along y: the y equality reads exactly -0.03... in frame a.
    let pulled = Isometry3::translation(1.0, 0.03, 0.0);
    let values: Vec<f64> = JointConstraint::of(&joint)
        .iter()
        .map(|c| c.value(&at(pulled), SCALE))
        .collect();
    assert!((values[1] - 0.03).abs() < 1e-15, "{values:?}");
    // Axis tilted by 0.2 rad about z: the misalignment is exactly 0.2.
    let tilted = Isometry3::translation(1.0, 0.0, 0.0)
        * nalgebra::UnitQuaternion::from_scaled_axis(Vector3::z() * 0.2);
    assert!((at(tilted).axis_misalignment(0) - 0.2).abs() < 1e-14);
}
