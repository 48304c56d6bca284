//! Lemke's method on a mixed LCP (`crate::solver::lcp`): the free
//! variables are eliminated by a Schur complement, Lemke's method solves
//! the LCP that remains, and the free variables are recovered.
//!
//! With `E` the `free` leading variables and `I` the rest,
//!
//! ```text
//! A_EE z_E + A_EI z_I + b_E = 0                   (z_E free)
//! w_I = A_IE z_E + A_II z_I + b_I >= 0  _|_  z_I >= 0.
//! ```
//!
//! Let `G` be a generalized inverse of `A_EE` (`A_EE G A_EE = A_EE`). When
//! `A` is symmetric positive semidefinite (the dual of a projection QP,
//! `A = J M^-1 J^T`), `range(A_EI) ⊆ range(A_EE)` and `A_IE` vanishes on
//! `null(A_EE)`, so the first line has a solution exactly when `b_E` lies in
//! `range(A_EE)` (for `A = J M^-1 J^T`: when the equality rows
//! `J_E dq = -b_E` are consistent), every solution is
//!
//! ```text
//! z_E = -G (b_E + A_EI z_I)  (+ anything in null(A_EE), which changes nothing below),
//! ```
//!
//! and substituting it leaves the LCP in `z_I` alone
//!
//! ```text
//! S = A_II - A_IE G A_EI,   q = b_I - A_IE G b_E,
//! ```
//!
//! (`S` does not depend on which generalized inverse `G` is, and it is
//! positive semidefinite when `A` is: a Schur complement). Redundant
//! equality rows (closed loops of joints: a four-bar linkage lists more
//! rows than it removes degrees of freedom) make `A_EE` singular, so `G`
//! is a pseudo-inverse: `G = D (D A_EE D)^+ D` with the Jacobi scaling `D`
//! of `A_EE` (`crate::solver::scaling`), so that the relative rank
//! tolerance [`EQUALITY_RANK_TOL_REL`] does not depend on masses and
//! lengths, and the SVD's pseudo-inverse of the scaled block (singular
//! values below that tolerance times the largest are dropped).
//! `D X^+ D` is a generalized inverse of `A_EE` (`A D (D A D)^+ D A =
//! D^-1 (D A D)(D A D)^+(D A D) D^-1 = A`), though not its Moore-Penrose
//! one, which is all the elimination needs.
//!
//! Inconsistent equalities (`b_E` not in the range: two joint rows asking
//! for different values of one quantity) are reported as
//! [`LemkeStatus::InconsistentEqualities`] with the part of `b_E` outside
//! the range, `|b_E - A_EE G b_E|_inf`, relative to `|b|_inf`, when it
//! exceeds [`EQUALITY_RANGE_TOL_REL`]. Any answer is checked on the whole
//! mixed problem (its natural map, `|w_E|` for the free rows, relative to
//! the data, against [`LemkeSettings::tol_residual_unscaled`]) before it is
//! returned, which also catches a non-symmetric `A` whose elimination does
//! not hold.

use nalgebra::{DMatrix, DVector, SVD};

use super::{LemkeFailure, LemkeSettings, LemkeSolution, LemkeStatus, solve_plain};
use crate::solver::lcp::Lcp;
use crate::solver::residuals::{lcp_natural_map, natural_map_relative};
use crate::solver::scaling::LcpScaling;

/// Singular values of the Jacobi-scaled `A_EE` (unit diagonal) below this
/// fraction of the largest count as zero: redundant rows. `A_EE = J_E M^-1
/// J_E^T` squares the singular values of the (whitened) equality rows, so
/// this treats rows dependent to about `1e-5` in angle as redundant; a
/// dependence formed in f64 leaves about `1e-16`.
pub const EQUALITY_RANK_TOL_REL: f64 = 1e-10;

/// Smallest tolerance on the part of `b_E` outside the range of `A_EE`,
/// relative to `|b|_inf`, for the equalities to count as consistent; the
/// tolerance used is the larger of this and Lemke's residual tolerance
/// ([`LemkeSettings::tol_residual`], the acceptance's inside the
/// projection): rows redundant up to that part are solved, and the final
/// check of the whole mixed problem decides.
pub const EQUALITY_RANGE_TOL_REL: f64 = 1e-9;

