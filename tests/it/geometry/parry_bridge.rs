//! The parry bridge: converted shapes and poses give parry queries the
//! answers known in closed form or by brute force.

use crate::support::proptest_config;
use approx::assert_relative_eq;
use constraint_stabilization::internals::geometry::{
    ConvexPolyhedron, isometry_from_parry, isometry_to_parry, point_from_parry, point_to_parry,
    vector_from_parry, vector_to_parry,
};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::query;
use parry3d_f64::shape::{Shape, SupportMap};
use proptest::prelude::*;

/// Distance between two axis-aligned boxes `[c - h, c + h]`: per axis gap
/// `max(0, |c_a - c_b| - h_a - h_b)`, combined by Pythagoras.
fn aabb_distance(ca: Vector3<f64>, ha: Vector3<f64>, cb: Vector3<f64>, hb: Vector3<f64>) -> f64 {
    let gap = (ca - cb).abs() - ha - hb;
    gap.map(|g| g.max(0.0)).norm()
}

#[test]
fn separated_cuboids_distance_is_the_axis_aligned_gap() {
    let ha = Vector3::new(1.0, 0.5, 0.25);
    let hb = Vector3::new(0.3, 2.0, 1.0);
    let a = ConvexPolyhedron::cuboid(ha).unwrap().to_parry().unwrap();
    let b = ConvexPolyhedron::cuboid(hb).unwrap().to_parry().unwrap();
    let cases = [
        Vector3::new(3.0, 0.0, 0.0),
        Vector3::new(2.0, 3.0, 0.0),
        Vector3::new(-2.0, -3.5, 2.0),
        Vector3::new(0.5, 0.0, 2.0),
    ];
    for cb in cases {
        let pose_a = isometry_to_parry(&Isometry3::identity());
        let pose_b = isometry_to_parry(&Isometry3::translation(cb.x, cb.y, cb.z));
        let d = query::distance(&pose_a, &a, &pose_b, &b).unwrap().distance;
        assert_relative_eq!(
            d,
            aabb_distance(Vector3::zeros(), ha, cb, hb),
            max_relative = 1e-9
        );
    }
}

/// Brute force for a cube (half extent 1) above a rotated cube: the gap is
/// `z_b - 1 - max_v (R v)_z` when B's lowest vertex is above A's top face
/// and over it.
#[test]
fn rotated_cuboid_above_a_face_matches_its_lowest_vertex() {
    let cube = ConvexPolyhedron::cuboid(Vector3::new(1.0, 1.0, 1.0)).unwrap();
    let parry_cube = cube.to_parry().unwrap();
    let rotation = UnitQuaternion::from_euler_angles(0.3, -0.4, 0.2);
    let iso_b = Isometry3::from_parts(Translation3::new(0.1, -0.2, 3.5), rotation);
    let lowest = cube
        .vertices()
        .iter()
        .map(|v| (iso_b * v).z)
        .fold(f64::INFINITY, f64::min);
    let lowest_xy = cube
        .vertices()
        .iter()
        .map(|v| iso_b * v)
        .min_by(|p, q| p.z.total_cmp(&q.z))
        .unwrap();
    assert!(lowest_xy.x.abs() < 1.0 && lowest_xy.y.abs() < 1.0);
    let d = query::distance(
        &isometry_to_parry(&Isometry3::identity()),
        &parry_cube,
        &isometry_to_parry(&iso_b),
        &parry_cube,
    )
    .unwrap()
    .distance;
    assert_relative_eq!(d, lowest - 1.0, max_relative = 1e-9);
}

#[test]
fn converted_shape_keeps_body_frame_vertices_and_mass() {
    let points: Vec<Point3<f64>> = [
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 3.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
    ]
    .iter()
    .map(|c| Point3::new(c[0] + 5.0, c[1] - 1.0, c[2]))
    .collect();
    let hull = ConvexPolyhedron::from_points(&points).unwrap();
    let parry_hull = hull.to_parry().unwrap();
    assert_eq!(parry_hull.points().len(), hull.vertices().len());
    for (ours, theirs) in hull.vertices().iter().zip(parry_hull.points()) {
        assert_eq!(*ours, point_from_parry(*theirs));
    }
    let mass = parry_hull.mass_properties(1.0);
    assert_relative_eq!(mass.mass(), hull.volume(), max_relative = 1e-12);
    assert!(vector_from_parry(mass.local_com).norm() <= 1e-12 * hull.scale());
}

