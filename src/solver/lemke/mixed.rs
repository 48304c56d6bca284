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
//! rows than it removes degrees of freedom) make `A_EE` singular. With the
//! Jacobi scaling `D` of `A_EE` (`crate::solver::scaling`: unit diagonal,
//! so that the relative rank tolerance [`EQUALITY_RANK_TOL_REL`] does not
//! depend on masses and lengths), the pivoted Cholesky factorization
//! (faer's, diagonal pivoting) `P X P^T = L L^T` of `X = D A_EE D` stops
//! at the numerical rank `r`: the first pivot below the tolerance. Then
//!
//! ```text
//! G = D P^T [(L_11 L_11^T)^-1, 0; 0, 0] P D
//! ```
//!
//! with `L_11` the leading `r x r` block: `X^- = P^T [(L_11 L_11^T)^-1, 0;
//! 0, 0] P` is a generalized inverse of `X` when its trailing Schur
//! complement vanishes (rank `r`), and `D X^- D` one of `A_EE` (`A D X^- D
//! A = D^-1 X X^- X D^-1 = A`). The factorization costs `O(e^2 r)`;
//! `G` itself is never formed: `G b_E` and `G A_EI` are two triangular
//! solves with `L_11` per column (`O(e r)` each), so a problem of equality
//! rows alone costs one factorization and two solves.
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

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt_pivoting::factor::{cholesky_in_place, cholesky_in_place_scratch};
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, Par};
use nalgebra::{DMatrix, DVector};

use super::{LemkeFailure, LemkeSettings, LemkeSolution, LemkeStatus, solve_plain};
use crate::solver::lcp::Lcp;
use crate::solver::residuals::{lcp_natural_map, natural_map_relative};
use crate::solver::scaling::LcpScaling;

/// Pivots of the pivoted Cholesky factor of the Jacobi-scaled `A_EE`
/// (unit diagonal) below this fraction of the first count as zero:
/// redundant rows. With a unit diagonal the pivot of a row is the squared
/// sine of its (whitened) angle to the span of the rows pivoted before it,
/// so this treats rows dependent to about `1e-5` in angle as redundant; a
/// dependence formed in f64 leaves about `1e-16`.
pub const EQUALITY_RANK_TOL_REL: f64 = 1e-10;

/// Smallest tolerance on the part of `b_E` outside the range of `A_EE`,
/// relative to `|b|_inf`, for the equalities to count as consistent; the
/// tolerance used is the larger of this and Lemke's residual tolerance
/// ([`LemkeSettings::tol_residual`], the acceptance's inside the
/// projection): rows redundant up to that part are solved, and the final
/// check of the whole mixed problem decides.
pub const EQUALITY_RANGE_TOL_REL: f64 = 1e-9;

