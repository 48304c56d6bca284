//! Active-set polishing of an interior-point solution (as in OSQP;
//! Stellato et al. 2020, section 4).
//!
//! An interior point stops with `z_i s_i ~ mu > 0` on every row. Where a row
//! is degenerate (`z_i = s_i = 0` at the solution: a contact exactly at its
//! target that nothing pushes) both only reach `~sqrt(mu)`, which is far
//! from the natural-map tolerance. Polishing guesses the active set
//! `S = {i : z_i > s_i}` and solves the equality-constrained problem
//!
//! ```text
//! [ I    G_S^T ] [ y  ]   [   0   ]
//! [ G_S  0     ] [ -z ] = [ -b_S  ]        (P = I in the whitened variables)
//! ```
//!
//! by iterative refinement with the quasi-definite regularization
//! `-delta I` in the lower block (factored once with QDLDL). Redundant rows
//! make the system singular; the refinement is then a proximal iteration
//! that keeps `z_S` near the interior point's (positive) multipliers.
//!
//! Equality rows (the first [`WhitenedQp::equalities`]) are always in `S`
//! and their multipliers are never clamped.
//!
//! A loose interior point can misjudge a row or two. The guess is then
//! corrected by primal-dual active-set steps (Hintermueller, Ito and
//! Kunisch 2002): drop the rows of `S` whose multiplier came out negative,
//! add the rows outside `S` that the polished `y` violates, solve again;
//! at most [`POLISH_MAX_ACTIVE_SET_UPDATES`] times, with a dead band of
//! [`POLISH_ACTIVE_SET_BAND`] so that rounding on degenerate rows cannot
//! make it cycle. The caller keeps the polished point only if its
//! residuals are better.

use clarabel::qdldl::{QDLDLFactorisation, QDLDLSettings};

use super::csc_from_triplets;

/// Regularization `delta` of the lower block, relative to the unit-scaled
/// problem.
pub const POLISH_DELTA: f64 = 1e-9;
/// Refinement steps at most.
pub const POLISH_MAX_REFINE: usize = 30;
/// Stop refining when the KKT residual is below this (unit-scaled data).
pub const POLISH_REFINE_TOL: f64 = 1e-15;

/// Active-set corrections after the first polish, at most.
pub const POLISH_MAX_ACTIVE_SET_UPDATES: usize = 5;
/// A multiplier below `-band` leaves the active set, a row value below
/// `-band` joins it (unit-scaled data).
pub const POLISH_ACTIVE_SET_BAND: f64 = 1e-13;

/// A unit-scaled QP `min 1/2 |y|^2, G y + b >= 0` with sparse rows, the
/// first `equalities` of them `G y + b = 0`.
pub struct WhitenedQp<'a> {
    /// Number of variables.
    pub n: usize,
    /// The first `equalities` rows are equalities.
    pub equalities: usize,
    /// Rows `G_i` as `(variable, value)` lists.
    pub rows: &'a [Vec<(usize, f64)>],
    /// `b`.
    pub b: &'a [f64],
}

/// Polished `(y, z)`, or `None` when a factorization fails.
pub fn polish(
    qp: &WhitenedQp,
    y: &[f64],
    z: &[f64],
    slack: &[f64],
) -> Option<(Vec<f64>, Vec<f64>)> {
    let mut active: Vec<usize> = (0..qp.rows.len())
        .filter(|&i| i < qp.equalities || z[i] > slack[i])
        .collect();
    let (mut y, mut z) = (y.to_vec(), z.to_vec());
    for _ in 0..=POLISH_MAX_ACTIVE_SET_UPDATES {
        (y, z) = solve_active(qp, &active, &y, &z)?;
        let next = corrected_active_set(qp, &active, &y, &z);
        if next == active {
            break;
        }
        active = next;
    }
    z.iter_mut()
        .skip(qp.equalities)
        .for_each(|v| *v = v.max(0.0));
    Some((y, z))
}

/// `S` without its negative multipliers, with the violated rows outside it.
fn corrected_active_set(qp: &WhitenedQp, active: &[usize], y: &[f64], z: &[f64]) -> Vec<usize> {
    let mut in_set = vec![false; qp.rows.len()];
    active.iter().for_each(|&i| in_set[i] = true);
    (0..qp.rows.len())
        .filter(|&i| {
            if i < qp.equalities {
                true
            } else if in_set[i] {
                z[i] >= -POLISH_ACTIVE_SET_BAND
            } else {
                let value: f64 = qp.b[i] + qp.rows[i].iter().map(|&(j, v)| v * y[j]).sum::<f64>();
                value < -POLISH_ACTIVE_SET_BAND
            }
        })
        .collect()
}

/// Solves the KKT system of the active set by refinement from `(y, z)`;
/// returns `y` and the (unclamped) multipliers, zero outside `active`.
fn solve_active(
    qp: &WhitenedQp,
    active: &[usize],
    y: &[f64],
    z: &[f64],
) -> Option<(Vec<f64>, Vec<f64>)> {
    let (n, m) = (qp.n, active.len());
    let mut triplets: Vec<(usize, usize, f64)> = (0..n).map(|j| (j, j, 1.0)).collect();
    for (r, &i) in active.iter().enumerate() {
        triplets.extend(qp.rows[i].iter().map(|&(j, v)| (j, n + r, v)));
        triplets.push((n + r, n + r, -POLISH_DELTA));
    }
    let kkt = csc_from_triplets(n + m, n + m, triplets);
    let signs: Vec<i8> = (0..n + m).map(|k| if k < n { 1 } else { -1 }).collect();
    let settings = QDLDLSettings {
        Dsigns: Some(signs),
        ..QDLDLSettings::default()
    };
    let mut factors = QDLDLFactorisation::new(&kkt, Some(settings)).ok()?;
    // x = [y; -z_S]
    let mut x: Vec<f64> = y.to_vec();
    x.extend(active.iter().map(|&i| -z[i]));
    for _ in 0..POLISH_MAX_REFINE {
        let mut r = kkt_residual(qp, active, &x);
        if r.iter().fold(0.0_f64, |a, v| a.max(v.abs())) <= POLISH_REFINE_TOL {
            break;
        }
        factors.solve(&mut r);
        x.iter_mut().zip(&r).for_each(|(xi, di)| *xi += di);
    }
    if !x.iter().all(|v| v.is_finite()) {
        return None;
    }
    let mut z_out = vec![0.0; qp.rows.len()];
    for (r, &i) in active.iter().enumerate() {
        z_out[i] = -x[n + r];
    }
    x.truncate(n);
    Some((x, z_out))
}

/// `rhs - K x` for the unregularized KKT system.
fn kkt_residual(qp: &WhitenedQp, active: &[usize], x: &[f64]) -> Vec<f64> {
    let n = qp.n;
    let mut r = vec![0.0; n + active.len()];
    for j in 0..n {
        r[j] = -x[j];
    }
    for (k, &i) in active.iter().enumerate() {
        let zi = x[n + k];
        let mut gy = 0.0;
        for &(j, v) in &qp.rows[i] {
            r[j] -= v * zi;
            gy += v * x[j];
        }
        r[n + k] = -qp.b[i] - gy;
    }
    r
}
