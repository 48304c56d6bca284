//! The parry bridge: converted shapes and poses give parry queries the
//! answers known in closed form or by brute force.

use approx::assert_relative_eq;
use constraint_stabilization::geometry::{
    ConvexPolyhedron, isometry_from_parry, isometry_to_parry, point_from_parry, point_to_parry,
    vector_from_parry, vector_to_parry,
};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::query;
use parry3d_f64::shape::Shape;
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
    #![proptest_config(ProptestConfig::with_cases(64))]

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
