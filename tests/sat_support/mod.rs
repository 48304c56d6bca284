//! The brute-force separating-axis oracle of the test suite (one copy,
//! included by `stabilize_support` and `vclip_support`): the exact
//! penetration depth of two posed convex polyhedra as the smallest overlap
//! of their projections over every face normal of either body and every
//! cross product of an edge of A with an edge of B (the facet normals of
//! the Minkowski difference are among these). Cost
//! O((F + E_A E_B)(V_A + V_B)): for tests, never for the library.
#![allow(dead_code)]

use constraint_stabilization::geometry::ConvexPolyhedron;
use nalgebra::{Isometry3, Vector3};

/// Edge pairs whose cross product is shorter than this fraction of the
/// product of their lengths give no axis (their directions are parallel
/// within rounding). Leaving out an axis can only raise the minimum, never
/// below the true depth: every axis's overlap bounds the depth from above.
pub const PARALLEL_EDGES: f64 = 1e-12;

/// The minima of the overlap over the candidate axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SatAxes {
    /// Smallest overlap over the face normals of both bodies.
    pub faces: f64,
    /// Smallest overlap over face normals and edge–edge cross products:
    /// the exact penetration depth when positive; when negative, some axis
    /// separates the bodies (by at least that gap).
    pub all: f64,
    /// The axis of `all`, unit, oriented from B towards A: translating A
    /// by `all` along it makes the bodies touch.
    pub axis: Vector3<f64>,
}

/// The separating-axis minima of A at `pose_a` and B at `pose_b` (world
/// frame).
pub fn sat_axes(
    a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
) -> SatAxes {
    let world = |poly: &ConvexPolyhedron, pose: &Isometry3<f64>| -> Vec<Vector3<f64>> {
        poly.vertices().iter().map(|p| (pose * p).coords).collect()
    };
    let (va, vb) = (world(a, pose_a), world(b, pose_b));
    // Moving A along +n separates after max_b - min_a, along -n after
    // max_a - min_b: the smaller, with its direction.
    let overlap = |n: Vector3<f64>| -> (f64, Vector3<f64>) {
        let range = |vs: &[Vector3<f64>]| {
            vs.iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    let x = n.dot(v);
                    (lo.min(x), hi.max(x))
                })
        };
        let ((lo_a, hi_a), (lo_b, hi_b)) = (range(&va), range(&vb));
        let (along, against) = (hi_b - lo_a, hi_a - lo_b);
        if along <= against {
            (along, n)
        } else {
            (against, -n)
        }
    };
    let smaller = |best: (f64, Vector3<f64>), next: (f64, Vector3<f64>)| {
        if next.0 < best.0 { next } else { best }
    };
    let start = (f64::INFINITY, Vector3::zeros());
    let face_best = a
        .faces()
        .iter()
        .map(|f| pose_a.rotation * f.plane.normal)
        .chain(b.faces().iter().map(|f| pose_b.rotation * f.plane.normal))
        .map(overlap)
        .fold(start, smaller);
    let mut best = face_best;
    for ea in a.edges() {
        let u = va[ea.head] - va[ea.tail];
        for eb in b.edges() {
            let v = vb[eb.head] - vb[eb.tail];
            let n = u.cross(&v);
            let norm = n.norm();
            if norm > PARALLEL_EDGES * u.norm() * v.norm() {
                best = smaller(best, overlap(n / norm));
            }
        }
    }
    SatAxes {
        faces: face_best.0,
        all: best.0,
        axis: best.1,
    }
}
