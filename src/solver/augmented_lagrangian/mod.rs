//! A warm-startable primal solver of the projection QP: the augmented
//! Lagrangian method with a semismooth Newton inner solve on the body-space
//! matrix.
//!
//! The problem (`super::projection`) is
//!
//! ```text
//! minimize 1/2 dq^T M dq   s.t.  w_i = b_i + J_i dq  = 0  (i in E, the first num_equalities rows)
//!                                w_i               >= 0  (i in I)
//! ```
//!
//! with `b = phi - target`. For multipliers `lambda` (`lambda_I >= 0`) and
//! penalties `rho_i > 0` its augmented Lagrangian is the convex, `C^1`,
//! piecewise quadratic function of `dq`
//!
//! ```text
//! L(dq) = 1/2 dq^T M dq + sum_E ( -lambda_i w_i + rho_i/2 w_i^2 )
//!                       + sum_I ( max(0, lambda_i - rho_i w_i)^2 - lambda_i^2 ) / (2 rho_i)
//! ```
//!
//! Its gradient is `M dq - J^T mu` with the updated multipliers
//! `mu_E = lambda_E - rho_E w_E`, `mu_I = max(0, lambda_I - rho_I w_I)`, and
//! its generalized Hessian is
//!
//! ```text
//! H = M + sum_{i in A} rho_i J_i^T J_i,     A = E u { i in I : lambda_i - rho_i w_i > 0 }
//! ```
//!
//! `H >= M` is positive definite whatever the rows are: four coplanar
//! contacts of a box on a face, a contact listed twice or a closed loop of
//! joints make `J_A` rank-deficient and the dual matrix `J M^-1 J^T`
//! singular, but never `H`. This is the matrix of Drake's SAP and of
//! MuJoCo's Newton solver, in positions.
//!
//! **Outer iteration** (the method of multipliers, a proximal point method
//! on the dual): minimize `L` over `dq` for the current `lambda`, then set
//! `lambda <- mu`. On the dual the step is
//! `lambda_{k+1} = argmax_lambda D(lambda) - sum_i (lambda_i - lambda_k,i)^2 / (2 rho_i)`,
//! so the dual error contracts on every iteration by at least
//! `1 / (1 + kappa sigma)` with `sigma` the smallest nonzero eigenvalue of
//! the Jacobi-scaled dual matrix on the active rows, when the penalties are
//! `rho_i = kappa / a_i` (`a_i = J_i M^-1 J_i^T`, so that every row's
//! penalty is the same dimensionless `kappa`: the method is invariant under
//! a rescaling of masses, lengths or of a single row).
//!
//! **Inner iteration** (semismooth Newton): `d = -H^-1 (M dq - J^T mu)`,
//! then the exact line search along `d` (`line_search`). `L` is piecewise
//! quadratic, so once the active set at the new point is the one `H` was
//! built with and the full step was taken, `dq` is the exact minimizer and
//! the inner iteration stops. Within one active set every Newton step and
//! every outer iteration reuses the same factor: a change of the active set
//! costs one numeric factorization, the symbolic analysis of the sparse
//! factor is done once per problem (`hessian`).
//!
//! **Answer**: after every outer iteration whose active set has not been
//! tried, the exact finish (`exact`): the equality-constrained QP of that
//! active set solved to rounding with the kept factor, its KKT conditions
//! verified to a band relative to the correction itself. A verified answer
//! `lambda`, `dq = M^-1 J^T lambda` (stationarity exact) that passes the
//! acceptance test of every solver ([`super::residuals`]) is returned.
//! When the outer iteration stops (its acceptance measure at most
//! [`AugmentedLagrangianSettings::stop_fraction`] of the tolerance, or a
//! stall) without a verified answer, the finish is tried once more with
//! active-set corrections; else the best accepted iterate is returned, or
//! with [`AugmentedLagrangianSettings::exact_only`] the solve fails with
//! [`AugmentedLagrangianFailure::NotExact`]. A **warm start** (multipliers
//! of a previous, similar problem) is first checked as it is: if it passes
//! the acceptance test and the finish's verification, the solver returns
//! it with zero iterations and no factorization. Else it is scaled by the
//! `s >= 0` that maximizes the dual function along it
//! (`State::scale_warm_start`: multipliers of a previous pass carry that
//! pass's violation, often a thousand times this one's), checked again,
//! the exact finish is tried on its active set, and the method starts
//! from it.
//!
//! **Infeasible problems** (rows no correction can satisfy) make `lambda`
//! grow without bound; the method stops at its iteration limit with
//! [`AugmentedLagrangianFailure::NotConverged`] and the caller's fallback
//! (clarabel) certifies the infeasibility.

