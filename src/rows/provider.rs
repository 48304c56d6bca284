//! The interface between the projection loop and a source of constraints.
//!
//! A provider evaluates its unilateral constraints `phi_k(q) >= 0` at a
//! configuration (negative = penetration, in length units) and its
//! equality constraints `e_j(q) = 0` (a joint's locked axes, in length
//! units), and linearizes them: `phi_k(q (+) dq) ≈ phi_k(q) + J_k dq`,
//! where `J_k` has a 6-vector block `[linear; angular]` per dynamic body it
//! involves (fixed bodies contribute no block).
//!
//! The merit of a measurement, which the line search must decrease, is
//! the sum of the squared violations beyond the tolerance `tol`:
//!
//! ```text
//! merit = sum_k min(0, phi_k + tol)^2 + sum_j max(0, |e_j| - tol)^2.
//! ```

use nalgebra::Vector6;

use super::BodyState;

/// Whether a row asks `phi + J dq >= target` or `phi + J dq = 0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RowKind {
    /// `phi + J dq >= target` (a contact, a joint limit).
    #[default]
    Inequality,
    /// `phi + J dq = 0` (a joint's locked axis).
    Equality,
}

/// One linearized constraint `phi + J dq >= target` (or `= 0`, by `kind`).
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintRow {
    /// Inequality or equality.
    pub kind: RowKind,
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
    /// Signed value of each measured unilateral constraint, in a fixed
    /// order that does not depend on the configuration (one entry per body
    /// pair for contacts): negative = penetration depth.
    pub values: Vec<f64>,
    /// Value of each equality constraint (0 when it holds), in a fixed
    /// order, length units.
    pub equalities: Vec<f64>,
}

impl Measurement {
    /// Depth of the deepest penetration (0 if none).
    pub fn deepest_penetration(&self) -> f64 {
        self.values.iter().fold(0.0, |deepest, &v| deepest.max(-v))
    }

    /// The largest equality error `|e_j|` (0 if none).
    pub fn largest_equality_error(&self) -> f64 {
        self.equalities
            .iter()
            .fold(0.0, |largest, &e| largest.max(e.abs()))
    }

    /// The largest violation of any kind: the deepest penetration or the
    /// largest equality error.
    pub fn worst_violation(&self) -> f64 {
        self.deepest_penetration()
            .max(self.largest_equality_error())
    }

    /// Merit: sum of squared violations beyond `tolerance` (module docs).
    pub fn merit(&self, tolerance: f64) -> f64 {
        let unilateral: f64 = self
            .values
            .iter()
            .map(|&v| (v + tolerance).min(0.0).powi(2))
            .sum();
        let equalities: f64 = self
            .equalities
            .iter()
            .map(|&e| (e.abs() - tolerance).max(0.0).powi(2))
            .sum();
        unilateral + equalities
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

    /// Whether the equality rows may be linearly dependent (a closed loop
    /// of joints): their right-hand side is then made consistent before
    /// solving (`projector/consistent_equalities.rs`). Default false.
    fn equalities_may_be_redundant(&self) -> bool {
        false
    }
}
