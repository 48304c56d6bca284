//! The exact finish: the equality-constrained QP of the active set the
//! augmented Lagrangian has found, solved to rounding with the factor of
//! `H` the iteration already has, then verified.
//!
//! The outer iteration contracts the dual error by `1 / (1 + kappa sigma)`
//! per step (module docs of [`super`]); where the Jacobi-scaled dual matrix
//! has small eigenvalues `sigma` (stiff chains, heavy bodies on light
//! ones) that is slow, and the acceptance test lets an answer through whose
//! infeasibility is small against the scene's scale but not against the
//! correction (`benchmarks/results/augmented_lagrangian.md`). Once the
//! active set `A` (equality rows and the rows with a positive multiplier)
//! is right, the minimizer is the solution of
//!
//! ```text
//! M dq = J_A^T lambda_A,      J_A dq = -b_A
//! ```
//!
//! **Solve.** From an iterate `(dq, lambda)` with residuals
//! `g = M dq - J_A^T lambda_A` and `h = -b_A - J_A dq`, the correction
//! `(delta, delta_lambda)` of the KKT system satisfies
//! `M delta - J_A^T delta_lambda = -g`, `J_A delta = h`. Adding
//! `J_A^T R_A J_A delta = J_A^T R_A h` (`R = diag(rho)`, the penalties `H`
//! was built with) to the first equation gives, with
//! `nu = delta_lambda + R_A h`,
//!
//! ```text
//! H delta = J_A^T nu - g,     S nu = h + J_A H^-1 g,     S = J_A H^-1 J_A^T
//! ```
//!
//! `S` is solved by conjugate gradients preconditioned with `R_A`, each
//! iteration one solve with the kept factor of `H`: in the Jacobi scaling
//! the preconditioned `S` has the eigenvalues `kappa sigma / (1 + kappa
//! sigma)` of the dual's `sigma`, clustered at 1 but for the few small
//! ones that slow the outer iteration, which CG resolves in about one
//! iteration each. Redundant rows (four coplanar corners, a row listed
//! twice) make `S` singular; the system is consistent (`h` lies in the range
//! of `J_A`), CG from zero stays in the range of the preconditioned
//! operator, and `lambda` keeps the split of the iterate it started from.
//! The correction is repeated (iterative refinement) until `h` is at
//! rounding.
//!
//! **Verification.** The answer `lambda` (clamped at 0 on inequality rows)
//! and `dq = M^-1 J^T lambda` must meet the KKT conditions to a band
//! relative to the correction's own size `L = max_i viol(b_i)` (not the
//! scene's, which the acceptance test uses): every row feasible within
//! `EXACT_BAND_REL L`, every row with a positive multiplier met within it,
//! no multiplier below `-EXACT_BAND_REL L / a_i`. A row of `A` with a
//! negative multiplier leaves it and a violated row outside joins it
//! (primal-dual active-set steps), at most `corrections` times. The caller
//! still puts the answer through the acceptance test.

use nalgebra::DVector;

use super::State;
use super::hessian::NewtonMatrix;
use crate::solver::residuals::{m_apply, m_inv, row_violation};

/// The KKT conditions of an exact answer hold within this fraction of the
/// correction's size (module docs): far below the 1e-6 relative agreement
/// asked of `dq`, above the rounding of `dq = M^-1 J^T lambda` (the
/// refinement's multiplier corrections `nu - R_A h` cancel about
/// `log10 kappa` digits: measured up to 1e-10 of the correction in `w`).
pub(super) const EXACT_BAND_REL: f64 = 1e-9;

/// The refinement stops once the feasibility and stationarity errors, as
/// row values, are this fraction of the verification band.
const REFINED_FRACTION_OF_BAND: f64 = 1e-3;

/// Refinement rounds of the KKT solve at most.
const MAX_REFINEMENTS: usize = 30;

/// Conjugate-gradient iterations on `S` at most, beyond the first ones
/// per row: rounding stops it well before this on every problem measured.
const MAX_CG_ITERATIONS: usize = 200;

/// CG on `S` stops when the preconditioned residual is this fraction of
/// its start (the refinement rounds take the rest).
const CG_RELATIVE_RESIDUAL: f64 = 1e-13;

/// The proximal regularization of the finish, in the Jacobi-scaled dual:
/// `S + delta R^-1` with `delta = kappa * DUAL_REGULARIZATION`, which in
/// the preconditioned operator (eigenvalues `kappa sigma / (1 + kappa
/// sigma)`) adds about `kappa DUAL_REGULARIZATION` to `kappa sigma`: the
/// dual's eigenvalues `sigma` are shifted by this much, as clarabel's
/// polish regularizes its KKT system (`-1e-9 I` on the unit-scaled rows).
/// Each refinement round removes all but `delta / (delta + e)` of an error
/// along an eigenvalue `e`; directions of near-redundant rows (`sigma`
/// below it) keep the split of the multipliers the finish started from
/// instead of the huge opposite forces their exact solution on a wrong
/// active set would ask for.
const DUAL_REGULARIZATION: f64 = 1e-9;

