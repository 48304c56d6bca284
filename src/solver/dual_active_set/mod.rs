//! The dual active-set method of Goldfarb and Idnani ("A numerically
//! stable dual method for solving strictly convex quadratic programs",
//! Math. Programming 27, 1983) for the projection QP of a small island,
//! in the range space of the active rows.
//!
//! The problem is `minimize 1/2 dq^T M dq` subject to `s_i = a_i^T dq + b_i
//! >= 0` (`a_i = J_i^T`, `b = phi - target`, inequality rows only). The
//! method starts at the unconstrained minimum `dq = 0` and adds violated
//! rows one at a time, keeping every iterate the minimizer over its
//! active set `A` (rows held as equalities) with multipliers `u >= 0`: it
//! is dual feasible throughout and primal feasible at the end, where it is
//! the answer. Its state is the lower Cholesky factor `L` of the active
//! rows' Delassus matrix `W_A = N_A^T M^-1 N_A` (`N_A` the active rows'
//! gradients; `L L^T = W_A`).
//!
//! **One step** toward a violated row `p` (`s_p < 0`), with `w = N_A^T M^-1
//! a_p` (nonzero only for active rows that share a body with `p`):
//!
//! ```text
//! y = L^-1 w,  r = L^-T y    (a_p's part in span(N_A): u <- u - t r, u_p <- u_p + t)
//! delta = w_pp - |y|^2       (|a_p|^2 outside that span, in M^-1)
//! z = M^-1 (a_p - N_A r)     (the primal direction: a_p^T z = delta, N_A^T z = 0)
//! t_full = -s_p / delta                         (row p becomes tight)
//! t_part = min over r_j > 0 of u_j / r_j        (multiplier j reaches 0)
//! ```
//!
//! With `t = min(t_full, t_part)`, `dq <- dq + t z`. A full step adds `p`
//! to `A` (`L` gains the row `[y^T, sqrt(delta)]`); a partial step drops
//! the row whose multiplier reached zero (its row of `L` removed, the
//! rows below it moved up and rotations of neighbouring columns, `L <- L
//! G`, restore the triangle) and steps toward `p` again. When `a_p` is a
//! combination of the active rows (`delta <= DEPENDENT_REL^2 w_pp`,
//! [`DEPENDENT_REL`]) the step is partial (`t = t_part`), and a row is
//! dropped: redundant contact rows (four corners on a face) are handled
//! so, the active rows always independent. `dq` still moves by `t z`, the
//! part of `a_p` outside their span (at rounding, or at most
//! `DEPENDENT_REL` of it), so that `M dq = N_A u + u_p a_p` holds in every
//! step: without it the multipliers drift from `dq`'s by that part (a
//! stationarity of 2e-4 was seen after a warm start on a friction
//! pyramid). The multipliers returned are those of the final `dq` on the
//! final active set, `W_A u = N_A^T dq` (two triangular solves). When, in addition, no
//! `r_j` is positive, no step exists: `a_p` is a non-positive combination
//! of tight rows, which certifies that the rows cannot all hold; that is
//! reported as [`DualActiveSetFailure::Infeasible`] and left to the solvers
//! that certify with a tolerance of their own
//! ([`crate::solver::FailureReason::certifies_infeasibility`] does not take
//! it).
//!
//! **Cost.** `M` is block diagonal, so `M^-1 a_i` has a row's twelve
//! entries and `w` costs a 6-product per shared body. A step costs
//! `O(q^2)` for the two triangular solves (`q = |A|`), `12 q` for `z`,
//! `12 m` to measure the inactive rows after a step, `O(q (q - k))`
//! to drop row `k`; the number of steps is about the size of the final
//! active set plus the drops. This is Goldfarb and Idnani's step in the
//! range space: their null-space form keeps `L^-T Q` (`n x n`), whose
//! column rotations cost `O(n (n - q))` a step, and measures dependence
//! without a difference of squares; here dependence is judged on `delta`,
//! whose rounding grows with the condition of `W_A`, so [`DEPENDENT_REL`]
//! sits far above the precision (every answer passes the same acceptance
//! test in `dq` as every solver's). Dense in `q`: for islands of a few
//! bodies with many rows (a stack with its friction pyramids, 100-250
//! rows on 30-42 entries of `dq`), where the interior point's 16-20
//! factorizations cost more (`benchmarks/results/solvers.md`).
//!
//! **Warm start** (`warm`): the rows whose multipliers mattered in a
//! neighbouring problem's answer (the last pass's or call's) are the first
//! active set, made dual feasible; the steps continue from there. It is
//! taken when more than half of those rows are violated at `dq = 0` and
//! no more of them left it for a negative multiplier than stayed; else
//! the method starts cold (a later pass of a call corrects the
//! linearization's error, whose rows push and pull unlike the first
//! pass's: `warm`'s module docs).
//!
//! **Order.** The most violated row, measured in `M^-1` lengths
//! (`s_i / |a_i|_{M^-1}`), is added first. A row counts as violated while
//! `s_i < -VIOLATION_OF_ACCEPTANCE tol_residual L` (`L` the acceptance
//! length, `super::residuals`): the answer's feasibility is then well
//! within the acceptance test that every answer passes.

