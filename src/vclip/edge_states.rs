//! The states with two edges or an edge and a face (Mirtich 1998, sections
//! 5.4–5.5).
//!
//! - E-E: the edge `E2` is clipped against `VR(E1)`: first the two
//!   vertex–edge walls (simple exclusion: `E1 ->` that vertex; otherwise the
//!   derivative check against the vertices), then, continuing the same clip
//!   (`l_lo`, `l_hi` kept), the two face–edge walls (simple exclusion:
//!   `E1 ->` that face; otherwise the derivative check against the crossed
//!   neighbour, vertex or face). A compound exclusion always updates. Then
//!   the same with roles swapped; if nothing moved, done.
//! - E-F: `E` is clipped against the face–edge planes of `VR(F)`. If
//!   excluded, `F ->` its boundary feature closest to `E` (distance kept).
//!   Else, with heights `d(l) = D_F(e(l))` at `l_lo` and `l_hi`: a sign
//!   change (or a zero) means `E` pierces or touches `F`: penetration.
//!   Otherwise `|d(l)|` is linear on the interval with slope
//!   `(d_h - d_t) sign(d)`: if it is `>= 0` the minimum is at `l_lo`
//!   (`F -> N_lo`, or `E ->` its tail if unclipped there), else at `l_hi`
//!   (`F -> N_hi`, or `E ->` its head). E-F never returns done.
//!
//! The closest boundary feature of `F` is found by scanning its boundary
//! edges (segment–segment distance to `E`, O(|F|)): exact, and no more
//! expensive than Mirtich's perimeter walk in the worst case.

use nalgebra::Point3;

use super::clip::{Clip, Exclusion};
use super::closest::segment_segment;
use super::derivative::{self, Reference};
use super::pair::Pair;
use super::state::{Step, Witness};
use crate::geometry::Feature;

/// E-E: `e[0]` of A, `e[1]` of B.
pub(crate) fn edge_edge(pair: &Pair, e: [usize; 2]) -> Step {
    for body in 0..2 {
        if let Some(to) = clip_against_edge_region(pair, body, e[body], e[1 - body]) {
            return Step::Move { body, to };
        }
    }
    Step::Done
}

/// Clips edge `y` of the other body against `VR(x)`, `x` an edge of `body`;
/// the neighbour `x` must move to, if any.
fn clip_against_edge_region(pair: &Pair, body: usize, x: usize, y: usize) -> Option<Feature> {
    let poly = pair.polys[body];
    let edge = &poly.edges()[x];
    let (tail, head) = pair.edge_in_other(1 - body, y);
    let other = &pair.polys[1 - body].edges()[y];
    let reference = |n: Feature| match n {
        Feature::Face(f) => {
            let plane = pair.face_plane_in_other(body, f);
            let height = |v: usize| plane.signed_distance(&pair.vertex(1 - body, v));
            Reference::Heights(height(other.tail), height(other.head))
        }
        Feature::Vertex(w) => Reference::Point(poly.vertices()[w]),
        // An edge's neighbours are vertices and faces only.
        Feature::Edge(_) => Reference::Point(poly.vertices()[edge.tail]),
    };
    let vertex_walls = [edge.tail, edge.head]
        .map(|w| (poly.vertex_edge_plane(x, w).flipped(), Feature::Vertex(w)));
    let mut clip = Clip::new(pair.slack);
    match clip.against_all(vertex_walls, &tail, &head) {
        Some(Exclusion::Simple(n)) => return Some(n),
        Some(Exclusion::Compound) => {
            return derivative::check_excluded(&clip, &tail, &head, reference);
        }
        None => {
            if let Some(n) = derivative::check(&clip, &tail, &head, reference) {
                return Some(n);
            }
        }
    }
    let face_walls = [edge.left_face, edge.right_face]
        .map(|f| (poly.face_edge_plane(x, f).flipped(), Feature::Face(f)));
    match clip.against_all(face_walls, &tail, &head) {
        Some(Exclusion::Simple(n)) => Some(n),
        Some(Exclusion::Compound) => derivative::check_excluded(&clip, &tail, &head, reference),
        None => derivative::check(&clip, &tail, &head, reference),
    }
}

/// E-F: edge `e` of `edge_body`, face `f` of the other body.
pub(crate) fn edge_face(pair: &Pair, edge_body: usize, e: usize, f: usize) -> Step {
    let face_body = 1 - edge_body;
    let poly_f = pair.polys[face_body];
    let (tail_f, head_f) = pair.edge_in_other(edge_body, e);
    let planes = poly_f.faces()[f]
        .edges
        .iter()
        .map(|&e_f| (poly_f.face_edge_plane(e_f, f), Feature::Edge(e_f)));
    let mut clip = Clip::new(pair.slack);
    if clip.against_all(planes, &tail_f, &head_f).is_some() {
        return Step::Move {
            body: face_body,
            to: closest_boundary_feature(pair, face_body, f, &tail_f, &head_f),
        };
    }
    let edge = &pair.polys[edge_body].edges()[e];
    let plane = pair.face_plane_in_other(face_body, f);
    let d_tail = plane.signed_distance(&pair.vertex(edge_body, edge.tail));
    let d_head = plane.signed_distance(&pair.vertex(edge_body, edge.head));
    let d_lo = d_tail + (d_head - d_tail) * clip.l_lo;
    let d_hi = d_tail + (d_head - d_tail) * clip.l_hi;
    // `|d(l)|` is linear on the interval (no sign change): one slope.
    let same_side = (d_lo > 0.0 && d_hi > 0.0) || (d_lo < 0.0 && d_hi < 0.0);
    if !same_side {
        return Step::Penetration(Witness::EdgeFace {
            edge_body,
            edge: e,
            face: f,
        });
    }
    let slope = derivative::face_slope(d_tail, d_head, clip.l_lo);
    let (neighbour, end) = if slope >= 0.0 {
        (clip.n_lo, edge.tail)
    } else {
        (clip.n_hi, edge.head)
    };
    match neighbour {
        Some(to) => Step::Move {
            body: face_body,
            to,
        },
        None => Step::Move {
            body: edge_body,
            to: Feature::Vertex(end),
        },
    }
}

/// The vertex or edge of the boundary of face `f` (body `body`) closest to
/// the segment `tail -> head` (in `body`'s frame).
fn closest_boundary_feature(
    pair: &Pair,
    body: usize,
    f: usize,
    tail: &Point3<f64>,
    head: &Point3<f64>,
) -> Feature {
    let poly = pair.polys[body];
    let mut best = (f64::INFINITY, Feature::Face(f));
    for &e in &poly.faces()[f].edges {
        let edge = &poly.edges()[e];
        let (a, b) = (&poly.vertices()[edge.tail], &poly.vertices()[edge.head]);
        let closest = segment_segment(tail, head, a, b);
        if closest.distance_squared < best.0 {
            let feature = if closest.t <= 0.0 {
                Feature::Vertex(edge.tail)
            } else if closest.t >= 1.0 {
                Feature::Vertex(edge.head)
            } else {
                Feature::Edge(e)
            };
            best = (closest.distance_squared, feature);
        }
    }
    best.1
}