/// An active-set correction that would change more than this fraction of
/// the active rows is not made: the guess was far off (measured on the
/// pyramids of `tests/data/engine`, whose near-redundant corner rows make
/// such corrections swing between sets of hundreds of rows without
/// settling), and the caller goes on iterating or falls back.
const MAX_CHANGED_FRACTION: f64 = 0.05;

/// The counts of one exact finish, for the log.
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct FinishCounts {
    pub cg_iterations: usize,
    pub refinements: usize,
    pub corrections: usize,
}

impl State<'_> {
    /// The size of the correction: the largest violation of a row by
    /// `dq = 0` (at least the smallest positive f64).
    pub(super) fn correction_length(&self) -> f64 {
        self.b
            .iter()
            .enumerate()
            .map(|(i, &b)| row_violation(self.qp.is_equality(i), b))
            .fold(f64::MIN_POSITIVE, f64::max)
    }

    /// Whether `lambda` (clamped on inequality rows) gives the exact
    /// minimizer: the KKT conditions within [`EXACT_BAND_REL`] of the
    /// correction's size (module docs). No factorization.
    pub(super) fn certified_exact(&self, lambda: &DVector<f64>) -> bool {
        let lambda = self.clamped(lambda);
        let dq = crate::solver::projection_lcp::dq_from_lambda(self.qp, self.metric, &lambda);
        let w = self.w(&dq);
        let band = EXACT_BAND_REL * self.correction_length();
        (0..w.len()).all(|i| {
            let wi = w[i];
            if !wi.is_finite() || !lambda[i].is_finite() {
                return false;
            }
            if self.qp.is_equality(i) {
                return self.rho[i] == 0.0 || wi.abs() <= band;
            }
            wi >= -band && (lambda[i] == 0.0 || wi <= band)
        })
    }

    /// The active set of `lambda`: the equality rows, and the inequality
    /// rows whose multiplier, as the displacement `lambda_i a_i` it alone
    /// would cause, exceeds the row's value `w_i` at
    /// `dq = M^-1 J^T lambda` (as the interior point's polish compares
    /// `z_i` with `s_i`): a row the iterate pushes a little while it is
    /// clear of its target is a degenerate row, not an active one.
    pub(super) fn active_guess(&self, lambda: &DVector<f64>) -> Vec<bool> {
        let lambda = self.clamped(lambda);
        let dq = crate::solver::projection_lcp::dq_from_lambda(self.qp, self.metric, &lambda);
        let w = self.w(&dq);
        (0..lambda.len())
            .map(|i| {
                self.rho[i] > 0.0
                    && (self.qp.is_equality(i) || lambda[i] * self.row_diagonal[i] > w[i])
            })
            .collect()
    }

    /// `lambda` with its inequality entries clamped at 0.
    pub(super) fn clamped(&self, lambda: &DVector<f64>) -> DVector<f64> {
        DVector::from_fn(lambda.len(), |i, _| {
            if self.qp.is_equality(i) {
                lambda[i]
            } else {
                lambda[i].max(0.0)
            }
        })
    }

    /// The exact minimizer's multipliers from the active set of `lambda`
    /// (module docs), or `None` when a factorization fails or the
    /// verification fails after `corrections` active-set corrections.
    pub(super) fn exact_finish(
        &mut self,
        newton: &mut NewtonMatrix,
        lambda: &DVector<f64>,
        corrections: usize,
    ) -> Option<(DVector<f64>, FinishCounts)> {
        let m = lambda.len();
        let mut counts = FinishCounts::default();
        let active_guess = self.active_guess(lambda);
        let mut active = active_guess;
        let mut lambda = DVector::from_fn(m, |i, _| if active[i] { lambda[i] } else { 0.0 });
        let band = EXACT_BAND_REL * self.correction_length();
        for round in 0..=corrections {
            self.ensure_factor(newton, &active).ok()?;
            let dq;
            (lambda, dq) = self.refine(newton, &active, lambda, &mut counts)?;
            let w = self.w(&dq);
            let a = &self.row_diagonal;
            let next: Vec<bool> = (0..m)
                .map(|i| {
                    if self.rho[i] == 0.0 {
                        false
                    } else if self.qp.is_equality(i) {
                        true
                    } else if active[i] {
                        lambda[i] * a[i] >= -band
                    } else {
                        w[i] < -band
                    }
                })
                .collect();
            if next == active {
                let answer = self.clamped(&lambda);
                return self.certified_exact(&answer).then_some((answer, counts));
            }
            let changes = next.iter().zip(&active).filter(|(x, y)| x != y).count();
            let active_rows = active.iter().filter(|&&x| x).count();
            if round == corrections || changes as f64 > MAX_CHANGED_FRACTION * active_rows as f64 {
                break;
            }
            counts.corrections += 1;
            for i in 0..m {
                if !next[i] {
                    lambda[i] = 0.0;
                }
            }
            active = next;
        }
        None
    }

    /// Iterative refinement of the KKT system of `active` from `lambda`
    /// (module docs), with `H` factored for `active`: the multipliers and
    /// `dq` (whose row values are more accurate than those of
    /// `M^-1 J^T lambda`, which cancel digits).
    fn refine(
        &self,
        newton: &mut NewtonMatrix,
        active: &[bool],
        mut lambda: DVector<f64>,
        counts: &mut FinishCounts,
    ) -> Option<(DVector<f64>, DVector<f64>)> {
        let mask = |v: &mut DVector<f64>| {
            for (x, &a) in v.iter_mut().zip(active) {
                if !a {
                    *x = 0.0;
                }
            }
        };
        let band = EXACT_BAND_REL * self.correction_length();
        let mut dq = crate::solver::projection_lcp::dq_from_lambda(self.qp, self.metric, &lambda);
        for _ in 0..MAX_REFINEMENTS {
            let g = m_apply(self.metric, &dq) - self.qp.apply_jt(&lambda);
            let mut h = -self.w(&dq);
            mask(&mut h);
            // The stationarity error as row values: what `dq = M^-1 J^T
            // lambda` would add to `w`.
            let g_rows = self.qp.apply_j(&m_inv(self.metric, &g));
            if h.amax().max(g_rows.amax()) <= REFINED_FRACTION_OF_BAND * band {
                break;
            }
            counts.refinements += 1;
            let h_inv_g = newton.solve(&g)?;
            let mut rhs = &h + self.qp.apply_j(&h_inv_g);
            mask(&mut rhs);
            let nu = self.schur_cg(newton, active, &rhs, counts)?;
            let delta = newton.solve(&(self.qp.apply_jt(&nu) - &g))?;
            let r_h = DVector::from_fn(h.len(), |i, _| self.rho[i] * h[i]);
            lambda += &nu - r_h;
            dq += delta;
            if !lambda.iter().all(|x| x.is_finite()) {
                return None;
            }
        }
        Some((lambda, dq))
    }

    /// Solves `S nu = rhs` (`S = J_A H^-1 J_A^T` on the rows of `active`,
    /// zero elsewhere) by conjugate gradients preconditioned with `R_A`.
    fn schur_cg(
        &self,
        newton: &mut NewtonMatrix,
        active: &[bool],
        rhs: &DVector<f64>,
        counts: &mut FinishCounts,
    ) -> Option<DVector<f64>> {
        let apply_s = |newton: &mut NewtonMatrix, x: &DVector<f64>| -> Option<DVector<f64>> {
            let y = newton.solve(&self.qp.apply_jt(x))?;
            let mut s = self.qp.apply_j(&y);
            for (v, &a) in s.iter_mut().zip(active) {
                if !a {
                    *v = 0.0;
                }
            }
            Some(s)
        };
        let precondition = |r: &DVector<f64>| DVector::from_fn(r.len(), |i, _| self.rho[i] * r[i]);
        // `S + delta R^-1` (the preconditioned operator plus `delta I`):
        // bounded answers where `S` is singular and the system is not
        // consistent (a wrong active set, then corrected).
        let delta = self.settings.penalty * DUAL_REGULARIZATION;
        let regularize = |x: &DVector<f64>, sx: &mut DVector<f64>| {
            for i in 0..x.len() {
                if active[i] && self.rho[i] > 0.0 {
                    sx[i] += delta * x[i] / self.rho[i];
                }
            }
        };
        let mut x = DVector::zeros(rhs.len());
        let mut r = rhs.clone();
        let mut z = precondition(&r);
        let mut p = z.clone();
        let mut rz = r.dot(&z);
        let start = rz;
        if start == 0.0 {
            return Some(x);
        }
        if !start.is_finite() || start < 0.0 {
            return None;
        }
        for _ in 0..MAX_CG_ITERATIONS {
            let mut sp = apply_s(newton, &p)?;
            regularize(&p, &mut sp);
            let curvature = p.dot(&sp);
            if !curvature.is_finite() || curvature <= 0.0 {
                break;
            }
            let alpha = rz / curvature;
            x.axpy(alpha, &p, 1.0);
            r.axpy(-alpha, &sp, 1.0);
            counts.cg_iterations += 1;
            z = precondition(&r);
            let rz_next = r.dot(&z);
            if rz_next <= CG_RELATIVE_RESIDUAL * CG_RELATIVE_RESIDUAL * start {
                break;
            }
            p = &z + &p * (rz_next / rz);
            rz = rz_next;
        }
        x.iter().all(|v| v.is_finite()).then_some(x)
    }
}