mod exact;
pub(crate) mod hessian;
mod line_search;

use std::time::Instant;

use nalgebra::DVector;

use super::kept_analyses::KeptAnalyses;
use super::metric::BlockMetric;
use super::outcome::Candidate;
use super::projection::ProjectionQp;
use super::projection_lcp::dq_from_lambda;
use super::residuals::{m_apply, m_inner, projection_residuals, row_diagonal};
use hessian::NewtonMatrix;
use line_search::{Direction, exact_step};

/// Settings of the augmented Lagrangian solver.
#[derive(Debug, Clone, PartialEq)]
pub struct AugmentedLagrangianSettings {
    /// The dimensionless penalty `kappa`: `rho_i = kappa / a_i` (module
    /// docs). Larger contracts the dual error faster per outer iteration
    /// (by `1 / (1 + kappa sigma)`) but raises the condition number of `H`
    /// (about `kappa` times the number of rows on one body). Default 1e6.
    pub penalty: f64,
    /// Outer (multiplier) iterations before giving up. Default 200.
    pub max_outer: usize,
    /// Newton steps in one inner minimization. Default 50.
    pub max_newton: usize,
    /// Dense Cholesky up to this many entries of `dq` (six per body),
    /// sparse above. Default 96 (16 bodies), chosen by measurement
    /// (`benchmarks/results/solvers.md`).
    pub dense_max_dofs: usize,
    /// The solver stops once the acceptance measure is at most this
    /// fraction of the tolerance (default 1e-3: a `dq` well inside the
    /// tolerance costs a few more outer iterations, each usually one
    /// solve with the kept factor), or at the rounding floor: an outer
    /// iteration that no longer halves it below a hundredth of the
    /// tolerance, or three in a row within the tolerance (it returns the
    /// best candidate within the tolerance).
    pub stop_fraction: f64,
    /// When the active set differs from the one `H` was factored with in
    /// at most this many rows, the Newton system of the new active set is
    /// solved by conjugate gradients preconditioned with the old factor
    /// (`pcg`: exact after about one iteration per changed row) instead of
    /// a new factorization. 0: factor on every change. Default 0: measured
    /// slower than factoring on the engine states (16 rows: rp05 pyramid
    /// 85-90 ms a call against 53-72 ms, `benchmarks/results/solvers.md`).
    pub max_rows_changed_without_factorization: usize,
    /// The sparse factor is supernodal (dense kernels on the 6x6 blocks of
    /// the bodies) rather than left to faer's flop-ratio choice. Default
    /// true, chosen by measurement (`benchmarks/results/solvers.md`: the
    /// box bins 143-184 ms a call against 212-290 ms).
    pub supernodal: bool,
    /// Only answers certified as the exact minimizer (`exact`: the
    /// equality-constrained QP of the found active set solved to rounding,
    /// its KKT conditions verified to `1e-9` of the correction) are
    /// returned; an answer that only passes the acceptance test is
    /// [`AugmentedLagrangianFailure::NotExact`] and the caller falls back
    /// (clarabel, polished). Default true: settled scenes rest only on exact
    /// answers (`benchmarks/results/coupling.md`, last section).
    pub exact_only: bool,
}

impl Default for AugmentedLagrangianSettings {
    fn default() -> Self {
        Self {
            penalty: 1e6,
            max_outer: 200,
            max_newton: 50,
            dense_max_dofs: 96,
            stop_fraction: 1e-3,
            max_rows_changed_without_factorization: 0,
            supernodal: true,
            exact_only: true,
        }
    }
}

