//! A dynamic Rapier body's own mass properties, in the scene body's frame.
//!
//! Rapier derives a rigid body's mass properties from its colliders'
//! densities (or masses) and any additional mass properties:
//! `RigidBody::mass()` is the mass and
//! `RigidBody::mass_properties().local_mprops` holds the centre
//! of mass `c_B` in the body frame and the principal inertia `d` in a
//! principal frame `Q` (body frame from principal frame). The scene body's
//! shape frame is the collider frame `P` for one collider and the body
//! frame for a compound, so in the shape frame
//!
//! ```text
//! c = P^-1 c_B,   I = R_P^T (Q diag(d) Q^T) R_P      (R_P the rotation of P)
//! ```
//!
//! composed in f64 from Rapier's f32 numbers. The bridge gives these to the
//! scene body ([`crate::body::Body::set_mass_properties`]), so that the
//! correction and the velocity projection act about the centre of mass and
//! with the inertia Rapier integrates. The centre is taken from Rapier only
//! when it differs from the shape's uniform-density centre by more than
//! [`ENGINE_COM_ROUNDING`] of the body's reach: for a body of one uniform
//! collider the two differ only by Rapier's f32 rounding, and the body
//! keeps its own (its convex part stays at the body frame, bit for bit).

use nalgebra::{Isometry3, Matrix3, Point3, Vector3};
use rapier3d::dynamics::RigidBody;

use super::convert::vector_to_f64;
use crate::body::{Body, BodyError};

/// Relative difference (of the body's reach) between Rapier's centre of
/// mass and the shape's uniform-density one below which the difference
/// is Rapier's f32 rounding and the shape's centre is kept (f32 rounding
/// is about `6e-8` relative; the centroid of a hull sums a few dozen
/// terms).
pub const ENGINE_COM_ROUNDING: f64 = 1e-5;

/// Mass properties of a dynamic Rapier body in the body frame, exactly as
/// Rapier holds them (f32 as f64).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct EngineMass {
    pub mass: f64,
    /// Centre of mass in the Rapier body frame.
    pub com_body: Vector3<f64>,
    /// Inertia about the centre of mass, in the body frame's axes.
    pub inertia_body: Matrix3<f64>,
}

impl EngineMass {
    /// A dynamic body's mass properties; `None` when they are not usable
    /// (a mass or an inertia that is zero or not finite: locked
    /// rotations, a body without colliders), and the scene body keeps the
    /// uniform density.
    pub fn of(body: &RigidBody) -> Option<Self> {
        let local = &body.mass_properties().local_mprops;
        let inverse_mass = f64::from(local.inv_mass);
        let inverse_inertia = local.inv_principal_inertia;
        let inverse = [inverse_inertia.x, inverse_inertia.y, inverse_inertia.z].map(f64::from);
        let usable = inverse_mass.is_finite()
            && inverse_mass > 0.0
            && inverse.iter().all(|i| i.is_finite() && *i > 0.0);
        if !usable {
            return None;
        }
        let q = local.principal_inertia_local_frame;
        let frame = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            f64::from(q.w),
            f64::from(q.x),
            f64::from(q.y),
            f64::from(q.z),
        ))
        .to_rotation_matrix();
        let principal = Matrix3::from_diagonal(&Vector3::from(inverse.map(|i| 1.0 / i)));
        Some(EngineMass {
            mass: f64::from(body.mass()),
            com_body: vector_to_f64(local.local_com),
            inertia_body: frame.matrix() * principal * frame.matrix().transpose(),
        })
    }

    /// Gives `body` these mass properties, the scene body's shape frame
    /// being `collider_in_body` in the Rapier body frame (module docs).
    pub fn apply(
        &self,
        body: &mut Body,
        collider_in_body: &Isometry3<f64>,
    ) -> Result<(), BodyError> {
        let to_shape = collider_in_body.inverse();
        let com_engine = (to_shape * Point3::from(self.com_body)).coords;
        let own = *body.com_offset();
        let com = match (com_engine - own).norm() > ENGINE_COM_ROUNDING * body.reach() {
            true => com_engine,
            false => own,
        };
        let r = to_shape.rotation.to_rotation_matrix();
        let inertia = r.matrix() * self.inertia_body * r.matrix().transpose();
        body.set_mass_properties(self.mass, com, inertia)
    }
}