use std::time::Instant;

use nalgebra::DVector;

use super::metric::BlockMetric;
use super::outcome::Candidate;
use super::projection::ProjectionQp;
use super::residuals::acceptance_length;
use factor::ActiveFactor;
use packed_row::{PackedRow, packed_rows};

mod factor;
mod packed_row;
mod warm;

/// A row is a combination of the active rows, at rounding, when the part
/// of it outside their span is at most this fraction of its length, both
/// in `M^-1` (`delta_p <= DEPENDENT_REL^2 w_pp`, module docs). The pivot
/// `delta_p` is a difference of squares whose rounding grows with the
/// condition of `W_A`, so the bound sits well above the precision.
pub const DEPENDENT_REL: f64 = 1e-5;

/// A row counts as violated while `s_i` is below `-VIOLATION_OF_ACCEPTANCE
/// tol_residual L` (module docs).
pub const VIOLATION_OF_ACCEPTANCE: f64 = 1e-3;

/// Steps (full, partial or dual) per row and per entry of `dq` before the
/// method gives up: it adds each row at most once between drops, and
/// about `|A| + drops` steps answer a problem (module docs); the limit
/// guards against cycling through degenerate ties.
pub const STEPS_PER_SIZE: usize = 4;

/// Problems of more entries of `dq` are refused (`NotApplicable`): its
/// dense `q x q` factor and `O(q^2)` steps are for islands of a few
/// bodies, and a user naming it for a large island gets the next solver
/// of the chain, not a long dense solve. `Auto` takes it up to 132
/// entries ([`crate::solver::SolverSettings::auto_dual_active_set_max_dofs`]).
pub const MAX_DOFS: usize = 600;

/// Why the dual active-set method gave no answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum DualActiveSetFailure {
    /// Equality rows, friction cones or rows of more than two bodies,
    /// which it does not take, or more than [`MAX_DOFS`] entries of `dq`.
    NotApplicable,
    /// A violated row that no step can satisfy (module docs).
    Infeasible,
    /// [`STEPS_PER_SIZE`] `(m + n)` steps, or a value that is not finite.
    NotConverged,
    /// The deadline passed.
    Deadline,
}

