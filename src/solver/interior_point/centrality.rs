//! Gondzio's multiple centrality correctors for the interior point's step
//! (after Mehrotra's predictor-corrector, `super::step`): each corrector
//! is one more solve with the iteration's factor of `H`.
//!
//! With the direction `d` and its step `alpha` to the boundary, a longer
//! trial step `alpha_t = min(1, alpha + DELTA_ALPHA)` gives the
//! complementarity products `v_i = (s_i + alpha_t ds_i)(lambda_i +
//! alpha_t dlambda_i)`. The products far from the centring target
//! `sigma mu` (below `BETA_MIN sigma mu`, which block the step, or above
//! `BETA_MAX sigma mu`) are moved into that box: the corrector solves the
//! Newton system with the complementarity residual `r_c = v - t`
//! (`t` = `v` clamped to the box; the rows and stationarity residuals zero)
//! and is added to `d`. It is kept when the step to the boundary grows by
//! at least `GAMMA DELTA_ALPHA`; otherwise the correction stops. Fewer
//! iterations, each with up to [`super::InteriorPointSettings::centrality_correctors`]
//! extra solves (no extra factorization).

use nalgebra::DVector;

use super::InteriorPointFailure;
use super::step::{Direction, Iterate, StepInputs, direction, max_step};
use crate::solver::augmented_lagrangian::hessian::NewtonMatrix;

/// How much longer than the current step the trial step is.
const DELTA_ALPHA: f64 = 0.1;
/// The box of complementarity products around the centring target.
const BETA_MIN: f64 = 0.1;
const BETA_MAX: f64 = 10.0;
/// A corrector is kept when it lengthens the step by this fraction of
/// `DELTA_ALPHA`.
const GAMMA: f64 = 0.1;

/// The direction `dir` corrected by up to `count` centrality correctors
/// towards products near `target` (`sigma mu`).
#[allow(clippy::too_many_arguments)]
pub(super) fn correct(
    inputs: &StepInputs<'_>,
    newton: &mut NewtonMatrix,
    it: &Iterate,
    d: &[f64],
    mut dir: Direction,
    target: f64,
    count: usize,
) -> Result<Direction, InteriorPointFailure> {
    let moved = inputs.moved;
    let m = moved.len();
    let mut alpha = max_step(it, &dir, moved).min(1.0);
    let zero_d = DVector::zeros(inputs.qp.num_dofs());
    let zero_p = DVector::zeros(m);
    for _ in 0..count {
        if alpha >= 1.0 || target.is_nan() || target <= 0.0 {
            break;
        }
        let trial = (alpha + DELTA_ALPHA).min(1.0);
        let r_c = DVector::from_fn(m, |i, _| {
            if !moved[i] {
                return 0.0;
            }
            let v = (it.s[i] + trial * dir.s[i]) * (it.lambda[i] + trial * dir.lambda[i]);
            if v < BETA_MIN * target {
                v - BETA_MIN * target
            } else if v > BETA_MAX * target {
                (v - BETA_MAX * target).min(BETA_MAX * target)
            } else {
                0.0
            }
        });
        let corrector = direction(inputs, newton, it, d, &zero_d, &zero_p, &r_c)?;
        let candidate = Direction {
            dq: &dir.dq + &corrector.dq,
            s: &dir.s + &corrector.s,
            lambda: &dir.lambda + &corrector.lambda,
        };
        let longer = max_step(it, &candidate, moved).min(1.0);
        if longer < alpha + GAMMA * DELTA_ALPHA {
            break;
        }
        dir = candidate;
        alpha = longer;
    }
    Ok(dir)
}
