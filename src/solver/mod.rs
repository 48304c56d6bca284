//! LCP and QP solvers (docs/design.md sections 3 and 5).
//!
//! The problem of one island is the projection QP
//!
//! ```text
//! minimize 1/2 dq^T M dq   subject to   phi + J dq >= target
//! ```
//!
//! ([`ProjectionQp`], `M` block diagonal), whose first
//! [`ProjectionQp::num_equalities`] rows may be equalities (joints), and
//! whose dual is the LCP `A = J M^-1 J^T`, `b = phi - target`
//! (`projection_lcp`; a mixed LCP with free multipliers for the equality
//! rows, [`Lcp::mixed`]), possibly with
//! friction cones ([`friction_cone`]; clarabel's primal form solves them,
//! the others their pyramid). Solvers:
//! - `closed_form`: one row;
//! - [`augmented_lagrangian`]: the augmented Lagrangian method with a
//!   semismooth Newton inner solve on `H = M + rho J_A^T J_A` (sparse
//!   Cholesky), warm-startable from multipliers;
//! - [`dual_active_set`]: Goldfarb and Idnani's dual active-set method,
//!   dense in the active rows, for islands of a few bodies with many rows;
//! - [`interior_point`]: a primal-dual interior point on the same
//!   body-space matrix (`H = M + J^T D J`, sparse Cholesky, symbolic
//!   analysis once per problem);
//! - [`clarabel_qp::primal`]: clarabel on the primal QP (sparse);
//! - [`clarabel_qp::dual`]: clarabel on the dual QP `min 1/2 z^T A z + b^T z, z >= 0`;
//! - [`lemke`]: Lemke's complementary pivoting (also general LCPs, [`Lcp`];
//!   equality rows eliminated first, through a sparse factor of their
//!   block, [`equality_elimination`], or a dense pivoted one, [`lemke::mixed`]);
//! - [`pgs`]: projected Gauss-Seidel, the game-engine baseline.
//!
//! [`solve_projection`] validates the problem, picks a solver, falls back
//! on failure, checks every answer with the metrics of [`residuals`] and
//! can cross-check two solvers (`cross_check`).

pub mod augmented_lagrangian;
pub mod clarabel_qp;
pub(crate) mod closed_form;
pub(crate) mod cone_residuals;
pub(crate) mod cross_check;
#[doc(hidden)]
pub mod dense_cholesky;
pub mod dual_active_set;
pub mod equality_elimination;
mod error;
pub mod friction_cone;
pub mod interior_point;
pub mod kept_analyses;
mod lcp;
pub mod lemke;
pub(crate) mod metric;
mod outcome;
pub(crate) mod packed_rows;
pub mod pgs;
mod projection;
pub(crate) mod projection_lcp;
#[doc(hidden)]
pub mod recorder;
pub mod residuals;
pub(crate) mod scaling;
mod solve;

pub use cross_check::{CrossCheck, CrossCheckOutcome, Differences};
pub use error::SolverError;
pub use friction_cone::FrictionCone;
pub use kept_analyses::KeptAnalyses;
pub use lcp::Lcp;
pub use metric::BlockMetric;
pub use outcome::{Candidate, FailureReason, Fallback, SolverKind};
pub use projection::{BodyMetric, JacobianRow, ProjectionQp};
pub use projection_lcp::{dq_from_lambda, lcp_matrix, projection_to_lcp};
pub use residuals::ProjectionResiduals;
pub use solve::{
    DEFAULT_AUTO_DUAL_ACTIVE_SET_MAX_DOFS, DEFAULT_AUTO_DUAL_ACTIVE_SET_VIOLATED_MAX_DOFS,
    DEFAULT_AUTO_INTERIOR_POINT_MIN_ROWS, PRECISION_STOP_CAP, ProjectionSolution, SolverChoice,
    SolverSettings, cross_check_projection, solve_projection, solve_projection_kept,
    solve_projection_warm,
};
