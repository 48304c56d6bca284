//! The convex parts of a scene's bodies: the index space of the narrow
//! phase.
//!
//! Contacts happen between convex parts; corrections move bodies. Part
//! indices run over the bodies in scene order and over each body's parts
//! in its order, so part `p` belongs to body `owner(p)` and
//! `p < q` with different owners implies `owner(p) < owner(q)`: a part pair
//! `(p, q)`, `p < q`, maps to the body pair `(owner(p), owner(q))` in the
//! same roles. Two parts of one body never form a pair (they move
//! together). In a scene of convex bodies part `p` is body `p`, its pose is
//! the body's pose bit for bit, and the body pairs of the broad phase are
//! the part pairs unchanged.

use std::borrow::Cow;
use std::ops::Range;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3};

use crate::body::rounded_aabb;
use crate::broad_phase::BodyPair;
use crate::geometry::curved::CurvedSolid;
use crate::geometry::{ConvexPolyhedron, Rounding};
use crate::scene::Scene;

/// The parts of every body of a scene, flattened.
#[derive(Debug, Clone, Default)]
pub struct SceneParts {
    shapes: Vec<Arc<ConvexPolyhedron>>,
    roundings: Vec<Option<Rounding>>,
    curved: Vec<Option<CurvedSolid>>,
    offsets: Vec<Option<Isometry3<f64>>>,
    owners: Vec<usize>,
    /// `first[b]..first[b + 1]` are body `b`'s parts.
    first: Vec<usize>,
    convex: bool,
}

impl SceneParts {
    /// The parts of the bodies of `scene`.
    pub fn of(scene: &Scene) -> Self {
        let mut parts = SceneParts {
            first: vec![0],
            convex: true,
            ..SceneParts::default()
        };
        for (index, body) in scene.bodies().iter().enumerate() {
            for (k, part) in body.parts().iter().enumerate() {
                parts.shapes.push(part.polyhedron().clone());
                parts.roundings.push(part.rounding());
                parts.curved.push(body.part_curved(k));
                parts.offsets.push(part.offset().copied());
                parts.owners.push(index);
            }
            parts.first.push(parts.shapes.len());
            parts.convex &= !body.is_compound();
        }
        parts
    }

    /// Polyhedron of each part.
    pub fn shapes(&self) -> &[Arc<ConvexPolyhedron>] {
        &self.shapes
    }

    /// The core and radius of part `part` if it is round.
    pub fn rounding(&self, part: usize) -> Option<Rounding> {
        self.roundings[part]
    }

    /// The true solid of part `part` if it is a cylinder or a cone.
    pub fn curved(&self, part: usize) -> Option<CurvedSolid> {
        self.curved[part]
    }

    /// Number of parts.
    pub fn len(&self) -> usize {
        self.shapes.len()
    }

    /// Whether there are no parts.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// Whether every body is convex (part index = body index).
    pub fn all_convex(&self) -> bool {
        self.convex
    }

    /// The body part `part` belongs to.
    pub fn owner(&self, part: usize) -> usize {
        self.owners[part]
    }

    /// The parts of body `body`.
    pub fn parts_of(&self, body: usize) -> Range<usize> {
        self.first[body]..self.first[body + 1]
    }

    /// The body pair of a part pair (same roles, module docs).
    pub fn owner_pair(&self, pair: BodyPair) -> BodyPair {
        BodyPair {
            body_a: self.owners[pair.body_a],
            body_b: self.owners[pair.body_b],
        }
    }

    /// World pose of `part` when its body's centre-of-mass pose is
    /// `body_pose` (that pose itself for a convex body).
    pub fn pose(&self, part: usize, body_pose: &Isometry3<f64>) -> Isometry3<f64> {
        match &self.offsets[part] {
            None => *body_pose,
            Some(offset) => body_pose * offset,
        }
    }

    /// World poses of every part, given every body's pose: the body poses
    /// themselves, borrowed, in a scene of convex bodies (no copy per pass).
    pub fn poses<'a>(&self, body_poses: &'a [Isometry3<f64>]) -> Cow<'a, [Isometry3<f64>]> {
        if self.convex {
            return Cow::Borrowed(body_poses);
        }
        (0..self.len())
            .map(|part| self.pose(part, &body_poses[self.owners[part]]))
            .collect()
    }

    /// The part pairs of the body pairs `body_pairs` (ascending, distinct
    /// bodies) whose parts' boxes, each grown by `margin / 2`, overlap, at
    /// the part poses `poses`; ascending. The body pairs themselves in a
    /// scene of convex bodies.
    ///
    /// `body_pairs` are the broad phase's candidates at the same poses and
    /// margin: bodies whose boxes, grown by `margin / 2`, overlap (closed
    /// intervals). A body of one part has that part's box (the same
    /// [`rounded_aabb`] at the same pose), so a pair of two one-part bodies
    /// is its part pair without a test, which could only repeat the broad
    /// phase's; a part's box is computed only when a pair of a body of
    /// several parts needs it, once.
    pub fn part_pairs(
        &self,
        body_pairs: &[BodyPair],
        poses: &[Isometry3<f64>],
        margin: f64,
    ) -> Vec<BodyPair> {
        if self.convex {
            return body_pairs.to_vec();
        }
        let mut boxes: Vec<Option<(Point3<f64>, Point3<f64>)>> = vec![None; self.len()];
        let mut box_of = |part: usize| {
            *boxes[part].get_or_insert_with(|| {
                rounded_aabb(
                    &self.shapes[part],
                    self.roundings[part].as_ref(),
                    &poses[part],
                )
            })
        };
        let grow = margin / 2.0;
        let overlap = |(min_p, max_p): (Point3<f64>, Point3<f64>),
                       (min_q, max_q): (Point3<f64>, Point3<f64>)| {
            (0..3).all(|k| min_p[k] - grow <= max_q[k] + grow && min_q[k] - grow <= max_p[k] + grow)
        };
        let mut pairs = Vec::new();
        for body_pair in body_pairs {
            let (parts_a, parts_b) = (
                self.parts_of(body_pair.body_a),
                self.parts_of(body_pair.body_b),
            );
            if parts_a.len() == 1 && parts_b.len() == 1 {
                pairs.push(BodyPair {
                    body_a: parts_a.start,
                    body_b: parts_b.start,
                });
                continue;
            }
            for p in parts_a {
                for q in parts_b.clone() {
                    if overlap(box_of(p), box_of(q)) {
                        pairs.push(BodyPair {
                            body_a: p,
                            body_b: q,
                        });
                    }
                }
            }
        }
        // Pairs of one first body with several second bodies interleave.
        pairs.sort_unstable();
        pairs
    }
}
