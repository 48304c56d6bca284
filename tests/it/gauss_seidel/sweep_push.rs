use constraint_stabilization::internals::contact::NormalBody;
use constraint_stabilization::internals::stabilizer::gauss_seidel::point::StoredPoint;
use constraint_stabilization::internals::stabilizer::gauss_seidel::sweep::*;
use nalgebra::{Isometry3, Matrix3, Point3, Vector3};

/// Rounding of one push on lengths of order 1.
const ROUNDING: f64 = 1e-15;

/// A unit-mass body with unit inertia above a fixed body, touching at
/// `lever` (body frame of the dynamic body) with separation `s`.
fn pair(lever: Vector3<f64>, s: f64) -> (SweepBodies, StoredPoint) {
    let bodies = SweepBodies {
        poses: vec![Isometry3::identity(), Isometry3::identity()],
        inverse_masses: vec![
            None,
            Some(InverseMass {
                mass: 1.0,
                inertia_body: Matrix3::identity(),
            }),
        ],
    };
    let point = StoredPoint {
        body_a: 1,
        body_b: 0,
        p_a_body: Point3::from(lever),
        p_b_body: Point3::from(lever - Vector3::y() * s),
        normal_body: NormalBody::B,
        n_ref: Vector3::y(),
    };
    (bodies, point)
}

fn parameters(baumgarte: f64, slop: f64, max_correction: f64) -> PushParameters {
    PushParameters {
        baumgarte,
        slop,
        max_correction,
    }
}

#[test]
fn central_push_removes_the_baumgarte_fraction() {
    let (mut bodies, point) = pair(Vector3::new(0.0, -1.0, 0.0), -0.1);
    bodies.sweep(&[point], &[], parameters(0.2, 0.0, f64::INFINITY));
    let after = point.measure(&bodies.poses[1], &bodies.poses[0]).separation;
    assert!((after - (-0.08)).abs() < ROUNDING, "{after}");
    assert_eq!(bodies.poses[0], Isometry3::identity());
}

#[test]
fn push_is_capped_and_respects_the_slop() {
    let (mut capped, point) = pair(Vector3::new(0.0, -1.0, 0.0), -0.1);
    capped.sweep(&[point], &[], parameters(1.0, 0.0, 0.03));
    let lift = capped.poses[1].translation.vector.y;
    assert!((lift - 0.03).abs() < ROUNDING, "{lift}");
    let (mut within_slop, point) = pair(Vector3::new(0.0, -1.0, 0.0), -0.004);
    let summary = within_slop.sweep(&[point], &[], parameters(0.2, 0.005, 0.2));
    assert_eq!(summary.pushed, 0);
    assert_eq!(within_slop.poses[1], Isometry3::identity());
}

#[test]
fn offset_push_uses_the_effective_mass() {
    // Lever (1, -1, 0), n = y: r x n = (0, 0, 1), K = 1 + 1 = 2, so the
    // body rises by lambda = 0.1 / 2 and turns by 0.05 about z, which
    // lifts the point by another 0.05 to first order.
    let (mut bodies, point) = pair(Vector3::new(1.0, -1.0, 0.0), -0.1);
    bodies.sweep(&[point], &[], parameters(1.0, 0.0, f64::INFINITY));
    let pose = &bodies.poses[1];
    assert!((pose.translation.vector.y - 0.05).abs() < ROUNDING);
    let angle = pose.rotation.scaled_axis();
    assert!((angle - Vector3::new(0.0, 0.0, 0.05)).norm() < ROUNDING);
}