/// Convergence threshold of the SVD (nalgebra's default, five ulps).
const SVD_EPS: f64 = 5.0 * f64::EPSILON;

/// Iteration limit of the SVD (nalgebra's `0` would mean none).
const SVD_MAX_ITERATIONS: usize = 10_000;

/// Solves a mixed LCP (`lcp.free() > 0`) by elimination (module docs).
pub(super) fn solve(lcp: &Lcp, settings: &LemkeSettings) -> Result<LemkeSolution, LemkeFailure> {
    let (e, n) = (lcp.free(), lcp.n());
    let ni = n - e;
    let (m, q) = (lcp.m(), lcp.q());
    let a_ee = m.view((0, 0), (e, e)).into_owned();
    let a_ei = m.view((0, e), (e, ni)).into_owned();
    let a_ie = m.view((e, 0), (ni, e)).into_owned();
    let b_e = q.rows(0, e).into_owned();
    let g = generalized_inverse(&a_ee, &b_e).ok_or_else(|| failure(inaccurate(f64::INFINITY)))?;
    let g_b = &g * &b_e;
    let outside = (&b_e - &a_ee * &g_b).amax();
    let scale = q.amax().max(f64::MIN_POSITIVE);
    // Consistent within what the final check accepts: Lemke's own
    // residual tolerance (the acceptance's, inside the projection), at
    // least `EQUALITY_RANGE_TOL_REL`.
    let range_tolerance = EQUALITY_RANGE_TOL_REL.max(settings.tol_residual);
    if outside.is_nan() || outside > range_tolerance * scale {
        let residual = outside / scale;
        log::debug!("lemke: equality rows inconsistent, {residual:.2e} of b outside the range");
        return Err(failure(LemkeStatus::InconsistentEqualities { residual }));
    }
    let g_a = &g * &a_ei;
    let s = m.view((e, e), (ni, ni)) - &a_ie * &g_a;
    let q_i = q.rows(e, ni) - &a_ie * &g_b;
    // Non-finite only when G overflowed (a nearly singular A_EE at the
    // edge of the rank tolerance).
    let reduced = Lcp::new(s, q_i).map_err(|_| failure(inaccurate(f64::INFINITY)))?;
    let inner = solve_plain(&reduced, settings)?;
    let z_e = -(g_b + g_a * &inner.z);
    let mut z = DVector::zeros(n);
    z.rows_mut(0, e).copy_from(&z_e);
    z.rows_mut(e, ni).copy_from(&inner.z);
    let relative = natural_map_relative(m, q, &z, e);
    if relative.is_nan() || relative > settings.tol_residual_unscaled {
        return Err(LemkeFailure {
            status: inaccurate(relative),
            attempts: inner.attempts,
            pivots: inner.pivots,
        });
    }
    let w = lcp.w(&z);
    Ok(LemkeSolution {
        residual: lcp_natural_map(&z, &w, q, e),
        z,
        w,
        ..inner
    })
}

fn inaccurate(residual: f64) -> LemkeStatus {
    LemkeStatus::Inaccurate { residual }
}

fn failure(status: LemkeStatus) -> LemkeFailure {
    LemkeFailure {
        status,
        attempts: Vec::new(),
        pivots: 0,
    }
}

/// `G = D (D A D)^+ D` (module docs), `None` when the SVD does not
/// converge or `G` is not finite.
fn generalized_inverse(a: &DMatrix<f64>, b: &DVector<f64>) -> Option<DMatrix<f64>> {
    let scaling = LcpScaling::jacobi(a, b);
    let svd = SVD::try_new(scaling.scale_m(a), true, true, SVD_EPS, SVD_MAX_ITERATIONS)?;
    let largest = svd.singular_values.max();
    let pinv = svd.pseudo_inverse(EQUALITY_RANK_TOL_REL * largest).ok()?;
    let d = DMatrix::from_diagonal(&scaling.d);
    let g = &d * pinv * &d;
    g.iter().all(|x| x.is_finite()).then_some(g)
}
