//! Thin faces of a hull and the vertices that make them.
//!
//! A face's plane is only as accurate as the face is wide: rounding of
//! order `u = ε·M` in the vertex coordinates (`M` the largest coordinate)
//! tilts the normal of a face of width `w` by about `u / w`, which moves a
//! plane by `u L / w` at the distance `L` of the farthest vertex. For
//! [`super::PLANARITY_TOLERANCE`]` = 1e-9` relative to the body's size this
//! needs `w ≳ 1e-6 max(L, M)`.
//!
//! The width of a convex polygon is attained with one of its sides flush
//! (rotating calipers): `w = min_edges max_vertices dist(vertex, line(edge))`.
//! When `w` is below [`THIN_FACE_TOLERANCE`]` * max(L, M)`, the vertices of
//! the face other than its two farthest apart (`a`, `b`) are dropped from
//! the point set and the hull is rebuilt. Every dropped vertex is within about `w` of
//! the segment `ab`, which stays in the hull, so each round moves the hull
//! by at most about `w`. Such faces come from points within `w` of an edge
//! (a sliver along it), or from clusters of points closer than `w`.

use std::collections::HashSet;

use nalgebra::Point3;

use super::coplanar::HullFaces;

/// Faces narrower than `THIN_FACE_TOLERANCE * max(L, M)` are removed by
/// dropping their inner vertices; see the module doc.
pub const THIN_FACE_TOLERANCE: f64 = 1e-6;

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
    let mut protected: HashSet<usize> = HashSet::new();
    let mut dropped: HashSet<usize> = HashSet::new();
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
