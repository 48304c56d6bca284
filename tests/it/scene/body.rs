//! Bodies: pose views, mass properties against parry3d-f64, validation.

use crate::support::proptest_config;
use approx::assert_relative_eq;
use constraint_stabilization::body::{Body, BodyDesc, BodyError, MassSpec, Shape};
use constraint_stabilization::scene::{Scene, SceneError};
use nalgebra::{Isometry3, Matrix3, Point3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::math::Vector;
use parry3d_f64::shape::Shape as _;
use proptest::prelude::*;

fn glam(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

fn matrix_of(m: &parry3d_f64::math::Matrix) -> Matrix3<f64> {
    Matrix3::from_fn(|r, c| m.col(c)[r])
}

fn desc(shape: Shape, translation: [f64; 3], rotation_xyzw: [f64; 4], mass: MassSpec) -> BodyDesc {
    BodyDesc {
        name: "b".into(),
        shape,
        translation: Vector3::from(translation),
        rotation_xyzw,
        mass,
    }
}

fn tetra_offset() -> Shape {
    Shape::ConvexHull {
        points: vec![
            Point3::new(1.0, 2.0, 3.0),
            Point3::new(2.0, 2.0, 3.0),
            Point3::new(1.0, 3.5, 3.0),
            Point3::new(1.0, 2.0, 3.7),
            Point3::new(1.1, 2.1, 3.1), // inside
        ],
    }
}

fn random_hull() -> impl Strategy<Value = Vec<Point3<f64>>> {
    let point = (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64);
    (
        prop::collection::vec(point, 4..30),
        (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
    )
        .prop_map(|(pts, (ox, oy, oz))| {
            pts.into_iter()
                .map(|(x, y, z)| Point3::new(x + ox, 0.5 * y + oy, 2.0 * z + oz))
                .collect()
        })
}

/// Unit quaternions `[x, y, z, w]` as a proptest strategy (shrinkable;
/// `dev_support::random::random_rotation` draws from a seeded RNG instead).
fn rotation_strategy() -> impl Strategy<Value = [f64; 4]> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, 0.1..1.0f64).prop_map(|(x, y, z, w)| {
        let n = (x * x + y * y + z * z + w * w).sqrt();
        [x / n, y / n, z / n, w / n]
    })
}

#[test]
fn untouched_body_keeps_its_user_pose_bit_for_bit() {
    // Slightly off-unit rotation: accepted, normalized inside, kept outside.
    let rotation = [0.1, -0.2, 0.3, 0.9274];
    let mut body = Body::new(desc(
        tetra_offset(),
        [0.1, 0.2, 0.3],
        rotation,
        MassSpec::Mass(2.0),
    ))
    .unwrap();
    let com_pose = *body.com_pose();
    body.set_com_pose(com_pose).unwrap();
    assert_eq!(body.rotation_user_xyzw(), rotation);
    assert_eq!(body.translation_user(), &Vector3::new(0.1, 0.2, 0.3));
    assert_eq!(body.com_pose(), &com_pose);
}

// The four-digit value of 1/sqrt(2) is the point of the test.
#[allow(clippy::approx_constant)]
#[test]
fn four_digit_quaternion_is_accepted_and_normalized() {
    let body = Body::new(desc(
        tetra_offset(),
        [0.0; 3],
        [0.0, 0.0, 0.7071, 0.7071],
        MassSpec::Fixed,
    ))
    .unwrap();
    assert_relative_eq!(
        body.com_pose().rotation.quaternion().norm(),
        1.0,
        epsilon = 1e-15
    );
    assert_eq!(body.rotation_user_xyzw(), [0.0, 0.0, 0.7071, 0.7071]);
}

proptest! {
    #![proptest_config(proptest_config::config(48))]

    /// Oracle: parry3d-f64's hull and mass properties, from the raw points
    /// in the shape frame, placed by the user pose.
    #[test]
    fn com_pose_and_inertia_match_parry(
        points in random_hull(),
        rotation in rotation_strategy(),
        translation in (-5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64),
        density in 0.1..10.0f64,
    ) {
        let (tx, ty, tz) = translation;
        let glam_points: Vec<Vector> = points.iter().map(|p| Vector::new(p.x, p.y, p.z)).collect();
        let Some(hull) = parry3d_f64::shape::ConvexPolyhedron::from_convex_hull(&glam_points) else {
            return Ok(()); // degenerate sample
        };
        let oracle = hull.mass_properties(density);
        prop_assume!(oracle.mass() > 1e-3);
        let body = match Body::new(desc(Shape::ConvexHull { points }, [tx, ty, tz], rotation, MassSpec::Density(density))) {
            Ok(body) => body,
            Err(e) => return Err(TestCaseError::fail(format!("{e}"))),
        };
        let user = body.user_pose();
        let com_oracle_world = user * Point3::new(oracle.local_com.x, oracle.local_com.y, oracle.local_com.z);
        let scale = body.polyhedron().expect("a convex body").scale();
        prop_assert!((body.com_world() - com_oracle_world).norm() <= 1e-9 * scale.max(1.0));
        let mass = body.mass().unwrap();
        prop_assert!((mass.mass - oracle.mass()).abs() <= 1e-9 * oracle.mass());
        let r = user.rotation.to_rotation_matrix();
        let inertia_oracle = r.matrix() * matrix_of(&oracle.reconstruct_inertia_matrix()) * r.matrix().transpose();
        let inertia = body.inertia_world().unwrap();
        prop_assert!((inertia - inertia_oracle).norm() <= 1e-8 * inertia_oracle.norm());
        let product = body.inverse_inertia_world().unwrap() * inertia;
        prop_assert!((product - Matrix3::identity()).norm() <= 1e-8);
        // Every body-frame vertex maps to the same world point by both poses.
        let offset = body.polyhedron().expect("a convex body").shape_origin_offset();
        for v_body in body.polyhedron().expect("a convex body").vertices() {
            let by_com = body.com_pose() * v_body;
            let by_user = user * (v_body + offset);
            prop_assert!((by_com - by_user).norm() <= 1e-12 * (scale + translation.0.abs() + 10.0));
        }
    }

    #[test]
    fn moved_com_pose_gives_consistent_user_pose(
        rotation in rotation_strategy(),
        new_rotation in rotation_strategy(),
        dx in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
    ) {
        let mut body = Body::new(desc(tetra_offset(), [1.0, -2.0, 0.5], rotation, MassSpec::Mass(1.0))).unwrap();
        let [x, y, z, w] = new_rotation;
        let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z));
        let t_com = body.com_pose().translation.vector + Vector3::new(dx.0, dx.1, dx.2);
        body.set_com_pose(Isometry3::from_parts(Translation3::from(t_com), q)).unwrap();
        let offset = body.polyhedron().expect("a convex body").shape_origin_offset();
        let com_from_user = body.user_pose() * Point3::from(offset);
        prop_assert!((com_from_user.coords - t_com).norm() <= 1e-12 * 10.0);
        prop_assert_eq!(body.com_pose().translation.vector, t_com);
        let stored = body.rotation_user_xyzw();
        let norm = stored.iter().map(|c| c * c).sum::<f64>().sqrt();
        prop_assert!((norm - 1.0).abs() <= 1e-15 * 4.0);
    }
}

