//! The one brute-force separating-axis (SAT) oracle of the tests, the
//! benchmarks and the examples: the exact penetration depth of two posed
//! convex polyhedra as the smallest overlap of their projections over every
//! face normal of either body and every cross product of an edge of A with
//! an edge of B (the facet normals of the Minkowski difference are among
//! these). Cost O((F + E_A E_B)(V_A + V_B)) per pair at most (an axis's
//! projection scan stops once its overlap cannot be the minimum): for
//! checking, never for the library.
//!
//! Per pair: [`sat_axes`] (the minima over face normals and over all axes,
//! and the axis), [`sat_overlap`], [`sat_axis`], [`separating_axis_depth`],
//! [`sat_overlap_at_most`] (a bound on the minimum, decided at the first
//! axis that meets it).
//! Over a scene (the pairs with a dynamic body, compound bodies part by
//! part): [`sat_depth`] of one pair of bodies, [`sat_deepest`],
//! [`exact_depth`] (deepest and the count of pairs beyond a tolerance).
//!
//! Only the polyhedra's vertices, topology and face normals and the bodies'
//! poses come from the library: nothing of V-Clip, the Gauss-map search,
//! the contact code or the stabilizer's report is used.

use constraint_stabilization::internals::geometry::ConvexPolyhedron;
use constraint_stabilization::scene::Scene;
use nalgebra::{Isometry3, Vector3};
use std::ops::ControlFlow;

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

/// Whether a candidate axis of [`visit_axes`] is a face normal or an
/// edge–edge cross product.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum AxisKind {
    Face,
    EdgePair,
}

/// What walks the candidate axes ([`visit_axes`]): a cutoff below which an
/// overlap matters, and what to do with one that does.
trait AxisVisitor {
    /// Overlaps at or above this cannot change the visitor's answer: the
    /// walk may skip them without finishing their projections.
    fn cutoff(&self) -> f64;
    /// One axis's overlap (below the cutoff), its axis oriented from B
    /// towards A, and its kind; `Break` ends the walk.
    fn visit(&mut self, overlap: f64, axis: Vector3<f64>, kind: AxisKind) -> ControlFlow<()>;
}

/// Walks the candidate axes of A at `pose_a` and B at `pose_b` (world
/// frame) in a fixed order: the face normals of A, those of B, then the
/// cross product of every edge of A with every edge of B (pairs parallel
/// within [`PARALLEL_EDGES`] left out). Each axis's overlap is the smaller
/// translation of A along `±axis` that makes the projections touch; an
/// axis whose overlap is at least the visitor's cutoff is skipped.
///
/// The projections are scanned a vertex of A and a vertex of B at a time;
/// both candidate translations (`max_b - min_a` and `max_a - min_b`) only
/// grow as vertices are added, so once both reach the cutoff the overlap
/// does too and the rest of the scan is skipped. Minima and maxima do not
/// round: an overlap that is finished is the same number whatever the
/// order of the scan.
fn visit_axes(
    a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
    visitor: &mut impl AxisVisitor,
) {
    let world = |poly: &ConvexPolyhedron, pose: &Isometry3<f64>| -> Vec<Vector3<f64>> {
        poly.vertices().iter().map(|p| (pose * p).coords).collect()
    };
    let (va, vb) = (world(a, pose_a), world(b, pose_b));
    // Moving A along +n separates after max_b - min_a, along -n after
    // max_a - min_b: the smaller, with its direction; `None` when both
    // reach `cutoff`.
    let overlap = |n: Vector3<f64>, cutoff: f64| -> Option<(f64, Vector3<f64>)> {
        let (mut lo_a, mut hi_a) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut lo_b, mut hi_b) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..va.len().max(vb.len()) {
            if let Some(v) = va.get(k) {
                let x = n.dot(v);
                (lo_a, hi_a) = (lo_a.min(x), hi_a.max(x));
            }
            if let Some(v) = vb.get(k) {
                let x = n.dot(v);
                (lo_b, hi_b) = (lo_b.min(x), hi_b.max(x));
            }
            if hi_b - lo_a >= cutoff && hi_a - lo_b >= cutoff {
                return None;
            }
        }
        let (along, against) = (hi_b - lo_a, hi_a - lo_b);
        Some(if along <= against {
            (along, n)
        } else {
            (against, -n)
        })
    };
    let face_normals = a
        .faces()
        .iter()
        .map(|f| pose_a.rotation * f.plane.normal)
        .chain(b.faces().iter().map(|f| pose_b.rotation * f.plane.normal));
    for n in face_normals {
        if let Some((depth, axis)) = overlap(n, visitor.cutoff())
            && visitor.visit(depth, axis, AxisKind::Face).is_break()
        {
            return;
        }
    }
    for ea in a.edges() {
        let u = va[ea.head] - va[ea.tail];
        for eb in b.edges() {
            let v = vb[eb.head] - vb[eb.tail];
            let n = u.cross(&v);
            let norm = n.norm();
            if norm > PARALLEL_EDGES * u.norm() * v.norm()
                && let Some((depth, axis)) = overlap(n / norm, visitor.cutoff())
                && visitor.visit(depth, axis, AxisKind::EdgePair).is_break()
            {
                return;
            }
        }
    }
}

