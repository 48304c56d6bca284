//! Residual metrics, in one place.
//!
//! LCP `(M, q)`, candidate `z`, `w = M z + q`:
//! - natural map: `||min(z, w)||_inf`, zero exactly at solutions. For the
//!   Siconos files it is divided by `max(1, ||q||_inf)` ([`lcp_natural_map`],
//!   the measure of `tests/data/siconos/README.md`).
//! - complementarity: `max_i |z_i w_i|`.
//!
//! Projection QP (see `super::projection`), with `b = phi - target`,
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
//!
//! These KKT measures judge `lambda` as much as `dq`. With redundant rows
//! (four coplanar corners of a box resting face-down, a contact listed
//! twice) `A` is singular and `lambda` is not unique: an interior point
//! stops with multipliers spread over the redundant rows, each with a small
//! `lambda_i w_i`, and the natural map and complementarity above stay at
//! 1e-6..1e-4 although `dq` is right to rounding. The projection only uses
//! `dq`, so a candidate is accepted on two measures of `dq` alone
//! ([`ProjectionResiduals::acceptance`]), with `lambda` only as a
//! certificate:
//!
//! - feasibility: `max_i max(0, -w_i) / L` with the acceptance length
//!   `L = ||b||_inf` (and the `|b|` of the cones): how far a linearized row
//!   is left below its target,
//!   relative to the largest violation the problem started with;
//! - optimality: `sqrt(gap / E)`, a certified bound on the relative error of
//!   `dq` in the `M`-norm, from the duality gap of the QP. For any
//!   `lambda >= 0` (the candidate's, clamped), with `v = M^-1 J^T lambda`,
//!   the dual objective `D(lambda) = -1/2 v^T M v - b^T lambda` is a lower
//!   bound of the optimum `P* = 1/2 dq*^T M dq*` (weak duality). Using
//!   `b^T lambda = lambda^T w - v^T M dq`, the gap of a feasible `dq` is
//!
//!   ```text
//!   gap = 1/2 dq^T M dq - D(lambda) = 1/2 ||dq - v||_M^2 + lambda^T w  >= 0
//!   ```
//!
//!   and since `P` is `M`-strongly convex and `dq*` minimizes it over the
//!   feasible set, `1/2 ||dq - dq*||_M^2 <= P(dq) - P* <= gap`. A slightly
//!   infeasible `dq` is the feasible point of the problem whose rows are
//!   relaxed to `max(w_i, 0)`, so the gap is taken with `w^+ = max(w, 0)`
//!   (the relaxation itself is bounded by the feasibility measure). The
//!   energy scale is `E = max(1/2 dq^T M dq, max_i max(0, -b_i)^2 / (2 a_i))`
//!   (the second term is the cost of the single most violated row alone, a
//!   lower bound of `P*`; with no violated row, `dq* = 0` and `E` is
//!   `L^2 / (2 max_i a_i)`, the cost of moving by `L` the row that moves most easily),
//!   so `sqrt(gap / E) >= ||dq - dq*||_M / sqrt(2 E)`,
//!   the error of `dq` relative to the size of the correction.
//!   Non-unique multipliers do not enter: any `lambda` that makes the gap
//!   small certifies `dq`, whichever of the many optimal `lambda` it is.
//!   Rounding: `w_i` carries an absolute error of about `u |b|` (`u` the
//!   unit roundoff), so `gap / E` has a floor of about `n u` and the
//!   optimality measure one of about `sqrt(n u)` (1e-7 at 500 rows): the
//!   tolerance on it cannot be much below 1e-6.
//!
//! **Equality rows** (the first [`ProjectionQp::num_equalities`], joints):
//! a row that must hold with equality is violated both ways, so its
//! infeasibility (in the feasibility measure, the primal infeasibility and
//! the natural map) is `|w_i| = |phi_i + J_i dq - target_i|`; its multiplier
//! is free: no sign, no complementarity (its complementarity term is 0 and
//! it is not clamped in `lambda^+`). The duality gap still certifies `dq`:
//! for `lambda_I >= 0` and any `lambda_E`, `D(lambda) = min_dq 1/2 dq^T M dq
//! - lambda^T (b + J dq)` is a lower bound of `P*` (at a feasible `dq`,
//! `lambda^T w = lambda_I^T w_I >= 0` since `w_E = 0`), and the identity
//! above gives `gap = 1/2 ||dq - v||_M^2 + lambda_I^T w_I + lambda_E^T w_E`.
//! A slightly infeasible `dq` is the feasible point of the problem whose
//! equality rows are moved to `b_E - w_E` (so that `w_E = 0`) and whose
//! inequality rows are relaxed to `w_I^+`; on it the equality terms vanish
//! and `gap = 1/2 ||dq - v||_M^2 + lambda_I^+ . w_I^+`, the relaxation
//! again bounded by the feasibility measure. The single-row bound of the
//! energy scale counts an equality row as violated whatever the sign of
//! `b_i`: `b_i^2 / (2 a_i)`.
//!
//! Friction cones enter every measure in the cone's sense (a cone's
//! infeasibility is `max(0, |w_t| - w_0)`, its multiplier is projected onto
//! the cone rather than clamped, its gap term is `z^T w`):
//! `super::cone_residuals`. The length scale `l` then includes the cones'
//! `|b_c|`.