#[test]
fn cuboid_mass_and_world_inertia_match_parry() {
    let half = Vector3::new(0.5, 1.0, 2.0);
    let angle = 0.7;
    let q = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), angle);
    let qc = q.quaternion();
    let body = Body::new(desc(
        Shape::Cuboid { half_extents: half },
        [3.0, 0.0, 0.0],
        [qc.i, qc.j, qc.k, qc.w],
        MassSpec::Mass(12.0),
    ))
    .unwrap();
    let oracle = parry3d_f64::shape::Cuboid::new(glam(&half)).mass_properties(12.0 / 8.0);
    let mass = body.mass().unwrap();
    assert_relative_eq!(mass.mass, oracle.mass(), max_relative = 1e-12);
    assert_relative_eq!(mass.density, 12.0 / 8.0, max_relative = 1e-12);
    let r = q.to_rotation_matrix();
    let expected =
        r.matrix() * matrix_of(&oracle.reconstruct_inertia_matrix()) * r.matrix().transpose();
    assert_relative_eq!(
        body.inertia_world().unwrap(),
        expected,
        max_relative = 1e-10,
        epsilon = 1e-12
    );
    assert_eq!(body.com_world(), Point3::new(3.0, 0.0, 0.0));
}

#[test]
fn displaced_com_pose_composes_world_rotation_on_the_left() {
    let body = Body::new(desc(
        tetra_offset(),
        [0.0; 3],
        [0.0, 0.0, 0.0, 1.0],
        MassSpec::Mass(1.0),
    ))
    .unwrap();
    let dtheta = Vector3::new(0.0, 0.0, 0.3);
    let moved = body.displaced_com_pose(&Vector3::new(0.1, 0.0, 0.0), &dtheta);
    let expected =
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.3) * body.com_pose().rotation;
    assert_relative_eq!(moved.rotation.angle_to(&expected), 0.0, epsilon = 1e-12);
    assert_relative_eq!(
        moved.translation.vector,
        body.com_pose().translation.vector + Vector3::new(0.1, 0.0, 0.0),
        epsilon = 1e-15
    );
}

#[test]
fn fixed_body_has_no_mass_properties() {
    let body = Body::new(desc(
        tetra_offset(),
        [0.0; 3],
        [0.0, 0.0, 0.0, 1.0],
        MassSpec::Fixed,
    ))
    .unwrap();
    assert!(body.is_fixed());
    assert!(body.mass().is_none() && body.inertia_world().is_none());
}

