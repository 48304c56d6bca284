//! Narrow phase: V-Clip over candidate body pairs, and the constraint rows
//! of a pair's contact.
//!
//! The signed value of a pair is its distance when separated and minus the
//! depth of the deepest vertex–face pair when penetrating (an upper bound of
//! the penetration depth, see [`crate::vclip::DeepestVertex`]).
//!
//! Rows (DESIGN.md section 3), with the normal `n` from the face's body
//! towards the vertex's body:
//! - penetrating, deepest vertex only: one row at the deepest vertex `p`,
//!   `phi = -depth`, with `p_face = p + depth n` its projection on the face
//!   plane;
//! - penetrating, manifold: one row per vertex of the vertex's body whose
//!   signed distance to the face plane is below the contact margin, so that
//!   a box sunk face-down into the ground is lifted flat instead of one
//!   corner at a time;
//! - separated closer than the contact margin: one row at the closest
//!   points, `n = (p_a - p_b) / d`. When `d` is too small for that quotient,
//!   the normal comes from the closest features (a face normal, or the cross
//!   product of two edges), else from the centres of mass.

use std::collections::HashMap;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Vector3};

use crate::broad_phase::BodyPair;
use crate::geometry::{ConvexPolyhedron, Feature};
use crate::projector::{ConstraintRow, ContactSide, contact_row};
use crate::vclip::{BodyRole, DeepestVertex, FeaturePair, Outcome, VClip, VClipResult};

/// Distance, relative to the pair's scale, below which the witness
/// difference of a separated pair is too small to give a normal.
pub const NORMAL_FROM_WITNESS_MIN_RELATIVE: f64 = 1e-9;

/// The geometry of one body as a contact sees it.
#[derive(Debug, Clone, Copy)]
pub struct BodyGeometry<'a> {
    /// The polyhedron in its body frame.
    pub shape: &'a ConvexPolyhedron,
    /// Centre-of-mass pose (body frame to world).
    pub pose: Isometry3<f64>,
    /// Index in the configuration being corrected, `None` if the body does
    /// not move (fixed).
    pub configuration_index: Option<usize>,
}

impl BodyGeometry<'_> {
    fn side(&self) -> ContactSide {
        self.configuration_index
            .map(|index| (index, Point3::from(self.pose.translation.vector)))
    }
}

/// Warm starts of V-Clip per body pair, valid across passes, line-search
/// trials and calls as long as the pair's two shapes are the same objects.
#[derive(Debug, Clone, Default)]
pub struct WarmStartCache {
    entries: HashMap<BodyPair, CachedPair>,
}

#[derive(Debug, Clone, Copy)]
struct CachedPair {
    shapes: (usize, usize),
    features: FeaturePair,
}

/// Identity of a shape object (its address), to tell a cached warm start
/// from one of another scene that reuses the body indices.
pub fn shape_identity(shape: &Arc<ConvexPolyhedron>) -> usize {
    Arc::as_ptr(shape) as usize
}

impl WarmStartCache {
    /// The cached start of `pair` if it was recorded for these shapes.
    pub fn get(&self, pair: BodyPair, shapes: (usize, usize)) -> Option<FeaturePair> {
        self.entries
            .get(&pair)
            .filter(|entry| entry.shapes == shapes)
            .map(|entry| entry.features)
    }

    /// Records the final feature pair of a query.
    pub fn insert(&mut self, pair: BodyPair, shapes: (usize, usize), features: FeaturePair) {
        self.entries.insert(pair, CachedPair { shapes, features });
    }

    /// Takes over every entry of `other` (newer queries win).
    pub fn merge(&mut self, other: WarmStartCache) {
        self.entries.extend(other.entries);
    }

