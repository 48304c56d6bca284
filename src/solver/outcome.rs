//! Outcomes shared by the solvers: which solver ran, what it produced, and
//! why a solver failed before another one took over.

use std::fmt;

use nalgebra::DVector;

use super::augmented_lagrangian::AugmentedLagrangianFailure;
use super::clarabel_qp::ClarabelFailure;
use super::dual_active_set::DualActiveSetFailure;
use super::interior_point::InteriorPointFailure;
use super::lemke::LemkeStatus;
use super::pgs::PgsStatus;

/// A solver of the projection QP / its LCP.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum SolverKind {
    /// Every constraint already holds (equality rows within the acceptance
    /// feasibility measure): `dq = 0`, `lambda = 0` (only under
    /// [`super::SolverChoice::Auto`]).
    Trivial,
    /// One row: `lambda = max(0, -b/a)` (`-b/a` for an equality row).
    ClosedForm,
    /// The augmented Lagrangian method with semismooth Newton on the
    /// body-space matrix ([`super::augmented_lagrangian`]).
    AugmentedLagrangian,
    /// The primal-dual interior point on the body-space matrix
    /// ([`super::interior_point`]).
    /// Goldfarb and Idnani's dual active-set method
    /// ([`super::dual_active_set`]).
    DualActiveSet,
    InteriorPoint,
    /// clarabel on the primal QP (variables `dq`).
    Clarabel,
    /// clarabel on the dual QP `min 1/2 z^T A z + b^T z, z >= 0`.
    ClarabelDual,
    /// Lemke's complementary pivoting on the LCP.
    Lemke,
    /// Projected Gauss-Seidel on the LCP.
    Pgs,
}

/// What a solver returns before the common residual check.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// The correction `dq` (six entries per body).
    pub dq: DVector<f64>,
    /// The multipliers `lambda` (one per row; free for equality rows).
    pub lambda: DVector<f64>,
    /// Interior-point iterations, pivots, sweeps or Newton steps.
    pub iterations: usize,
    /// Numeric factorizations made by the library's own Cholesky (as
    /// `ProjectionSolution::factorizations`).
    pub factorizations: usize,
}

/// Why one solver did not deliver a solution.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum FailureReason {
    /// The solver does not apply to this problem (the closed form on more
    /// than one row, PGS on a zero diagonal, a QP form of a non-symmetric
    /// or indefinite LCP).
    NotApplicable,
    /// A violated row with a zero Jacobian: no correction can satisfy it.
    Infeasible,
    /// clarabel stopped with a status other than (almost) solved.
    Clarabel(ClarabelFailure),
    /// Lemke's method ended without a solution (after the regularized
    /// retries).
    Lemke(LemkeStatus),
    /// PGS did not reach the tolerance.
    Pgs(PgsStatus),
    /// The augmented Lagrangian solver gave up.
    AugmentedLagrangian(AugmentedLagrangianFailure),
    /// The interior point on the body-space matrix gave up.
    /// The dual active-set method's failure.
    DualActiveSet(DualActiveSetFailure),
    InteriorPoint(InteriorPointFailure),
    /// The caller's deadline ([`super::SolverSettings::deadline`]) had
    /// passed before the solver ran, or while it ran (clarabel's time
    /// limit, Lemke before a pivot, PGS before a sweep, the augmented
    /// Lagrangian before a Newton step): no answer, and no other solver is
    /// tried after it.
    DeadlinePassed,
    /// A dense solver (Lemke, PGS, clarabel's dual form, all on the
    /// assembled `A = J M^-1 J^T`) on more rows than
    /// [`super::SolverSettings::dense_max_rows`]: not run.
    AboveDenseLimit {
        /// Rows of the problem it would have solved (the pyramid's, for a
        /// problem with cones).
        rows: usize,
        /// The limit.
        limit: usize,
    },
    /// The solver returned a solution whose residual, checked by us against
    /// the original problem, is above the tolerance.
    ResidualTooLarge {
        /// The acceptance measure ([`super::ProjectionResiduals::acceptance`]).
        residual: f64,
        /// The tolerance it was checked against.
        tolerance: f64,
    },
}

impl FailureReason {
    /// Whether the failure is a certificate that the problem has no
    /// solution: a violated row with a zero Jacobian, clarabel's primal
    /// infeasibility certificate, Lemke's ray termination (for a
    /// positive semidefinite matrix, copositive-plus, a ray means that the
    /// LCP is infeasible), equality rows that Lemke's elimination found
    /// inconsistent, or the interior point's Farkas certificate
    /// ([`InteriorPointFailure::Infeasible`]).
    pub fn certifies_infeasibility(&self) -> bool {
        matches!(
            self,
            Self::Infeasible
                | Self::Clarabel(ClarabelFailure::PrimalInfeasible)
                | Self::InteriorPoint(InteriorPointFailure::Infeasible)
                | Self::Lemke(LemkeStatus::Ray)
                | Self::Lemke(LemkeStatus::InconsistentEqualities { .. })
        )
    }
}

impl fmt::Display for FailureReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotApplicable => write!(f, "not applicable to this problem"),
            Self::Infeasible => write!(f, "a violated row has a zero Jacobian"),
            Self::Clarabel(c) => write!(f, "clarabel: {c:?}"),
            Self::Lemke(s) => write!(f, "lemke: {s:?}"),
            Self::Pgs(s) => write!(f, "pgs: {s:?}"),
            Self::AugmentedLagrangian(s) => write!(f, "augmented Lagrangian: {s:?}"),
            Self::InteriorPoint(s) => write!(f, "interior point: {s:?}"),
            Self::DualActiveSet(s) => write!(f, "dual active set: {s:?}"),
            Self::DeadlinePassed => write!(f, "the deadline passed"),
            Self::AboveDenseLimit { rows, limit } => {
                write!(f, "{rows} rows, above the dense solvers' limit of {limit}")
            }
            Self::ResidualTooLarge {
                residual,
                tolerance,
            } => {
                write!(f, "residual {residual:.3e} above tolerance {tolerance:.3e}")
            }
        }
    }
}

/// A solver that was tried and failed, before the one that succeeded.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Fallback {
    /// The solver that failed.
    pub solver: SolverKind,
    /// Why.
    pub reason: FailureReason,
}
