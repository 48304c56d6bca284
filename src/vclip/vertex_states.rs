//! The states with a vertex: vertex–vertex, vertex–edge, vertex–face
//! (Mirtich 1998, section 5.1–5.3).
//!
//! - V-V: if `V2` is on the negative side of a plane `VP(V1, E)` (outside
//!   `VR(V1)`), `V1 -> E` (the most violated plane); the same with roles
//!   swapped; else done.
//! - V-E: if `V` violates a wall of `VR(E)` (vertex–edge walls first, then
//!   the most violated face–edge wall), `E ->` that neighbour. Else `E` is
//!   clipped against `VR(V)`: a simple exclusion moves `V` to the excluding
//!   edge, otherwise the derivative check (distance to `V`) may move `V` to
//!   `N_lo` or `N_hi`; if nothing moves, done.
//! - V-F: if `V` violates face–edge planes of `VR(F)`, `F ->` the edge of
//!   the most violated one. With heights `d = D_F(V)` and `d' = D_F(V')` for
//!   the other end `V'` of an edge of `V`, an edge "points toward F" when
//!   `d > 0, d' < d` or `d < 0, d' > d`: then `V -> ` that edge. Else, if
//!   `d > 0`, done; if not, the vertex–face local minimum.
//!
//! All heights over `F` are computed with `F`'s plane pulled back into the
//! vertex's frame, the same way as in the edge–face state, so that the two
//! states take consistent decisions for an edge parallel to `F`.

use super::clip::{Clip, Exclusion};
use super::derivative::{self, Reference};
use super::local_min::local_minimum;
use super::pair::Pair;
use super::state::Step;
use crate::geometry::{Feature, Plane};
use nalgebra::Point3;

/// V-V: `v[0]` of A, `v[1]` of B.
pub(crate) fn vertex_vertex(pair: &Pair, v: [usize; 2]) -> Step {
    for body in 0..2 {
        let other = pair.vertex_in_other(1 - body, v[1 - body]);
        if let Some(e) = most_violated_vertex_plane(pair, body, v[body], &other) {
            return Step::Move {
                body,
                to: Feature::Edge(e),
            };
        }
    }
    Step::Done
}

/// The edge `e` of vertex `v` (body `body`) with the most negative
/// `D_{VP(v, e)}(p)`, if any is negative (`p` in `body`'s frame).
fn most_violated_vertex_plane(
    pair: &Pair,
    body: usize,
    v: usize,
    p: &Point3<f64>,
) -> Option<usize> {
    let poly = pair.polys[body];
    let mut best = None;
    let mut most_negative = -pair.slack;
    for &e in poly.vertex_edges(v) {
        let d = poly.vertex_edge_plane(e, v).signed_distance(p);
        if d < most_negative {
            most_negative = d;
            best = Some(e);
        }
    }
    best
}

/// V-E: vertex `v` of body `vertex_body`, edge `e` of the other body.
pub(crate) fn vertex_edge(pair: &Pair, vertex_body: usize, v: usize, e: usize) -> Step {
    let edge_body = 1 - vertex_body;
    let p = pair.vertex_in_other(vertex_body, v);
    if let Some(neighbour) = violated_edge_wall(pair, edge_body, e, &p) {
        return Step::Move {
            body: edge_body,
            to: neighbour,
        };
    }
    let poly = pair.polys[vertex_body];
    let (tail, head) = pair.edge_in_other(edge_body, e);
    let planes = poly
        .vertex_edges(v)
        .iter()
        .map(|&e_v| (poly.vertex_edge_plane(e_v, v), Feature::Edge(e_v)));
    let mut clip = Clip::new(pair.slack);
    let reference = |_| Reference::Point(pair.vertex(vertex_body, v));
    let update = match clip.against_all(planes, &tail, &head) {
        Some(Exclusion::Simple(n)) => Some(n),
        Some(Exclusion::Compound) => derivative::check_excluded(&clip, &tail, &head, reference),
        None => derivative::check(&clip, &tail, &head, reference),
    };
    match update {
        Some(to) => Step::Move {
            body: vertex_body,
            to,
        },
        None => Step::Done,
    }
}

/// The wall of `VR(e)` (body `body`) that `p` violates: a vertex–edge wall
/// first, else the most violated face–edge wall.
fn violated_edge_wall(pair: &Pair, body: usize, e: usize, p: &Point3<f64>) -> Option<Feature> {
    let poly = pair.polys[body];
    let edge = &poly.edges()[e];
    for w in [edge.tail, edge.head] {
        if poly.vertex_edge_plane(e, w).signed_distance(p) > pair.slack {
            return Some(Feature::Vertex(w));
        }
    }
    let mut best = None;
    let mut most_violated = pair.slack;
    for f in [edge.left_face, edge.right_face] {
        let d = poly.face_edge_plane(e, f).signed_distance(p);
        if d > most_violated {
            most_violated = d;
            best = Some(Feature::Face(f));
        }
    }
    best
}

/// V-F: vertex `v` of body `vertex_body`, face `f` of the other body.
pub(crate) fn vertex_face(pair: &Pair, vertex_body: usize, v: usize, f: usize) -> Step {
    let face_body = 1 - vertex_body;
    let p = pair.vertex_in_other(vertex_body, v);
    if let Some(e) = most_violated_face_edge_plane(pair, face_body, f, &p) {
        return Step::Move {
            body: face_body,
            to: Feature::Edge(e),
        };
    }
    let plane = pair.face_plane_in_other(face_body, f);
    if let Some(e) = edge_toward_plane(pair, vertex_body, v, &plane) {
        return Step::Move {
            body: vertex_body,
            to: Feature::Edge(e),
        };
    }
    if plane.signed_distance(&pair.vertex(vertex_body, v)) > 0.0 {
        Step::Done
    } else {
        local_minimum(pair, vertex_body, v, f)
    }
}

/// The boundary edge of face `f` (body `body`) whose face–edge plane `p`
/// is most below, if `p` is below any.
fn most_violated_face_edge_plane(
    pair: &Pair,
    body: usize,
    f: usize,
    p: &Point3<f64>,
) -> Option<usize> {
    let poly = pair.polys[body];
    let mut best = None;
    let mut most_negative = -pair.slack;
    for &e in &poly.faces()[f].edges {
        let d = poly.face_edge_plane(e, f).signed_distance(p);
        if d < most_negative {
            most_negative = d;
            best = Some(e);
        }
    }
    best
}

/// An edge of vertex `v` (body `body`) along which the height over `plane`
/// (given in `body`'s frame) moves toward zero.
fn edge_toward_plane(pair: &Pair, body: usize, v: usize, plane: &Plane) -> Option<usize> {
    let poly = pair.polys[body];
    let d = plane.signed_distance(&poly.vertices()[v]);
    poly.vertex_edges(v).iter().copied().find(|&e| {
        let d_other = plane.signed_distance(&poly.vertices()[poly.other_vertex(e, v)]);
        (d > 0.0 && d_other < d - pair.slack) || (d < 0.0 && d_other > d + pair.slack)
    })
}
