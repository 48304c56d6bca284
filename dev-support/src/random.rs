//! Random rotations, poses, convex hulls and mixed shapes for the tests and benchmarks
//! (seeded by the caller: every use passes its own seeded RNG, so that a
//! run draws the same shapes every time).

use constraint_stabilization::body::Shape;
use constraint_stabilization::internals::geometry::ConvexPolyhedron;
use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};
use rand::Rng;

/// A uniformly random rotation: a quaternion drawn uniformly in the unit
/// 4-ball (rejection sampling, away from 0), normalized.
pub fn random_rotation(rng: &mut impl Rng) -> UnitQuaternion<f64> {
    loop {
        let q = Quaternion::new(
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

/// A random pose: [`random_rotation`], translation uniform in
/// `[-extent, extent]³`.
pub fn random_pose(rng: &mut impl Rng, extent: f64) -> Isometry3<f64> {
    let t = Vector3::new(
        rng.random_range(-extent..extent),
        rng.random_range(-extent..extent),
        rng.random_range(-extent..extent),
    );
    Isometry3::from_parts(Translation3::from(t), random_rotation(rng))
}

/// A point uniform in the unit ball (rejection sampling).
pub fn random_in_ball(rng: &mut impl Rng) -> Point3<f64> {
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

/// The library's hull of `points` (`ConvexPolyhedron::from_points`), or
/// `None` where it has no volume.
fn hull(points: &[Point3<f64>]) -> Option<ConvexPolyhedron> {
    ConvexPolyhedron::from_points(points).ok()
}

/// A random hull of `n` points in a ball of radius `radius` (retries until
/// the hull is valid).
pub fn random_hull(rng: &mut impl Rng, n: usize, radius: f64) -> ConvexPolyhedron {
    loop {
        let points: Vec<Point3<f64>> = (0..n).map(|_| random_in_ball(rng) * radius).collect();
        if let Some(poly) = hull(&points) {
            return poly;
        }
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

/// Kinds of [`mixed_shape`]: sphere, capsule, rounded cuboid, rounded hull,
/// cuboid, hull, cylinder, cone.
pub const MIXED_SHAPE_KINDS: usize = 8;

/// A random shape of kind `kind % MIXED_SHAPE_KINDS` whose dimensions are
/// `scale` times 0.2 to 0.8 (hull points within `0.6 scale` of the origin).
pub fn mixed_shape(rng: &mut impl Rng, kind: usize, scale: f64) -> Shape {
    let mut size = || scale * rng.random_range(0.2..0.8);
    match kind % MIXED_SHAPE_KINDS {
        0 => Shape::Sphere { radius: size() },
        1 => Shape::Capsule {
            half_height: size(),
            radius: 0.5 * size(),
        },
        2 => Shape::RoundCuboid {
            half_extents: Vector3::new(size(), size(), size()),
            radius: 0.3 * size(),
        },
        3 | 5 => {
            let points = (0..12)
                .map(|_| Point3::from(Vector3::from_fn(|_, _| scale * rng.random_range(-0.6..0.6))))
                .collect();
            if kind % MIXED_SHAPE_KINDS == 3 {
                Shape::RoundConvexHull {
                    points,
                    radius: scale * rng.random_range(0.05..0.2),
                }
            } else {
                Shape::ConvexHull { points }
            }
        }
        4 => Shape::Cuboid {
            half_extents: Vector3::new(size(), size(), size()),
        },
        6 => Shape::Cylinder {
            half_height: size(),
            radius: size(),
        },
        _ => Shape::Cone {
            half_height: size(),
            radius: size(),
        },
    }
}
