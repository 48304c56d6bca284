//! The generic projection: linearized unilateral constraints, the
//! smallest mass-weighted correction, and a backtracking line search on the
//! true constraints.
//!
//! Configuration: for each dynamic body `i` a centre-of-mass position `x_i`
//! and a rotation `R_i`. A correction `dq = (dx_i, dtheta_i)` (6 entries per
//! body, `dtheta` a world-frame rotation vector) is applied as
//!
//! ```text
//! x_i <- x_i + alpha dx_i,      R_i <- exp(alpha dtheta_i) R_i.
//! ```
//!
//! A [`ConstraintProvider`](crate::rows::ConstraintProvider) evaluates, at a configuration, constraints
//! `phi_k(q) >= 0` (negative = penetration) with Jacobian rows `J_k`. One
//! projection step solves
//!
//! ```text
//! minimize 1/2 dq^T M dq   subject to   phi_k + J_k dq >= target_k,
//! M = blockdiag(m_i I3, I_i^world),
//! ```
//!
//! then scales `dq` by the largest `alpha in {1, beta, beta^2, ...}` for which
//! the merit on the *true* constraints (`sum_k min(0, phi_k + tol)^2`, the
//! squared penetrations beyond the tolerance) decreases sufficiently and no
//! constraint that was clear becomes penetrating beyond the tolerance
//! ([`line_search`]), after scaling `dq` so that no body moves further than
//! its trust region ([`TrustRegion`]). The loop is independent of the geometry: contacts from
//! V-Clip are one provider; analytic providers test it alone.

mod consistent_equalities;
pub mod friction;
pub mod friction_rows;
mod line_search;
mod step;
pub mod trust_region;

pub use line_search::{LineSearchOutcome, line_search};
pub use step::{
    Plan, PlannedStep, ProjectionStatus, ProjectionSummary, StepOutcome, StepReport, WarmStartOf,
    plan_step, plan_step_warm, project, projection_qp, projection_qp_weighted, projection_step,
    take_step,
};
pub use trust_region::{TrustRegion, radius_of_gyration};
