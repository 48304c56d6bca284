//! The exact penetration depth of a scene, measured independently of the
//! library's contact code, by brute force over separating axes: for every
//! pair of bodies of which at least one is dynamic, the candidate axes are
//! the face normals of both bodies and the cross products of every edge of
//! one with every edge of the other. For two convex polyhedra the
//! penetration depth (the length of the shortest translation that
//! separates them) is the smallest overlap of their projections over these
//! axes, and they are disjoint or touching if one overlap is `<= 0`.
//!
//! Only the polyhedra's vertices and topology (which vertices make a face,
//! which two make an edge) and the bodies' poses are taken from the
//! library; normals and edge directions are recomputed here from the world
//! vertices (Newell's normal, head minus tail), and nothing of V-Clip, the
//! Gauss-map search or the stabilizer's report is used. A pair whose
//! axis-aligned boxes (of the world vertices) are disjoint is separated
//! along a coordinate axis and has depth 0: this test only skips pairs
//! whose depth is exactly 0.

use constraint_stabilization::body::Body;
use constraint_stabilization::scene::Scene;
use nalgebra::Vector3;

/// One body in world frame: vertices, unit face normals, unit edge
/// directions (parallel duplicates removed), bounding box.
pub struct WorldHull {
    vertices: Vec<Vector3<f64>>,
    normals: Vec<Vector3<f64>>,
    edges: Vec<Vector3<f64>>,
    lo: Vector3<f64>,
    hi: Vector3<f64>,
}

/// Two unit directions closer than this (|cross| below it) are parallel.
const PARALLEL: f64 = 1e-9;

fn push_unique(list: &mut Vec<Vector3<f64>>, v: Vector3<f64>) {
    if let Some(unit) = v.try_normalize(0.0)
        && !list.iter().any(|u| u.cross(&unit).norm() < PARALLEL)
    {
        list.push(unit);
    }
}

impl WorldHull {
    /// The body's polyhedron at its current pose.
    pub fn of(body: &Body) -> Self {
        let pose = body.com_pose();
        let poly = body.polyhedron().expect("a convex body");
        let vertices: Vec<Vector3<f64>> =
            poly.vertices().iter().map(|p| (pose * p).coords).collect();
        let mut normals = Vec::new();
        for face in poly.faces() {
            // Newell's normal of the face polygon.
            let n = face.vertices.len();
            let normal = (0..n).fold(Vector3::zeros(), |acc, i| {
                let (p, q) = (
                    vertices[face.vertices[i]],
                    vertices[face.vertices[(i + 1) % n]],
                );
                acc + (p - q).cross(&(p + q))
            });
            push_unique(&mut normals, normal);
        }
        let mut edges = Vec::new();
        for edge in poly.edges() {
            push_unique(&mut edges, vertices[edge.head] - vertices[edge.tail]);
        }
        let lo = vertices
            .iter()
            .fold(Vector3::repeat(f64::INFINITY), |a, v| a.inf(v));
        let hi = vertices
            .iter()
            .fold(Vector3::repeat(f64::NEG_INFINITY), |a, v| a.sup(v));
        WorldHull {
            vertices,
            normals,
            edges,
            lo,
            hi,
        }
    }

    fn extent(&self, axis: &Vector3<f64>) -> (f64, f64) {
        self.vertices
            .iter()
            .map(|v| v.dot(axis))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| {
                (lo.min(d), hi.max(d))
            })
    }
}

/// Penetration depth of two hulls (0 if they are disjoint or touch).
pub fn pair_depth(a: &WorldHull, b: &WorldHull) -> f64 {
    if (0..3).any(|k| a.hi[k] <= b.lo[k] || b.hi[k] <= a.lo[k]) {
        return 0.0;
    }
    let mut depth = f64::INFINITY;
    let mut overlap = |axis: &Vector3<f64>| {
        let ((a_lo, a_hi), (b_lo, b_hi)) = (a.extent(axis), b.extent(axis));
        depth = depth.min((a_hi - b_lo).min(b_hi - a_lo));
        depth <= 0.0
    };
    if a.normals.iter().chain(&b.normals).any(&mut overlap) {
        return 0.0;
    }
    for ea in &a.edges {
        for eb in &b.edges {
            let axis = ea.cross(eb);
            // Parallel edges give no axis of their own (the face normals
            // cover that case).
            if let Some(unit) = axis.try_normalize(PARALLEL)
                && overlap(&unit)
            {
                return 0.0;
            }
        }
    }
    depth.max(0.0)
}

/// The exact depths of a scene, over every pair with a dynamic body.
#[derive(Debug, Clone, Copy)]
pub struct ExactDepth {
    /// Deepest penetration of any pair (0 if none).
    pub deepest: f64,
    /// Pairs penetrating deeper than the tolerance given.
    pub penetrating: usize,
    /// The tolerance the pairs were counted against.
    pub tolerance: f64,
}

impl ExactDepth {
    /// Whether no pair penetrates deeper than the tolerance.
    pub fn resolved(&self) -> bool {
        self.deepest <= self.tolerance
    }

    /// "resolved" or "unresolved".
    pub fn verdict(&self) -> &'static str {
        if self.resolved() {
            "resolved"
        } else {
            "unresolved"
        }
    }
}

/// Brute force over all pairs of `scene` with at least one dynamic body;
/// `tolerance` is the stabilizer's (`Report::tolerance`).
pub fn exact_depth(scene: &Scene, tolerance: f64) -> ExactDepth {
    let bodies = scene.bodies();
    let hulls: Vec<WorldHull> = bodies.iter().map(WorldHull::of).collect();
    let mut result = ExactDepth {
        deepest: 0.0,
        penetrating: 0,
        tolerance,
    };
    for i in 0..hulls.len() {
        for j in i + 1..hulls.len() {
            if bodies[i].is_fixed() && bodies[j].is_fixed() {
                continue;
            }
            let depth = pair_depth(&hulls[i], &hulls[j]);
            result.deepest = result.deepest.max(depth);
            result.penetrating += usize::from(depth > tolerance);
        }
    }
    result
}
