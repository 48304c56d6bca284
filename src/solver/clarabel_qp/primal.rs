//! The primal projection QP for clarabel, in metric-whitened, unit-scaled
//! variables.
//!
//! With `M_k = L_k L_k^T` per body (see `crate::solver::metric`) and
//! `y = L^T dq`, the objective is `1/2 |y|^2`. Row `i` becomes
//! `b_i + G_i y >= 0` with `G_ik = L_k^-1 J_ik^T` and `b = phi - target`.
//! Each row is divided by `g_i = |G_i|` (so `g_i^2 = A_ii`, the LCP
//! diagonal) and the variables by `s = max_i max(0, -b_i) / g_i`, the
//! distance in `y` of the most violated row from its half-space (`y = s y^`;
//! `s = max_i |b_i| / g_i` when no row is violated):
//!
//! ```text
//! minimize 1/2 |y^|^2   s.t.   -G^_i y^ + sigma_i = b_i / (g_i s),  sigma >= 0
//! ```
//!
//! with `G^_i = G_i / g_i`: `P = I`, unit rows, violations of at most one,
//! whatever the masses and lengths, and an optimal objective of at least
//! `1/2` (the cost of the most violated row alone). clarabel stops on an
//! absolute or a relative duality gap ([`ClarabelSettings::tol_gap`]); with
//! the optimum of order one both are relative to the correction. (Scaling by
//! `max_i |b_i| / g_i` instead would let a separated near contact, `b_i`
//! up to the contact margin, set the scale: on resting piles, where
//! penetrations are 1e-4 of the margin, the objective is then 1e-4 and
//! clarabel's absolute gap of 1e-8 leaves a relative gap of 2e-4 in
//! `dq^T M dq`.)
//! The KKT condition
//! `y^ = G^^T z^` maps back to `M dq = J^T lambda` with
//!
//! ```text
//! dq_k = s L_k^-T y^_k,     lambda_i = s z^_i / g_i.
//! ```
//!
//! Rows with `g_i = 0` (no body moves them) are left out, with
//! `lambda_i = 0`; the caller rejects such a row when it is violated. When
//! its [`ProjectionResiduals::acceptance`] (the measures the caller accepts
//! on) is above [`ClarabelSettings::polish_above`], the interior point is
//! polished ([`super::polish`]) and the better of the two points is
//! returned: a polish that makes the answer worse is never kept.
//!
//! Equality rows (the first [`ProjectionQp::num_equalities`]) are
//! whitened and scaled the same way and go first, in clarabel's
//! `ZeroConeT` (`sigma_i = 0`, `z^_i` free); they count in `s` whatever the
//! sign of `b_i` (`|b_i| / g_i`), and the polish keeps them always active
//! with free multipliers.
//!
//! Friction cones ([`super::cone`]) follow the rows, three entries of
//! `sigma` each in a `SecondOrderConeT(3)`, whitened and scaled the same
//! way with one common factor per cone. A row that is a cone's normal row
//! (same Jacobian, `phi` and target) is implied by the cone and left out
//! (`rows_implied_by_cones`): fewer rows, and no degenerate pair of
//! constraints active together at every sticking contact. A problem with cones is not
//! polished (the polish solves for active half-spaces); clarabel's point is
//! returned, and the caller's residual check judges it in the cone's sense.

use clarabel::algebra::CscMatrix;
use nalgebra::{DVector, Vector6};

use super::cone::{WhiteCone, blocks_norm, scaled_entries, whiten_cone, whitened_blocks};
use super::polish::{WhitenedQp, polish};
use super::{ClarabelSettings, ConeLayout, csc_from_triplets, run_with_cones};
use crate::solver::friction_cone::CONE_DIM;
use crate::solver::metric::BlockMetric;
use crate::solver::outcome::{Candidate, FailureReason};
use crate::solver::projection::ProjectionQp;
use crate::solver::residuals::{ProjectionResiduals, projection_residuals, row_violation};

