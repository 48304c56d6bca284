//! Shared helpers of the V-Clip tests: random shapes and poses, and the
//! parry3d-f64 oracle (GJK distance, intersection test, EPA contact).
#![allow(dead_code)]

use constraint_stabilization::geometry::{ConvexPolyhedron, isometry_to_parry};
use constraint_stabilization::vclip::{BodyRole, DeepestVertex, Outcome, VClipResult};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::math::Pose;
use parry3d_f64::query;
use parry3d_f64::shape::ConvexPolyhedron as ParryPolyhedron;
use rand::Rng;

/// A parry pose equal to `iso`.
pub fn parry_pose(iso: &Isometry3<f64>) -> Pose {
    isometry_to_parry(iso)
}

/// The same solid as a parry shape.
pub fn parry_shape(poly: &ConvexPolyhedron) -> ParryPolyhedron {
    poly.to_parry().expect("a valid polyhedron converts")
}

/// Our polyhedron, hull of `points` (the project's `from_points`).
pub fn hull(points: &[Point3<f64>]) -> Option<ConvexPolyhedron> {
    ConvexPolyhedron::from_points(points).ok()
}

/// A random hull of `n` points in a ball of radius `radius` (retries until
/// the hull is valid).
pub fn random_hull(rng: &mut impl Rng, n: usize, radius: f64) -> ConvexPolyhedron {
    loop {
        let points: Vec<Point3<f64>> = (0..n).map(|_| random_in_ball(rng) * radius).collect();
        let points: Vec<Point3<f64>> = points.into_iter().collect();
        if let Some(poly) = hull(&points) {
            return poly;
        }
    }
}

fn random_in_ball(rng: &mut impl Rng) -> Point3<f64> {
    loop {
        let p = Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if p.norm_squared() <= 1.0 {
            return Point3::from(p);
        }
    }
}

/// A uniformly random rotation.
pub fn random_rotation(rng: &mut impl Rng) -> UnitQuaternion<f64> {
    loop {
        let q = nalgebra::Quaternion::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let norm = q.norm();
        if norm > 0.1 && norm <= 1.0 {
            return UnitQuaternion::from_quaternion(q);
        }
    }
}

/// A random pose with translation in `[-extent, extent]³`.
pub fn random_pose(rng: &mut impl Rng, extent: f64) -> Isometry3<f64> {
    let t = Vector3::new(
        rng.random_range(-extent..extent),
        rng.random_range(-extent..extent),
        rng.random_range(-extent..extent),
    );
    Isometry3::from_parts(Translation3::from(t), random_rotation(rng))
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

/// A random hull of `n` points (4 to 200 in the tests), most near a sphere
/// of radius `radius` so that the hull keeps many of them, with random
/// aspect ratios so that flat and thin hulls occur too.
pub fn random_hull_varied(rng: &mut impl Rng, n: usize, radius: f64) -> ConvexPolyhedron {
    let stretch = Vector3::new(
        rng.random_range(0.2..1.0),
        rng.random_range(0.2..1.0),
        rng.random_range(0.2..1.0),
    );
    loop {
        let points: Vec<Point3<f64>> = (0..n)
            .map(|_| {
                let p = random_in_ball(rng).coords;
                let p = if p.norm() > 1e-3 && rng.random_bool(0.7) {
                    p.normalize()
                } else {
                    p
                };
                Point3::from(p.component_mul(&stretch) * radius)
            })
            .collect();
        if let Some(poly) = hull(&points) {
            return poly;
        }
    }
}
