//! Typed errors of the solver layer.
//!
//! Two kinds of things go wrong:
//! - the *input* is invalid (wrong dimensions, NaN, a non-positive mass, an
//!   inertia tensor that is not symmetric positive definite): the problem is
//!   rejected at the boundary before any solver runs;
//! - every solver that was tried *failed* on a valid problem: the error
//!   carries the list of [`Fallback`]s, one per solver and reason.

use thiserror::Error;

use super::outcome::Fallback;

/// Why a problem was rejected or could not be solved.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SolverError {
    /// Two lengths that must agree do not.
    #[error("dimension mismatch: {what} has length {found}, expected {expected}")]
    DimensionMismatch {
        /// Which array.
        what: &'static str,
        /// The length implied by the rest of the problem.
        expected: usize,
        /// The length that was given.
        found: usize,
    },
    /// A number is NaN or infinite.
    #[error("{what}[{index}] is not finite")]
    NonFinite {
        /// Which array.
        what: &'static str,
        /// Index of the first offending entry.
        index: usize,
    },
    /// A body mass is not a finite positive number.
    #[error("body {body}: mass {mass} must be finite and positive")]
    NonPositiveMass {
        /// Body index.
        body: usize,
        /// The value that was given.
        mass: f64,
    },
    /// A world-frame inertia tensor is not symmetric (relative to its size).
    #[error("body {body}: inertia tensor is not symmetric")]
    InertiaNotSymmetric {
        /// Body index.
        body: usize,
    },
    /// A world-frame inertia tensor is not positive definite.
    #[error("body {body}: inertia tensor is not positive definite")]
    InertiaNotPositiveDefinite {
        /// Body index.
        body: usize,
    },
    /// A Jacobian block names a body that does not exist.
    #[error("row {row}: body index {body} out of range (there are {bodies} bodies)")]
    BodyOutOfRange {
        /// Row index.
        row: usize,
        /// The body index that was given.
        body: usize,
        /// Number of bodies.
        bodies: usize,
    },
    /// A Jacobian row names the same body twice.
    #[error("row {row}: body {body} appears twice")]
    DuplicateBody {
        /// Row index.
        row: usize,
        /// The repeated body index.
        body: usize,
    },
    /// A violated row (`phi < target`, or for an equality row
    /// `phi != target` beyond the acceptance tolerance) whose Jacobian is
    /// zero: no correction can satisfy it (every body it names is fixed).
    #[error("row {row} is violated and no body can move it (zero Jacobian)")]
    InfeasibleRow {
        /// Row index.
        row: usize,
    },
    /// `num_equalities` (of a [`super::ProjectionQp`], or the free
    /// variables of a mixed [`super::Lcp`]) exceeds the number of rows.
    #[error("{num_equalities} equality rows, but only {rows} rows")]
    TooManyEqualities {
        /// The number of equality rows (free variables) given.
        num_equalities: usize,
        /// The number of rows.
        rows: usize,
    },
    /// A friction cone with a negative coefficient, or tangents whose
    /// blocks are not over the normal's bodies in its order.
    #[error("friction cone {cone}: negative mu, or tangents over other bodies than the normal")]
    InvalidCone {
        /// Cone index.
        cone: usize,
    },
    /// A problem with cones whose pyramid would have fewer than three
    /// directions.
    #[error("cone_facets is {0}: a pyramid needs at least 3 directions")]
    ConeFacets(usize),
    /// An LCP matrix is not square.
    #[error("LCP matrix is {rows}x{cols}, not square")]
    NotSquare {
        /// Rows of M.
        rows: usize,
        /// Columns of M.
        cols: usize,
    },
    /// A QP solver was asked to solve an LCP whose matrix is not symmetric
    /// positive semidefinite (the LCP is then not the optimality condition
    /// of a convex QP).
    #[error("the LCP matrix is not symmetric positive semidefinite: no QP form")]
    NotSymmetricPsd,
    /// Every solver that was tried failed; in the order they were tried.
    #[error("no solver succeeded: {}", describe(.0))]
    AllSolversFailed(Vec<Fallback>),
}

fn describe(fallbacks: &[Fallback]) -> String {
    let parts: Vec<String> = fallbacks
        .iter()
        .map(|f| format!("{:?}: {}", f.solver, f.reason))
        .collect();
    parts.join("; ")
}