fn error_of(d: BodyDesc) -> BodyError {
    Body::new(d).unwrap_err()
}

#[test]
fn invalid_values_are_errors_naming_their_field() {
    let cube = || Shape::Cuboid {
        half_extents: Vector3::new(1.0, 1.0, 1.0),
    };
    let id = [0.0, 0.0, 0.0, 1.0];
    let cases: Vec<(BodyDesc, &str)> = vec![
        (
            desc(cube(), [0.0, f64::NAN, 0.0], id, MassSpec::Fixed),
            "translation",
        ),
        (
            desc(cube(), [f64::INFINITY, 0.0, 0.0], id, MassSpec::Fixed),
            "translation",
        ),
        (
            desc(cube(), [0.0; 3], [0.0, 0.0, 0.0, 1.01], MassSpec::Fixed),
            "rotation",
        ),
        (
            desc(cube(), [0.0; 3], [0.0; 4], MassSpec::Fixed),
            "rotation",
        ),
        (
            desc(cube(), [0.0; 3], [f64::NAN, 0.0, 0.0, 1.0], MassSpec::Fixed),
            "rotation",
        ),
        (desc(cube(), [0.0; 3], id, MassSpec::Mass(0.0)), "mass"),
        (desc(cube(), [0.0; 3], id, MassSpec::Mass(-1.0)), "mass"),
        (
            desc(cube(), [0.0; 3], id, MassSpec::Mass(f64::INFINITY)),
            "mass",
        ),
        (
            desc(cube(), [0.0; 3], id, MassSpec::Density(f64::NAN)),
            "density",
        ),
        (
            desc(cube(), [0.0; 3], id, MassSpec::Density(1e308 * 10.0)),
            "density",
        ),
        (
            desc(
                Shape::Cuboid {
                    half_extents: Vector3::new(1.0, 0.0, 1.0),
                },
                [0.0; 3],
                id,
                MassSpec::Fixed,
            ),
            "shape",
        ),
        (
            desc(
                Shape::ConvexHull {
                    points: vec![
                        Point3::origin(),
                        Point3::new(1.0, 0.0, 0.0),
                        Point3::new(0.0, 1.0, 0.0),
                        Point3::new(1.0, 1.0, 0.0),
                    ],
                },
                [0.0; 3],
                id,
                MassSpec::Fixed,
            ),
            "shape",
        ),
    ];
    for (d, field) in cases {
        let label = format!("{d:?}");
        let e = error_of(d);
        assert_eq!(e.field(), field, "{label}: {e}");
    }
    assert!(matches!(
        error_of(desc(cube(), [0.0; 3], [0.0, 0.0, 0.0, 2.0], MassSpec::Fixed)),
        BodyError::RotationNotUnit { norm } if norm == 2.0
    ));
}

#[test]
fn density_whose_mass_overflows_is_an_error() {
    // Volume 8e150 and inertia are finite; the mass 8e350 is not.
    let big = Shape::Cuboid {
        half_extents: Vector3::new(1e50, 1e50, 1e50),
    };
    let e = error_of(desc(
        big,
        [0.0; 3],
        [0.0, 0.0, 0.0, 1.0],
        MassSpec::Density(1e200),
    ));
    assert!(matches!(e, BodyError::DegenerateMass { .. }), "{e}");
}

#[test]
fn scene_error_names_index_and_name() {
    let mut scene = Scene::new();
    let cube = Shape::Cuboid {
        half_extents: Vector3::new(1.0, 1.0, 1.0),
    };
    scene
        .add_body(desc(
            cube.clone(),
            [0.0; 3],
            [0.0, 0.0, 0.0, 1.0],
            MassSpec::Fixed,
        ))
        .unwrap();
    let mut bad = desc(cube, [0.0; 3], [0.0, 0.0, 0.0, 1.0], MassSpec::Mass(-2.0));
    bad.name = "crate".into();
    let e = scene.add_body(bad).unwrap_err();
    assert!(
        matches!(&e, SceneError::Body { index: 1, name, source: BodyError::InvalidMass(_) } if name == "crate")
    );
    let message = e.to_string();
    assert!(
        message.contains("body 1") && message.contains("crate") && message.contains("mass"),
        "{message}"
    );
    assert_eq!(scene.len(), 1);
    let mut nan_pose = *scene.bodies()[0].com_pose();
    nan_pose.translation.vector.y = f64::NAN;
    let e = scene.set_com_pose(0, nan_pose).unwrap_err();
    assert!(
        matches!(
            &e,
            SceneError::Body {
                index: 0,
                source: BodyError::NonFiniteTranslation { component: 1, .. },
                ..
            }
        ),
        "{e}"
    );
    assert_eq!(
        scene.set_com_pose(3, nan_pose).unwrap_err(),
        SceneError::NoSuchBody { index: 3, len: 1 }
    );
}