/// Why the augmented Lagrangian solver gave up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum AugmentedLagrangianFailure {
    /// The outer iteration limit (an infeasible problem, or a dual error
    /// that contracts too slowly).
    NotConverged,
    /// A Cholesky factorization of `H` failed (rounding).
    Factorization,
    /// The deadline passed.
    Deadline,
    /// The answer passed the acceptance test but the exact finish could
    /// not certify it as the exact minimizer
    /// ([`AugmentedLagrangianSettings::exact_only`]).
    NotExact,
}

/// The inputs of one solve beside the problem.
pub struct Start<'a> {
    /// Multipliers to start from, one per row (missing entries are 0;
    /// inequality entries are clamped at 0).
    pub warm: Option<&'a DVector<f64>>,
    /// Stop with the acceptance measure at most this.
    pub tolerance: f64,
    /// The interior point's stop target is raised by this factor, at most
    /// to [`crate::solver::PRECISION_STOP_CAP`] times `tolerance`
    /// ([`crate::solver::SolverSettings::precision_length`]); 1: the
    /// problem to its own length.
    pub relaxation: f64,
    /// Give up at this instant.
    pub deadline: Option<Instant>,
    /// The caller's store of sparse symbolic analyses
    /// ([`crate::solver::KeptAnalyses`]): the body-space matrix's analysis
    /// is taken from it, or made and kept there. `None`: made for this
    /// solve alone.
    pub kept: Option<&'a KeptAnalyses>,
}

/// Solves `qp` (linear rows only; the caller passes the pyramid of a
/// problem with cones). `Candidate::iterations` counts Newton steps.
pub fn solve(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    settings: &AugmentedLagrangianSettings,
    start: &Start<'_>,
) -> Result<Candidate, AugmentedLagrangianFailure> {
    let mut state = State::new(qp, metric, settings, start);
    let target = settings.stop_fraction * start.tolerance;
    let warm_given = start.warm.is_some();
    // The warm start as it is: accepted at the caller's tolerance and
    // certified exact.
    let (warm, mut previous) = state.candidate();
    if warm_given && previous <= start.tolerance && state.certified_exact(&state.lambda) {
        log::trace!("augmented Lagrangian: warm start accepted as it is");
        return Ok(warm);
    }
    if warm_given && state.scale_warm_start() {
        let (scaled, acceptance) = state.candidate();
        if acceptance <= start.tolerance && state.certified_exact(&state.lambda) {
            log::trace!("augmented Lagrangian: scaled warm start accepted as it is");
            return Ok(scaled);
        }
        previous = acceptance;
    }
    let mut newton =
        NewtonMatrix::new(qp, settings.dense_max_dofs, settings.supernodal, start.kept);
    let mut tried = None;
    if warm_given
        && let Some(answer) =
            state.try_exact(&mut newton, &mut tried, WARM_CORRECTIONS, start.tolerance)
    {
        state.log_answer(0, &newton, "exact finish from the warm start");
        return Ok(answer);
    }
    // The best candidate within the tolerance so far, and the outer
    // iterations in a row that did not halve the acceptance measure.
    let mut best: Option<(Candidate, f64)> = None;
    let mut stalls = 0;
    for outer in 0..settings.max_outer {
        if start.deadline.is_some_and(|d| Instant::now() >= d) {
            return best
                .map(|(c, _)| c)
                .ok_or(AugmentedLagrangianFailure::Deadline);
        }
        state.minimize_inner(&mut newton)?;
        state.lambda = state.mu();
        if let Some(answer) = state.try_exact(&mut newton, &mut tried, 0, start.tolerance) {
            state.log_answer(outer + 1, &newton, "exact finish");
            return Ok(answer);
        }
        let (candidate, acceptance) = state.candidate();
        stalls = if acceptance > STALL_RATIO * previous {
            stalls + 1
        } else {
            0
        };
        previous = acceptance;
        if acceptance <= start.tolerance && best.as_ref().is_none_or(|(_, b)| acceptance < *b) {
            best = Some((candidate, acceptance));
        }
        let floor = stalls > 0 && acceptance <= STALL_FRACTION_OF_TOLERANCE * start.tolerance;
        let done = acceptance <= target || floor || stalls >= STALL_PATIENCE;
        if !done {
            continue;
        }
        tried = None;
        if let Some(answer) =
            state.try_exact(&mut newton, &mut tried, FINAL_CORRECTIONS, start.tolerance)
        {
            state.log_answer(outer + 1, &newton, "exact finish with corrections");
            return Ok(answer);
        }
        if let Some((answer, _)) = best.take() {
            state.log_answer(outer + 1, &newton, "not certified exact");
            if settings.exact_only {
                return Err(AugmentedLagrangianFailure::NotExact);
            }
            return Ok(answer);
        }
    }
    match best {
        Some(_) if settings.exact_only => Err(AugmentedLagrangianFailure::NotExact),
        Some((answer, _)) => Ok(answer),
        None => Err(AugmentedLagrangianFailure::NotConverged),
    }
}

