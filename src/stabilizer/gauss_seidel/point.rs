//! A contact point stored in body frames, so that its separation can be
//! measured again at any poses of its two bodies without a new query.
//!
//! Box2D's `b2PositionSolverManifold` keeps the reference face's normal and
//! a point on it in the reference body's frame and the clip points in the
//! incident body's frame. Here a manifold point has a point on each body
//! (`p_a` on A, `p_b` on B's reference face, or the other way round) and a
//! normal from B towards A; they are stored as
//!
//! ```text
//! p_a_body = X_a^-1 p_a_world,   p_b_body = X_b^-1 p_b_world,
//! n_ref    = R_ref^T n_world     (ref: the body of the reference face)
//! ```
//!
//! and at poses `X_a`, `X_b` the separation is
//!
//! ```text
//! s = (R_ref n_ref) . (X_a p_a_body - X_b p_b_body)      (negative = penetration)
//! ```
//!
//! At the poses of the detection this is the manifold's separation (to
//! rounding). A vertex below a reference face keeps its depth under a
//! motion of either body, as the plane through `p_b` turns with the face.

use nalgebra::{Isometry3, Point3, Vector3};

use crate::contact::{ContactPoint, NormalBody};

/// One contact point of a pair, in body frames (COM frames).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StoredPoint {
    /// First body of the pair (scene index).
    pub body_a: usize,
    /// Second body of the pair (scene index).
    pub body_b: usize,
    /// The point on A, A's frame.
    pub p_a_body: Point3<f64>,
    /// The point on B, B's frame.
    pub p_b_body: Point3<f64>,
    /// The body whose rotation carries the normal.
    pub normal_body: NormalBody,
    /// Unit normal from B towards A, in the frame of `normal_body`.
    pub n_ref: Vector3<f64>,
}

/// A stored point measured at given poses, world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasuredPoint {
    /// The point on A.
    pub p_a_world: Point3<f64>,
    /// The point on B.
    pub p_b_world: Point3<f64>,
    /// Unit normal from B towards A.
    pub n_world: Vector3<f64>,
    /// `n . (p_a - p_b)`: negative = penetration.
    pub separation: f64,
}

impl StoredPoint {
    /// The point `point` of the pair `(body_a, body_b)` at poses `pose_a`,
    /// `pose_b`, stored in body frames.
    pub fn new(
        (body_a, body_b): (usize, usize),
        point: &ContactPoint,
        normal_body: NormalBody,
        pose_a: &Isometry3<f64>,
        pose_b: &Isometry3<f64>,
    ) -> Self {
        let pose_ref = match normal_body {
            NormalBody::A => pose_a,
            NormalBody::B => pose_b,
        };
        StoredPoint {
            body_a,
            body_b,
            p_a_body: pose_a.inverse_transform_point(&point.point_a_world),
            p_b_body: pose_b.inverse_transform_point(&point.point_b_world),
            normal_body,
            n_ref: pose_ref.inverse_transform_vector(&point.normal_world),
        }
    }

    /// The point at poses `pose_a`, `pose_b` of its two bodies.
    pub fn measure(&self, pose_a: &Isometry3<f64>, pose_b: &Isometry3<f64>) -> MeasuredPoint {
        let pose_ref = match self.normal_body {
            NormalBody::A => pose_a,
            NormalBody::B => pose_b,
        };
        let p_a_world = pose_a * self.p_a_body;
        let p_b_world = pose_b * self.p_b_body;
        let n_world = pose_ref.rotation * self.n_ref;
        MeasuredPoint {
            p_a_world,
            p_b_world,
            n_world,
            separation: n_world.dot(&(p_a_world - p_b_world)),
        }
    }
}
