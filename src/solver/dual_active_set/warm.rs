//! The dual active-set method's warm start: the rows whose multipliers
//! were positive in the answer of a neighbouring problem (the last pass's
//! or the last call's, `crate::stabilizer`'s solver warm starts) as the
//! first active set.
//!
//! The rows `W` with a warm multiplier that matters
//! ([`WARM_ACTIVE_SHARE`]), largest share first, enter `A` as in a full
//! step: row `p` appends `[y^T, sqrt(delta)]` to `L` (`y = L^-1 N_A^T
//! M^-1 a_p`, `delta = w_pp - |y|^2`), and a row whose part outside the
//! span of `N_A` is at most [`super::DEPENDENT_REL`] of its length is left
//! out, so the active rows stay independent. The minimizer of `1/2 dq^T M
//! dq` with the rows of `A` held as equalities (`a_i^T dq + b_i = 0`) is
//!
//! ```text
//! dq = M^-1 N_A u,    W_A u = -b_A    (L y = -b_A, L^T u = y)
//! ```
//!
//! Goldfarb and Idnani's iteration needs `u >= 0` (dual feasibility):
//! while a multiplier is negative, the rows of the negative ones leave
//! `A` (their rows of `L` removed as in a drop) and `u` is solved again.
//! What is left is an iterate of the method (the minimizer over its
//! active set, with multipliers `u >= 0`), so the steps continue from it
//! to the same minimizer: the dual value of any dual-feasible point is at
//! most the optimum's, and every step raises it. When the warm start
//! already satisfies every row, the method returns it with no step.
//!
//! **When.** Between two calls on an engine's consecutive states the
//! rows press as they did; between the passes of one call they do not:
//! a later pass corrects the linearization's error, and the rows its
//! first pass held tight hold or pull about as often as they push. On
//! the engine states the second passes' warm sets were mostly dropped
//! again (the pyramids: 130 of 170 rows), so that the warm start made
//! whole calls 6-14 % more instructions than cold starts. A warm set
//! whose rows are at most half violated at `dq = 0` (`b_i < 0`) is
//! therefore not taken (`start` returns `None`): every such set that was
//! dropped above was one, and the calls then cost 0.94-1.005x the
//! instructions of cold starts (callgrind, one thread, `probes friction
//! FILE 0` on seven engine states; 0.87x on the Rapier heavy stack with
//! friction). The caller also starts cold when more rows were dropped
//! than kept.
//!
//! **Cost.** Building `L` from `|W|` rows costs about `|W|^3 / 3`
//! (the triangular solves of the appends) and one measure of every row
//! (`12 m`), where a cold start pays the same appends plus a measure of
//! every row and a search for the most violated one per step, and the
//! drops and re-adds of rows that a cold order picks up too early.

use std::time::Instant;

use nalgebra::DVector;

use super::DEPENDENT_REL;
use super::factor::ActiveFactor;
use super::packed_row::PackedRow;

/// A warm multiplier counts when its row's share of `|dq|_M`, `lambda_i
/// |a_i|_{M^-1}`, exceeds this fraction of the largest: an interior
/// point's answer holds every row at a positive multiplier, its inactive
/// ones at rounding level, and those must not enter. A row left out
/// that belongs to the answer is added by a step.
pub const WARM_ACTIVE_SHARE: f64 = 1e-6;

/// The warm start's active set and multipliers (module docs).
pub(super) struct WarmStart {
    /// The active rows, in the factor's order.
    pub active: Vec<usize>,
    /// Their multipliers, all `>= 0`.
    pub u: Vec<f64>,
    /// Rows dropped for a negative multiplier.
    pub drops: usize,
}

/// Builds `factor` (empty on entry) on the rows of `warm` with a
/// multiplier that matters and returns the dual-feasible active set, or
/// `None`, with the factor empty, when at most half of those rows are
/// violated at `dq = 0` (module docs) or when `deadline` passes while the
/// factor is built (the caller then starts cold, and its steps stop at
/// the deadline).
/// `diagonal` holds `w_ii = a_i^T M^-1 a_i`; a row no body moves
/// (`w_ii = 0`) never enters.
pub(super) fn start(
    warm: &DVector<f64>,
    rows: &[PackedRow],
    scaled: &[PackedRow],
    diagonal: &[f64],
    b: &DVector<f64>,
    factor: &mut ActiveFactor,
    deadline: Option<Instant>,
) -> Option<WarmStart> {
    // Each row's share of `|dq|_M`: `lambda_i |a_i|_{M^-1}`.
    let share = |i: usize| warm[i] * diagonal[i].sqrt();
    let largest = (0..rows.len()).map(share).fold(0.0, f64::max);
    let mut candidates: Vec<usize> = (0..rows.len())
        .filter(|&i| diagonal[i] > 0.0 && share(i) > WARM_ACTIVE_SHARE * largest)
        .collect();
    candidates.sort_by(|&i, &j| share(j).total_cmp(&share(i)));
    // Mostly rows that hold at `dq = 0`: a later pass's correction (module
    // docs), left to a cold start.
    let violated = candidates.iter().filter(|&&i| b[i] < 0.0).count();
    if 2 * violated <= candidates.len() {
        return None;
    }
    let mut active: Vec<usize> = Vec::with_capacity(candidates.len().min(factor.capacity));
    let mut column = Vec::with_capacity(factor.capacity);
    let mut y = Vec::with_capacity(factor.capacity);
    for p in candidates {
        if active.len() == factor.capacity {
            break;
        }
        if deadline.is_some_and(|d| Instant::now() >= d) {
            *factor = ActiveFactor::new(factor.capacity);
            return None;
        }
        column.clear();
        column.extend(active.iter().map(|&j| rows[j].dot_packed(&scaled[p])));
        factor.solve_lower_into(&column, &mut y);
        let delta = diagonal[p] - y.iter().map(|x| x * x).sum::<f64>();
        if delta > DEPENDENT_REL * DEPENDENT_REL * diagonal[p] {
            factor.append(&y, delta.sqrt());
            active.push(p);
        }
    }
    let mut drops = 0;
    loop {
        let minus_b: Vec<f64> = active.iter().map(|&j| -b[j]).collect();
        let u = factor.solve_upper(&factor.solve_lower(&minus_b));
        let negative: Vec<usize> = (0..u.len()).filter(|&k| u[k] < 0.0).collect();
        if negative.is_empty() {
            return Some(WarmStart { active, u, drops });
        }
        // Last first, so that the positions before stay valid.
        for &k in negative.iter().rev() {
            factor.remove(k, active.len());
            active.remove(k);
        }
        drops += negative.len();
    }
}