/// The running minima of [`sat_axes`].
struct Minima {
    faces: f64,
    best: (f64, Vector3<f64>),
}

impl AxisVisitor for Minima {
    /// Only a strictly smaller overlap replaces the minimum.
    fn cutoff(&self) -> f64 {
        self.best.0
    }

    fn visit(&mut self, overlap: f64, axis: Vector3<f64>, kind: AxisKind) -> ControlFlow<()> {
        if overlap < self.best.0 {
            self.best = (overlap, axis);
        }
        if kind == AxisKind::Face {
            self.faces = self.best.0;
        }
        ControlFlow::Continue(())
    }
}

/// The separating-axis minima of A at `pose_a` and B at `pose_b` (world
/// frame): the smallest overlap over the candidate axes of [`visit_axes`]
/// (the first of equal ones).
pub fn sat_axes(
    a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
) -> SatAxes {
    let mut minima = Minima {
        faces: f64::INFINITY,
        best: (f64::INFINITY, Vector3::zeros()),
    };
    visit_axes(a, pose_a, b, pose_b, &mut minima);
    SatAxes {
        faces: minima.faces,
        all: minima.best.0,
        axis: minima.best.1,
    }
}

/// The search of [`sat_overlap_at_most`]: whether an overlap at most
/// `bound` has been seen.
struct AtMost {
    bound: f64,
    found: bool,
}

impl AxisVisitor for AtMost {
    /// Overlaps above the bound are skipped: the next double above it.
    fn cutoff(&self) -> f64 {
        self.bound.next_up()
    }

