//! The deepest-vertex search (docs/design.md section 4), this project's
//! extension of V-Clip.
//!
//! From a penetration witness with face `F` (plane `P`) of one body:
//! 1. start at the penetrating vertex: the vertex of a vertex–face witness,
//!    or the end of the piercing edge of an edge–face witness with the
//!    smaller `D_P` (it is on or below `P`);
//! 2. move to the neighbour (other end of an incident edge) with the most
//!    negative `D_P` while that is below the current value.
//!
//! `D_P` is linear and the vertex graph of a convex polyhedron is that of
//! the simplex method, so a vertex with no better neighbour minimizes `D_P`
//! over the whole body. `P` is pulled back into the vertex body's frame
//! once, so the walk costs one dot product per vertex examined.
//!
//! Face refinement ([`VClipSettings::refine_face`](super::VClipSettings),
//! on by default). The witness face is where V-Clip happened to detect the
//! penetration, not a good direction to separate along: on random hulls
//! its depth is often well above parry's EPA depth (measured:
//! `CHANGELOG.md`, 2026-11-22, "face refinement"). Every face plane of
//! either body with the other body's deepest vertex under it is a valid
//! answer (the push-out argument holds for each), and the
//! smallest such depth is the separating-axis bound over face normals. The
//! refinement climbs towards it locally: it tries the faces adjacent to the
//! current face (same body) and the faces around the current deepest vertex
//! (the other body, with that body's deepest vertex found by a descent from
//! the current face), moves to the least deep, and repeats while the depth
//! strictly decreases. Each try is a descent started next to its answer.

use nalgebra::Isometry3;

use super::pair::Pair;
use super::state::Witness;
use super::types::{BodyRole, DeepestVertex};
use crate::geometry::{ConvexPolyhedron, Plane};

/// The deepest vertex–face pair from a witness. `poses[i]` is body `i`'s
/// pose.
pub(crate) fn deepest_vertex(
    pair: &Pair,
    poses: [&Isometry3<f64>; 2],
    witness: Witness,
    refine: bool,
) -> DeepestVertex {
    let (vertex_body, start, face) = match witness {
        Witness::VertexFace {
            vertex_body,
            vertex,
            face,
        } => (vertex_body, vertex, face),
        Witness::EdgeFace {
            edge_body,
            edge,
            face,
        } => {
            let plane = pair.face_plane_in_other(1 - edge_body, face);
            let e = &pair.polys[edge_body].edges()[edge];
            let lower = |v: usize| plane.signed_distance(&pair.vertex(edge_body, v));
            let start = if lower(e.tail) <= lower(e.head) {
                e.tail
            } else {
                e.head
            };
            (edge_body, start, face)
        }
    };
    if refine {
        let from_witness = refine_face(pair, candidate(pair, vertex_body, start, face));
        let from_opposed = refine_face(pair, opposed_candidate(pair, vertex_body, face));
        let best = if from_opposed.3 > from_witness.3 {
            from_opposed
        } else {
            from_witness
        };
        let (vertex_body, start, face, _) = best;
        return walk_to_deepest(pair, poses, vertex_body, start, face);
    }
    walk_to_deepest(pair, poses, vertex_body, start, face)
}

/// A vertex–face candidate: vertex body, vertex, face (of the other body),
/// height `D_P(vertex)` (negative below).
type Candidate = (usize, usize, usize, f64);

/// The deepest vertex under `face` of the other body, by descent from
/// `start` (of `vertex_body`).
fn candidate(pair: &Pair, vertex_body: usize, start: usize, face: usize) -> Candidate {
    let plane = pair.face_plane_in_other(1 - vertex_body, face);
    let (vertex, height) = descend(pair.polys[vertex_body], &plane, start);
    (vertex_body, vertex, face, height)
}

/// The second start of the refinement: the face of the witness's vertex
/// body whose normal is most opposed to the witness face's normal, with the
/// roles of the bodies swapped. A local search from the witness face alone
/// can stop in a poor local minimum (a face far from the contact); starting
/// also from the other side makes that rarer (measured on the demo scenes
/// of 1,000 bodies: `CHANGELOG.md`, 2026-11-22, "face refinement").
fn opposed_candidate(pair: &Pair, vertex_body: usize, witness_face: usize) -> Candidate {
    let face_body = 1 - vertex_body;
    let witness_normal = pair.face_plane_in_other(face_body, witness_face).normal;
    let vertex_poly = pair.polys[vertex_body];
    let opposed = (0..vertex_poly.faces().len())
        .max_by(|&f, &g| {
            let along = |k: usize| -vertex_poly.faces()[k].plane.normal.dot(&witness_normal);
            along(f).total_cmp(&along(g))
        })
        .unwrap_or(0);
    let start = pair.polys[face_body].faces()[witness_face].vertices[0];
    candidate(pair, face_body, start, opposed)
}

/// Local search for the least deep vertex–face pair, from `current`.
pub(crate) fn refine_face(pair: &Pair, mut current: Candidate) -> Candidate {
    loop {
        let (vertex_body, vertex, face, _) = current;
        let face_body = 1 - vertex_body;
        let face_poly = pair.polys[face_body];
        let vertex_poly = pair.polys[vertex_body];
        let mut best = current;
        for &e in &face_poly.faces()[face].edges {
            let edge = &face_poly.edges()[e];
            let g = if edge.left_face == face {
                edge.right_face
            } else {
                edge.left_face
            };
            let c = candidate(pair, vertex_body, vertex, g);
            if c.3 > best.3 {
                best = c;
            }
        }
        let start_on_face_body = face_poly.faces()[face].vertices[0];
        for &e in vertex_poly.vertex_edges(vertex) {
            let edge = &vertex_poly.edges()[e];
            for g in [edge.left_face, edge.right_face] {
                let c = candidate(pair, face_body, start_on_face_body, g);
                if c.3 > best.3 {
                    best = c;
                }
            }
        }
        if best.3 > current.3 {
            current = best;
        } else {
            return current;
        }
    }
}

/// Walks from `start` (body `vertex_body`) to the vertex deepest below face
/// `face` of the other body.
pub(crate) fn walk_to_deepest(
    pair: &Pair,
    poses: [&Isometry3<f64>; 2],
    vertex_body: usize,
    start: usize,
    face: usize,
) -> DeepestVertex {
    let face_body = 1 - vertex_body;
    let plane = pair.face_plane_in_other(face_body, face);
    let (vertex, height) = descend(pair.polys[vertex_body], &plane, start);
    let normal_body = pair.polys[face_body].faces()[face].plane.normal;
    DeepestVertex {
        vertex_body: BodyRole::from_index(vertex_body),
        vertex,
        face,
        depth: (-height).max(0.0),
        vertex_world: poses[vertex_body] * pair.vertex(vertex_body, vertex),
        normal_world: poses[face_body].rotation * normal_body,
    }
}

/// Steepest descent of `D_plane` over the vertex graph; the final vertex and
/// its height. Terminates: the height strictly decreases at every move.
pub(crate) fn descend(poly: &ConvexPolyhedron, plane: &Plane, start: usize) -> (usize, f64) {
    let mut current = start;
    let mut height = plane.signed_distance(&poly.vertices()[start]);
    loop {
        let mut next = None;
        for &e in poly.vertex_edges(current) {
            let w = poly.other_vertex(e, current);
            let d = plane.signed_distance(&poly.vertices()[w]);
            if d < height {
                height = d;
                next = Some(w);
            }
        }
        match next {
            Some(w) => current = w,
            None => return (current, height),
        }
    }
}
