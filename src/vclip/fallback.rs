//! The exhaustive fallback, used when the walk hits its iteration cap.
//!
//! Slow but simple and correct, with no walk and no state:
//! - Intersection: two convex polyhedra intersect iff an edge of one meets
//!   a face of the other (their surfaces cross), or one contains the other
//!   (then vertex 0 of it is inside the other). An edge `t -> h` meets face
//!   `F` (plane `P`) if `D_P(t)` and `D_P(h)` do not have the same strict
//!   sign and the crossing point `t + (h - t) D_P(t) / (D_P(t) - D_P(h))`
//!   is inside every face–edge plane of `F`. O(E_a F_b + E_b F_a) plane tests.
//! - Penetrating: for every face of both bodies, the minimum of its plane's
//!   signed distance over the other body's vertices; the face where that
//!   minimum is largest (the least deep face, the separating-axis test over
//!   face normals) gives the deepest vertex–face pair. O(F V).
//! - Separated: the distance of two disjoint convex polyhedra is the
//!   minimum over vertex–face pairs (vertex above the face, projecting into
//!   it) and edge–edge pairs. O(V F + E²).

use nalgebra::{Isometry3, Point3};

use super::closest::segment_segment;
use super::pair::Pair;
use super::types::{BodyRole, DeepestVertex, FeaturePair, Outcome};
use crate::geometry::{ConvexPolyhedron, Feature, Plane};

/// The exhaustive answer and the feature pair that witnesses it.
pub(crate) fn exhaustive(pair: &Pair, poses: [&Isometry3<f64>; 2]) -> (Outcome, FeaturePair) {
    if intersecting(pair) {
        let deepest = least_deep_face(pair, poses);
        let vertex_body = if deepest.vertex_body == BodyRole::A {
            0
        } else {
            1
        };
        let mut features = [Feature::Vertex(0); 2];
        features[vertex_body] = Feature::Vertex(deepest.vertex);
        features[1 - vertex_body] = Feature::Face(deepest.face);
        (
            Outcome::Penetrating(deepest),
            FeaturePair::from_array(features),
        )
    } else {
        let closest = closest_features(pair);
        let [p_a, p_b] = closest.points;
        (
            Outcome::Separated {
                distance: (p_a - p_b).norm(),
                witness_a_world: poses[0] * p_a,
                witness_b_world: poses[0] * p_b,
            },
            FeaturePair::from_array(closest.features),
        )
    }
}

/// Whether the two bodies share a point (touching counts, up to rounding).
pub(crate) fn intersecting(pair: &Pair) -> bool {
    let contains = |outer: usize| {
        let p = pair.vertex_in_other(1 - outer, 0);
        pair.polys[outer]
            .faces()
            .iter()
            .all(|face| face.plane.signed_distance(&p) <= 0.0)
    };
    edge_meets_face(pair, 0) || edge_meets_face(pair, 1) || contains(0) || contains(1)
}

/// Whether an edge of the other body meets a face of `face_body`.
fn edge_meets_face(pair: &Pair, face_body: usize) -> bool {
    let poly = pair.polys[face_body];
    let edge_body = 1 - face_body;
    (0..pair.polys[edge_body].edges().len()).any(|e| {
        let (t, h) = pair.edge_in_other(edge_body, e);
        (0..poly.faces().len()).any(|f| segment_meets_face(poly, f, &t, &h))
    })
}

fn segment_meets_face(poly: &ConvexPolyhedron, f: usize, t: &Point3<f64>, h: &Point3<f64>) -> bool {
    let plane = &poly.faces()[f].plane;
    let (dt, dh) = (plane.signed_distance(t), plane.signed_distance(h));
    if (dt > 0.0 && dh > 0.0) || (dt < 0.0 && dh < 0.0) || (dt == 0.0 && dh == 0.0) {
        return false;
    }
    let crossing = t + (h - t) * (dt / (dt - dh));
    poly.faces()[f]
        .edges
        .iter()
        .all(|&e| poly.face_edge_plane(e, f).signed_distance(&crossing) >= 0.0)
}