/// Solves a mixed LCP (`lcp.free() > 0`) by elimination (module docs).
pub(super) fn solve(lcp: &Lcp, settings: &LemkeSettings) -> Result<LemkeSolution, LemkeFailure> {
    let (e, n) = (lcp.free(), lcp.n());
    let ni = n - e;
    let (m, q) = (lcp.m(), lcp.q());
    let a_ee = m.view((0, 0), (e, e)).into_owned();
    let a_ei = m.view((0, e), (e, ni)).into_owned();
    let a_ie = m.view((e, 0), (ni, e)).into_owned();
    let b_e = q.rows(0, e).into_owned();
    let not_finite = || failure(inaccurate(f64::INFINITY));
    let g = EqualityInverse::new(&a_ee, &b_e).ok_or_else(not_finite)?;
    let g_b = g
        .apply(&DMatrix::from_column_slice(e, 1, b_e.as_slice()))
        .ok_or_else(not_finite)?
        .column(0)
        .into_owned();
    check_range(&(&b_e - &a_ee * &g_b), q, settings)?;
    let g_a = g.apply(&a_ei).ok_or_else(not_finite)?;
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

/// The range test of the module docs: `Err` with
/// [`LemkeStatus::InconsistentEqualities`] when the part of `b_E` outside
/// the range of `A_EE`, `outside = b_E - A_EE G b_E`, exceeds what the
/// final check accepts (Lemke's own residual tolerance, the acceptance's
/// inside the projection, at least [`EQUALITY_RANGE_TOL_REL`]) relative
/// to `|b|_inf`.
pub(crate) fn check_range(
    outside: &DVector<f64>,
    b: &DVector<f64>,
    settings: &LemkeSettings,
) -> Result<(), LemkeFailure> {
    let outside = outside.amax();
    let scale = b.amax().max(f64::MIN_POSITIVE);
    let range_tolerance = EQUALITY_RANGE_TOL_REL.max(settings.tol_residual);
    if outside.is_nan() || outside > range_tolerance * scale {
        let residual = outside / scale;
        log::debug!("lemke: equality rows inconsistent, {residual:.2e} of b outside the range");
        return Err(failure(LemkeStatus::InconsistentEqualities { residual }));
    }
    Ok(())
}

/// [`LemkeStatus::Inaccurate`] with `residual`.
pub(crate) fn inaccurate(residual: f64) -> LemkeStatus {
    LemkeStatus::Inaccurate { residual }
}

/// A failure before any pivot.
pub(crate) fn failure(status: LemkeStatus) -> LemkeFailure {
    LemkeFailure {
        status,
        attempts: Vec::new(),
        pivots: 0,
    }
}

/// The generalized inverse `G = D P^T [(L_11 L_11^T)^-1, 0; 0, 0] P D` of
/// `A_EE` (module docs), kept as its factor: `G` is applied by two
/// triangular solves with `L_11` (`O(e r)` per column), never formed.
struct EqualityInverse {
    /// The pivoted Cholesky factor of `X = D A_EE D`: `L` in the lower
    /// triangle (the leading `rank` columns are used).
    factor: Mat<f64>,
    /// The numerical rank `r`.
    rank: usize,
    /// The pivoting: row `i` of `P X P^T` is row `perm[i]` of `X`.
    perm: Vec<usize>,
    /// The Jacobi scaling `D`.
    d: DVector<f64>,
}

impl EqualityInverse {
    /// Factors the Jacobi-scaled `A_EE`; `None` when the factorization
    /// fails.
    fn new(a: &DMatrix<f64>, b: &DVector<f64>) -> Option<Self> {
        let scaling = LcpScaling::jacobi(a, b);
        let scaled = scaling.scale_m(a);
        let n = scaled.nrows();
        let mut factor = Mat::<f64>::from_fn(n, n, |i, j| scaled[(i, j)]);
        let (mut perm, mut perm_inv) = (vec![0usize; n], vec![0usize; n]);
        let params = Default::default();
        let mut workspace =
            MemBuffer::try_new(cholesky_in_place_scratch::<usize, f64>(n, Par::Seq, params))
                .ok()?;
        cholesky_in_place(
            factor.as_mut(),
            &mut perm,
            &mut perm_inv,
            Par::Seq,
            MemStack::new(&mut workspace),
            params,
        )
        .ok()?;
        // The pivots `L_jj^2` do not increase (each is the largest left);
        // the rank is where they fall below the tolerance relative to the
        // first.
        let first = if n > 0 { factor[(0, 0)].powi(2) } else { 0.0 };
        let rank = (0..n)
            .take_while(|&j| factor[(j, j)].powi(2) > EQUALITY_RANK_TOL_REL * first)
            .count();
        Some(Self {
            factor,
            rank,
            perm,
            d: scaling.d,
        })
    }

    /// `G x` for every column of `x` (`e` rows); `None` when it is not
    /// finite (a nearly singular `A_EE` at the edge of the rank tolerance).
    fn apply(&self, x: &DMatrix<f64>) -> Option<DMatrix<f64>> {
        let (r, k) = (self.rank, x.ncols());
        let (perm, d) = (&self.perm, &self.d);
        let mut y = Mat::<f64>::from_fn(r, k, |i, j| d[perm[i]] * x[(perm[i], j)]);
        let l_11 = self.factor.as_ref().submatrix(0, 0, r, r);
        solve_lower_triangular_in_place(l_11, y.as_mut(), Par::Seq);
        solve_upper_triangular_in_place(l_11.transpose(), y.as_mut(), Par::Seq);
        let mut g_x = DMatrix::zeros(x.nrows(), k);
        for i in 0..r {
            for j in 0..k {
                g_x[(perm[i], j)] = d[perm[i]] * y[(i, j)];
            }
        }
        g_x.iter().all(|v| v.is_finite()).then_some(g_x)
    }
}
