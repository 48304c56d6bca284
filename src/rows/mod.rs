//! Linearized constraint rows: what the narrow phase hands the projection.
//!
//! A [`ConstraintProvider`] evaluates, at a [`Configuration`] of dynamic
//! bodies, constraints `phi_k(q) >= 0` (negative = penetration, in length
//! units) and linearizes them into rows `phi_k + J_k dq >= target`, where
//! `J_k` has a 6-vector block `[linear; angular]` per dynamic body it
//! involves (fixed bodies contribute no block). A correction `dq` holds six
//! entries per body, `[dx; dtheta]` in the world frame, applied as
//! `x += dx`, `R = exp(dtheta) R` ([`moved_configuration`]).
//!
//! The contacts of [`crate::contact`] are one provider; the analytic
//! providers of the tests are others. The projection loop
//! ([`crate::projector`]) sees only this interface.

mod configuration;
mod provider;

pub use configuration::{BodyInertia, BodyState, Configuration, moved_configuration};
pub use provider::{ConstraintProvider, ConstraintRow, Measurement, RowFriction, RowKind};
