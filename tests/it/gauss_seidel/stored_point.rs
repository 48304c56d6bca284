use constraint_stabilization::internals::contact::{ContactPoint, NormalBody};
use nalgebra::{Isometry3, Point3, Vector3};
use nalgebra::{Translation3, UnitQuaternion};

use constraint_stabilization::internals::stabilizer::gauss_seidel::point::*;

/// Rounding of a separation recomputed through two frame changes,
/// for lengths of order 1.
const ROUNDING: f64 = 1e-14;

fn posed(translation: [f64; 3], axis_angle: [f64; 3]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(Vector3::from(translation)),
        UnitQuaternion::from_scaled_axis(Vector3::from(axis_angle)),
    )
}

#[test]
fn stored_point_measures_its_manifold_separation() {
    let pose_a = posed([0.1, 0.9, -0.2], [0.3, -0.1, 0.2]);
    let pose_b = posed([0.0, -0.5, 0.0], [0.0, 0.2, 0.0]);
    let normal = Vector3::new(0.1, 1.0, -0.05).normalize();
    let point = ContactPoint {
        point_a_world: Point3::new(0.2, -0.01, 0.3),
        point_b_world: Point3::new(0.2, -0.01, 0.3) + normal * 0.01,
        normal_world: normal,
        separation: -0.01,
    };
    for body in [NormalBody::A, NormalBody::B] {
        let stored = StoredPoint::new((1, 2), &point, body, &pose_a, &pose_b);
        let measured = stored.measure(&pose_a, &pose_b);
        assert!((measured.separation - point.separation).abs() < ROUNDING);
    }
}

#[test]
fn lifting_the_body_of_a_point_raises_its_separation_by_the_lift() {
    let pose_a = posed([0.0, 0.4, 0.0], [0.0, 0.0, 0.0]);
    let pose_b = posed([0.0, -0.5, 0.0], [0.0, 0.0, 0.0]);
    let point = ContactPoint {
        point_a_world: Point3::new(0.0, -0.1, 0.0),
        point_b_world: Point3::new(0.0, 0.0, 0.0),
        normal_world: Vector3::y(),
        separation: -0.1,
    };
    let stored = StoredPoint::new((0, 1), &point, NormalBody::B, &pose_a, &pose_b);
    let lifted = posed([0.0, 0.45, 0.0], [0.0, 0.0, 0.0]);
    let measured = stored.measure(&lifted, &pose_b);
    assert!((measured.separation - (-0.05)).abs() < ROUNDING);
}
