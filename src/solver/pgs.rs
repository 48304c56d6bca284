//! Projected Gauss-Seidel on the LCP: the baseline of game engines
//! (Catto's sequential impulses are the same iteration on the Jacobian).
//!
//! One sweep updates each unknown in turn, with the latest values of the
//! others:
//!
//! ```text
//! z_i <- max(0, z_i - (q_i + M_i z) / M_ii)
//! ```
//!
//! The free variables of a mixed LCP (`super::lcp`: the bilateral rows of
//! joints) are not clamped: `z_i <- z_i - (q_i + M_i z) / M_ii`, a plain
//! Gauss-Seidel step on `w_i = 0`; their residual is `|w_i|`
//! ([`natural_map_abs`]). Gauss-Seidel converges on a consistent
//! positive semidefinite system with a positive diagonal, also a singular
//! one (redundant rows of a closed loop); on an inconsistent one (no `z_E`
//! makes `w_E = 0`) it stops at the sweep limit.
//!
//! It converges for symmetric positive definite `M` (Cottle, Pang and
//! Stone 1992, section 5.2), slowly when `M` is ill-conditioned, and may not
//! converge otherwise; it needs `M_ii > 0`. The iteration runs on the
//! Jacobi-scaled problem of `super::scaling` (the iterates are the same up
//! to scaling; the residual is then relative), and stops when the natural
//! map falls below the tolerance, or at the sweep limit or the deadline
//! (checked before each sweep), both failures: a non-converged `z` is never
//! returned.

use std::time::Instant;

use nalgebra::{DMatrix, DVector};

use super::lcp::Lcp;
use super::residuals::{
    lcp_natural_map, natural_map_abs, natural_map_certified, natural_map_relative,
};
use super::scaling::LcpScaling;

/// Settings of PGS.
#[derive(Debug, Clone, PartialEq)]
pub struct PgsSettings {
    /// Sweep limit.
    pub max_sweeps: usize,
    /// Stop when `||min(z~, w~)||_inf` on the scaled problem is below this.
    /// The default is ten times below the projection check
    /// ([`super::SolverSettings::tol_residual`], 1e-9), whose per-row
    /// normalization differs from the Jacobi scaling by factors of order one.
    pub tol_residual: f64,
    /// The iterate must also have a natural map at most this relative to
    /// the caller's data ([`natural_map_relative`]): the scaled test alone
    /// can pass a `z` whose natural map is a large fraction of the data
    /// (the kept fuzz input
    /// `tests/data/fuzz/lcp_solvers/crash-pgs-natural-map`;
    /// `benchmarks/results/fuzzing.md`).
    pub tol_residual_unscaled: f64,
    /// Stop before the next sweep once this instant has passed
    /// ([`PgsStatus::DeadlinePassed`]); `None`: no limit. Default `None`.
    pub deadline: Option<Instant>,
}

impl Default for PgsSettings {
    fn default() -> Self {
        Self {
            max_sweeps: 1000,
            tol_residual: 1e-10,
            tol_residual_unscaled: 1e-6,
            deadline: None,
        }
    }
}

/// Why PGS did not return a solution.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum PgsStatus {
    /// `M_ii <= 0`: the update divides by it.
    NonPositiveDiagonal {
        /// The row.
        row: usize,
    },
    /// The sweep limit was reached first.
    MaxSweeps {
        /// Scaled natural-map residual at the end.
        residual: f64,
    },
    /// The deadline ([`PgsSettings::deadline`]) passed first.
    DeadlinePassed {
        /// Sweeps done.
        sweeps: usize,
    },
    /// An iterate stopped being finite.
    Diverged {
        /// Sweeps done.
        sweeps: usize,
    },
}

/// A converged PGS solution.
#[derive(Debug, Clone, PartialEq)]
pub struct PgsSolution {
    /// `z`: `z_I >= 0`, the free `z_E` of either sign.
    pub z: DVector<f64>,
    /// `w = M z + q`, on the original data.
    pub w: DVector<f64>,
    /// Sweeps done.
    pub sweeps: usize,
    /// Natural map on the scaled problem (what was checked).
    pub residual_scaled: f64,
    /// `||min(z, w)||_inf / max(1, ||q||_inf)` on the original data.
    pub residual: f64,
}

/// Runs PGS from `z = 0`.
pub fn solve(lcp: &Lcp, settings: &PgsSettings) -> Result<PgsSolution, PgsStatus> {
    if let Some(row) = lcp.m().diagonal().iter().position(|&d| d <= 0.0) {
        return Err(PgsStatus::NonPositiveDiagonal { row });
    }
    let scaling = LcpScaling::jacobi(lcp.m(), lcp.q());
    // Rows of M~ as contiguous columns of its transpose.
    let m = scaling.scale_m(lcp.m());
    let m_t = m.transpose();
    let q = scaling.scale_q(lcp.q());
    let free = lcp.free();
    let mut z = DVector::zeros(q.len());
    let mut residual = f64::INFINITY;
    for sweep in 1..=settings.max_sweeps {
        if settings.deadline.is_some_and(|d| Instant::now() >= d) {
            return Err(PgsStatus::DeadlinePassed { sweeps: sweep - 1 });
        }
        gauss_seidel_sweep(&m_t, &q, free, &mut z);
        let w = m_t.tr_mul(&z) + &q;
        residual = natural_map_abs(&z, &w, free);
        if !residual.is_finite() {
            return Err(PgsStatus::Diverged { sweeps: sweep });
        }
        // The cheap test first; the certified one (rounding of w included)
        // only when it passes.
        if residual <= settings.tol_residual
            && natural_map_certified(&m, &q, &z, free) <= settings.tol_residual
            && natural_map_relative(lcp.m(), lcp.q(), &scaling.unscale_z(&z), free)
                <= settings.tol_residual_unscaled
        {
            log::trace!("pgs: converged after {sweep} sweeps, residual {residual:.2e}");
            let z_orig = scaling.unscale_z(&z);
            let w_orig = lcp.w(&z_orig);
            return Ok(PgsSolution {
                residual: lcp_natural_map(&z_orig, &w_orig, lcp.q(), free),
                z: z_orig,
                w: w_orig,
                sweeps: sweep,
                residual_scaled: residual,
            });
        }
    }
    log::debug!(
        "pgs: {} sweeps, residual {residual:.2e}",
        settings.max_sweeps
    );
    Err(PgsStatus::MaxSweeps { residual })
}

/// One in-place sweep; `m_t` is `M~^T`, whose column `i` is row `i` of `M~`.
/// The first `free` unknowns are not clamped (module docs).
fn gauss_seidel_sweep(m_t: &DMatrix<f64>, q: &DVector<f64>, free: usize, z: &mut DVector<f64>) {
    for i in 0..q.len() {
        let row = m_t.column(i);
        let w_i = row.dot(z) + q[i];
        let step = z[i] - w_i / row[i];
        z[i] = if i < free { step } else { step.max(0.0) };
    }
}
