//! The state of a dynamic body as the correction sees it: its
//! centre-of-mass pose and its mass properties.
//!
//! A body's state is its centre-of-mass position `x` and rotation `R`
//! (world frame). Its metric block is `blockdiag(m I3, I)` with the
//! world-frame inertia `I = R I_body R^T`. A correction `(dx, dtheta)` is
//! applied as `x += dx`, `R = exp(dtheta) R`: the rotation vector `dtheta`
//! acts in the world frame, and the exponential keeps `R` a rotation
//! whatever the step.

use nalgebra::{Isometry3, Matrix3, Point3, Translation3, UnitQuaternion, Vector3};

/// Centre-of-mass pose of one dynamic body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState {
    /// Centre of mass, world frame.
    pub position: Point3<f64>,
    /// Rotation from the body frame to the world frame.
    pub rotation: UnitQuaternion<f64>,
}

impl BodyState {
    /// This state moved by `alpha (dx, dtheta)`.
    pub fn moved(&self, dx: &Vector3<f64>, dtheta: &Vector3<f64>, alpha: f64) -> Self {
        BodyState {
            position: self.position + dx * alpha,
            rotation: UnitQuaternion::from_scaled_axis(dtheta * alpha) * self.rotation,
        }
    }

    /// The pose as an isometry (body frame to world).
    pub fn isometry(&self) -> Isometry3<f64> {
        Isometry3::from_parts(Translation3::from(self.position.coords), self.rotation)
    }
}

/// Mass and body-frame inertia of one dynamic body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyInertia {
    /// Mass (> 0).
    pub mass: f64,
    /// Inertia tensor about the centre of mass, body frame (symmetric
    /// positive definite).
    pub inertia_body: Matrix3<f64>,
}

impl BodyInertia {
    /// World-frame inertia `R I_body R^T` at `rotation`.
    pub fn inertia_world(&self, rotation: &UnitQuaternion<f64>) -> Matrix3<f64> {
        let r = rotation.to_rotation_matrix();
        r.matrix() * self.inertia_body * r.matrix().transpose()
    }
}