/// Active-set corrections of the exact finish from a warm start (its
/// active set is that of a neighbouring problem).
const WARM_CORRECTIONS: usize = 2;

/// Active-set corrections of the exact finish once the outer iteration
/// has stopped.
const FINAL_CORRECTIONS: usize = 3;

/// The iterate of one solve.
struct State<'a> {
    qp: &'a ProjectionQp,
    metric: &'a [BlockMetric],
    settings: &'a AugmentedLagrangianSettings,
    b: DVector<f64>,
    rho: Vec<f64>,
    /// `a_i = J_i M^-1 J_i^T`.
    row_diagonal: Vec<f64>,
    lambda: DVector<f64>,
    dq: DVector<f64>,
    /// The active set `H` was last factored with.
    factored: Option<Vec<bool>>,
    /// The active set of the last Newton step.
    last_active: Option<Vec<bool>>,
    newton_steps: usize,
    factorizations: usize,
    /// Newton steps solved by preconditioned CG, and its iterations.
    pcg_steps: usize,
    pcg_iterations: usize,
}

impl<'a> State<'a> {
    fn new(
        qp: &'a ProjectionQp,
        metric: &'a [BlockMetric],
        settings: &'a AugmentedLagrangianSettings,
        start: &Start<'_>,
    ) -> Self {
        let m = qp.num_rows();
        // A row no body moves (a_i = 0) holds or was rejected before
        // (`solve::check_zero_rows`): it gets no penalty and no force.
        let row_diagonal = row_diagonal(qp, metric);
        let rho = row_diagonal
            .iter()
            .map(|&a| if a > 0.0 { settings.penalty / a } else { 0.0 })
            .collect();
        let lambda = DVector::from_fn(m, |i, _| {
            let value = start
                .warm
                .and_then(|w| w.get(i).copied())
                .filter(|x| x.is_finite())
                .unwrap_or(0.0);
            if qp.is_equality(i) {
                value
            } else {
                value.max(0.0)
            }
        });
        let dq = dq_from_lambda(qp, metric, &lambda);
        Self {
            qp,
            metric,
            settings,
            b: qp.b(),
            rho,
            row_diagonal,
            lambda,
            dq,
            factored: None,
            last_active: None,
            newton_steps: 0,
            factorizations: 0,
            pcg_steps: 0,
            pcg_iterations: 0,
        }
    }

    /// The exact finish (`exact`) from the current multipliers, unless
    /// their active set is the one tried last (`tried`): the answer when it
    /// is verified and passes the acceptance test at `tolerance`.
    fn try_exact(
        &mut self,
        newton: &mut NewtonMatrix,
        tried: &mut Option<Vec<bool>>,
        corrections: usize,
        tolerance: f64,
    ) -> Option<Candidate> {
        let active = self.active_guess(&self.lambda);
        if tried.as_deref() == Some(&active) {
            return None;
        }
        *tried = Some(active);
        let lambda = self.lambda.clone();
        let (answer, counts) = self.exact_finish(newton, &lambda, corrections)?;
        // Stationarity exact, as every answer of the solver (the refined
        // `dq` differs from it by the rounding of the multipliers).
        let dq = dq_from_lambda(self.qp, self.metric, &answer);
        let acceptance = projection_residuals(self.qp, self.metric, &dq, &answer).acceptance();
        log::trace!(
            "augmented Lagrangian: exact finish verified ({} CG iterations, {} refinements, \
             {} corrections), acceptance {acceptance:.2e}",
            counts.cg_iterations,
            counts.refinements,
            counts.corrections
        );
        (acceptance <= tolerance).then(|| {
            self.lambda = answer.clone();
            Candidate {
                dq,
                lambda: answer,
                iterations: self.newton_steps,
                factorizations: self.factorizations,
            }
        })
    }

