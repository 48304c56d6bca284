//! Oracles for solver answers, computed here from the problem's data only:
//! no residual, metric or `J` product of the library is used, so a defect
//! there cannot hide a wrong answer.
//!
//! Projection QP `min 1/2 dq^T M dq` s.t. `phi + J dq >= target`, answer
//! `(dq, lambda)`. The KKT conditions of a convex QP are sufficient for
//! optimality, and `dq` is unique (`M` positive definite), so passing all
//! four checks proves `dq` right:
//!
//! ```text
//! primal feasibility   w = phi - target + J dq >= 0
//! dual feasibility     lambda >= 0
//! complementarity      lambda_i w_i = 0
//! stationarity         dq = M^-1 J^T lambda
//! ```
//!
//! Each is made dimensionless with the data's scales: lengths by
//! `l = ||phi - target||_inf`, multipliers by `||lambda||_inf`, `dq` in the
//! `M`-norm. LCP `(M, q)`, answer `z`: `w = M z + q`, `z >= 0`, `w >= 0`,
//! `z . w = 0`, lengths by `max(1, ||q||_inf)` as in
//! `tests/data/siconos/README.md`.

use constraint_stabilization::solver::ProjectionQp;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};

/// The oracle's tolerance on each relative KKT measure. The library's own
/// check uses 1e-9 on similar (not identical) measures; ten times that
/// leaves room for the different normalizations, and a wrong active set
/// gives measures of order one.
pub const KKT_TOL: f64 = 1e-8;

/// The oracle's tolerance on the relative residuals of an LCP answer: the
/// acceptance threshold of `tests/data/siconos/README.md`.
pub const LCP_TOL: f64 = 1e-9;

/// Relative KKT measures of a projection QP answer (each 0 for an exact
/// solution).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kkt {
    /// `max_i max(0, -w_i) / l`.
    pub infeasibility: f64,
    /// `max_i max(0, -lambda_i) / ||lambda||_inf`.
    pub negative_multiplier: f64,
    /// `max_i |lambda_i w_i| / (l ||lambda||_inf)`.
    pub complementarity: f64,
    /// `||dq - M^-1 J^T lambda||_M / max(||dq||_M, ||M^-1 J^T lambda||_M)`.
    pub stationarity: f64,
}

impl Kkt {
    /// The largest measure.
    pub fn worst(&self) -> f64 {
        self.infeasibility
            .max(self.negative_multiplier)
            .max(self.complementarity)
            .max(self.stationarity)
    }
}

fn ratio(num: f64, den: f64) -> f64 {
    if num == 0.0 { 0.0 } else { num / den }
}

/// `w = phi - target + J dq`, row by row from the row blocks.
pub fn constraint_values(qp: &ProjectionQp, dq: &DVector<f64>) -> DVector<f64> {
    DVector::from_fn(qp.rows.len(), |i, _| {
        let jdq: f64 = qp.rows[i]
            .blocks
            .iter()
            .map(|(k, g)| (0..6).map(|c| g[c] * dq[6 * k + c]).sum::<f64>())
            .sum();
        qp.phi[i] - qp.target[i] + jdq
    })
}

/// `M v`, body by body (`m I3` on the translation, the world inertia on
/// the rotation).
pub fn apply_metric(qp: &ProjectionQp, v: &DVector<f64>) -> DVector<f64> {
    let mut out = DVector::zeros(v.len());
    for (k, body) in qp.bodies.iter().enumerate() {
        let lin = Vector3::new(v[6 * k], v[6 * k + 1], v[6 * k + 2]) * body.mass;
        let ang = body.inertia_world * Vector3::new(v[6 * k + 3], v[6 * k + 4], v[6 * k + 5]);
        for c in 0..3 {
            out[6 * k + c] = lin[c];
            out[6 * k + 3 + c] = ang[c];
        }
    }
    out
}

/// `sqrt(v^T M v)`.
pub fn metric_norm(qp: &ProjectionQp, v: &DVector<f64>) -> f64 {
    v.dot(&apply_metric(qp, v)).max(0.0).sqrt()
}

