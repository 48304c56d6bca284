//! The state machine of V-Clip (Mirtich 1998, section 5): one step from a
//! feature pair, dispatched on the kinds of the two features.
//!
//! Each handler either accepts the pair as the closest pair (Theorem 1: the
//! closest points of the two features lie in each other's Voronoi regions),
//! moves one feature to a neighbour, or reports a penetration witness. The
//! handlers are written for "a feature of body `s` and a feature of body
//! `1 - s`", so that V-E, V-F and E-F serve both orders. A face–face pair is
//! not a state: the face of B is demoted to one of its edges.

use super::edge_states::{edge_edge, edge_face};
use super::pair::Pair;
use super::vertex_states::{vertex_edge, vertex_face, vertex_vertex};
use crate::geometry::Feature;

/// A penetration witness, before the deepest-vertex search.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Witness {
    /// A vertex below every face plane of the other body (local minimum),
    /// with the face whose plane it is least below.
    VertexFace {
        vertex_body: usize,
        vertex: usize,
        face: usize,
    },
    /// An edge that crosses (or touches) a face inside its Voronoi prism.
    EdgeFace {
        edge_body: usize,
        edge: usize,
        face: usize,
    },
}

/// The result of one handler.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Step {
    /// The pair is the closest pair.
    Done,
    /// Replace the feature of `body` by `to`.
    Move { body: usize, to: Feature },
    /// The bodies interpenetrate.
    Penetration(Witness),
}

/// One step of the walk from `features` (`[feature of A, feature of B]`).
pub(crate) fn step(pair: &Pair, features: [Feature; 2]) -> Step {
    use Feature::{Edge, Face, Vertex};
    match (features[0], features[1]) {
        (Vertex(a), Vertex(b)) => vertex_vertex(pair, [a, b]),
        (Vertex(a), Edge(b)) => vertex_edge(pair, 0, a, b),
        (Edge(a), Vertex(b)) => vertex_edge(pair, 1, b, a),
        (Vertex(a), Face(b)) => vertex_face(pair, 0, a, b),
        (Face(a), Vertex(b)) => vertex_face(pair, 1, b, a),
        (Edge(a), Edge(b)) => edge_edge(pair, [a, b]),
        (Edge(a), Face(b)) => edge_face(pair, 0, a, b),
        (Face(a), Edge(b)) => edge_face(pair, 1, b, a),
        (Face(_), Face(b)) => Step::Move {
            body: 1,
            to: Edge(pair.polys[1].faces()[b].edges[0]),
        },
    }
}
