//! Residual metrics, in one place.
//!
//! LCP `(M, q)`, candidate `z`, `w = M z + q`:
//! - natural map: `||min(z, w)||_inf`, zero exactly at solutions. For the
//!   Siconos files it is divided by `max(1, ||q||_inf)` ([`lcp_natural_map`],
//!   the measure of `tests/data/siconos/README.md`).
//! - complementarity: `max_i |z_i w_i|`.
//!
//! Projection QP (see [`super::projection`]), with `b = phi - target`,
//! `w = b + J dq`, `a_i = J_i M^-1 J_i^T` (the diagonal of the LCP matrix) and
//! the length scale `l = max(||b||_inf, tiny)`. Each metric is dimensionless,
//! so it is unchanged when lengths or masses are rescaled (`a_i lambda_i` and
//! `w_i` are both lengths):
//! - natural map: `max_i |min(a_i lambda_i, w_i)| / l`
//! - complementarity: `max_i a_i lambda_i |w_i| / (l f)` with the force
//!   scale `f = max(l, max_j a_j lambda_j)` (a product normalized by the size
//!   of both factors, as interior-point codes do: with `l^2` alone, large
//!   multipliers would amplify rounding in `w`)
//! - primal infeasibility: `max_i max(0, -w_i) / l`
//! - stationarity: `||dq - M^-1 J^T lambda||_M / max(||dq||_M, ||M^-1 J^T lambda||_M)`
//!   (zero by construction for the LCP solvers; measures clarabel's primal
//!   and dual agreeing)
//! - objective `1/2 dq^T M dq` and displacement `sqrt(dq^T M dq)` (absolute).

use nalgebra::{DMatrix, DVector};

use super::metric::BlockMetric;
use super::projection::ProjectionQp;

/// `||min(z, w)||_inf / max(1, ||q||_inf)`: the README measure of the
/// Siconos LCP files.
pub fn lcp_natural_map(z: &DVector<f64>, w: &DVector<f64>, q: &DVector<f64>) -> f64 {
    natural_map_abs(z, w) / q.amax().max(1.0)
}

/// `||min(z, w)||_inf`, unnormalized.
pub fn natural_map_abs(z: &DVector<f64>, w: &DVector<f64>) -> f64 {
    z.iter()
        .zip(w.iter())
        .map(|(a, b)| a.min(*b).abs())
        .fold(0.0, f64::max)
}

/// `||min(z, w)||_inf` with `w = M z + q` computed here, plus the rounding
/// uncertainty of each computed `w_i`:
///
/// ```text
/// max_i ( |min(z_i, w_i)| + delta_i ),   delta_i = sqrt(n) u (|M| |z| + |q|)_i
/// ```
///
/// (`u` the unit roundoff; `sqrt(n) u` is the usual statistical estimate of
/// the error of a dot product of length `n`, Higham 2002, section 3.1).
/// A `z` so large that its `w` is lost to cancellation cannot pass: a
/// regularized LCP `M + eps I` with no solution for `eps = 0` has a `z` of
/// size `1/eps` whose computed `w` can look complementary.
pub fn natural_map_certified(m: &DMatrix<f64>, q: &DVector<f64>, z: &DVector<f64>) -> f64 {
    let w = m * z + q;
    let abs_w = m.abs() * z.abs() + q.abs();
    let gamma = (q.len() as f64).sqrt().max(1.0) * f64::EPSILON;
    (0..z.len())
        .map(|i| z[i].min(w[i]).abs() + gamma * abs_w[i])
        .fold(0.0, f64::max)
}

/// `max_i |z_i w_i|`.
pub fn complementarity_abs(z: &DVector<f64>, w: &DVector<f64>) -> f64 {
    z.iter()
        .zip(w.iter())
        .map(|(a, b)| (a * b).abs())
        .fold(0.0, f64::max)
}

