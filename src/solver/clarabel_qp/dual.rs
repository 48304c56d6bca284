//! The LCP as a dual QP for clarabel:
//!
//! ```text
//! minimize 1/2 z^T A z + b^T z   s.t.   z >= 0
//! ```
//!
//! whose KKT conditions are exactly the LCP `z >= 0, w = A z + b >= 0,
//! z^T w = 0` when `A` is symmetric positive semidefinite (`w` is the
//! multiplier of `z >= 0`). clarabel form: `P = triu(A~)`, `c = b~`,
//! `-z~ + s = 0`, `s >= 0`, on the Jacobi-scaled problem of
//! `crate::solver::scaling` (unit diagonal, `||b~||_inf = 1`). `P` is
//! dense: `n (n + 1) / 2` entries.
//!
//! A mixed LCP (`crate::solver::lcp`, the dual of a projection with
//! equality rows) has free leading variables `z_E`: they get no cone row,
//! so the KKT conditions are `w_E = 0` (`z_E` free) and the LCP on the
//! rest. With inconsistent equalities (`b_E` outside the range of `A_EE`)
//! the objective is unbounded below along the null space of `A_EE`, which
//! clarabel reports as dual infeasible.
//!
//! The interior point is polished as in [`super::polish`], densely: with the
//! active set `S = {i : z~_i > w~_i}`, solve `M~_SS z~_S = -q~_S` by
//! iterative refinement on `M~_SS + delta I` (a proximal iteration that
//! stays near the interior point's `z~_S` when `M~_SS` is singular); the
//! free variables are always in `S` and never clamped. The polished point
//! is kept when its natural map is smaller.

use nalgebra::{DMatrix, DVector};

use super::polish::{
    POLISH_ACTIVE_SET_BAND, POLISH_DELTA, POLISH_MAX_ACTIVE_SET_UPDATES, POLISH_MAX_REFINE,
    POLISH_REFINE_TOL,
};
use super::{ClarabelPoint, ClarabelSettings, csc_from_triplets, run};
use crate::solver::lcp::Lcp;
use crate::solver::outcome::FailureReason;
use crate::solver::residuals::{natural_map_abs, natural_map_relative};
use crate::solver::scaling::LcpScaling;

/// A solution of the LCP from clarabel on its dual QP.
#[derive(Debug, Clone, PartialEq)]
pub struct DualSolution {
    /// `z` (`z_I >= 0`; the free `z_E` of a mixed LCP of either sign).
    pub z: DVector<f64>,
    /// `w = M z + q`, recomputed from `z` on the original data.
    pub w: DVector<f64>,
    /// Interior-point iterations.
    pub iterations: usize,
}

/// Largest natural map, relative to the data
/// ([`natural_map_relative`]), of a solution [`solve_lcp`] returns.
/// The projection path checks its answers itself (`solver::residuals`);
/// a general LCP needs this check, since clarabel can report as solved a
/// point that is not a solution (the kept fuzz input
/// `tests/data/fuzz/lcp_solvers/crash-clarabel-dual`;
/// `benchmarks/results/fuzzing.md`).
pub const TOL_NATURAL_MAP_RELATIVE: f64 = 1e-6;

/// Solves a symmetric positive semidefinite LCP with clarabel. Fails with
/// [`FailureReason::NotApplicable`] when `M` is not symmetric PSD, and with
/// [`FailureReason::ResidualTooLarge`] when the answer's natural map is
/// above [`TOL_NATURAL_MAP_RELATIVE`].
pub fn solve_lcp(lcp: &Lcp, settings: &ClarabelSettings) -> Result<DualSolution, FailureReason> {
    if !lcp.is_symmetric_psd() {
        return Err(FailureReason::NotApplicable);
    }
    let solution = solve_lcp_unchecked(lcp, settings)?;
    let residual = natural_map_relative(lcp.m(), lcp.q(), &solution.z, lcp.free());
    if residual > TOL_NATURAL_MAP_RELATIVE {
        return Err(FailureReason::ResidualTooLarge {
            residual,
            tolerance: TOL_NATURAL_MAP_RELATIVE,
        });
    }
    Ok(solution)
}