    fn log_answer(&self, outer: usize, newton: &NewtonMatrix, how: &str) {
        log::trace!(
            "augmented Lagrangian: {how} after {outer} outer iterations, {} Newton steps \
             ({} of them by preconditioned CG, {} CG iterations), {} factorizations ({})",
            self.newton_steps,
            self.pcg_steps,
            self.pcg_iterations,
            self.factorizations,
            if newton.is_dense() { "dense" } else { "sparse" }
        );
    }

    /// Scales the multipliers by the `s >= 0` that maximizes the dual
    /// along them, `D(s lambda) = -s^2/2 lambda^T A lambda - s b^T lambda`
    /// (`A = J M^-1 J^T`): `s = -b^T lambda / lambda^T A lambda`. The
    /// multipliers of a previous pass or call have the right pattern but
    /// the size of that problem's violation (a second pass removes a
    /// thousandth of the first's): scaled, they fit this one. Returns
    /// whether they changed.
    fn scale_warm_start(&mut self) -> bool {
        let jdq = self.qp.apply_j(&self.dq);
        let curvature = self.lambda.dot(&jdq);
        let scale = -self.b.dot(&self.lambda) / curvature;
        if !scale.is_finite() || curvature <= 0.0 || scale == 1.0 {
            return false;
        }
        let scale = scale.max(0.0);
        log::trace!("augmented Lagrangian: warm start scaled by {scale:.3e}");
        self.lambda *= scale;
        self.dq *= scale;
        true
    }

    /// The candidate of the current multipliers and its acceptance
    /// measure (NaN counts as infinite).
    fn candidate(&self) -> (Candidate, f64) {
        let dq = dq_from_lambda(self.qp, self.metric, &self.lambda);
        let residuals = projection_residuals(self.qp, self.metric, &dq, &self.lambda);
        let acceptance = residuals.acceptance();
        let candidate = Candidate {
            dq,
            lambda: self.lambda.clone(),
            iterations: self.newton_steps,
            factorizations: self.factorizations,
        };
        (
            candidate,
            if acceptance.is_nan() {
                f64::INFINITY
            } else {
                acceptance
            },
        )
    }

    fn w(&self, dq: &DVector<f64>) -> DVector<f64> {
        &self.b + self.qp.apply_j(dq)
    }

    /// `mu` at the current `dq` (module docs).
    fn mu(&self) -> DVector<f64> {
        let w = self.w(&self.dq);
        DVector::from_fn(w.len(), |i, _| {
            let p = self.lambda[i] - self.rho[i] * w[i];
            if self.qp.is_equality(i) {
                p
            } else {
                p.max(0.0)
            }
        })
    }

    /// The active set at the current `dq`. A row whose
    /// `lambda_i - rho_i w_i` is within rounding of 0 keeps its state in
    /// `previous` (both states give a valid generalized Hessian there; a
    /// flip by rounding would cost a factorization for nothing).
    fn active(&self, previous: Option<&[bool]>) -> Vec<bool> {
        let w = self.w(&self.dq);
        let length = self.b.amax();
        (0..w.len())
            .map(|i| {
                if self.rho[i] == 0.0 {
                    return false;
                }
                if self.qp.is_equality(i) {
                    return true;
                }
                let p = self.lambda[i] - self.rho[i] * w[i];
                let undecided = p.abs() <= ACTIVE_SWITCH_REL * self.rho[i] * length;
                match previous {
                    Some(previous) if undecided => previous[i],
                    _ => p > 0.0,
                }
            })
            .collect()
    }