/// Every residual of a candidate solution of a projection QP.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ProjectionResiduals {
    /// Scale-relative natural map of the dual LCP.
    pub natural_map: f64,
    /// Scale-relative complementarity.
    pub complementarity: f64,
    /// Scale-relative violation of `phi + J dq >= target`.
    pub primal_infeasibility: f64,
    /// Relative disagreement of `dq` with `M^-1 J^T lambda`.
    pub stationarity: f64,
    /// `1/2 dq^T M dq` (mass x length^2).
    pub objective: f64,
    /// `sqrt(dq^T M dq)` (sqrt(mass) x length).
    pub displacement: f64,
}

impl ProjectionResiduals {
    /// The largest of the relative residuals (natural map, complementarity,
    /// primal infeasibility, stationarity): what a tolerance is checked
    /// against.
    pub fn worst(&self) -> f64 {
        self.natural_map
            .max(self.complementarity)
            .max(self.primal_infeasibility)
            .max(self.stationarity)
    }
}

/// `sqrt(v^T M v)`.
pub fn m_norm(metric: &[BlockMetric], v: &DVector<f64>) -> f64 {
    m_inner(metric, v, v).max(0.0).sqrt()
}

/// `u^T M v`.
pub fn m_inner(metric: &[BlockMetric], u: &DVector<f64>, v: &DVector<f64>) -> f64 {
    metric
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let uk = u.fixed_rows::<6>(6 * k).into_owned();
            let vk = v.fixed_rows::<6>(6 * k).into_owned();
            uk.dot(&b.apply(&vk))
        })
        .sum()
}

/// `M^-1 v`.
pub fn m_inv(metric: &[BlockMetric], v: &DVector<f64>) -> DVector<f64> {
    let mut out = DVector::zeros(v.len());
    for (k, b) in metric.iter().enumerate() {
        let vk = v.fixed_rows::<6>(6 * k).into_owned();
        out.fixed_rows_mut::<6>(6 * k).copy_from(&b.apply_inv(&vk));
    }
    out
}

/// `a_i = J_i M^-1 J_i^T` for every row.
pub fn row_diagonal(qp: &ProjectionQp, metric: &[BlockMetric]) -> Vec<f64> {
    qp.rows
        .iter()
        .map(|row| {
            row.blocks
                .iter()
                .map(|(k, g)| g.dot(&metric[*k].apply_inv(g)))
                .sum()
        })
        .collect()
}

/// Length scale `l` of the residuals: `||b||_inf`, or the smallest positive
/// f64 when `b = 0` (then every residual numerator is zero at a solution).
pub fn length_scale(b: &DVector<f64>) -> f64 {
    b.amax().max(f64::MIN_POSITIVE)
}

/// Residuals of `(dq, lambda)` for the projection QP.
pub fn projection_residuals(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    dq: &DVector<f64>,
    lambda: &DVector<f64>,
) -> ProjectionResiduals {
    let b = qp.b();
    let w = &b + qp.apply_j(dq);
    let l = length_scale(&b);
    let a = row_diagonal(qp, metric);
    let a_fallback = a.iter().copied().fold(0.0, f64::max);
    let force: Vec<f64> = (0..w.len())
        .map(|i| if a[i] > 0.0 { a[i] } else { a_fallback } * lambda[i])
        .collect();
    let f = force.iter().fold(l, |m, x| m.max(x.abs()));
    let mut natural_map: f64 = 0.0;
    let mut complementarity: f64 = 0.0;
    let mut primal_infeasibility: f64 = 0.0;
    for i in 0..w.len() {
        natural_map = natural_map.max(force[i].min(w[i]).abs() / l);
        complementarity = complementarity.max((force[i] * w[i]).abs() / (l * f));
        primal_infeasibility = primal_infeasibility.max((-w[i]).max(0.0) / l);
    }
    let dq_dual = m_inv(metric, &qp.apply_jt(lambda));
    let norm = m_norm(metric, dq).max(m_norm(metric, &dq_dual));
    let stationarity = if norm > 0.0 {
        m_norm(metric, &(dq - &dq_dual)) / norm
    } else {
        0.0
    };
    let displacement = m_norm(metric, dq);
    ProjectionResiduals {
        natural_map,
        complementarity,
        primal_infeasibility,
        stationarity,
        objective: 0.5 * displacement * displacement,
        displacement,
    }
}
