//! Backtracking line search on the true constraints.
//!
//! Given the correction `dq` of the linearized problem, try
//! `alpha = 1, beta, beta^2, ...` and accept the first `alpha` with
//!
//! ```text
//! merit(q (+) alpha dq) <= (1 - sigma alpha) merit(q)            (sufficient decrease)
//! phi_k(q) >= -tol  =>  phi_k(q (+) alpha dq) >= -max(tol, rho d)  for all k
//! ```
//!
//! (a clear constraint is not pushed in by more than a fraction `rho` of the
//! worst violation `d` before the step, the deepest penetration or the
//! largest equality error: no overshoot into neighbours; an equality within
//! the tolerance is not pushed off by more either). With an allowed
//! penetration `p` (included in `tol`), which shifts every depth and the
//! tolerance alike, the same test is measured from `p`:
//! `-(p + max(tol - p, rho (d - p)))`. Measured from zero, a contact at the
//! edge of a 5 mm allowance could not move at all while a neighbour 0.3 mm
//! beyond it was being removed, and the island stalled (the pile of 200 of
//! `examples/with_and_without.rs` under `RespectAllowedPenetration`).
//!
//! where `merit = sum_k min(0, phi_k + tol)^2 + sum_j max(0, |e_j| - tol)^2`
//! (`e_j` the equality constraints, [`crate::rows::Measurement::merit`]). For the linearization,
//! `phi_k + alpha J_k dq` shrinks every penetration by at least a factor
//! `(1 - alpha)`, so the linear model predicts `merit(alpha) <= (1 - alpha)^2
//! merit(0)`; `sigma` asks for a small fraction of that on the true geometry.
//! Below `alpha_min` nothing is accepted: the configuration stays as it was
//! and the caller reports the stall. The merit therefore never rises.

use nalgebra::DVector;

use crate::rows::moved_configuration;
use crate::rows::{BodyState, Configuration, ConstraintProvider, Measurement};
use crate::settings::LineSearchSettings;

/// The result of a line search.
#[derive(Debug, Clone, PartialEq)]
pub enum LineSearchOutcome {
    /// `alpha` was accepted; `configuration` is the moved one.
    Accepted {
        /// Accepted step length in (0, 1].
        alpha: f64,
        /// Number of trial configurations measured.
        trials: usize,
        /// The moved configuration.
        configuration: Configuration,
        /// The constraints measured there.
        measurement: Measurement,
    },
    /// No step down to `min_step` was acceptable.
    Rejected {
        /// Number of trial configurations measured.
        trials: usize,
    },
}

/// Backtracks along `dq` from `configuration`, whose constraints measured
/// `before`; `tolerance` includes `allowed_penetration`, from which the
/// push test is measured (module docs).
pub fn line_search<P: ConstraintProvider + ?Sized>(
    provider: &mut P,
    configuration: &[BodyState],
    dq: &DVector<f64>,
    before: &Measurement,
    tolerance: f64,
    allowed_penetration: f64,
    settings: &LineSearchSettings,
) -> LineSearchOutcome {
    let merit_before = before.merit(tolerance);
    let allowed_new_depth = allowed_penetration
        + (tolerance - allowed_penetration).max(
            settings.new_penetration_fraction * (before.worst_violation() - allowed_penetration),
        );
    let mut alpha = 1.0;
    let mut trials = 0;
    while alpha >= settings.min_step {
        let trial = moved_configuration(configuration, dq, alpha);
        let measurement = provider.measure(&trial);
        trials += 1;
        let merit = measurement.merit(tolerance);
        let decreased = merit <= (1.0 - settings.sufficient_decrease * alpha) * merit_before;
        if decreased && !starts_penetrating(before, &measurement, tolerance, allowed_new_depth) {
            log::debug!(
                "  line search: alpha {alpha} accepted, merit {merit_before:.3e} -> {merit:.3e}"
            );
            return LineSearchOutcome::Accepted {
                alpha,
                trials,
                configuration: trial,
                measurement,
            };
        }
        let pushed = first_pushed(before, &measurement, tolerance, allowed_new_depth);
        log::debug!(
            "  line search: alpha {alpha} rejected, merit {merit_before:.3e} -> {merit:.3e}{}",
            pushed.map_or(String::new(), |(kind, k, b, a)| format!(
                ", {kind} {k} pushed from {b:.3e} to {a:.3e}"
            ))
        );
        alpha *= settings.shrink;
    }
    LineSearchOutcome::Rejected { trials }
}

/// Whether a constraint that was clear (within the tolerance) before is
/// penetrating deeper than `allowed_depth` after, or an equality that held
/// within the tolerance is off by more than `allowed_depth`. Measurements
/// of different lengths cannot be compared and count as a violation.
fn starts_penetrating(
    before: &Measurement,
    after: &Measurement,
    tolerance: f64,
    allowed_depth: f64,
) -> bool {
    before.values.len() != after.values.len()
        || before.equalities.len() != after.equalities.len()
        || before
            .values
            .iter()
            .zip(&after.values)
            .any(|(&b, &a)| b >= -tolerance && a < -allowed_depth)
}

/// The first constraint that [`starts_penetrating`] finds pushed: its
/// kind, index, value before and after (for the log).
fn first_pushed(
    before: &Measurement,
    after: &Measurement,
    tolerance: f64,
    allowed_depth: f64,
) -> Option<(&'static str, usize, f64, f64)> {
    before
        .values
        .iter()
        .zip(&after.values)
        .position(|(&b, &a)| b >= -tolerance && a < -allowed_depth)
        .map(|k| ("constraint", k, before.values[k], after.values[k]))
}
