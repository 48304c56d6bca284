//! `ConvexPolyhedron::from_faces` rejects a planar but non-convex face.
//!
//! The box `[0, 2]^3` with its top face split at an inner vertex
//! `v = (1, 1, 2)` into three coplanar faces whose angles at `v` are 80°,
//! 80° and 200°: every vertex is on or below every face plane, yet the third
//! face is not a convex polygon, which V-Clip's Voronoi regions assume.

use constraint_stabilization::internals::geometry::{ConvexPolyhedron, GeometryError};
use nalgebra::{Point3, Vector3};

/// Orders the vertices of a convex face counter-clockwise about `normal`.
fn ccw(points: &[Point3<f64>], mut face: Vec<usize>, normal: Vector3<f64>) -> Vec<usize> {
    let centre = face
        .iter()
        .fold(Vector3::zeros(), |acc, &i| acc + points[i].coords)
        / face.len() as f64;
    let u = (points[face[0]].coords - centre).normalize();
    let w = normal.cross(&u);
    face.sort_by(|&a, &b| {
        let angle = |i: usize| {
            let r = points[i].coords - centre;
            r.dot(&w).atan2(r.dot(&u))
        };
        angle(a).total_cmp(&angle(b))
    });
    face
}

fn split_top_box(reflex_angle_degrees: f64) -> Result<ConvexPolyhedron, GeometryError> {
    let a1 = ((360.0 - reflex_angle_degrees) / 2.0_f64).to_radians(); // second ray
    let a2 = (360.0 - reflex_angle_degrees).to_radians(); // third ray
    // Rays from v = (1, 1) at angles 0, a1, a2 hit the square's boundary.
    let hit = |angle: f64| {
        let d = Vector3::new(angle.cos(), angle.sin(), 0.0);
        let t = [
            (2.0 - 1.0) / d.x,
            (0.0 - 1.0) / d.x,
            (2.0 - 1.0) / d.y,
            (0.0 - 1.0) / d.y,
        ]
        .into_iter()
        .filter(|t| t.is_finite() && *t > 0.0)
        .fold(f64::INFINITY, f64::min);
        Point3::new(1.0 + t * d.x, 1.0 + t * d.y, 2.0)
    };
    let mut points: Vec<Point3<f64>> = (0..8)
        .map(|i| {
            Point3::new(
                2.0 * (i & 1) as f64,
                2.0 * ((i >> 1) & 1) as f64,
                2.0 * ((i >> 2) & 1) as f64,
            )
        })
        .collect();
    points.extend([Point3::new(1.0, 1.0, 2.0), hit(0.0), hit(a1), hit(a2)]);
    let (v, r0, r1, r2) = (8, 9, 10, 11);
    let on = |i: usize, axis: usize, value: f64| (points[i][axis] - value).abs() < 1e-12;
    let mut faces = Vec::new();
    for (axis, value) in [(0, 0.0), (0, 2.0), (1, 0.0), (1, 2.0), (2, 0.0)] {
        let mut normal = Vector3::zeros();
        normal[axis] = if value > 0.0 { 1.0 } else { -1.0 };
        let face: Vec<usize> = (0..12).filter(|&i| on(i, axis, value)).collect();
        faces.push(ccw(&points, face, normal));
    }
    // Top: the three pieces between the rays, each as the set of its corners.
    let top_corners = [6usize, 7, 5, 4]; // (0,2), (2,2), (2,0), (0,0) at z = 2
    let angle_of = |i: usize| {
        let r = points[i] - points[v];
        r.y.atan2(r.x).rem_euclid(std::f64::consts::TAU)
    };
    let rays = [(r0, 0.0), (r1, a1), (r2, a2)];
    for k in 0..3 {
        let (start, from) = rays[k];
        let (end, to) = if k == 2 {
            (r0, std::f64::consts::TAU)
        } else {
            rays[k + 1]
        };
        let mut inner: Vec<usize> = top_corners
            .iter()
            .copied()
            .filter(|&i| angle_of(i) > from && angle_of(i) < to)
            .collect();
        inner.sort_by(|&a, &b| angle_of(a).total_cmp(&angle_of(b)));
        let mut face = vec![v, start];
        face.extend(inner);
        face.push(end);
        faces.push(face);
    }
    points.truncate(12);
    ConvexPolyhedron::from_faces(points, faces)
}

#[test]
fn top_split_into_convex_pieces_is_accepted() {
    // Angles 120°, 120°, 120° at v: three convex pieces.
    let split = split_top_box(120.0).unwrap();
    assert_eq!(split.faces().len(), 8);
    assert!((split.volume() - 8.0).abs() < 1e-12);
}

#[test]
fn planar_non_convex_face_is_rejected() {
    let result = split_top_box(200.0);
    assert!(
        matches!(result, Err(GeometryError::NotConvex(_))),
        "{result:?}"
    );
}