use nalgebra::{DMatrix, DVector, Vector6};

use super::cone_residuals::{ConeAtCandidate, cones_at, projected_multipliers};
use super::metric::BlockMetric;
use super::projection::ProjectionQp;

/// `||min(z, w)||_inf / max(||q||_inf, ||M||_inf ||z||_inf)` for
/// `w = M z + q` (the unnormalized value when the data are zero): the
/// natural map relative to the size of the data at `z`, invariant under
/// scaling `M`, `q` (and so `z`) by positive factors. The acceptance of a
/// general LCP's solution by Lemke and clarabel (`lemke::solve`,
/// `clarabel_qp::dual::solve_lcp`). The first `free` variables are free
/// (a mixed LCP, [`natural_map_abs`]; 0 for a plain LCP).
pub fn natural_map_relative(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    z: &DVector<f64>,
    free: usize,
) -> f64 {
    let w = m * z + q;
    let natural = natural_map_abs(z, &w, free);
    let size = q.amax().max(m.amax() * z.amax());
    if size > 0.0 { natural / size } else { natural }
}

/// `||min(z, w)||_inf / max(1, ||q||_inf)`: the measure of the Siconos
/// LCP files (`tests/data/siconos/README.md`); the first `free` variables
/// free ([`natural_map_abs`]).
pub fn lcp_natural_map(z: &DVector<f64>, w: &DVector<f64>, q: &DVector<f64>, free: usize) -> f64 {
    natural_map_abs(z, w, free) / q.amax().max(1.0)
}

/// `||min(z, w)||_inf`, unnormalized, for an LCP whose first `free`
/// variables are free (a mixed LCP, `super::lcp`; 0 for a plain one):
/// their entries are `|w_i|` (a free variable's row must vanish; the
/// natural map of a free `z_i` is `z_i - (z_i - w_i) = w_i`).
pub fn natural_map_abs(z: &DVector<f64>, w: &DVector<f64>, free: usize) -> f64 {
    z.iter()
        .zip(w.iter())
        .enumerate()
        .map(|(i, (a, b))| natural_map_entry(*a, *b, i < free))
        .fold(0.0, f64::max)
}

