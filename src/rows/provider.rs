//! The interface between the projection loop and a source of constraints.
//!
//! A provider evaluates its unilateral constraints `phi_k(q) >= 0` at a
//! configuration (negative = penetration, in length units) and linearizes
//! them: `phi_k(q (+) dq) ≈ phi_k(q) + J_k dq`, where `J_k` has a 6-vector
//! block `[linear; angular]` per dynamic body it involves (fixed bodies
//! contribute no block).

use nalgebra::Vector6;

use super::BodyState;

/// One linearized constraint `phi + J dq >= target`.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintRow {
    /// Constraint value at the current configuration (negative = penetration).
    pub phi: f64,
    /// Non-zero blocks of `J`: (body index in the configuration, `[d phi / d x;
    /// d phi / d theta]`).
    pub blocks: Vec<(usize, Vector6<f64>)>,
    /// Coulomb friction of a resting contact (`None`: frictionless), see
    /// [`crate::projector::friction`].
    pub friction: Option<RowFriction>,
}

/// The friction of one contact row: coefficient and the Jacobians of the
/// relative tangential displacement along two unit tangents `t_1, t_2`
/// orthogonal to the normal (blocks in the same bodies and order as the
/// row's).
#[derive(Debug, Clone, PartialEq)]
pub struct RowFriction {
    /// Friction coefficient `mu > 0`.
    pub mu: f64,
    /// Blocks of `J_t1` and `J_t2`.
    pub tangents: [Vec<(usize, Vector6<f64>)>; 2],
}

/// The true (not linearized) state of the constraints at a configuration.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Measurement {
    /// Signed value of each measured constraint, in a fixed order that does
    /// not depend on the configuration (one entry per body pair for
    /// contacts): negative = penetration depth.
    pub values: Vec<f64>,
}

impl Measurement {
    /// Depth of the deepest penetration (0 if none).
    pub fn deepest_penetration(&self) -> f64 {
        self.values.iter().fold(0.0, |deepest, &v| deepest.max(-v))
    }

    /// Merit: sum of squared penetrations beyond `tolerance`.
    pub fn merit(&self, tolerance: f64) -> f64 {
        self.values
            .iter()
            .map(|&v| (v + tolerance).min(0.0).powi(2))
            .sum()
    }
}

/// A source of unilateral constraints over a configuration of dynamic bodies.
pub trait ConstraintProvider {
    /// The linearized constraints at `configuration`: every violated
    /// constraint and every one close enough to matter (a contact margin).
    fn linearize(&mut self, configuration: &[BodyState]) -> Vec<ConstraintRow>;

    /// The true constraint values at `configuration` (used by the line search
    /// and the convergence test).
    fn measure(&mut self, configuration: &[BodyState]) -> Measurement;
}
