//! One predictor-corrector step of the interior-point method (module docs
//! of [`super`]): the affine direction, Mehrotra's centring parameter
//! `sigma = (mu_aff / mu)^3`, the corrected direction with the same factor,
//! and the step to [`super::InteriorPointSettings::step_fraction`] of the
//! boundary.

use nalgebra::DVector;

use super::InteriorPointFailure;
use crate::solver::augmented_lagrangian::hessian::NewtonMatrix;
use crate::solver::metric::BlockMetric;
use crate::solver::packed_rows::PackedRows;
use crate::solver::projection::ProjectionQp;
use crate::solver::residuals::m_apply;

/// The iterate: correction, slacks and multipliers.
pub(super) struct Iterate {
    pub dq: DVector<f64>,
    pub s: DVector<f64>,
    pub lambda: DVector<f64>,
    /// `J^T lambda` of the current multipliers once computed (by the
    /// Farkas radius after a step), so that the next step's stationarity
    /// residual does not form it again; `None` after `lambda` changes.
    pub jt_lambda: Option<DVector<f64>>,
}

impl Iterate {
    /// `J^T lambda` of the current multipliers, formed once.
    pub(super) fn jt_lambda(&mut self, inputs: &StepInputs<'_>) -> &DVector<f64> {
        self.jt_lambda
            .get_or_insert_with(|| inputs.apply_jt(&self.lambda))
    }
}

/// The fixed data of a step.
pub(super) struct StepInputs<'a> {
    pub qp: &'a ProjectionQp,
    pub metric: &'a [BlockMetric],
    pub b: &'a DVector<f64>,
    /// Rows some body moves (the others keep `lambda = 0` and no weight).
    pub moved: &'a [bool],
    /// `a_i = J_i M^-1 J_i^T`.
    pub a: &'a [f64],
    /// The rows packed (`None`: a row over more than two bodies; the
    /// general path then).
    pub packed: Option<&'a PackedRows>,
}

impl StepInputs<'_> {
    /// `J v`.
    fn apply_j(&self, v: &DVector<f64>) -> DVector<f64> {
        match self.packed {
            Some(packed) => packed.apply_j(v),
            None => self.qp.apply_j(v),
        }
    }

    /// `J^T v`.
    pub(super) fn apply_jt(&self, v: &DVector<f64>) -> DVector<f64> {
        match self.packed {
            Some(packed) => packed.apply_jt(v),
            None => self.qp.apply_jt(v),
        }
    }

    /// Factors `H = M + J^T D J` (`d` zero on the rows no body moves).
    fn factor(&self, newton: &mut NewtonMatrix, d: &[f64]) -> Result<(), ()> {
        match self.packed {
            Some(packed) => newton.factor_packed(packed, self.metric, d),
            None => newton.factor(self.qp, self.metric, d, self.moved),
        }
        .map_err(|_| ())
    }
}

/// When the factorization of `H` fails (rounding: `D` spans more than the
/// precision near the end of the iteration, or at extreme mass ratios),
/// it is retried with every `D_i` at most this over `a_i`, the weight at
/// which row `i` dominates `H` by `1e12` in its own direction. The step
/// is then an inexact Newton step (the residuals are recomputed exactly
/// at the next iterate, so the iteration corrects it).
const CLAMPED_WEIGHT: f64 = 1e12;

/// A direction `(ddq, ds, dlambda)`.
pub(super) struct Direction {
    pub dq: DVector<f64>,
    pub s: DVector<f64>,
    pub lambda: DVector<f64>,
}

/// What one step did: the complementarity gap `sum_i s_i lambda_i` after
/// it, and whether `H` had to be factored with clamped weights (the
/// iteration is then at the rounding floor of its weights).
#[derive(Debug, Clone, Copy)]
pub(super) struct StepTaken {
    pub gap: f64,
    pub clamped: bool,
}