    /// Number of cached pairs.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether nothing is cached.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

/// V-Clip on two bodies, `a` the pair's first body (a penetration comes
/// back as V-Clip's refined, shallow vertex–face pair).
pub fn query(
    vclip: &VClip,
    a: &BodyGeometry,
    b: &BodyGeometry,
    warm_start: Option<FeaturePair>,
) -> Result<VClipResult, crate::vclip::VClipError> {
    vclip.query(a.shape, &a.pose, b.shape, &b.pose, warm_start)
}

/// Distance when separated, minus the deepest-vertex depth when penetrating.
pub fn signed_value(outcome: &Outcome) -> f64 {
    match outcome {
        Outcome::Separated { distance, .. } => *distance,
        Outcome::Penetrating(deepest) => -deepest.depth,
    }
}

/// The constraint rows of a pair with V-Clip result `result` (no row for a
/// separated pair at or beyond `margin`).
pub fn contact_rows(
    result: &VClipResult,
    a: &BodyGeometry,
    b: &BodyGeometry,
    margin: f64,
    manifold: bool,
) -> Vec<ConstraintRow> {
    match &result.outcome {
        Outcome::Penetrating(deepest) => penetration_rows(deepest, a, b, margin, manifold),
        Outcome::Separated {
            distance,
            witness_a_world,
            witness_b_world,
        } if *distance < margin => {
            let normal =
                separation_normal(result, a, b, witness_a_world, witness_b_world, *distance);
            vec![contact_row(
                witness_a_world,
                witness_b_world,
                &normal,
                a.side(),
                b.side(),
            )]
        }
        Outcome::Separated { .. } => Vec::new(),
    }
}

fn penetration_rows(
    deepest: &DeepestVertex,
    a: &BodyGeometry,
    b: &BodyGeometry,
    margin: f64,
    manifold: bool,
) -> Vec<ConstraintRow> {
    let (vertex_body, face_body) = match deepest.vertex_body {
        BodyRole::A => (a, b),
        BodyRole::B => (b, a),
    };
    let normal = deepest.normal_world;
    let plane_point = deepest.vertex_world + normal * deepest.depth;
    let row_at = |p: &Point3<f64>| {
        let on_plane = p - normal * normal.dot(&(p - plane_point));
        contact_row(p, &on_plane, &normal, vertex_body.side(), face_body.side())
    };
    if !manifold {
        return vec![row_at(&deepest.vertex_world)];
    }
    vertex_body
        .shape
        .vertices()
        .iter()
        .map(|v| vertex_body.pose * v)
        .filter(|p| normal.dot(&(p - plane_point)) < margin)
        .map(|p| row_at(&p))
        .collect()
}

/// Unit normal from B towards A of a separated pair.
fn separation_normal(
    result: &VClipResult,
    a: &BodyGeometry,
    b: &BodyGeometry,
    witness_a: &Point3<f64>,
    witness_b: &Point3<f64>,
    distance: f64,
) -> Vector3<f64> {
    let scale = a.shape.scale().min(b.shape.scale());
    if distance > NORMAL_FROM_WITNESS_MIN_RELATIVE * scale {
        return (witness_a - witness_b) / distance;
    }
    let centres = a.pose.translation.vector - b.pose.translation.vector;
    let from_features = feature_normal(result.final_pair, a, b);
    let normal = from_features.unwrap_or(centres);
    let oriented = if normal.dot(&centres) < 0.0 {
        -normal
    } else {
        normal
    };
    oriented.try_normalize(0.0).unwrap_or_else(Vector3::z)
}

/// A normal of touching features: a face's normal, or the cross product of
/// two edges (orientation left to the caller).
fn feature_normal(pair: FeaturePair, a: &BodyGeometry, b: &BodyGeometry) -> Option<Vector3<f64>> {
    match (pair.a, pair.b) {
        (_, Feature::Face(f)) => Some(b.pose.rotation * b.shape.faces()[f].plane.normal),
        (Feature::Face(f), _) => Some(-(a.pose.rotation * a.shape.faces()[f].plane.normal)),
        (Feature::Edge(ea), Feature::Edge(eb)) => {
            let da = a.pose.rotation * a.shape.edges()[ea].direction;
            let db = b.pose.rotation * b.shape.edges()[eb].direction;
            da.cross(&db).try_normalize(f64::EPSILON)
        }
        _ => None,
    }
}