proptest! {
    #![proptest_config(proptest_config::config(64))]

    #[test]
    fn pose_round_trip_maps_points_the_same_way(
        axis_angle in prop::array::uniform3(-3.0..3.0f64),
        translation in prop::array::uniform3(-100.0..100.0f64),
        point in prop::array::uniform3(-10.0..10.0f64),
    ) {
        let iso = Isometry3::new(Vector3::from(translation), Vector3::from(axis_angle));
        let pose = isometry_to_parry(&iso);
        let p_body = Point3::from(point);
        let ours = iso * p_body;
        let theirs = point_from_parry(pose.transform_point(point_to_parry(&p_body)));
        prop_assert!((ours - theirs).norm() <= 1e-12 * (1.0 + ours.coords.norm()));
        let v = Vector3::from(point);
        let rotated = vector_from_parry(pose.rotation * vector_to_parry(&v));
        prop_assert!((iso.rotation * v - rotated).norm() <= 1e-12 * (1.0 + v.norm()));
        let back = isometry_from_parry(&pose);
        prop_assert!((back * p_body - ours).norm() <= 1e-12 * (1.0 + ours.coords.norm()));
    }

    #[test]
    fn cuboid_distance_matches_axis_aligned_gap(
        ha in prop::array::uniform3(0.1..3.0f64),
        hb in prop::array::uniform3(0.1..3.0f64),
        cb in prop::array::uniform3(-10.0..10.0f64),
    ) {
        let (ha, hb, cb) = (Vector3::from(ha), Vector3::from(hb), Vector3::from(cb));
        let expected = aabb_distance(Vector3::zeros(), ha, cb, hb);
        prop_assume!(expected > 1e-3);
        let a = ConvexPolyhedron::cuboid(ha).unwrap().to_parry().unwrap();
        let b = ConvexPolyhedron::cuboid(hb).unwrap().to_parry().unwrap();
        let d = query::distance(
            &isometry_to_parry(&Isometry3::identity()),
            &a,
            &isometry_to_parry(&Isometry3::translation(cb.x, cb.y, cb.z)),
            &b,
        )
        .unwrap()
        .distance;
        prop_assert!((d - expected).abs() <= 1e-9 * (1.0 + expected), "{d} vs {expected}");
    }
}

/// parry's own mass properties (`Shape::mass_properties`) of the converted
/// Mirtich shapes agree with ours: these shapes have no nearly coplanar
/// faces, which parry would merge.
#[test]
fn mirtich_shapes_keep_their_mass_in_parry() {
    let shapes = [
        ConvexPolyhedron::icosahedron(1.5).unwrap(),
        ConvexPolyhedron::disk(1.0, 0.1, 60).unwrap(),
        ConvexPolyhedron::geodesic_sphere(2.0, 3).unwrap(),
    ];
    for shape in shapes {
        let mass = shape.to_parry().unwrap().mass_properties(1.0);
        assert_relative_eq!(mass.mass(), shape.volume(), max_relative = 1e-9);
        let ours: Vec<f64> = {
            let mut e: Vec<f64> = shape
                .mass_properties()
                .inertia_unit_density
                .symmetric_eigen()
                .eigenvalues
                .iter()
                .copied()
                .collect();
            e.sort_by(f64::total_cmp);
            e
        };
        let mut theirs = vector_from_parry(mass.principal_inertia());
        theirs.as_mut_slice().sort_by(f64::total_cmp);
        // The sum of the principal moments is the trace, which survives a
        // repeated eigenvalue exactly; single eigenvalues from parry's
        // (glamx's) closed-form 3x3 solver lose about sqrt(ε) when two
        // coincide (the disk: I_xx = I_yy; the icosphere: all three).
        assert_relative_eq!(ours.iter().sum::<f64>(), theirs.sum(), max_relative = 1e-9);
        for (a, b) in ours.iter().zip(theirs.iter()) {
            assert_relative_eq!(*a, *b, max_relative = 1e-7);
        }
    }
}

proptest! {
    #![proptest_config(proptest_config::config(32))]

    /// The converted hull has the same vertices, hence the same support
    /// function, which is all GJK uses.
    #[test]
    fn converted_hull_has_the_same_support_points(
        points in prop::collection::vec(prop::array::uniform3(-1.0..1.0f64), 4..100),
        directions in prop::collection::vec(prop::array::uniform3(-1.0..1.0f64), 8),
    ) {
        let points: Vec<Point3<f64>> = points.into_iter().map(Point3::from).collect();
        let Ok(hull) = ConvexPolyhedron::from_points(&points) else {
            return Ok(());
        };
        let parry_hull = hull.to_parry().unwrap();
        for d in directions {
            let d = Vector3::from(d);
            let ours = hull.vertices().iter().map(|v| v.coords.dot(&d)).fold(f64::NEG_INFINITY, f64::max);
            let theirs = point_from_parry(parry_hull.local_support_point(vector_to_parry(&d)));
            prop_assert!((theirs.coords.dot(&d) - ours).abs() <= 1e-12 * (1.0 + ours.abs()));
        }
    }
}
