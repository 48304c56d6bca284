//! Comparing two solutions of one projection QP.
//!
//! `lambda` is not unique when rows are redundant (four coplanar contacts of
//! a box constrain three degrees of freedom), so two correct solvers may
//! disagree on it. `dq` is unique (the objective is strictly convex in `dq`),
//! and so are `w = b + J dq` and the objective. The differences reported:
//!
//! ```text
//! dq:        ||dq_1 - dq_2||_M / max(||dq_1||_M, ||dq_2||_M)
//! w:         ||w_1 - w_2||_inf / max(||b||_inf, tiny)
//! objective: |f_1 - f_2| / max(f_1, f_2),   f = 1/2 dq^T M dq
//! ```
//!
//! (each 0 when both sides are 0).

use nalgebra::DVector;

use super::metric::BlockMetric;
use super::outcome::{FailureReason, SolverKind};
use super::projection::ProjectionQp;
use super::residuals::{ProjectionResiduals, length_scale, m_norm};

/// Relative differences between two solutions.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Differences {
    /// Relative M-norm difference of `dq`.
    pub dq_rel: f64,
    /// Difference of `w`, relative to `||b||_inf`.
    pub w_rel: f64,
    /// Relative difference of the objective.
    pub objective_rel: f64,
}

impl Differences {
    /// The largest of the three.
    pub fn worst(&self) -> f64 {
        self.dq_rel.max(self.w_rel).max(self.objective_rel)
    }
}

/// The result of solving again with a second solver.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct CrossCheck {
    /// The second solver.
    pub reference: SolverKind,
    /// Its residuals and the differences, or why it failed.
    pub outcome: CrossCheckOutcome,
    /// The problem had friction cones: both sides solved its pyramid, one
    /// problem with linear rows that both solvers take
    /// (`super::solve`).
    pub on_pyramid: bool,
}

/// What the second solver produced.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum CrossCheckOutcome {
    /// Both solved: their differences and the reference's residuals.
    Compared {
        /// Differences of the two solutions.
        differences: Differences,
        /// Residuals of the reference solution.
        reference_residuals: ProjectionResiduals,
    },
    /// The reference solver failed.
    ReferenceFailed(FailureReason),
}

fn ratio(num: f64, den: f64) -> f64 {
    if den > 0.0 { num / den } else { 0.0 }
}

/// Differences between `dq_1` and `dq_2` for the same problem.
pub fn differences(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    dq_1: &DVector<f64>,
    dq_2: &DVector<f64>,
) -> Differences {
    let n1 = m_norm(metric, dq_1);
    let n2 = m_norm(metric, dq_2);
    let dq_rel = ratio(m_norm(metric, &(dq_1 - dq_2)), n1.max(n2));
    let w_rel = (qp.apply_j(dq_1) - qp.apply_j(dq_2)).amax() / length_scale(&qp.b());
    let (f1, f2) = (0.5 * n1 * n1, 0.5 * n2 * n2);
    Differences {
        dq_rel,
        w_rel,
        objective_rel: ratio((f1 - f2).abs(), f1.max(f2)),
    }
}
