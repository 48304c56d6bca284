//! A dynamic body held still, and mass properties given by an engine.
//!
//! # Held still
//!
//! [`Body::hold_fixed`] makes a dynamic body count as fixed (no mass
//! properties, [`Body::is_fixed`]) until [`Body::release`]: an engine's
//! sleeping body is an obstacle for the awake ones around it, never moved.
//! Its mass properties are kept aside and come back unchanged.
//!
//! # Engine mass properties
//!
//! [`Body::set_mass_properties`] replaces the uniform-density mass
//! properties derived from the shape by an engine's own: mass `m`, centre
//! of mass `c` in the shape frame and inertia `I` about `c` in the body
//! axes (those of the shape frame). The body frame's origin moves from the
//! old centre `c_0` to `c`, so each part's offset (part frame to body
//! frame, `body::parts`) moves by `c_0 - c`:
//!
//! ```text
//! offset_i' = Translation(c_0 - c) offset_i,   t_com = t_user + R c
//! ```
//!
//! and the user pose, the truth, is unchanged.

use nalgebra::{Matrix3, Vector3};

use super::{Body, BodyError, BodyMass, com_pose_of};

impl Body {
    /// Holds a dynamic body still: it counts as fixed until
    /// [`Body::release`]. No effect on a fixed or already held body.
    pub fn hold_fixed(&mut self) {
        if let Some(mass) = self.mass.take() {
            self.held_mass = Some(mass);
        }
    }

    /// Gives a held body its mass properties back (no effect otherwise).
    pub fn release(&mut self) {
        if let Some(mass) = self.held_mass.take() {
            self.mass = Some(mass);
        }
    }

    /// Whether the body is dynamic but held still ([`Body::hold_fixed`]).
    pub fn is_held(&self) -> bool {
        self.held_mass.is_some()
    }

    /// Sets a dynamic body's mass properties to an engine's (module docs):
    /// mass `mass`, centre of mass `com_shape` in the shape frame, inertia
    /// `inertia_body` about it in the body axes. The user pose is kept.
    /// Errors: a fixed body ([`BodyError::InvalidMass`]: it has none), a
    /// mass not finite and positive, a centre not finite, an inertia not
    /// finite or not invertible ([`BodyError::DegenerateMass`]).
    pub fn set_mass_properties(
        &mut self,
        mass: f64,
        com_shape: Vector3<f64>,
        inertia_body: Matrix3<f64>,
    ) -> Result<(), BodyError> {
        let Some(old) = self.mass.or(self.held_mass) else {
            return Err(BodyError::InvalidMass(mass));
        };
        if !(mass.is_finite() && mass > 0.0) {
            return Err(BodyError::InvalidMass(mass));
        }
        let inverse_inertia_body = inertia_body.try_inverse();
        let usable = com_shape.iter().all(|c| c.is_finite())
            && inertia_body.iter().all(|c| c.is_finite())
            && inverse_inertia_body.is_some_and(|m| m.iter().all(|c| c.is_finite()));
        let (true, Some(inverse_inertia_body)) = (usable, inverse_inertia_body) else {
            return Err(BodyError::DegenerateMass {
                given: self.mass_spec,
                volume: mass / old.density,
            });
        };
        let shift = self.origin_offset - com_shape;
        if shift != Vector3::zeros() {
            for part in &mut self.parts {
                part.shift(&shift);
            }
            self.origin_offset = com_shape;
            self.com_pose = com_pose_of(
                &self.translation_user,
                self.com_pose.rotation,
                &self.origin_offset,
            );
        }
        let engine_mass = BodyMass {
            mass,
            density: old.density * mass / old.mass,
            inertia_body,
            inverse_inertia_body,
        };
        match self.held_mass.is_some() {
            true => self.held_mass = Some(engine_mass),
            false => self.mass = Some(engine_mass),
        }
        Ok(())
    }
}
