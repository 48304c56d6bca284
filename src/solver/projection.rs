//! The projection QP: the smallest mass-weighted correction that satisfies
//! linearized non-penetration constraints (docs/design.md section 3).
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
//! minimize 1/2 dq^T M dq   subject to   phi_i + J_i dq  = target_i   for i <  num_equalities (E)
//!                                         phi_i + J_i dq >= target_i   for i >= num_equalities (I)
//! ```
//!
//! For a contact row `phi_i` is the signed gap (negative = penetration),
//! `target_i >= 0` a small margin. The first
//! [`ProjectionQp::num_equalities`] rows are bilateral (joints): their
//! multipliers have either sign. The dual is the mixed LCP
//! `A = J M^-1 J^T`, `b = phi - target`:
//!
//! ```text
//! w = A lambda + b,   w_E = 0 (lambda_E free),   lambda_I >= 0, w_I >= 0, lambda_I^T w_I = 0
//! ```
//!
//! with `dq = M^-1 J^T lambda` (see [`super::projection_lcp`]). `dq` is
//! unique because `M` is positive definite; `lambda` is not when rows are
//! redundant (a closed loop of joints lists dependent equality rows).
//! Equality rows never carry friction cones.
//!
//! A problem may also carry friction cones ([`FrictionCone`], three-dimensional
//! second-order cones `w_c = (b_c + J_n dq, mu J_t1 dq, mu J_t2 dq) in K`).
//! It is then a second-order cone program that only clarabel solves as it
//! is; the other solvers solve its pyramid ([`ProjectionQp::pyramid`], with
//! [`ProjectionQp::cone_facets`] directions), a QP with linear rows only.
//! The multipliers of a problem with cones are the rows' `lambda_i`, then
//! three per cone (`z_c`, [`super::friction_cone`]).

use nalgebra::{DVector, Matrix3, Vector6};

use super::error::SolverError;
use super::friction_cone::{CONE_DIM, FrictionCone};
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
    /// Constraint rows `J_i`: the first [`Self::num_equalities`] are
    /// equalities, the rest inequalities (module docs).
    pub rows: Vec<JacobianRow>,
    /// Constraint values `phi_i` at the current configuration (length units;
    /// negative = penetration).
    pub phi: Vec<f64>,
    /// Required values `target_i` (length units, usually a small margin >= 0).
    pub target: Vec<f64>,
    /// Friction cones (module docs); empty for a QP with linear rows only.
    pub cones: Vec<FrictionCone>,
    /// Directions `K >= 3` of the pyramid that replaces the cones for the
    /// solvers of linear rows ([`ProjectionQp::pyramid`]); unused without
    /// cones.
    pub cone_facets: usize,
    /// The first `num_equalities` rows are equalities
    /// `phi_i + J_i dq = target_i` (bilateral rows of joints, free
    /// multipliers); the rest are inequalities `>=`. At most `rows.len()`;
    /// default 0 (inequalities only).
    pub num_equalities: usize,
}

impl ProjectionQp {
    /// Number of constraint rows.
    pub fn num_rows(&self) -> usize {
        self.rows.len()
    }

    /// Whether row `i` is an equality row (`i < num_equalities`).
    pub fn is_equality(&self, i: usize) -> bool {
        i < self.num_equalities
    }

    /// Number of multipliers: one per row, three per cone.
    pub fn num_multipliers(&self) -> usize {
        self.rows.len() + CONE_DIM * self.cones.len()
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

    /// `J^T lambda` (length `num_dofs`), with the cones' forces when
    /// `lambda` has their multipliers too (module docs).
    pub fn apply_jt(&self, lambda: &DVector<f64>) -> DVector<f64> {
        let mut out = DVector::zeros(self.num_dofs());
        for (row, l) in self.rows.iter().zip(lambda.iter()) {
            for (k, g) in &row.blocks {
                let mut block = out.fixed_rows_mut::<6>(6 * k);
                block += g * *l;
            }
        }
        let n = self.rows.len();
        for (c, cone) in self.cones.iter().enumerate() {
            if lambda.len() >= n + CONE_DIM * (c + 1) {
                let z = lambda.fixed_rows::<CONE_DIM>(n + CONE_DIM * c).into_owned();
                cone.add_force(&z, &mut out);
            }
        }
        out
    }

    /// The rows whose transposes carry the multipliers, in their order:
    /// the rows, then `(J_n, mu J_t1, mu J_t2)` of each cone.
    pub fn multiplier_rows(&self) -> Vec<JacobianRow> {
        let mut rows = self.rows.clone();
        rows.extend(self.cones.iter().flat_map(FrictionCone::rows));
        rows
    }

    /// The problem with every cone replaced by its [`Self::cone_facets`]
    /// facets (appended after the rows, cone by cone, with target 0; the
    /// equality rows stay first), and
    /// for each of its rows the index of the row or cone it comes from
    /// (cone `c` as `num_rows + c`).
    pub fn pyramid(&self) -> (ProjectionQp, Vec<usize>) {
        let n = self.rows.len();
        let mut pyramid = ProjectionQp {
            cones: Vec::new(),
            ..self.clone()
        };
        let mut origins: Vec<usize> = (0..n).collect();
        for (c, cone) in self.cones.iter().enumerate() {
            for (row, phi) in cone.facets(self.cone_facets) {
                pyramid.rows.push(row);
                pyramid.phi.push(phi);
                pyramid.target.push(0.0);
                origins.push(n + c);
            }
        }
        (pyramid, origins)
    }

    /// Checks dimensions, finiteness, masses and inertia tensors, and
    /// returns the factored metric. Every solver entry point calls this.
    pub fn validate(&self) -> Result<Vec<BlockMetric>, SolverError> {
        let n = self.rows.len();
        check_len("phi", n, self.phi.len())?;
        check_len("target", n, self.target.len())?;
        check_finite("phi", &self.phi)?;
        check_finite("target", &self.target)?;
        if self.num_equalities > n {
            return Err(SolverError::TooManyEqualities {
                num_equalities: self.num_equalities,
                rows: n,
            });
        }
        for (i, row) in self.rows.iter().enumerate() {
            self.validate_row(i, row)?;
        }
        self.validate_cones()?;
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

impl ProjectionQp {
    /// Each cone: finite data, `mu >= 0`, valid rows, tangents over the
    /// normal's bodies in its order, and enough pyramid directions.
    fn validate_cones(&self) -> Result<(), SolverError> {
        if !self.cones.is_empty() && self.cone_facets < MIN_CONE_FACETS {
            return Err(SolverError::ConeFacets(self.cone_facets));
        }
        for (c, cone) in self.cones.iter().enumerate() {
            let values = [cone.mu, cone.phi, cone.target];
            check_finite("friction cone", &values).map_err(|_| SolverError::NonFinite {
                what: "friction cone",
                index: c,
            })?;
            if cone.mu < 0.0 {
                return Err(SolverError::InvalidCone { cone: c });
            }
            let index = self.rows.len() + c;
            self.validate_row(index, &cone.normal)?;
            for tangent in &cone.tangents {
                self.validate_row(index, tangent)?;
                let same_bodies = tangent.blocks.len() == cone.normal.blocks.len()
                    && tangent
                        .blocks
                        .iter()
                        .zip(&cone.normal.blocks)
                        .all(|((a, _), (b, _))| a == b);
                if !same_bodies {
                    return Err(SolverError::InvalidCone { cone: c });
                }
            }
        }
        Ok(())
    }
}

/// The fewest directions of a pyramid (a triangle).
pub const MIN_CONE_FACETS: usize = 3;

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
