//! The projection QP: the smallest mass-weighted correction that satisfies
//! linearized non-penetration constraints (DESIGN.md section 3).
//!
//! For the dynamic bodies of one island, a correction `dq` has six entries
//! per body, `[dx (3), dtheta (3)]`: a translation of the centre of mass and
//! a world-frame rotation vector. The metric is
//!
//! ```text
//! M = blockdiag(m_k I3, I_k)          I_k: world-frame inertia about the centre of mass
//! ```
//!
//! and the problem is
//!
//! ```text
//! minimize 1/2 dq^T M dq   subject to   phi_i + J_i dq >= target_i   for every row i.
//! ```
//!
//! `phi_i` is the signed gap (negative = penetration), `target_i >= 0` a small
//! margin. Its dual is the LCP `A = J M^-1 J^T`, `b = phi - target`:
//! `lambda >= 0, w = A lambda + b >= 0, lambda^T w = 0`, with
//! `dq = M^-1 J^T lambda` (see [`super::projection_lcp`]). `dq` is unique
//! because `M` is positive definite; `lambda` is not when rows are redundant.

use nalgebra::{DVector, Matrix3, Vector6};

use super::error::SolverError;
use super::metric::BlockMetric;

/// Mass properties of one dynamic body of an island.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyMetric {
    /// Mass, finite and positive (any consistent unit).
    pub mass: f64,
    /// Inertia tensor about the centre of mass, in the world frame
    /// (`R I_body R^T`); symmetric positive definite.
    pub inertia_world: Matrix3<f64>,
}

/// One linearized constraint row, sparse over bodies.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct JacobianRow {
    /// `(body index into ProjectionQp::bodies, [linear (3); angular (3)])`:
    /// the derivative of the constraint value with respect to that body's
    /// `[dx; dtheta]` (world frame). Each body appears at most once; fixed
    /// bodies do not appear at all.
    pub blocks: Vec<(usize, Vector6<f64>)>,
}

/// The projection QP of one island.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ProjectionQp {
    /// The dynamic bodies; `dq` has `6 * bodies.len()` entries.
    pub bodies: Vec<BodyMetric>,
    /// Constraint rows `J_i`.
    pub rows: Vec<JacobianRow>,
    /// Constraint values `phi_i` at the current configuration (length units;
    /// negative = penetration).
    pub phi: Vec<f64>,
    /// Required values `target_i` (length units, usually a small margin >= 0).
    pub target: Vec<f64>,
}

impl ProjectionQp {
    /// Number of constraint rows.
    pub fn num_rows(&self) -> usize {
        self.rows.len()
    }

    /// Number of entries of `dq`: six per body.
    pub fn num_dofs(&self) -> usize {
        6 * self.bodies.len()
    }

    /// `b_i = phi_i - target_i`: the LCP's constant term.
    pub fn b(&self) -> DVector<f64> {
        DVector::from_iterator(
            self.phi.len(),
            self.phi.iter().zip(&self.target).map(|(p, t)| p - t),
        )
    }

    /// `J dq` (length `num_rows`).
    pub fn apply_j(&self, dq: &DVector<f64>) -> DVector<f64> {
        DVector::from_iterator(
            self.rows.len(),
            self.rows.iter().map(|row| {
                row.blocks
                    .iter()
                    .map(|(k, g)| g.dot(&dq.fixed_rows::<6>(6 * k)))
                    .sum::<f64>()
            }),
        )
    }

    /// `J^T lambda` (length `num_dofs`).
    pub fn apply_jt(&self, lambda: &DVector<f64>) -> DVector<f64> {
        let mut out = DVector::zeros(self.num_dofs());
        for (row, l) in self.rows.iter().zip(lambda.iter()) {
            for (k, g) in &row.blocks {
                let mut block = out.fixed_rows_mut::<6>(6 * k);
                block += g * *l;
            }
        }
        out
    }

    /// Checks dimensions, finiteness, masses and inertia tensors, and
    /// returns the factored metric. Every solver entry point calls this.
    pub fn validate(&self) -> Result<Vec<BlockMetric>, SolverError> {
        let n = self.rows.len();
        check_len("phi", n, self.phi.len())?;
        check_len("target", n, self.target.len())?;
        check_finite("phi", &self.phi)?;
        check_finite("target", &self.target)?;
        for (i, row) in self.rows.iter().enumerate() {
            self.validate_row(i, row)?;
        }
        self.bodies
            .iter()
            .enumerate()
            .map(|(k, b)| BlockMetric::new(k, b))
            .collect()
    }

    fn validate_row(&self, i: usize, row: &JacobianRow) -> Result<(), SolverError> {
        let bodies = self.bodies.len();
        for (j, (k, g)) in row.blocks.iter().enumerate() {
            if *k >= bodies {
                return Err(SolverError::BodyOutOfRange {
                    row: i,
                    body: *k,
                    bodies,
                });
            }
            if row.blocks[..j].iter().any(|(other, _)| other == k) {
                return Err(SolverError::DuplicateBody { row: i, body: *k });
            }
            if !g.iter().all(|x| x.is_finite()) {
                return Err(SolverError::NonFinite {
                    what: "jacobian row",
                    index: i,
                });
            }
        }
        Ok(())
    }
}

fn check_len(what: &'static str, expected: usize, found: usize) -> Result<(), SolverError> {
    if expected == found {
        Ok(())
    } else {
        Err(SolverError::DimensionMismatch {
            what,
            expected,
            found,
        })
    }
}

pub(crate) fn check_finite(what: &'static str, values: &[f64]) -> Result<(), SolverError> {
    match values.iter().position(|x| !x.is_finite()) {
        Some(index) => Err(SolverError::NonFinite { what, index }),
        None => Ok(()),
    }
}