    fn visit(&mut self, overlap: f64, _: Vector3<f64>, _: AxisKind) -> ControlFlow<()> {
        if overlap <= self.bound {
            self.found = true;
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

/// Whether [`sat_overlap`] of the pair is at most `bound`, decided at the
/// first candidate axis whose overlap is at most `bound` (the minimum over
/// the axes is at most `bound` exactly when one of them is): the same
/// answer as `sat_overlap(..) <= bound`, usually after a few face normals
/// when the bodies are apart.
pub fn sat_overlap_at_most(
    a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
    bound: f64,
) -> bool {
    let mut search = AtMost {
        bound,
        found: false,
    };
    visit_axes(a, pose_a, b, pose_b, &mut search);
    search.found
}

/// The smallest overlap of the projections of two posed polyhedra over
/// every face normal of both and every cross product of an edge of each
/// ([`sat_axes`]): the exact penetration depth when positive; when
/// negative, some axis separates the bodies (by at least that gap).
pub fn sat_overlap(
    poly_a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    poly_b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
) -> f64 {
    sat_axes(poly_a, pose_a, poly_b, pose_b).all
}

/// [`sat_overlap`] and the axis that realizes it, oriented from B towards A
/// (translating A by the overlap along it makes the bodies touch).
pub fn sat_axis(
    poly_a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    poly_b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
) -> (f64, Vector3<f64>) {
    let axes = sat_axes(poly_a, pose_a, poly_b, pose_b);
    (axes.all, axes.axis)
}

/// The two minima of [`separating_axis_depth`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisDepths {
    /// Minimum overlap over the face normals of both bodies.
    pub faces: f64,
    /// Minimum over face normals and edge–edge cross products: the exact
    /// penetration depth.
    pub all: f64,
}

/// Exact penetration depth of two convex polyhedra ([`sat_axes`]) clamped
/// at 0: `faces` is the minimum over face normals only (the best that a
/// vertex–face answer can reach); `all` adds the edge pairs. Both are 0
/// when some axis separates.
pub fn separating_axis_depth(
    a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
) -> AxisDepths {
    let axes = sat_axes(a, pose_a, b, pose_b);
    AxisDepths {
        faces: axes.faces.max(0.0),
        all: axes.all.max(0.0),
    }
}

/// Penetration depth of bodies `a` and `b` of `scene` ([`sat_overlap`],
/// 0 when some axis separates): for compound bodies, the deepest over their
/// part pairs. A body with a round or curved part (sphere, capsule,
/// rounded cuboid or hull, cylinder, cone) is measured by the
/// support-function oracle instead ([`crate::support_oracle`]): on the
/// true shapes, not on the library's polyhedra of cylinders and cones
/// (whose depths exceed the true ones by at most their
/// `Shape::surface_deviation`).
pub fn sat_depth(scene: &Scene, a: usize, b: usize) -> f64 {
    let (body_a, body_b) = (&scene.bodies()[a], &scene.bodies()[b]);
    let mut deepest: f64 = 0.0;
    let round = |body: &constraint_stabilization::body::Body| {
        body.parts().iter().any(|p| p.rounding().is_some())
            || body.shape().surface_deviation() > 0.0
    };
    if round(body_a) || round(body_b) {
        // Round and curved parts are not polyhedra: the support-function
        // oracle.
        return crate::support_oracle::body_depth(body_a, body_b);
    }
    for (part_a, pose_a) in body_a.parts().iter().zip(body_a.part_poses()) {
        for (part_b, pose_b) in body_b.parts().iter().zip(body_b.part_poses()) {
            let overlap = sat_overlap(part_a.polyhedron(), &pose_a, part_b.polyhedron(), &pose_b);
            deepest = deepest.max(overlap);
        }
    }
    deepest
}

/// `depth(a, b)` of every pair `a < b` of `scene` with at least one dynamic
/// body whose world AABBs (from the exact world vertices) overlap: pairs of
/// fixed bodies cannot be corrected, and pairs with disjoint boxes cannot
/// penetrate.
pub fn pair_depths(
    scene: &Scene,
    depth: impl Fn(usize, usize) -> f64,
) -> Vec<((usize, usize), f64)> {
    let aabbs: Vec<_> = scene.bodies().iter().map(|b| b.world_aabb()).collect();
    let overlap = |a: usize, b: usize| {
        let ((min_a, max_a), (min_b, max_b)) = (aabbs[a], aabbs[b]);
        (0..3).all(|k| min_a[k] <= max_b[k] && min_b[k] <= max_a[k])
    };
    let mut depths = Vec::new();
    for a in 0..scene.len() {
        for b in a + 1..scene.len() {
            let both_fixed = scene.bodies()[a].is_fixed() && scene.bodies()[b].is_fixed();
            if both_fixed || !overlap(a, b) {
                continue;
            }
            depths.push(((a, b), depth(a, b)));
        }
    }
    depths
}

/// The largest `depth(a, b)` over the pairs of [`pair_depths`] and the pair
/// (0 and `None` when no pair is deeper than 0).
pub fn deepest_over_pairs(
    scene: &Scene,
    depth: impl Fn(usize, usize) -> f64,
) -> (f64, Option<(usize, usize)>) {
    let mut worst = (0.0, None);
    for (pair, d) in pair_depths(scene, depth) {
        if d > worst.0 {
            worst = (d, Some(pair));
        }
    }
    worst
}

/// The deepest brute-force separating-axis depth [`sat_depth`] of the
/// scene and the pair it is in: the exact deepest penetration.
pub fn sat_deepest(scene: &Scene) -> (f64, Option<(usize, usize)>) {
    deepest_over_pairs(scene, |a, b| sat_depth(scene, a, b))
}

/// The exact depths of a scene ([`exact_depth`]), over every pair with a
/// dynamic body.
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

/// [`sat_depth`] over every pair of `scene` with a dynamic body: the
/// deepest, and how many pairs are deeper than `tolerance` (the
/// stabilizer's, `Report::tolerance`).
pub fn exact_depth(scene: &Scene, tolerance: f64) -> ExactDepth {
    let depths = pair_depths(scene, |a, b| sat_depth(scene, a, b));
    ExactDepth {
        deepest: depths.iter().fold(0.0, |deepest, &(_, d)| d.max(deepest)),
        penetrating: depths.iter().filter(|&&(_, d)| d > tolerance).count(),
        tolerance,
    }
}
