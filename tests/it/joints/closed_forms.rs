//! Closed forms of the projection with joints: the mass-weighted split of
//! a ball joint's separation and of a hinge's misalignment, a pendulum
//! returning to its pivot, a hinge angle returning to its limit.

use constraint_stabilization::body::MassSpec;
use constraint_stabilization::joints::{Joint, JointAxes, JointKind, JointLimits};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Settings, Stabilizer, Status};
use dev_support::joints::{ball_joint_pulled_apart, oracle_joint_errors, pendulum_off_pivot};
use dev_support::scene::{IDENTITY_XYZW, cuboid, xyzw};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};

/// Agreement with a closed form, relative to the length or angle moved:
/// far below the tolerance (1e-6 of the scene's scale), above rounding.
const CLOSED_FORM: f64 = 1e-7;

fn cube(
    name: &str,
    half: f64,
    at: [f64; 3],
    rotation: [f64; 4],
    mass: MassSpec,
) -> constraint_stabilization::BodyDesc {
    cuboid(name, [half; 3], at, rotation, mass)
}

fn stabilize(scene: &mut Scene) -> constraint_stabilization::Report {
    let mut stabilizer = Stabilizer::new(Settings::default()).expect("default settings");
    let report = stabilizer.stabilize(scene).expect("valid scene");
    assert_eq!(report.status, Status::Converged, "{report:?}");
    report
}

fn translation(scene: &Scene, body: usize) -> Vector3<f64> {
    *scene.bodies()[body].translation_user()
}

fn rotation(scene: &Scene, body: usize) -> UnitQuaternion<f64> {
    scene.bodies()[body].user_pose().rotation
}

#[test]
fn a_ball_joint_pulled_apart_closes_in_the_ratio_of_the_masses_without_turning() {
    let (m_a, m_b, d) = (1.0, 3.0, 0.04);
    let mut scene = ball_joint_pulled_apart(m_a, m_b, d);
    let report = stabilize(&mut scene);
    let moved_a = translation(&scene, 0).x;
    let moved_b = translation(&scene, 1).x - (1.0 + d);
    assert!(
        (moved_a - d * m_b / (m_a + m_b)).abs() <= CLOSED_FORM * d,
        "{moved_a}"
    );
    assert!(
        (moved_b + d * m_a / (m_a + m_b)).abs() <= CLOSED_FORM * d,
        "{moved_b}"
    );
    for body in 0..2 {
        assert!(
            rotation(&scene, body).angle() <= CLOSED_FORM,
            "body {body} turned"
        );
        assert!(translation(&scene, body).yz().norm() <= CLOSED_FORM * d);
    }
    let errors = oracle_joint_errors(&scene, &scene.joints()[0]);
    assert!(errors.separation <= report.tolerance, "{errors:?}");
    assert!(report.joint_error_before > d * 0.99 && report.joint_error_after <= report.tolerance);
}

#[test]
fn a_misaligned_hinge_is_realigned_with_the_mass_weighted_split_of_the_turn() {
    // Two cubes of one size (inertia proportional to mass) hinged about x
    // at their common centre line; b's hinge axis turned by theta about z.
    let (m_a, m_b, theta) = (2.0, 5.0, 0.1);
    let turned = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), theta);
    let mut scene = Scene::new();
    scene
        .add_body(cube(
            "a",
            0.25,
            [0.0, 0.0, 0.0],
            IDENTITY_XYZW,
            MassSpec::Mass(m_a),
        ))
        .unwrap();
    scene
        .add_body(cube(
            "b",
            0.25,
            [1.0, 0.0, 0.0],
            xyzw(&turned),
            MassSpec::Mass(m_b),
        ))
        .unwrap();
    // Only the rotations locked (a generic joint whose free axis is x),
    // with the anchors at the centres of mass: turning a body does not
    // move its anchor, and nothing pulls the cubes together.
    scene
        .add_joint(Joint {
            name: "aligned axes".into(),
            kind: JointKind::Generic {
                locked: JointAxes {
                    linear: [false; 3],
                    angular: [false, true, true],
                },
                limits: JointLimits::NONE,
            },
            body_a: 0,
            body_b: 1,
            frame_a: Isometry3::identity(),
            frame_b: Isometry3::identity(),
        })
        .unwrap();
    let report = stabilize(&mut scene);
    let turn_a = rotation(&scene, 0).scaled_axis();
    let turn_b = (rotation(&scene, 1) * turned.inverse()).scaled_axis();
    let expected_a = theta * m_b / (m_a + m_b);
    let expected_b = -theta * m_a / (m_a + m_b);
    assert!(
        (turn_a.z - expected_a).abs() <= CLOSED_FORM * theta,
        "{turn_a}"
    );
    assert!(
        (turn_b.z - expected_b).abs() <= CLOSED_FORM * theta,
        "{turn_b}"
    );
    assert!(turn_a.xy().norm() + turn_b.xy().norm() <= CLOSED_FORM * theta);
    for body in 0..2 {
        let start = [0.0, 1.0][body];
        assert!((translation(&scene, body) - Vector3::new(start, 0.0, 0.0)).norm() <= CLOSED_FORM);
    }
    assert!(report.joint_error_after <= report.tolerance);
}

#[test]
fn a_pendulum_link_off_its_fixed_pivot_returns_to_it() {
    let mut scene = pendulum_off_pivot();
    let before = oracle_joint_errors(&scene, &scene.joints()[0]);
    assert!(before.separation > 0.05);
    let report = stabilize(&mut scene);
    let after = oracle_joint_errors(&scene, &scene.joints()[0]);
    assert!(after.separation <= report.tolerance, "{after:?}");
    assert_eq!(translation(&scene, 0), Vector3::new(0.0, 2.0, 0.0));
}

#[test]
fn a_hinge_angle_beyond_its_limit_returns_exactly_to_the_limit() {
    let limit = 0.5;
    let mut scene = Scene::new();
    scene
        .add_body(cube(
            "frame",
            0.1,
            [0.0, 0.0, 0.0],
            IDENTITY_XYZW,
            MassSpec::Fixed,
        ))
        .unwrap();
    let opened = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.7);
    scene
        .add_body(cuboid(
            "door",
            [0.05, 0.5, 0.3],
            [1.0, 0.0, 0.0],
            xyzw(&opened),
            MassSpec::Mass(4.0),
        ))
        .unwrap();
    // Hinge about x through the door's centre, held by the fixed frame.
    scene
        .add_joint(Joint {
            name: "hinge".into(),
            kind: JointKind::Revolute {
                limit: Some([-limit, limit]),
            },
            body_a: 0,
            body_b: 1,
            frame_a: Isometry3::translation(1.0, 0.0, 0.0),
            frame_b: Isometry3::identity(),
        })
        .unwrap();
    let report = stabilize(&mut scene);
    let angle = rotation(&scene, 1).scaled_axis();
    let scale = report.scale;
    // At the limit, short of it by at most the target margin and never
    // beyond it by more than the tolerance (both lengths; angles times L).
    assert!(angle.x <= limit + report.tolerance / scale, "{angle}");
    assert!(angle.x >= limit - 2.0 * report.tolerance / scale, "{angle}");
    assert!(angle.yz().norm() <= report.tolerance / scale);
    let joint = &report.joints[0];
    assert!(joint.before.angle_limit > 0.19 && joint.after.angle_limit <= report.tolerance / scale);
}
