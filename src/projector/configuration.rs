//! Poses of the dynamic bodies of a projection and their metric.
//!
//! A body's state is its centre-of-mass position `x` and rotation `R`
//! (world frame). The metric block of body `i` is `blockdiag(m_i I3, I_i)`
//! with the world-frame inertia `I_i = R_i I_body R_i^T`.
//! A correction `dq` is applied as `x += dx`, `R = exp(dtheta) R`: the
//! rotation vector `dtheta` acts in the world frame, and the exponential
//! keeps `R` a rotation whatever the step.

use nalgebra::{DVector, Isometry3, Matrix3, Point3, Translation3, UnitQuaternion, Vector3};

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

/// The states of the dynamic bodies of one projection, in a fixed order:
/// body `i` owns entries `6 i .. 6 i + 6` of a correction.
pub type Configuration = Vec<BodyState>;

/// `configuration` moved by `alpha dq`.
pub fn moved_configuration(
    configuration: &[BodyState],
    dq: &DVector<f64>,
    alpha: f64,
) -> Configuration {
    configuration
        .iter()
        .enumerate()
        .map(|(i, state)| {
            let dx = dq.fixed_rows::<3>(6 * i).into_owned();
            let dtheta = dq.fixed_rows::<3>(6 * i + 3).into_owned();
            state.moved(&dx, &dtheta, alpha)
        })
        .collect()
}