/// `M^-1 J^T lambda`: the correction the multipliers imply.
pub fn dq_of_lambda(qp: &ProjectionQp, lambda: &DVector<f64>) -> DVector<f64> {
    let mut force = vec![Vector6::<f64>::zeros(); qp.bodies.len()];
    for (row, l) in qp.rows.iter().zip(lambda.iter()) {
        for (k, g) in &row.blocks {
            force[*k] += g * *l;
        }
    }
    let mut dq = DVector::zeros(6 * qp.bodies.len());
    for (k, body) in qp.bodies.iter().enumerate() {
        let inverse: Matrix3<f64> = body
            .inertia_world
            .try_inverse()
            .expect("test inertia is invertible");
        let lin = force[k].fixed_rows::<3>(0) / body.mass;
        let ang = inverse * force[k].fixed_rows::<3>(3);
        for c in 0..3 {
            dq[6 * k + c] = lin[c];
            dq[6 * k + 3 + c] = ang[c];
        }
    }
    dq
}

/// The KKT measures of `(dq, lambda)` for `qp`.
pub fn projection_kkt(qp: &ProjectionQp, dq: &DVector<f64>, lambda: &DVector<f64>) -> Kkt {
    let w = constraint_values(qp, dq);
    let length = qp
        .phi
        .iter()
        .zip(&qp.target)
        .map(|(p, t)| (p - t).abs())
        .fold(f64::MIN_POSITIVE, f64::max);
    let lambda_scale = lambda.amax();
    let implied = dq_of_lambda(qp, lambda);
    let norm = metric_norm(qp, dq).max(metric_norm(qp, &implied));
    Kkt {
        infeasibility: w.iter().map(|&x| (-x).max(0.0)).fold(0.0, f64::max) / length,
        negative_multiplier: ratio(
            lambda.iter().map(|&x| (-x).max(0.0)).fold(0.0, f64::max),
            lambda_scale,
        ),
        complementarity: ratio(lambda.component_mul(&w).amax(), length * lambda_scale),
        stationarity: ratio(metric_norm(qp, &(dq - implied)), norm),
    }
}

/// Panics with `context` unless `(dq, lambda)` passes every KKT check to
/// [`KKT_TOL`].
pub fn assert_kkt(qp: &ProjectionQp, dq: &DVector<f64>, lambda: &DVector<f64>, context: &str) {
    assert_eq!(dq.len(), 6 * qp.bodies.len(), "{context}: dq length");
    assert_eq!(lambda.len(), qp.rows.len(), "{context}: lambda length");
    let kkt = projection_kkt(qp, dq, lambda);
    assert!(kkt.worst() <= KKT_TOL, "{context}: {kkt:?}");
}

/// `||dq_1 - dq_2||_M / max(||dq_1||_M, ||dq_2||_M)` (0 when both are 0).
pub fn relative_metric_distance(
    qp: &ProjectionQp,
    dq_1: &DVector<f64>,
    dq_2: &DVector<f64>,
) -> f64 {
    let norm = metric_norm(qp, dq_1).max(metric_norm(qp, dq_2));
    ratio(metric_norm(qp, &(dq_1 - dq_2)), norm)
}

/// Relative residuals of an LCP answer `z` (each 0 for an exact solution),
/// with `w = M z + q` computed here and `s = max(1, ||q||_inf)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LcpResiduals {
    /// `||min(z, w)||_inf / s`: the measure of the Siconos README.
    pub natural_map: f64,
    /// `max_i max(0, -z_i, -w_i) / s`.
    pub infeasibility: f64,
    /// `max_i |z_i w_i| / (s max(1, ||z||_inf))`.
    pub complementarity: f64,
}

impl LcpResiduals {
    /// The largest residual.
    pub fn worst(&self) -> f64 {
        self.natural_map
            .max(self.infeasibility)
            .max(self.complementarity)
    }
}

/// The residuals of `z` for the LCP `(m, q)`.
pub fn lcp_residuals(m: &DMatrix<f64>, q: &DVector<f64>, z: &DVector<f64>) -> LcpResiduals {
    assert_eq!(z.len(), q.len(), "z has the size of the problem");
    let w = m * z + q;
    let scale = q.amax().max(1.0);
    let worst = |f: &dyn Fn(usize) -> f64| (0..z.len()).map(f).fold(0.0, f64::max);
    LcpResiduals {
        natural_map: worst(&|i| z[i].min(w[i]).abs()) / scale,
        infeasibility: worst(&|i| (-z[i]).max(-w[i]).max(0.0)) / scale,
        complementarity: worst(&|i| (z[i] * w[i]).abs()) / (scale * z.amax().max(1.0)),
    }
}

/// Panics with `context` unless `z` solves `(m, q)` to `tol`.
pub fn assert_lcp_solved(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    z: &DVector<f64>,
    tol: f64,
    context: &str,
) {
    let r = lcp_residuals(m, q, z);
    assert!(r.worst() <= tol, "{context}: {r:?}, z = {z}");
}
