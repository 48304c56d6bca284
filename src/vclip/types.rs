//! Inputs and outputs of a V-Clip query: the feature pair (the state of the
//! walk, cached per body pair for warm starts), the outcome and its status.
//!
//! Frames: body frames have their origin at the centre of mass (see
//! [`crate::geometry`]); a pose maps a body frame to the world frame. Every
//! `*_world` field is in the world frame.

use nalgebra::{Point3, Vector3};

use crate::geometry::Feature;

/// Which of the two bodies of a query a feature belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BodyRole {
    /// The first polyhedron of the query (`poly_a`).
    A,
    /// The second polyhedron of the query (`poly_b`).
    B,
}

impl BodyRole {
    /// The role of body index 0 (A) or 1 (B).
    pub(crate) fn from_index(index: usize) -> Self {
        if index == 0 { BodyRole::A } else { BodyRole::B }
    }

    /// The other body.
    pub fn other(self) -> Self {
        match self {
            BodyRole::A => BodyRole::B,
            BodyRole::B => BodyRole::A,
        }
    }
}

/// A feature of body A and a feature of body B: the state of V-Clip.
/// Cache the final pair of a query per body pair and pass it as the warm
/// start of the next query of the same pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct FeaturePair {
    /// Feature of body A.
    pub a: Feature,
    /// Feature of body B.
    pub b: Feature,
}

impl FeaturePair {
    /// The cold start: vertex 0 of each body.
    pub fn cold() -> Self {
        FeaturePair {
            a: Feature::Vertex(0),
            b: Feature::Vertex(0),
        }
    }

    pub(crate) fn from_array(features: [Feature; 2]) -> Self {
        FeaturePair {
            a: features[0],
            b: features[1],
        }
    }

    /// `[a, b]`.
    pub fn to_array(self) -> [Feature; 2] {
        [self.a, self.b]
    }
}

/// The deepest vertex–face pair of a penetration (docs/design.md section 4).
///
/// `face` belongs to the other body than `vertex_body`. With `P` the face
/// plane, `depth = -D_P(vertex) >= 0`, and the vertex minimizes `D_P` over
/// all vertices of its body: translating the vertex's body by
/// `depth * normal_world` makes it touch, not penetrate, the face's plane,
/// which supports the face's body, so the bodies are then separated (or
/// touching). `depth` is thus an upper bound of the penetration depth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeepestVertex {
    /// The body that owns `vertex`.
    pub vertex_body: BodyRole,
    /// Vertex index in `vertex_body`.
    pub vertex: usize,
    /// Face index in the other body.
    pub face: usize,
    /// `-D_P(vertex) >= 0`, length units.
    pub depth: f64,
    /// The vertex, world frame.
    pub vertex_world: Point3<f64>,
    /// Outward unit normal of the face, world frame: it points from the
    /// face's body towards the vertex's body.
    pub normal_world: Vector3<f64>,
}

/// What a query found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Outcome {
    /// The bodies are disjoint (or touch: `distance` near 0).
    Separated {
        /// Distance between the bodies, `>= 0`.
        distance: f64,
        /// Closest point of body A, world frame.
        witness_a_world: Point3<f64>,
        /// Closest point of body B, world frame.
        witness_b_world: Point3<f64>,
    },
    /// The bodies interpenetrate.
    Penetrating(DeepestVertex),
}

/// Why a query used the brute-force fallback instead of the V-Clip walk.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FallbackReason {
    /// The walk reached the iteration cap (a cycle caused by rounding, or a
    /// cap set too low): the answer is exhaustive, O(features²).
    IterationCap,
    /// The walk revisited a state and no remembered pair passed the
    /// closest-pair test within the tie tolerance.
    Cycle,
}

/// The result of a query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VClipResult {
    /// Separated or penetrating, with witnesses.
    pub outcome: Outcome,
    /// The last feature pair: the closest features when separated, the
    /// penetration witness when penetrating. Use it as the next warm start.
    pub final_pair: FeaturePair,
    /// Number of state transitions of the walk (0 for an immediate answer).
    pub iterations: usize,
    /// `Some` when the answer comes from the brute-force fallback.
    pub fallback: Option<FallbackReason>,
    /// The walk revisited a state (a rounding tie between pairs of features
    /// at the same distance) and the answer is the closest remembered pair
    /// that passed Mirtich's Theorem 1 within
    /// [`VClipSettings::tie_tolerance`](super::VClipSettings::tie_tolerance).
    pub resolved_cycle: bool,
}

impl VClipResult {
    /// Whether the answer comes from the fallback rather than the walk.
    pub fn fell_back(&self) -> bool {
        self.fallback.is_some()
    }
}