/// Solves `qp` (module docs), from the multipliers `warm` when given (one
/// per row; of another length they are ignored). `Candidate::iterations`
/// counts the steps and the warm start's drops, `Candidate::factorizations`
/// is 1 when a warm start built the factor, else 0 (the factor is updated,
/// never made again).
pub fn solve(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    tol_residual: f64,
    deadline: Option<Instant>,
    warm: Option<&DVector<f64>>,
) -> Result<Candidate, DualActiveSetFailure> {
    if qp.num_equalities > 0 || !qp.cones.is_empty() || qp.num_dofs() > MAX_DOFS {
        return Err(DualActiveSetFailure::NotApplicable);
    }
    let rows = packed_rows(qp).ok_or(DualActiveSetFailure::NotApplicable)?;
    let n = qp.num_dofs();
    let m = qp.num_rows();
    let b = qp.b();
    // `M^-1 a_i`, packed like the rows, and `w_ii = a_i^T M^-1 a_i`.
    let scaled: Vec<PackedRow> = rows.iter().map(|row| row.scaled(metric)).collect();
    let diagonal: Vec<f64> = rows
        .iter()
        .zip(&scaled)
        .map(|(a, x)| a.dot_packed(x))
        .collect();
    // A row no body moves (`w_ii = 0`) is never added: it holds or the
    // problem was rejected before (`super::solve`).
    let inverse_lengths: Vec<f64> = diagonal
        .iter()
        .map(|&w| if w > 0.0 { 1.0 / w.sqrt() } else { 0.0 })
        .collect();
    let violated_below = -VIOLATION_OF_ACCEPTANCE * tol_residual * acceptance_length(qp);
    let mut factor = ActiveFactor::new(n.min(m));
    let mut dq = DVector::zeros(n);
    let mut active: Vec<usize> = Vec::new();
    let mut u: Vec<f64> = Vec::new();
    let mut steps = 0;
    let mut factorizations = 0;
    let start = warm
        .filter(|w| w.len() == m)
        .and_then(|warm| warm::start(warm, &rows, &scaled, &diagonal, &b, &mut factor, deadline));
    match start {
        Some(start)
            if start.u.iter().all(|x| x.is_finite()) && start.drops <= start.active.len() =>
        {
            for (&j, &uj) in start.active.iter().zip(&start.u) {
                scaled[j].add_to(uj, dq.as_mut_slice());
            }
            (active, u, steps) = (start.active, start.u, start.drops);
            factorizations = usize::from(!active.is_empty());
        }
        Some(_) => factor = ActiveFactor::new(n.min(m)),
        None => {}
    }
    let mut is_active = vec![false; m];
    for &j in &active {
        is_active[j] = true;
    }
    let b_rows = b.clone();
    // The rows measured at the start: `s = J dq + b`, which is `b` from
    // `dq = 0` (no warm start).
    let mut slack = match active.is_empty() {
        true => b,
        false => DVector::from_iterator(
            m,
            rows.iter()
                .zip(b.iter())
                .map(|(row, &b_i)| row.dot(dq.as_slice()) + b_i),
        ),
    };
    let limit = STEPS_PER_SIZE * (m + n);
    // The steps' work vectors, reused: `w`, `y = L^-1 w`, `r = L^-T y`
    // and the primal direction `z`.
    let mut column = Vec::with_capacity(n.min(m));
    let (mut y, mut r) = (Vec::with_capacity(n.min(m)), Vec::with_capacity(n.min(m)));
    let mut z = DVector::zeros(n);
    // The most violated row, in M^-1 lengths; none: the answer.
    while let Some(p) = most_violated(&slack, &inverse_lengths, &is_active, violated_below) {
        let mut u_p = 0.0;
        loop {
            steps += 1;
            if steps > limit {
                return Err(DualActiveSetFailure::NotConverged);
            }
            if deadline.is_some_and(|d| Instant::now() >= d) {
                return Err(DualActiveSetFailure::Deadline);
            }
            // w = N_A^T M^-1 a_p, y = L^-1 w, r = L^-T y.
            column.clear();
            column.extend(active.iter().map(|&j| rows[j].dot_packed(&scaled[p])));
            factor.solve_lower_into(&column, &mut y);
            let delta = diagonal[p] - y.iter().map(|x| x * x).sum::<f64>();
            factor.solve_upper_into(&y, &mut r);
            // The partial step: the first active multiplier to reach zero.
            let mut partial: Option<(f64, usize)> = None;
            for (j, &rj) in r.iter().enumerate() {
                if rj > 0.0 {
                    let t = u[j] / rj;
                    if partial.is_none_or(|(best, _)| t < best) {
                        partial = Some((t, j));
                    }
                }
            }
            let dependent = delta <= DEPENDENT_REL * DEPENDENT_REL * diagonal[p]
                || active.len() == factor.capacity;
            let full = (!dependent).then(|| -slack[p] / delta);
            let (t, drop) = match (full, partial) {
                (None, None) => return Err(DualActiveSetFailure::Infeasible),
                (Some(t_full), Some((t_part, j))) if t_part < t_full => (t_part, Some(j)),
                (Some(t_full), _) => (t_full, None),
                (None, Some((t_part, j))) => (t_part, Some(j)),
            };
            if !t.is_finite() {
                return Err(DualActiveSetFailure::NotConverged);
            }
            for (uj, rj) in u.iter_mut().zip(r.iter()) {
                *uj -= t * rj;
            }
            u_p += t;
            // z = M^-1 (a_p - N_A r): moves s_p by delta per unit, keeps
            // the active rows tight. In a dependent step it is the part of
            // a_p outside span(N_A), below DEPENDENT_REL of it, and moving
            // along it keeps M dq = N_A u + u_p a_p exact.
            z.fill(0.0);
            scaled[p].add_to(1.0, z.as_mut_slice());
            for (&j, &rj) in active.iter().zip(&r) {
                scaled[j].add_to(-rj, z.as_mut_slice());
            }
            dq.axpy(t, &z, 1.0);
            // s <- s + t J z on the inactive rows (the active ones stay at
            // 0; a dropped row is measured again).
            let z_slice = z.as_slice();
            for ((s_i, row), &on) in slack.as_mut_slice().iter_mut().zip(&rows).zip(&is_active) {
                if !on {
                    *s_i += t * row.dot(z_slice);
                }
            }
            match drop {
                Some(j) => {
                    factor.remove(j, active.len());
                    let dropped = active.remove(j);
                    is_active[dropped] = false;
                    slack[dropped] = rows[dropped].dot(dq.as_slice()) + b_rows[dropped];
                    u.remove(j);
                }
                None => {
                    factor.append(&y, delta.sqrt());
                    active.push(p);
                    is_active[p] = true;
                    u.push(u_p);
                    break;
                }
            }
        }
    }
    // The multipliers of `dq` on the final active set, `W_A u = N_A^T dq`:
    // a dependent step moves `u` along `r` with `N_A r = a_p` only to
    // within `DEPENDENT_REL`, so the iterated `u` drifts from `dq`'s by
    // that much per such step; `dq` moves only by exact steps.
    let n_a_dq: Vec<f64> = active.iter().map(|&j| rows[j].dot(dq.as_slice())).collect();
    let u = factor.solve_upper(&factor.solve_lower(&n_a_dq));
    let mut lambda = DVector::zeros(m);
    for (&i, &ui) in active.iter().zip(&u) {
        lambda[i] = ui.max(0.0);
    }
    if !(dq.iter().all(|x| x.is_finite()) && lambda.iter().all(|x| x.is_finite())) {
        return Err(DualActiveSetFailure::NotConverged);
    }
    Ok(Candidate {
        dq,
        lambda,
        iterations: steps,
        factorizations,
    })
}

/// The row with the most negative `s_i / |a_i|_{M^-1}` among the inactive
/// rows violated beyond `violated_below` (`inverse_lengths`: `1 /
/// |a_i|_{M^-1}`, 0 for a row no body moves).
fn most_violated(
    slack: &DVector<f64>,
    inverse_lengths: &[f64],
    is_active: &[bool],
    violated_below: f64,
) -> Option<usize> {
    let mut best: Option<(f64, usize)> = None;
    for (i, (&s, &inverse)) in slack.as_slice().iter().zip(inverse_lengths).enumerate() {
        if s >= violated_below || is_active[i] || inverse == 0.0 {
            continue;
        }
        let measure = s * inverse;
        if best.is_none_or(|(b, _)| measure < b) {
            best = Some((measure, i));
        }
    }
    best.map(|(_, i)| i)
}