/// The whitened, normalized problem: rows `G^_i` over the variables, the
/// right-hand sides, the friction cones ([`super::cone`]) and the maps back.
struct Whitened {
    /// Indices of the rows kept (`g_i > 0`).
    active: Vec<usize>,
    /// How many of the kept rows are equality rows (they come first).
    equalities: usize,
    /// Row norms `g_i` of the kept rows.
    norms: Vec<f64>,
    /// `G^_i` of the kept rows, as `(variable, value)`.
    rows: Vec<Vec<(usize, f64)>>,
    /// `b_i / (g_i s)` of the kept rows.
    rhs: Vec<f64>,
    /// The cones kept (some row moved by a body).
    cones: Vec<WhiteCone>,
    /// Variable scale `s`.
    s: f64,
}

fn whiten(qp: &ProjectionQp, metric: &[BlockMetric]) -> Whitened {
    let b = qp.b();
    let mut w = Whitened {
        active: Vec::new(),
        equalities: 0,
        norms: Vec::new(),
        rows: Vec::new(),
        rhs: Vec::new(),
        cones: Vec::new(),
        s: 0.0,
    };
    let mut any_scale: f64 = 0.0;
    let implied = rows_implied_by_cones(qp);
    for (i, row) in qp.rows.iter().enumerate() {
        if implied[i] {
            continue;
        }
        let blocks = whitened_blocks(row, metric);
        let g = blocks_norm(&blocks);
        if g > 0.0 && g.is_finite() {
            w.active.push(i);
            w.norms.push(g);
            w.rows.push(scaled_entries(&blocks, g));
            let equality = qp.is_equality(i);
            w.equalities += usize::from(equality);
            w.s = w.s.max(row_violation(equality, b[i]) / g);
            any_scale = any_scale.max(b[i].abs() / g);
        }
    }
    for (c, cone) in qp.cones.iter().enumerate() {
        if let Some(white) = whiten_cone(c, cone, metric) {
            w.s = w.s.max(-white.b / white.norm);
            any_scale = any_scale.max(white.b.abs() / white.norm);
            w.cones.push(white);
        }
    }
    if w.s <= 0.0 {
        // No violated row: the answer is `dq = 0`; any scale will do.
        w.s = any_scale;
    }
    let s = w.s;
    w.rhs = w
        .active
        .iter()
        .zip(&w.norms)
        .map(|(&i, g)| b[i] / (g * s))
        .collect();
    w
}

/// For each row, whether it is the normal row of a friction cone with the
/// same `phi` and target (an inequality): the cone `w_0 >= |(w_1, w_2)|`
/// implies `w_0 = b + J_n dq >= 0`, so the row is left out of clarabel's
/// problem (its multiplier 0; the cone's `z_0` carries the force). Cones
/// are matched to rows in order, as the projector builds them (one per
/// row with friction, in row order); a cone matching no later row leaves
/// every row in. Measured on the MuJoCo bin with `mu = 1`
/// (`benchmarks/results/engine_friction.md`): the cone problems of a call
/// solved in 122 ms instead of 274 and 112 instead of 163.
fn rows_implied_by_cones(qp: &ProjectionQp) -> Vec<bool> {
    let mut implied = vec![false; qp.num_rows()];
    let mut next = qp.num_equalities;
    for cone in &qp.cones {
        let matches = |i: usize| {
            qp.rows[i] == cone.normal && qp.phi[i] == cone.phi && qp.target[i] == cone.target
        };
        match (next..qp.num_rows()).find(|&i| matches(i)) {
            Some(i) => {
                implied[i] = true;
                next = i + 1;
            }
            None => return vec![false; qp.num_rows()],
        }
    }
    implied
}