/// Takes one step; `newton` is refactored with the iterate's `D`.
pub(super) fn newton_step(
    inputs: &StepInputs<'_>,
    newton: &mut NewtonMatrix,
    it: &mut Iterate,
    step_fraction: f64,
    correctors: usize,
) -> Result<StepTaken, InteriorPointFailure> {
    let (qp, moved) = (inputs.qp, inputs.moved);
    let m = qp.num_rows();
    let active_rows = moved.iter().filter(|&&x| x).count().max(1);
    let r_d = m_apply(inputs.metric, &it.dq) - it.jt_lambda(inputs);
    let r_p = inputs.apply_j(&it.dq) + inputs.b - &it.s;
    let mu = (0..m)
        .filter(|&i| moved[i])
        .map(|i| it.s[i] * it.lambda[i])
        .sum::<f64>()
        / active_rows as f64;
    let d: Vec<f64> = (0..m)
        .map(|i| {
            if moved[i] {
                it.lambda[i] / it.s[i]
            } else {
                0.0
            }
        })
        .collect();
    let clamped = inputs.factor(newton, &d).is_err();
    if clamped {
        let clamped: Vec<f64> = d
            .iter()
            .zip(inputs.a)
            .map(|(&x, &a)| {
                if a > 0.0 {
                    x.min(CLAMPED_WEIGHT / a)
                } else {
                    x
                }
            })
            .collect();
        log::trace!("interior point: factorization failed, retried with clamped weights");
        inputs
            .factor(newton, &clamped)
            .map_err(|_| InteriorPointFailure::Factorization)?;
    }
    // Predictor: r_c = S lambda.
    let r_c_aff = DVector::from_fn(m, |i, _| it.s[i] * it.lambda[i]);
    let affine = direction(inputs, newton, it, &d, &r_d, &r_p, &r_c_aff)?;
    let alpha_aff = max_step(it, &affine, moved).min(1.0);
    let mu_aff = (0..m)
        .filter(|&i| moved[i])
        .map(|i| {
            (it.s[i] + alpha_aff * affine.s[i]) * (it.lambda[i] + alpha_aff * affine.lambda[i])
        })
        .sum::<f64>()
        / active_rows as f64;
    let sigma = (mu_aff / mu).clamp(0.0, 1.0).powi(3);
    // Corrector: r_c = S lambda + ds_aff dlambda_aff - sigma mu.
    let r_c = DVector::from_fn(m, |i, _| {
        if moved[i] {
            it.s[i] * it.lambda[i] + affine.s[i] * affine.lambda[i] - sigma * mu
        } else {
            0.0
        }
    });
    let step = direction(inputs, newton, it, &d, &r_d, &r_p, &r_c)?;
    let step = if correctors > 0 {
        super::centrality::correct(inputs, newton, it, &d, step, sigma * mu, correctors)?
    } else {
        step
    };
    let alpha = (step_fraction * max_step(it, &step, moved)).min(1.0);
    log::trace!(
        "interior point: mu {mu:.3e}, affine step {alpha_aff:.3}, sigma {sigma:.2e}, step {alpha:.3}"
    );
    it.dq.axpy(alpha, &step.dq, 1.0);
    it.s.axpy(alpha, &step.s, 1.0);
    it.lambda.axpy(alpha, &step.lambda, 1.0);
    it.jt_lambda = None;
    let finite = it
        .dq
        .iter()
        .chain(&it.s)
        .chain(&it.lambda)
        .all(|x| x.is_finite());
    if !finite {
        // The iterates diverged (an infeasible problem).
        return Err(InteriorPointFailure::NotConverged);
    }
    let gap = (0..m)
        .filter(|&i| moved[i])
        .map(|i| it.s[i] * it.lambda[i])
        .sum();
    Ok(StepTaken { gap, clamped })
}

/// The direction for the complementarity residual `r_c` (module docs of
/// [`super`]).
pub(super) fn direction(
    inputs: &StepInputs<'_>,
    newton: &mut NewtonMatrix,
    it: &Iterate,
    d: &[f64],
    r_d: &DVector<f64>,
    r_p: &DVector<f64>,
    r_c: &DVector<f64>,
) -> Result<Direction, InteriorPointFailure> {
    let qp = inputs.qp;
    let m = qp.num_rows();
    let moved = inputs.moved;
    // S^-1 r_c + D r_p
    let weighted = DVector::from_fn(m, |i, _| {
        if moved[i] {
            r_c[i] / it.s[i] + d[i] * r_p[i]
        } else {
            0.0
        }
    });
    let rhs = -(r_d + inputs.apply_jt(&weighted));
    let ddq = newton
        .solve(&rhs)
        .ok_or(InteriorPointFailure::Factorization)?;
    let ds = inputs.apply_j(&ddq) + r_p;
    let dlambda = DVector::from_fn(m, |i, _| {
        if moved[i] {
            -(r_c[i] + it.lambda[i] * ds[i]) / it.s[i]
        } else {
            0.0
        }
    });
    Ok(Direction {
        dq: ddq,
        s: ds,
        lambda: dlambda,
    })
}

/// The largest `alpha` with `s + alpha ds >= 0` and
/// `lambda + alpha dlambda >= 0` on the moved rows (infinite when no
/// entry decreases): the least ratio `x_i / -dx_i` over the decreasing
/// entries. A ratio is divided out only when it beats the least so far
/// (`x_i < alpha (-dx_i)`, which holds for every decreasing entry while
/// `alpha` is infinite), so most rows cost a product, not a division.
pub(super) fn max_step(it: &Iterate, dir: &Direction, moved: &[bool]) -> f64 {
    let mut alpha = f64::INFINITY;
    let mut limit = |x: f64, dx: f64| {
        if dx < 0.0 && x < alpha * -dx {
            alpha = x / -dx;
        }
    };
    for i in (0..moved.len()).filter(|&i| moved[i]) {
        limit(it.s[i], dir.s[i]);
        limit(it.lambda[i], dir.lambda[i]);
    }
    alpha
}
