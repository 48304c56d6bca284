//! V-Clip fixtures shared by the V-Clip tests and the benchmarks
//! (`benchmarks/vclip.rs`, `benchmarks/contact_depth.rs`): the parry3d-f64
//! oracle (GJK distance, intersection test, EPA contact), a brute-force
//! distance, and Mirtich's experiments ([`experiments`]). Random shapes and
//! poses are in [`crate::random`], the separating-axis depth in
//! [`crate::sat`].

pub mod experiments;

use constraint_stabilization::internals::geometry::{ConvexPolyhedron, isometry_to_parry};
use constraint_stabilization::internals::vclip::{BodyRole, DeepestVertex, Outcome, VClipResult};
use nalgebra::{Isometry3, Point3, Translation3};
use parry3d_f64::math::Pose;
use parry3d_f64::query;
use parry3d_f64::shape::ConvexPolyhedron as ParryPolyhedron;

/// A parry pose equal to `iso`.
pub fn parry_pose(iso: &Isometry3<f64>) -> Pose {
    isometry_to_parry(iso)
}

/// The same solid as a parry shape.
pub fn parry_shape(poly: &ConvexPolyhedron) -> ParryPolyhedron {
    poly.to_parry().expect("a valid polyhedron converts")
}

/// parry's GJK distance (0 when touching or intersecting).
pub fn parry_distance(
    a: &ParryPolyhedron,
    pose_a: &Isometry3<f64>,
    b: &ParryPolyhedron,
    pose_b: &Isometry3<f64>,
) -> f64 {
    query::distance(&parry_pose(pose_a), a, &parry_pose(pose_b), b)
        .expect("polyhedra are supported")
        .distance
}

/// parry's intersection test.
pub fn parry_intersects(
    a: &ParryPolyhedron,
    pose_a: &Isometry3<f64>,
    b: &ParryPolyhedron,
    pose_b: &Isometry3<f64>,
) -> bool {
    query::intersection_test(&parry_pose(pose_a), a, &parry_pose(pose_b), b)
        .expect("polyhedra are supported")
        .intersecting
}

/// parry's EPA penetration depth (`-dist` of the contact), 0 if separated.
pub fn parry_depth(
    a: &ParryPolyhedron,
    pose_a: &Isometry3<f64>,
    b: &ParryPolyhedron,
    pose_b: &Isometry3<f64>,
) -> f64 {
    query::contact(&parry_pose(pose_a), a, &parry_pose(pose_b), b, 0.0)
        .expect("polyhedra are supported")
        .map_or(0.0, |c| (-c.dist).max(0.0))
}

/// The separated distance, or `None` if penetrating.
pub fn separated_distance(result: &VClipResult) -> Option<f64> {
    match result.outcome {
        Outcome::Separated { distance, .. } => Some(distance),
        Outcome::Penetrating(_) => None,
    }
}

/// The pose of the vertex's body shifted by `depth * normal`.
pub fn pushed_out(
    deepest: &DeepestVertex,
    pose_a: &Isometry3<f64>,
    pose_b: &Isometry3<f64>,
    extra: f64,
) -> (Isometry3<f64>, Isometry3<f64>) {
    let shift = Translation3::from(deepest.normal_world * (deepest.depth + extra));
    match deepest.vertex_body {
        BodyRole::A => (shift * pose_a, *pose_b),
        BodyRole::B => (*pose_a, shift * pose_b),
    }
}

/// Brute-force distance of two disjoint convex polyhedra, in the world
/// frame: the minimum over vertex–face pairs (vertex above the face plane
/// and projecting inside the polygon) and edge–edge pairs. An oracle
/// independent of V-Clip's walk, exact up to rounding where GJK is not
/// (parry's GJK stops at a relative gap of about 1e-8 in near-degenerate
/// configurations). Meaningless for intersecting bodies.
pub fn brute_force_distance(
    a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
) -> f64 {
    let world = |poly: &ConvexPolyhedron, pose: &Isometry3<f64>| -> Vec<Point3<f64>> {
        poly.vertices().iter().map(|p| pose * p).collect()
    };
    let (va, vb) = (world(a, pose_a), world(b, pose_b));
    let mut best = f64::INFINITY;
    for (poly, pose, verts, others) in [(a, pose_a, &va, &vb), (b, pose_b, &vb, &va)] {
        for face in poly.faces() {
            let n = pose.rotation * face.plane.normal;
            let corners: Vec<Point3<f64>> = face.vertices.iter().map(|&v| verts[v]).collect();
            for p in others {
                let height = n.dot(&(p - corners[0]));
                let inside = (0..corners.len()).all(|i| {
                    let (c0, c1) = (corners[i], corners[(i + 1) % corners.len()]);
                    n.cross(&(c1 - c0)).dot(&(p - c0)) >= 0.0
                });
                if height >= 0.0 && inside {
                    best = best.min(height);
                }
            }
        }
    }
    for ea in a.edges() {
        for eb in b.edges() {
            let d = segment_distance(&va[ea.tail], &va[ea.head], &vb[eb.tail], &vb[eb.head]);
            best = best.min(d);
        }
    }
    best
}

fn point_segment_distance(p: &Point3<f64>, a: &Point3<f64>, b: &Point3<f64>) -> f64 {
    let d = b - a;
    let t = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    (p - (a + d * t)).norm()
}

fn segment_distance(p0: &Point3<f64>, p1: &Point3<f64>, q0: &Point3<f64>, q1: &Point3<f64>) -> f64 {
    let mut best = point_segment_distance(p0, q0, q1)
        .min(point_segment_distance(p1, q0, q1))
        .min(point_segment_distance(q0, p0, p1))
        .min(point_segment_distance(q1, p0, p1));
    // Interior critical point of the two lines, via the common normal.
    let (u, v) = (p1 - p0, q1 - q0);
    let n = u.cross(&v);
    let nn = n.norm_squared();
    if nn > 0.0 {
        let w = q0 - p0;
        let s = w.cross(&v).dot(&n) / nn;
        let t = w.cross(&u).dot(&n) / nn;
        if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
            best = best.min(((p0 + u * s) - (q0 + v * t)).norm());
        }
    }
    best
}