impl Whitened {
    /// `A` and `b` of clarabel's form: the rows, then three per cone.
    fn constraints(&self, n: usize) -> (CscMatrix<f64>, Vec<f64>) {
        let cone_rows = self.cones.iter().flat_map(|cone| cone.rows.iter());
        let triplets = self
            .rows
            .iter()
            .chain(cone_rows)
            .enumerate()
            .flat_map(|(r, row)| row.iter().map(move |&(j, v)| (r, j, -v)))
            .collect();
        let mut rhs = self.rhs.clone();
        for cone in &self.cones {
            rhs.extend([cone.b / (cone.norm * self.s), 0.0, 0.0]);
        }
        (csc_from_triplets(rhs.len(), n, triplets), rhs)
    }
}

/// Solves the projection QP with clarabel (primal form).
pub fn solve(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    settings: &ClarabelSettings,
) -> Result<Candidate, FailureReason> {
    let white = whiten(qp, metric);
    let n = qp.num_dofs();
    if white.s == 0.0 || !white.s.is_finite() {
        // b = 0 on every movable row: dq = 0 and lambda = 0 solve it exactly.
        return Ok(Candidate {
            dq: DVector::zeros(n),
            lambda: DVector::zeros(qp.num_multipliers()),
            iterations: 0,
            factorizations: 0,
        });
    }
    let (a, rhs) = white.constraints(n);
    let p = CscMatrix::identity(n);
    let point = run_with_cones(
        &p,
        &vec![0.0; n],
        &a,
        &rhs,
        ConeLayout {
            zero: white.equalities,
            nonnegative: white.rows.len() - white.equalities,
            second_order: white.cones.len(),
        },
        settings,
    )
    .map_err(FailureReason::Clarabel)?;
    let raw = unscale(qp, metric, &white, &point.x, &point.z, point.iterations);
    if !white.cones.is_empty() {
        // The active-set polish knows half-spaces only; the interior
        // point's answer is checked against the cones as it is.
        return Ok(raw);
    }
    let worst = |c: &Candidate| -> f64 {
        let r: ProjectionResiduals = projection_residuals(qp, metric, &c.dq, &c.lambda);
        r.acceptance()
    };
    let raw_res = worst(&raw);
    if raw_res <= settings.polish_above {
        log::trace!("clarabel primal: residual {raw_res:.2e}, not polished");
        return Ok(raw);
    }
    let whitened = WhitenedQp {
        n,
        equalities: white.equalities,
        rows: &white.rows,
        b: &white.rhs,
    };
    let Some((y, z)) = polish(&whitened, &point.x, &point.z, &point.s) else {
        return Ok(raw);
    };
    let polished = unscale(qp, metric, &white, &y, &z, point.iterations);
    let polished_res = worst(&polished);
    log::trace!("clarabel primal: residual {raw_res:.2e}, polished {polished_res:.2e}");
    Ok(if polished_res < raw_res {
        polished
    } else {
        raw
    })
}

/// `dq_k = s L_k^-T y_k`, `lambda_i = s z_i / g_i`.
fn unscale(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    white: &Whitened,
    y: &[f64],
    z: &[f64],
    iterations: usize,
) -> Candidate {
    let mut dq = DVector::zeros(qp.num_dofs());
    for (k, body) in metric.iter().enumerate() {
        let y_k = Vector6::from_iterator(y[6 * k..6 * k + 6].iter().copied());
        dq.fixed_rows_mut::<6>(6 * k)
            .copy_from(&(body.solve_lt(&y_k) * white.s));
    }
    let mut lambda = DVector::zeros(qp.num_multipliers());
    for (r, &i) in white.active.iter().enumerate() {
        lambda[i] = white.s * z[r] / white.norms[r];
    }
    let (rows, cone_z) = z.split_at(white.rows.len());
    for (cone, z) in white.cones.iter().zip(cone_z.chunks_exact(CONE_DIM)) {
        let start = qp.num_rows() + CONE_DIM * cone.index;
        for (j, z_j) in z.iter().enumerate() {
            lambda[start + j] = white.s * z_j / cone.norm;
        }
    }
    debug_assert_eq!(rows.len(), white.active.len());
    Candidate {
        dq,
        lambda,
        iterations,
        factorizations: 0,
    }
}
