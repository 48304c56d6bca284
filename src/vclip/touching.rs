//! Touching or penetrating? The classification of a done state whose
//! closest points (nearly) coincide.
//!
//! Theorem 1 also holds at distance 0, but then it only says that the
//! bodies share a point: two coincident cubes end the walk in a
//! vertex–vertex state at distance 0. Whether they merely touch or overlap
//! in volume is decided by the separating-axis theorem restricted to the
//! contact: two convex polyhedra that share a point `c` and do not overlap
//! are separated by a plane through `c` that is either a face plane
//! containing `c` or spanned by an edge of each body containing `c`. The
//! candidates come from the smallest features containing the closest points
//! (a vertex of an edge if the point is at its end): the faces around them
//! and the cross products of their edges. Each is tested with descents over
//! the vertex graphs (the extreme vertex of a convex polyhedron along a
//! direction, as in [`super::deepest`]), so the test costs a few walks.
//!
//! If a candidate separates within the touch tolerance, the bodies touch:
//! the separated outcome (distance ~0) stands. Otherwise they penetrate,
//! and the face candidate with the least depth, with the deepest vertex
//! under it, is the answer.

use nalgebra::Point3;

use super::deepest::{descend, walk_to_deepest};
use super::pair::Pair;
use super::types::DeepestVertex;
use crate::geometry::{ConvexPolyhedron, Feature, Plane};
use nalgebra::Isometry3;

/// `None` if the bodies only touch at `points` (`[on A, on B]`, A's frame,
/// closest points of `features`), else their deepest vertex–face pair.
pub(crate) fn classify_contact(
    pair: &Pair,
    poses: [&Isometry3<f64>; 2],
    features: [Feature; 2],
    points: &[Point3<f64>; 2],
    tol: f64,
) -> Option<DeepestVertex> {
    let point_b = pair.to_other[0].point(&points[1]);
    let minimal = [
        smallest_feature(pair.polys[0], features[0], &points[0], tol),
        smallest_feature(pair.polys[1], features[1], &point_b, tol),
    ];
    let starts = [
        some_vertex(pair.polys[0], minimal[0]),
        some_vertex(pair.polys[1], minimal[1]),
    ];
    let mut least_deep: Option<(f64, usize, usize, usize)> = None;
    for (face_body, &feature) in minimal.iter().enumerate() {
        let vertex_body = 1 - face_body;
        for f in faces_around(pair.polys[face_body], feature) {
            let plane = pair.face_plane_in_other(face_body, f);
            let (v, height) = descend(pair.polys[vertex_body], &plane, starts[vertex_body]);
            if height >= -tol {
                return None;
            }
            if least_deep.is_none_or(|(h, ..)| height > h) {
                least_deep = Some((height, vertex_body, v, f));
            }
        }
    }
    if edge_pair_separates(pair, minimal, starts, &points[0], tol) {
        return None;
    }
    let (_, vertex_body, v, f) = least_deep?;
    Some(walk_to_deepest(pair, poses, vertex_body, v, f))
}

/// The vertex of `feature` at `p` if `p` is one of its vertices (within
/// `tol`), else `feature`.
fn smallest_feature(
    poly: &ConvexPolyhedron,
    feature: Feature,
    p: &Point3<f64>,
    tol: f64,
) -> Feature {
    match feature {
        Feature::Edge(e) => {
            let edge = &poly.edges()[e];
            [edge.tail, edge.head]
                .into_iter()
                .find(|&w| (poly.vertices()[w] - p).norm() <= tol)
                .map_or(feature, Feature::Vertex)
        }
        _ => feature,
    }
}

/// A vertex of `feature`: where the descents start.
fn some_vertex(poly: &ConvexPolyhedron, feature: Feature) -> usize {
    match feature {
        Feature::Vertex(v) => v,
        Feature::Edge(e) => poly.edges()[e].tail,
        Feature::Face(f) => poly.faces()[f].vertices[0],
    }
}

/// The faces that contain `feature`.
fn faces_around(poly: &ConvexPolyhedron, feature: Feature) -> Vec<usize> {
    match feature {
        Feature::Vertex(v) => {
            let mut faces: Vec<usize> = poly
                .vertex_edges(v)
                .iter()
                .flat_map(|&e| [poly.edges()[e].left_face, poly.edges()[e].right_face])
                .collect();
            faces.sort_unstable();
            faces.dedup();
            faces
        }
        Feature::Edge(e) => vec![poly.edges()[e].left_face, poly.edges()[e].right_face],
        Feature::Face(f) => vec![f],
    }
}

/// The edges that contain `feature` (none for a face: a separating plane
/// through an interior point of a face is that face's plane).
fn edges_around(poly: &ConvexPolyhedron, feature: Feature) -> Vec<usize> {
    match feature {
        Feature::Vertex(v) => poly.vertex_edges(v).to_vec(),
        Feature::Edge(e) => vec![e],
        Feature::Face(_) => Vec::new(),
    }
}

/// Whether a plane through `contact` (A's frame) spanned by an edge of each
/// minimal feature separates the bodies within `tol`.
fn edge_pair_separates(
    pair: &Pair,
    minimal: [Feature; 2],
    starts: [usize; 2],
    contact: &Point3<f64>,
    tol: f64,
) -> bool {
    let edges_b: Vec<_> = edges_around(pair.polys[1], minimal[1])
        .into_iter()
        .map(|e| {
            let (t, h) = pair.edge_in_other(1, e);
            h - t
        })
        .collect();
    for e_a in edges_around(pair.polys[0], minimal[0]) {
        let edge = &pair.polys[0].edges()[e_a];
        for u_b in &edges_b {
            let n = edge.direction.cross(u_b);
            let norm = n.norm();
            if norm <= f64::EPSILON * u_b.norm() {
                continue;
            }
            let plane = Plane::through(contact, n / norm);
            if separates(pair, &plane, starts, tol)
                || separates(pair, &plane.flipped(), starts, tol)
            {
                return true;
            }
        }
    }
    false
}

/// Whether `plane` (A's frame) has A on its negative side and B on its
/// positive side, within `tol`.
fn separates(pair: &Pair, plane: &Plane, starts: [usize; 2], tol: f64) -> bool {
    let (_, a_top) = descend(pair.polys[0], &plane.flipped(), starts[0]);
    if -a_top > tol {
        return false;
    }
    let plane_b = pair.to_other[1].pull_back_plane(plane);
    let (_, b_bottom) = descend(pair.polys[1], &plane_b, starts[1]);
    b_bottom >= -tol
}