/// The face (of either body) whose plane the other body sinks least below,
/// with that body's deepest vertex under it.
fn least_deep_face(pair: &Pair, poses: [&Isometry3<f64>; 2]) -> DeepestVertex {
    let mut best: Option<(f64, usize, usize, usize)> = None;
    for face_body in 0..2 {
        let vertex_body = 1 - face_body;
        for f in 0..pair.polys[face_body].faces().len() {
            let plane = pair.face_plane_in_other(face_body, f);
            let (v, height) = lowest_vertex(pair.polys[vertex_body], &plane);
            if best.is_none_or(|(h, ..)| height > h) {
                best = Some((height, vertex_body, v, f));
            }
        }
    }
    // Every polyhedron has at least four faces, so `best` is set.
    let (_, vertex_body, v, f) = best.unwrap_or((0.0, 1, 0, 0));
    super::deepest::walk_to_deepest(pair, poses, vertex_body, v, f)
}

/// The vertex of `poly` with the smallest signed distance to `plane`.
fn lowest_vertex(poly: &ConvexPolyhedron, plane: &Plane) -> (usize, f64) {
    poly.vertices()
        .iter()
        .map(|p| plane.signed_distance(p))
        .enumerate()
        .fold(
            (0, f64::INFINITY),
            |best, (v, d)| if d < best.1 { (v, d) } else { best },
        )
}

/// Closest features and points of two disjoint bodies.
struct Closest {
    distance_squared: f64,
    features: [Feature; 2],
    /// On A, on B; A's frame.
    points: [Point3<f64>; 2],
}

impl Closest {
    fn offer(&mut self, distance_squared: f64, features: [Feature; 2], points: [Point3<f64>; 2]) {
        if distance_squared < self.distance_squared {
            *self = Closest {
                distance_squared,
                features,
                points,
            };
        }
    }
}

fn closest_features(pair: &Pair) -> Closest {
    let mut best = Closest {
        distance_squared: f64::INFINITY,
        features: [Feature::Vertex(0); 2],
        points: [pair.vertex(0, 0), pair.vertex_in_other(1, 0)],
    };
    for face_body in 0..2 {
        vertex_face_candidates(pair, face_body, &mut best);
    }
    edge_edge_candidates(pair, &mut best);
    best
}

/// Vertices of the other body above a face of `face_body`, projecting into it.
fn vertex_face_candidates(pair: &Pair, face_body: usize, best: &mut Closest) {
    let poly = pair.polys[face_body];
    let vertex_body = 1 - face_body;
    for v in 0..pair.polys[vertex_body].vertices().len() {
        let p = pair.vertex_in_other(vertex_body, v);
        for (f, face) in poly.faces().iter().enumerate() {
            let height = face.plane.signed_distance(&p);
            let inside = || {
                face.edges
                    .iter()
                    .all(|&e| poly.face_edge_plane(e, f).signed_distance(&p) >= 0.0)
            };
            if height >= 0.0 && height * height < best.distance_squared && inside() {
                let q = p - face.plane.normal * height;
                let mut features = [Feature::Face(f); 2];
                features[vertex_body] = Feature::Vertex(v);
                let mut points = [q, p];
                if face_body == 1 {
                    points = [pair.to_other[1].point(&p), pair.to_other[1].point(&q)];
                }
                best.offer(height * height, features, points);
            }
        }
    }
}

fn edge_edge_candidates(pair: &Pair, best: &mut Closest) {
    let poly_a = pair.polys[0];
    for (e_a, edge_a) in poly_a.edges().iter().enumerate() {
        let (t_a, h_a) = (pair.vertex(0, edge_a.tail), pair.vertex(0, edge_a.head));
        for e_b in 0..pair.polys[1].edges().len() {
            let (t_b, h_b) = pair.edge_in_other(1, e_b);
            let closest = segment_segment(&t_a, &h_a, &t_b, &h_b);
            if closest.distance_squared < best.distance_squared {
                let features = [
                    edge_feature(poly_a, e_a, closest.s),
                    edge_feature(pair.polys[1], e_b, closest.t),
                ];
                let points = [t_a + (h_a - t_a) * closest.s, t_b + (h_b - t_b) * closest.t];
                best.offer(closest.distance_squared, features, points);
            }
        }
    }
}

/// The vertex at an end of edge `e` if `l` is 0 or 1, else the edge.
fn edge_feature(poly: &ConvexPolyhedron, e: usize, l: f64) -> Feature {
    let edge = &poly.edges()[e];
    if l <= 0.0 {
        Feature::Vertex(edge.tail)
    } else if l >= 1.0 {
        Feature::Vertex(edge.head)
    } else {
        Feature::Edge(e)
    }
}
