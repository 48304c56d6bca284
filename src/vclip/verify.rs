//! Theorem 1 of Mirtich (1998) as a check with a tolerance: closest points
//! `x ∈ X`, `y ∈ Y` of two features are the closest points of the bodies if
//! `y ∈ VR(X)` and `x ∈ VR(Y)`. Used only to accept a pair when the walk
//! revisits a state (a rounding tie, see [`super::query`]).
//!
//! Membership in a Voronoi region with tolerance `tol`: every wall plane
//! (oriented with the region on its positive side) has `D(y) >= -tol`:
//! - `VR(V)`: the planes `VP(V, E)` of the edges of `V`;
//! - `VR(E)`: the two vertex–edge and two face–edge planes, negated;
//! - `VR(F)`: the face–edge planes of its boundary and its own plane.

use nalgebra::Point3;

use super::pair::Pair;
use crate::geometry::{ConvexPolyhedron, Feature};

/// Whether `y` (in the body's frame) is in `VR(feature)` up to `tol`.
pub(crate) fn in_region(
    poly: &ConvexPolyhedron,
    feature: Feature,
    y: &Point3<f64>,
    tol: f64,
) -> bool {
    match feature {
        Feature::Vertex(v) => poly
            .vertex_edges(v)
            .iter()
            .all(|&e| poly.vertex_edge_plane(e, v).signed_distance(y) >= -tol),
        Feature::Edge(e) => {
            let edge = &poly.edges()[e];
            let vertex_ok = [edge.tail, edge.head]
                .iter()
                .all(|&w| poly.vertex_edge_plane(e, w).signed_distance(y) <= tol);
            let face_ok = [edge.left_face, edge.right_face]
                .iter()
                .all(|&f| poly.face_edge_plane(e, f).signed_distance(y) <= tol);
            vertex_ok && face_ok
        }
        Feature::Face(f) => {
            let face = &poly.faces()[f];
            face.plane.signed_distance(y) >= -tol
                && face
                    .edges
                    .iter()
                    .all(|&e| poly.face_edge_plane(e, f).signed_distance(y) >= -tol)
        }
    }
}

/// Whether closest points `[on A, on B]` (A's frame) of `features` satisfy
/// Theorem 1 up to `tol`.
pub(crate) fn is_closest_pair(
    pair: &Pair,
    features: [Feature; 2],
    points: &[Point3<f64>; 2],
    tol: f64,
) -> bool {
    let x_in_b = pair.to_other[0].point(&points[0]);
    log::debug!(
        "v-clip: verify {features:?}: y in VR(X) {}, x in VR(Y) {}",
        in_region(pair.polys[0], features[0], &points[1], tol),
        in_region(pair.polys[1], features[1], &x_in_b, tol)
    );
    in_region(pair.polys[0], features[0], &points[1], tol)
        && in_region(pair.polys[1], features[1], &x_in_b, tol)
}