/// `|w|` for a free variable, `|min(z, w)|` otherwise.
fn natural_map_entry(z: f64, w: f64, free: bool) -> f64 {
    if free { w.abs() } else { z.min(w).abs() }
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
/// size `1/eps` whose computed `w` can look complementary. The first
/// `free` variables are free ([`natural_map_abs`]).
pub fn natural_map_certified(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    z: &DVector<f64>,
    free: usize,
) -> f64 {
    // `w` and `|M| |z| + |q|` in one sweep over the columns of the nonzero
    // `z_j` (an LCP answer is mostly zeros).
    let mut w = q.clone();
    let mut abs_w = q.abs();
    for (j, &zj) in z.iter().enumerate().filter(|(_, zj)| **zj != 0.0) {
        for (i, &mij) in m.column(j).iter().enumerate() {
            w[i] += mij * zj;
            abs_w[i] += mij.abs() * zj.abs();
        }
    }
    let gamma = (q.len() as f64).sqrt().max(1.0) * f64::EPSILON;
    (0..z.len())
        .map(|i| natural_map_entry(z[i], w[i], i < free) + gamma * abs_w[i])
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
    /// Scale-relative violation of `phi + J dq >= target` (`= target` for
    /// equality rows: `|w_i|`).
    pub primal_infeasibility: f64,
    /// Relative disagreement of `dq` with `M^-1 J^T lambda`.
    pub stationarity: f64,
    /// `1/2 dq^T M dq` (mass x length^2).
    pub objective: f64,
    /// `sqrt(dq^T M dq)` (sqrt(mass) x length).
    pub displacement: f64,
    /// `max_i max(0, -w_i) / L` (`|w_i|` for equality rows),
    /// `L = ||b||_inf`: the violation of the linearized rows relative to
    /// the acceptance length.
    pub feasibility: f64,
    /// Duality gap `1/2 ||dq - v||_M^2 + lambda^+ . w^+` relative to the
    /// energy scale `E` (module docs).
    pub duality_gap: f64,
    /// `sqrt(duality_gap)`: a certified bound on `||dq - dq*||_M / sqrt(2 E)`,
    /// the relative error of `dq` (module docs).
    pub optimality: f64,
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

    /// What a candidate is accepted on: the larger of
    /// [`feasibility`](Self::feasibility) and
    /// [`duality_gap`](Self::duality_gap), two measures of `dq` alone
    /// (module docs). Unlike [`worst`](Self::worst), redundant rows with
    /// non-unique multipliers do not raise it.
    pub fn acceptance(&self) -> f64 {
        self.feasibility.max(self.duality_gap)
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

/// `M v`.
pub fn m_apply(metric: &[BlockMetric], v: &DVector<f64>) -> DVector<f64> {
    per_block(metric, v, BlockMetric::apply)
}

/// `M^-1 v`.
pub fn m_inv(metric: &[BlockMetric], v: &DVector<f64>) -> DVector<f64> {
    per_block(metric, v, BlockMetric::apply_inv)
}

/// `f(M_k, v_k)` for every body's six entries `v_k`.
fn per_block(
    metric: &[BlockMetric],
    v: &DVector<f64>,
    f: impl Fn(&BlockMetric, &Vector6<f64>) -> Vector6<f64>,
) -> DVector<f64> {
    let mut out = DVector::zeros(v.len());
    for (k, b) in metric.iter().enumerate() {
        let vk = v.fixed_rows::<6>(6 * k).into_owned();
        out.fixed_rows_mut::<6>(6 * k).copy_from(&f(b, &vk));
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

/// How far row `i` with value `w_i` is from holding: `|w_i|` for an
/// equality row, `max(0, -w_i)` for an inequality row (module docs).
pub fn row_violation(equality: bool, w_i: f64) -> f64 {
    if equality { w_i.abs() } else { (-w_i).max(0.0) }
}

/// The acceptance length `L = max(||b||_inf, |b| of the cones)` of a
/// problem (module docs).
pub fn acceptance_length(qp: &ProjectionQp) -> f64 {
    qp.cones
        .iter()
        .fold(length_scale(&qp.b()), |l, cone| l.max(cone.b().abs()))
}

/// Length scale `l` of the residuals: `||b||_inf`, or the smallest positive
/// f64 when `b = 0` (then every residual numerator is zero at a solution).
pub fn length_scale(b: &DVector<f64>) -> f64 {
    b.amax().max(f64::MIN_POSITIVE)
}

/// What [`projection_residuals`] computes once for its measures: the
/// problem's `b` and row diagonal `a_i = J_i M^-1 J_i^T`, the candidate's
/// row values `w = J dq + b`, its multipliers projected onto their cones
/// `lambda_+`, and `v = M^-1 J^T lambda_+`.
struct CandidateTerms<'a> {
    b: &'a DVector<f64>,
    a: &'a [f64],
    w: &'a DVector<f64>,
    lambda_plus: &'a DVector<f64>,
    v: &'a DVector<f64>,
}

/// The acceptance measures of `dq` (module docs): feasibility relative to
/// `l_accept`, the relative duality gap, and its square root; with the
/// cones' terms (`super::cone_residuals`).
fn acceptance_measures(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    dq: &DVector<f64>,
    terms: &CandidateTerms,
    cones: &[ConeAtCandidate],
    l_accept: f64,
) -> (f64, f64, f64) {
    let CandidateTerms {
        b,
        a,
        w,
        lambda_plus,
        v,
    } = *terms;
    let feasibility = cones
        .iter()
        .map(ConeAtCandidate::infeasibility)
        .chain(
            w.iter()
                .enumerate()
                .map(|(i, wi)| row_violation(qp.is_equality(i), *wi)),
        )
        .fold(0.0, f64::max)
        / l_accept;
    let stationarity_gap = dq - v;
    let stationarity_energy = 0.5 * m_inner(metric, &stationarity_gap, &stationarity_gap).max(0.0);
    // Equality rows: w_E moved to 0 in the relaxed problem (module docs).
    let complementarity_energy: f64 = lambda_plus
        .iter()
        .zip(w.iter())
        .enumerate()
        .filter(|(i, _)| !qp.is_equality(*i))
        .map(|(_, (l, wi))| l * wi.max(0.0))
        .sum::<f64>()
        + cones.iter().map(ConeAtCandidate::gap).sum::<f64>();
    let gap = stationarity_energy + complementarity_energy;
    // The cost of a single violated row (or cone's normal row) alone; an
    // equality row is violated whatever the sign of b_i.
    let single_row_bound = (0..b.len())
        .filter(|&i| a[i] > 0.0)
        .map(|i| (-row_violation(qp.is_equality(i), b[i]), a[i]))
        .chain(cones.iter().map(|cone| (cone.b, cone.a)))
        .map(|(b, a)| b.min(0.0).powi(2) / (2.0 * a))
        .fold(0.0, f64::max);
    // No violated row: `dq* = 0`, and the scale is the cost of moving by
    // `L` the row with the largest `a_i` (the one that moves most easily).
    let a_max = a
        .iter()
        .copied()
        .chain(cones.iter().map(|cone| cone.a))
        .fold(0.0, f64::max);
    let floor = if single_row_bound > 0.0 || a_max == 0.0 {
        single_row_bound
    } else {
        l_accept * l_accept / (2.0 * a_max)
    };
    let energy = (0.5 * m_inner(metric, dq, dq))
        .max(floor)
        .max(f64::MIN_POSITIVE);
    let duality_gap = if gap == 0.0 { 0.0 } else { gap / energy };
    (feasibility, duality_gap, duality_gap.sqrt())
}

/// Residuals of `(dq, lambda)` for the projection QP, with the problem's
/// own acceptance length `L = max(||b||_inf, |b| of its cones)` (module
/// docs).
pub fn projection_residuals(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    dq: &DVector<f64>,
    lambda: &DVector<f64>,
) -> ProjectionResiduals {
    let b = qp.b();
    let w = &b + qp.apply_j(dq);
    let a = row_diagonal(qp, metric);
    let a_fallback = a.iter().copied().fold(0.0, f64::max);
    let cones = cones_at(qp, metric, dq, lambda, a_fallback);
    let l = acceptance_length(qp);
    let force: Vec<f64> = (0..w.len())
        .map(|i| if a[i] > 0.0 { a[i] } else { a_fallback } * lambda[i])
        .collect();
    let f = cones
        .iter()
        .map(ConeAtCandidate::force)
        .chain(force.iter().map(|x| x.abs()))
        .fold(l, f64::max);
    let mut natural_map: f64 = 0.0;
    let mut complementarity: f64 = 0.0;
    let mut primal_infeasibility: f64 = 0.0;
    for i in 0..w.len() {
        let equality = qp.is_equality(i);
        natural_map = natural_map.max(natural_map_entry(force[i], w[i], equality) / l);
        if !equality {
            complementarity = complementarity.max((force[i] * w[i]).abs() / (l * f));
        }
        primal_infeasibility = primal_infeasibility.max(row_violation(equality, w[i]) / l);
    }
    for cone in &cones {
        natural_map = natural_map.max(cone.natural_map() / l);
        complementarity = complementarity.max(cone.complementarity() / (l * f));
        primal_infeasibility = primal_infeasibility.max(cone.infeasibility() / l);
    }
    let dq_dual = m_inv(metric, &qp.apply_jt(lambda));
    let norm = m_norm(metric, dq).max(m_norm(metric, &dq_dual));
    let stationarity = if norm > 0.0 {
        m_norm(metric, &(dq - &dq_dual)) / norm
    } else {
        0.0
    };
    let displacement = m_norm(metric, dq);
    // The multipliers projected onto their cones; where nothing changes
    // (the usual case), their correction is the one just computed.
    let lambda_plus = projected_multipliers(qp, lambda);
    let v = match lambda_plus == *lambda {
        true => dq_dual,
        false => m_inv(metric, &qp.apply_jt(&lambda_plus)),
    };
    let terms = CandidateTerms {
        b: &b,
        a: &a,
        w: &w,
        lambda_plus: &lambda_plus,
        v: &v,
    };
    let (feasibility, duality_gap, optimality) =
        acceptance_measures(qp, metric, dq, &terms, &cones, l);
    ProjectionResiduals {
        feasibility,
        duality_gap,
        optimality,
        natural_map,
        complementarity,
        primal_infeasibility,
        stationarity,
        objective: 0.5 * displacement * displacement,
        displacement,
    }
}