    /// The Newton direction `H_A^-1 rhs` of the active set `active`: with
    /// the kept factor when it was made for `active`; by conjugate
    /// gradients preconditioned with it when few rows changed state
    /// ([`AugmentedLagrangianSettings::max_rows_changed_without_factorization`]);
    /// else after a new factorization.
    fn newton_direction(
        &mut self,
        newton: &mut NewtonMatrix,
        active: &[bool],
        rhs: &DVector<f64>,
    ) -> Result<DVector<f64>, AugmentedLagrangianFailure> {
        let changed = self
            .factored
            .as_ref()
            .map(|factored| factored.iter().zip(active).filter(|(a, b)| a != b).count());
        match changed {
            Some(0) => {
                return newton
                    .solve(rhs)
                    .ok_or(AugmentedLagrangianFailure::Factorization);
            }
            Some(changed) if changed <= self.settings.max_rows_changed_without_factorization => {
                if let Some(d) = self.pcg(newton, active, rhs, changed + PCG_EXTRA_ITERATIONS) {
                    return Ok(d);
                }
            }
            _ => {}
        }
        self.ensure_factor(newton, active)?;
        newton
            .solve(rhs)
            .ok_or(AugmentedLagrangianFailure::Factorization)
    }

    /// Factors `H` for `active` unless the kept factor was made for it.
    fn ensure_factor(
        &mut self,
        newton: &mut NewtonMatrix,
        active: &[bool],
    ) -> Result<(), AugmentedLagrangianFailure> {
        if self.factored.as_deref() == Some(active) {
            return Ok(());
        }
        self.factored = None;
        newton
            .factor(self.qp, self.metric, &self.rho, active)
            .map_err(|_| AugmentedLagrangianFailure::Factorization)?;
        self.factorizations += 1;
        self.factored = Some(active.to_vec());
        Ok(())
    }

    /// `H_A x = M x + sum_{i in A} rho_i J_i^T J_i x`.
    fn apply_h(&self, active: &[bool], x: &DVector<f64>) -> DVector<f64> {
        let mut jx = self.qp.apply_j(x);
        for (i, value) in jx.iter_mut().enumerate() {
            *value *= if active[i] { self.rho[i] } else { 0.0 };
        }
        m_apply(self.metric, x) + self.qp.apply_jt(&jx)
    }

    /// Solves `H_A x = rhs` by conjugate gradients preconditioned with the
    /// kept factor of `H` on another active set. `H_A` differs from it by
    /// one rank-one term per changed row, so the preconditioned matrix is
    /// the identity plus a matrix of that rank and CG is exact after one
    /// iteration more than the changed rows (in exact arithmetic). `None`
    /// when the preconditioned residual is not below [`PCG_RELATIVE_RESIDUAL`]
    /// of its start within `max_iterations` (rounding): the caller factors.
    fn pcg(
        &mut self,
        newton: &mut NewtonMatrix,
        active: &[bool],
        rhs: &DVector<f64>,
        max_iterations: usize,
    ) -> Option<DVector<f64>> {
        let mut x = DVector::zeros(rhs.len());
        let mut r = rhs.clone();
        let mut z = newton.solve(&r)?;
        let mut p = z.clone();
        let mut rz = r.dot(&z);
        let start = rz;
        if start.is_nan() || start <= 0.0 {
            return None;
        }
        for iteration in 1..=max_iterations {
            let hp = self.apply_h(active, &p);
            let curvature = p.dot(&hp);
            if curvature.is_nan() || curvature <= 0.0 {
                return None;
            }
            let alpha = rz / curvature;
            x.axpy(alpha, &p, 1.0);
            r.axpy(-alpha, &hp, 1.0);
            z = newton.solve(&r)?;
            let rz_next = r.dot(&z);
            self.pcg_iterations += 1;
            if rz_next <= PCG_RELATIVE_RESIDUAL * PCG_RELATIVE_RESIDUAL * start {
                log::trace!("augmented Lagrangian: CG step exact after {iteration} iterations");
                self.pcg_steps += 1;
                return Some(x);
            }
            p = &z + &p * (rz_next / rz);
            rz = rz_next;
        }
        None
    }