/// As [`solve_lcp`], for a matrix known to be symmetric PSD by construction
/// (`J M^-1 J^T`): skips the eigenvalue check.
pub fn solve_lcp_unchecked(
    lcp: &Lcp,
    settings: &ClarabelSettings,
) -> Result<DualSolution, FailureReason> {
    let n = lcp.n();
    let free = lcp.free();
    let zero_solves = lcp
        .q()
        .iter()
        .enumerate()
        .all(|(i, &x)| if i < free { x == 0.0 } else { x >= 0.0 });
    if zero_solves {
        return Ok(DualSolution {
            z: DVector::zeros(n),
            w: lcp.q().clone(),
            iterations: 0,
        });
    }
    let scaling = LcpScaling::jacobi(lcp.m(), lcp.q());
    let m = scaling.scale_m(lcp.m());
    let q = scaling.scale_q(lcp.q());
    let mut p_triplets = Vec::with_capacity(n * (n + 1) / 2);
    for j in 0..n {
        for i in 0..=j {
            // Symmetrize: the average of the two triangles.
            p_triplets.push((i, j, 0.5 * (m[(i, j)] + m[(j, i)])));
        }
    }
    let p = csc_from_triplets(n, n, p_triplets);
    // `-z_i + s = 0, s >= 0` for the complementary variables only.
    let bounded = n - free;
    let a = csc_from_triplets(
        bounded,
        n,
        (0..bounded).map(|r| (r, free + r, -1.0)).collect(),
    );
    let point: ClarabelPoint = run(&p, q.as_slice(), &a, &vec![0.0; bounded], settings)
        .map_err(FailureReason::Clarabel)?;
    let raw = clamp_bounded(DVector::from_vec(point.x), free);
    let residual = |z: &DVector<f64>| natural_map_abs(z, &(&m * z + &q), free);
    let raw_residual = residual(&raw);
    let z_scaled = match polish_dense(&m, &q, &raw, free) {
        Some(p) if residual(&p) < raw_residual => p,
        _ => raw,
    };
    let z = scaling.unscale_z(&z_scaled);
    let w = lcp.w(&z);
    Ok(DualSolution {
        z,
        w,
        iterations: point.iterations,
    })
}

/// `z` with its complementary entries (after the first `free`) clamped at 0.
fn clamp_bounded(mut z: DVector<f64>, free: usize) -> DVector<f64> {
    z.iter_mut().skip(free).for_each(|v| *v = v.max(0.0));
    z
}

/// Dense active-set polish of `z` for the scaled LCP `(m, q)` whose first
/// `free` variables are free (always active), with the primal-dual
/// active-set corrections of [`super::polish`].
fn polish_dense(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    z: &DVector<f64>,
    free: usize,
) -> Option<DVector<f64>> {
    let w = m * z + q;
    let mut active: Vec<usize> = (0..z.len()).filter(|&i| i < free || z[i] > w[i]).collect();
    let mut z = z.clone();
    for _ in 0..=POLISH_MAX_ACTIVE_SET_UPDATES {
        z = solve_active_dense(m, q, &active, &z)?;
        let w = m * &z + q;
        let next: Vec<usize> = (0..z.len())
            .filter(|&i| {
                if i < free {
                    true
                } else if active.contains(&i) {
                    z[i] >= -POLISH_ACTIVE_SET_BAND
                } else {
                    w[i] < -POLISH_ACTIVE_SET_BAND
                }
            })
            .collect();
        if next == active {
            break;
        }
        active = next;
    }
    Some(clamp_bounded(z, free))
}

/// `M_SS z_S = -q_S` by refinement on `M_SS + delta I` from `z`; zero
/// outside `S`, unclamped.
fn solve_active_dense(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    active: &[usize],
    z: &DVector<f64>,
) -> Option<DVector<f64>> {
    let k = active.len();
    if k == 0 {
        return Some(DVector::zeros(z.len()));
    }
    let m_ss = DMatrix::from_fn(k, k, |a, b| m[(active[a], active[b])]);
    let q_s = DVector::from_fn(k, |a, _| q[active[a]]);
    let chol = (&m_ss + DMatrix::identity(k, k) * POLISH_DELTA).cholesky()?;
    let mut z_s = DVector::from_fn(k, |a, _| z[active[a]]);
    for _ in 0..POLISH_MAX_REFINE {
        let r = -&q_s - &m_ss * &z_s;
        if r.amax() <= POLISH_REFINE_TOL {
            break;
        }
        z_s += chol.solve(&r);
    }
    let mut out = DVector::zeros(z.len());
    for (a, &i) in active.iter().enumerate() {
        out[i] = z_s[a];
    }
    out.iter().all(|v| v.is_finite()).then_some(out)
}
