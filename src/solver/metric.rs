//! The block-diagonal mass metric `M = blockdiag(m_k I3, I_k)`, factored once
//! per body.
//!
//! Per body, `M_k = L_k L_k^T` with `L_k = blockdiag(sqrt(m_k) I3, C_k)` and
//! `C_k` the lower Cholesky factor of the world inertia `I_k`. The solvers
//! use `M^-1` (to form `A = J M^-1 J^T` and `dq = M^-1 J^T lambda`) and
//! `L^-1` (to change variables to `y = L^T dq`, in which the metric is the
//! identity). Nothing is ever inverted densely: every operation is per
//! 6x6 block.

use nalgebra::{Matrix3, Vector3, Vector6};

use super::error::SolverError;
use super::projection::BodyMetric;

/// Relative asymmetry `max|I - I^T| / max|I|` accepted in an inertia
/// tensor. Rotating a body-frame tensor (`R I R^T`) in f64 leaves an
/// asymmetry of a few ulps; anything larger is a caller's mistake.
pub const INERTIA_SYMMETRY_TOL_REL: f64 = 1e-9;

/// Smallest squared Cholesky pivot of an inertia tensor, relative to its
/// largest entry. Below it the tensor is treated as singular: a body that
/// thin (1e-12 in squared aspect ratio) has no usable rotational metric.
pub const INERTIA_MIN_PIVOT_REL: f64 = 1e-12;

/// A validated, factored body metric.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockMetric {
    /// Mass.
    pub mass: f64,
    /// Symmetrized world inertia `I_k`.
    pub inertia: Matrix3<f64>,
    /// `I_k^-1`, from the Cholesky factor.
    pub inertia_inv: Matrix3<f64>,
    /// Lower Cholesky factor `C_k` of `I_k`.
    pub inertia_chol: Matrix3<f64>,
}

impl BlockMetric {
    /// Validates body `index` (positive finite mass, symmetric positive
    /// definite finite inertia) and factors it.
    pub fn new(index: usize, body: &BodyMetric) -> Result<Self, SolverError> {
        if !(body.mass.is_finite() && body.mass > 0.0) {
            return Err(SolverError::NonPositiveMass {
                body: index,
                mass: body.mass,
            });
        }
        let i = &body.inertia_world;
        if !i.iter().all(|x| x.is_finite()) {
            return Err(SolverError::NonFinite {
                what: "inertia_world",
                index,
            });
        }
        let size = i.amax();
        if (i - i.transpose()).amax() > INERTIA_SYMMETRY_TOL_REL * size {
            return Err(SolverError::InertiaNotSymmetric { body: index });
        }
        let inertia = (i + i.transpose()) * 0.5;
        let chol = inertia
            .cholesky()
            .ok_or(SolverError::InertiaNotPositiveDefinite { body: index })?;
        let inertia_chol = chol.l();
        // A pivot of the factor squared is at least the smallest eigenvalue;
        // a pivot that vanishes against the largest entry means a tensor
        // singular to working precision.
        let min_pivot = inertia_chol.diagonal().min();
        if min_pivot * min_pivot <= INERTIA_MIN_PIVOT_REL * size {
            return Err(SolverError::InertiaNotPositiveDefinite { body: index });
        }
        Ok(Self {
            mass: body.mass,
            inertia,
            inertia_inv: chol.inverse(),
            inertia_chol,
        })
    }

    /// `M_k v`.
    pub fn apply(&self, v: &Vector6<f64>) -> Vector6<f64> {
        let lin = v.fixed_rows::<3>(0) * self.mass;
        let ang = self.inertia * v.fixed_rows::<3>(3);
        stack(&lin, &ang)
    }

    /// `M_k` as a 6x6 matrix: `blockdiag(m_k I3, I_k)`.
    pub fn matrix(&self) -> nalgebra::Matrix6<f64> {
        let mut m = nalgebra::Matrix6::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).fill_diagonal(self.mass);
        m.fixed_view_mut::<3, 3>(3, 3).copy_from(&self.inertia);
        m
    }

    /// `M_k^-1 v`.
    pub fn apply_inv(&self, v: &Vector6<f64>) -> Vector6<f64> {
        let lin = v.fixed_rows::<3>(0) / self.mass;
        let ang = self.inertia_inv * v.fixed_rows::<3>(3);
        stack(&lin, &ang)
    }

    /// `L_k^-1 v` (forward substitution with the Cholesky factor).
    pub fn solve_l(&self, v: &Vector6<f64>) -> Vector6<f64> {
        let lin = v.fixed_rows::<3>(0) / self.mass.sqrt();
        let ang = lower_solve(&self.inertia_chol, &v.fixed_rows::<3>(3).into_owned());
        stack(&lin, &ang)
    }

    /// `L_k^-T v` (back substitution with the Cholesky factor).
    pub fn solve_lt(&self, v: &Vector6<f64>) -> Vector6<f64> {
        let lin = v.fixed_rows::<3>(0) / self.mass.sqrt();
        let ang = upper_solve(
            &self.inertia_chol.transpose(),
            &v.fixed_rows::<3>(3).into_owned(),
        );
        stack(&lin, &ang)
    }
}

fn stack(lin: &Vector3<f64>, ang: &Vector3<f64>) -> Vector6<f64> {
    Vector6::new(lin.x, lin.y, lin.z, ang.x, ang.y, ang.z)
}

fn lower_solve(l: &Matrix3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    let x0 = v.x / l[(0, 0)];
    let x1 = (v.y - l[(1, 0)] * x0) / l[(1, 1)];
    let x2 = (v.z - l[(2, 0)] * x0 - l[(2, 1)] * x1) / l[(2, 2)];
    Vector3::new(x0, x1, x2)
}

fn upper_solve(u: &Matrix3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    let x2 = v.z / u[(2, 2)];
    let x1 = (v.y - u[(1, 2)] * x2) / u[(1, 1)];
    let x0 = (v.x - u[(0, 1)] * x1 - u[(0, 2)] * x2) / u[(0, 0)];
    Vector3::new(x0, x1, x2)
}
