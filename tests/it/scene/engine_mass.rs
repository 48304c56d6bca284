use constraint_stabilization::Body;
use nalgebra::{Isometry3, Point3};
use nalgebra::{Matrix3, Vector3};

use constraint_stabilization::body::{BodyDesc, MassSpec, Shape, ShapePart};

fn bar() -> Body {
    let part = |x: f64| ShapePart {
        shape: Shape::Cuboid {
            half_extents: Vector3::new(0.5, 0.5, 0.5),
        },
        translation: Vector3::new(x, 0.0, 0.0),
        rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
    };
    Body::new(BodyDesc {
        name: "bar".into(),
        shape: Shape::Compound {
            parts: vec![part(-0.5), part(0.5)],
        },
        translation: Vector3::new(1.0, 2.0, 3.0),
        rotation_xyzw: [0.0, 0.0, 0.38268343236508984, 0.9238795325112867],
        mass: MassSpec::Mass(2.0),
    })
    .expect("a valid compound")
}

/// Moving the centre of mass keeps every part where it was in the
/// world, and the centre where it was given.
#[test]
fn a_moved_centre_of_mass_keeps_the_parts_in_place() {
    let mut body = bar();
    let before: Vec<Isometry3<f64>> = body.part_poses().collect();
    let com = Vector3::new(0.25, 0.0, 0.0);
    let inertia = Matrix3::from_diagonal(&Vector3::new(0.3, 0.5, 0.5));
    body.set_mass_properties(3.0, com, inertia)
        .expect("valid mass properties");
    for (a, b) in before.iter().zip(body.part_poses()) {
        assert!((a.translation.vector - b.translation.vector).norm() < 1e-14);
        assert!(a.rotation.angle_to(&b.rotation) < 1e-14);
    }
    let expected = body.user_pose() * Point3::from(com);
    assert!((body.com_world() - expected).norm() < 1e-14);
    assert_eq!(body.mass().map(|m| m.mass), Some(3.0));
    assert_eq!(body.mass().map(|m| m.inertia_body), Some(inertia));
}

/// A held body counts as fixed and comes back with its mass.
#[test]
fn a_held_body_is_fixed_until_released() {
    let mut body = bar();
    let mass = *body.mass().expect("dynamic");
    body.hold_fixed();
    assert!(body.is_fixed() && body.is_held());
    body.release();
    assert!(!body.is_fixed() && !body.is_held());
    assert_eq!(body.mass(), Some(&mass));
    assert!(
        body.set_mass_properties(f64::NAN, Vector3::zeros(), Matrix3::identity())
            .is_err()
    );
}