    /// Minimizes the augmented Lagrangian over `dq` for the current
    /// multipliers (semismooth Newton with exact line search).
    fn minimize_inner(
        &mut self,
        newton: &mut NewtonMatrix,
    ) -> Result<(), AugmentedLagrangianFailure> {
        for _ in 0..self.settings.max_newton {
            let active = self.active(self.last_active.as_deref());
            let m_dq = m_apply(self.metric, &self.dq);
            let gradient = &m_dq - self.qp.apply_jt(&self.mu());
            let d = self.newton_direction(newton, &active, &(-&gradient))?;
            self.last_active = Some(active.clone());
            self.newton_steps += 1;
            let w = self.w(&self.dq);
            let s = self.qp.apply_j(&d);
            let direction = Direction {
                m_dq: d.dot(&m_dq),
                m_d: m_inner(self.metric, &d, &d),
                w: w.as_slice(),
                s: s.as_slice(),
                lambda: self.lambda.as_slice(),
                rho: &self.rho,
                num_equalities: self.qp.num_equalities,
            };
            // No descent left: the minimizer up to rounding.
            let Some(t) = exact_step(&direction) else {
                return Ok(());
            };
            self.dq += &d * t;
            // A full Newton step that kept the active set lands on the
            // minimizer of that quadratic piece; a step lost in the
            // rounding of dq changes nothing more.
            let full = (t - 1.0).abs() <= NEWTON_UNIT_STEP_REL;
            if full && self.active(Some(&active)) == active {
                return Ok(());
            }
            let step = t.abs() * direction.m_d.max(0.0).sqrt();
            if step <= NEGLIGIBLE_STEP_REL * m_inner(self.metric, &self.dq, &self.dq).sqrt() {
                return Ok(());
            }
        }
        Ok(())
    }
}

/// An outer iteration that does not halve the acceptance measure below
/// this fraction of the tolerance has reached the rounding floor: the
/// solver stops there. Between it and the tolerance the iteration goes on
/// (an answer just inside the tolerance was measured 3e-4 relative off
/// clarabel's in one body's motion on a pressed pyramid, 1.8e-5 at this
/// fraction) until [`STALL_PATIENCE`] iterations in a row fail to halve
/// it, and returns the best candidate within the tolerance.
const STALL_FRACTION_OF_TOLERANCE: f64 = 1e-2;

/// Outer iterations in a row that do not halve the acceptance measure,
/// above [`STALL_FRACTION_OF_TOLERANCE`], before the solver stops with the
/// best candidate within the tolerance (a rounding floor there: iterating
/// to the limit cost a pyramid 200 iterations).
const STALL_PATIENCE: usize = 3;

/// An outer iteration that leaves the acceptance measure above this
/// fraction of the previous one did not make progress (the stall rules
/// below).
const STALL_RATIO: f64 = 0.5;

/// `|lambda_i - rho_i w_i|` at most this times `rho_i ||b||_inf` is within
/// rounding of the switch of row `i` (the rounding of `w_i` is about
/// `u ||b||_inf`, with some room for the sum over a row's blocks).
const ACTIVE_SWITCH_REL: f64 = 1e-13;

/// CG iterations allowed beyond the number of changed rows (rounding).
const PCG_EXTRA_ITERATIONS: usize = 3;

/// A CG solve is exact enough for the Newton step once the residual's
/// norm in the inverse of the preconditioner is this fraction of its start
/// (the line search stays exact; the outer iteration's acceptance test
/// certifies the answer).
const PCG_RELATIVE_RESIDUAL: f64 = 1e-10;

/// A Newton step whose M-norm is at most this fraction of `||dq||_M`
/// is rounding: the inner minimization stops.
const NEGLIGIBLE_STEP_REL: f64 = 1e-14;

/// A step this close to 1 counts as the full Newton step (rounding of the
/// line search's root, and the residual a CG-solved step leaves,
/// [`PCG_RELATIVE_RESIDUAL`]).
const NEWTON_UNIT_STEP_REL: f64 = 1e-9;
