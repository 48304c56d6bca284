//! Thin faces of a hull and the vertices that make them.
//!
//! A face whose width `w` is at the scale of the rounding of the input has
//! no reliable plane: rounding of order `u = ε·M` in the vertex coordinates
//! (`M` the largest coordinate; the body-frame vertices are rounded when
//! the centre of mass is subtracted) tilts the normal of a face of width
//! `w` by about `δ = u / w`. The tilt moves the plane by `δ w = u` over the
//! face itself, and by `δ x` at a lateral distance `x`; that matters only
//! for a vertex nearly on the extension of the plane, i.e. across an edge
//! whose dihedral angle `θ` is nearly flat. Faces are merged when their
//! vertices are within [`super::COPLANAR_TOLERANCE`]` * max(L, M)` of one
//! plane, so an unmerged neighbour has `θ ≳ COPLANAR_TOLERANCE max(L, M) /
//! w`, which is `1e-12 / 2.2e-16 ≈ 4500` times `δ`: wide or thin, a face of
//! the exact hull keeps every other vertex below its plane. The width
//! therefore need not be large compared with the body, only compared with
//! the rounding.
//!
//! The width of a convex polygon is attained with one of its sides flush
//! (rotating calipers): `w = min_edges max_vertices dist(vertex, line(edge))`.
//! When `w` is below [`THIN_FACE_TOLERANCE`]` * max(L, M)`, the vertices of
//! the face other than its two farthest apart (`a`, `b`) are dropped from
//! the point set and the hull is rebuilt. Every dropped vertex is within
//! about `w` of the segment `ab`, which stays in the hull, so each round
//! moves the hull by at most about `w`. Such faces come from points within
//! `w` of an edge (a sliver along it), or from clusters of points closer
//! than `w` that the duplicate merge
//! ([`super::DUPLICATE_TOLERANCE`]` * L`) left apart.
//!
//! The tolerance sits between those two: above the duplicate merge, and a
//! factor 10 below [`super::FLATNESS_TOLERANCE`]` * L`, the width below
//! which a point set is rejected as flat. A set that is accepted as a solid
//! is at least `FLATNESS_TOLERANCE * L` wide, so its faces across that
//! width (the sides of a thin slab) are wider than the thin-face tolerance
//! whenever `M < 10 L`, and the solid keeps its corners. (A tolerance
//! above the flatness one would not: at `1e-6` the sides of a slab
//! `[-1, 1]² × [-t, t]` with `t = 7.3e-7`, width `1.46e-6` against
//! `1e-6 max(L, M) = 2.83e-6`, would be dropped and its hull would come
//! back as a tetrahedron, although the flatness test accepts the slab as
//! a solid.) Farther from the origin the
//! rounding `ε M` itself approaches the flatness tolerance: at `M = 1e8 L`
//! it is `2.2e-8 L`.

use nalgebra::Point3;

use super::coplanar::HullFaces;
use super::hull::FLATNESS_TOLERANCE;
use super::index_maps::IndexSet;

/// Faces narrower than `THIN_FACE_TOLERANCE * max(L, M)` are removed by
/// dropping their inner vertices; see the module doc. Ten times the
/// duplicate merge [`super::DUPLICATE_TOLERANCE`], a tenth of the flatness
/// tolerance [`super::FLATNESS_TOLERANCE`], so that every solid the hull
/// accepts (relative width above `FLATNESS_TOLERANCE`) keeps its faces.
/// A face this thin has a normal accurate to about `ε / 1e-9 ≈ 2e-7` rad.
pub const THIN_FACE_TOLERANCE: f64 = FLATNESS_TOLERANCE / 10.0;

/// Vertices (indices into `points`) to drop so that no face is narrower
/// than `min_width`; empty when every face is wide enough.
///
/// Faces are taken thinnest first. The two farthest corners `a, b` of a
/// thin face are protected for the rest of the round and its other corners
/// dropped, unless protected by an earlier face; a face whose `a` or `b`
/// was already dropped waits for the next round. So every dropped vertex
/// is within about its face's width of a segment whose ends are kept
/// (two faces of a close pair of points would otherwise drop one each).
pub(crate) fn thin_face_vertices(
    points: &[Point3<f64>],
    hull: &HullFaces,
    min_width: f64,
) -> Vec<usize> {
    let corners_of = |cycle: &[usize]| -> Vec<Point3<f64>> {
        cycle.iter().map(|&v| points[hull.vertices[v]]).collect()
    };
    let mut thin: Vec<(f64, &Vec<usize>)> = hull
        .faces
        .iter()
        .map(|cycle| (polygon_width(&corners_of(cycle)), cycle))
        .filter(|(width, _)| *width < min_width)
        .collect();
    thin.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut protected: IndexSet<usize> = IndexSet::default();
    let mut dropped: IndexSet<usize> = IndexSet::default();
    for (_, cycle) in thin {
        let (a, b) = diametral_pair(&corners_of(cycle));
        let (a, b) = (cycle[a], cycle[b]);
        if dropped.contains(&a) || dropped.contains(&b) {
            continue;
        }
        protected.extend([a, b]);
        dropped.extend(cycle.iter().copied().filter(|v| !protected.contains(v)));
    }
    let mut dropped: Vec<usize> = dropped.into_iter().map(|v| hull.vertices[v]).collect();
    dropped.sort_unstable();
    dropped
}

/// Minimum width of a convex polygon: over its edges, the largest distance
/// of a vertex from the edge's line.
fn polygon_width(corners: &[Point3<f64>]) -> f64 {
    let n = corners.len();
    (0..n)
        .map(|i| {
            let a = corners[i];
            let along = corners[(i + 1) % n] - a;
            let length = along.norm();
            corners
                .iter()
                .map(|c| (c - a).cross(&along).norm() / length)
                .fold(0.0, f64::max)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Positions (in `corners`) of the two corners farthest apart.
fn diametral_pair(corners: &[Point3<f64>]) -> (usize, usize) {
    let mut best = (0, 1, -1.0);
    for i in 0..corners.len() {
        for j in i + 1..corners.len() {
            let d = (corners[i] - corners[j]).norm_squared();
            if d > best.2 {
                best = (i, j, d);
            }
        }
    }
    (best.0, best.1)
}
