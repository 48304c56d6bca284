//! One run of Lemke's complementary pivoting (Lemke 1965; Cottle, Pang and
//! Stone 1992, section 4.4) on a scaled LCP, and the extraction of `z` from
//! its final basis.
//!
//! Start from the basis `w` with the artificial variable `z0` at the value
//! that makes `w = q + d z0 >= 0`. Then repeat: the complement of the
//! variable that just left enters; the lexicographic ratio test picks the
//! row that leaves. The path ends when `z0` leaves (a solution), when an
//! entering column has no positive entry (a secondary ray), at the pivot
//! limit, or at the deadline (checked before each pivot).

use std::time::Instant;

use nalgebra::{DMatrix, DVector};

use super::ratio::{RatioTolerances, leaving_row};
use super::tableau::Tableau;

/// How a path ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathEnd {
    /// `z0` left the basis: the basis is complementary.
    Complementary,
    /// Ray termination.
    Ray,
    /// Pivot limit.
    PivotLimit,
    /// The deadline passed.
    DeadlinePassed,
}

/// A finished path.
pub struct Path {
    /// How it ended.
    pub end: PathEnd,
    /// The final tableau.
    pub tableau: Tableau,
    /// Pivots made.
    pub pivots: usize,
}

/// Options of one run.
pub struct PathOptions {
    /// Pivot limit.
    pub max_pivots: usize,
    /// Refactorize the tableau every this many pivots (0 = never).
    pub refactor_every: usize,
    /// Stop before the next pivot once this instant has passed.
    pub deadline: Option<Instant>,
    /// Ratio-test tolerances.
    pub ratio: RatioTolerances,
}

fn complement(variable: usize, n: usize) -> usize {
    if variable < n {
        variable + n
    } else {
        variable - n
    }
}

/// Runs Lemke's method on `(m, q)` with covering vector `d > 0`.
pub fn run(m: &DMatrix<f64>, d: &DVector<f64>, q: &DVector<f64>, options: &PathOptions) -> Path {
    let n = q.len();
    let mut tableau = Tableau::new(m, d, q);
    if q.iter().all(|&x| x >= 0.0) {
        return Path {
            end: PathEnd::Complementary,
            tableau,
            pivots: 0,
        };
    }
    let mut entering = tableau.z0();
    let mut pivots = 0;
    loop {
        if pivots >= options.max_pivots {
            return Path {
                end: PathEnd::PivotLimit,
                tableau,
                pivots,
            };
        }
        if options.deadline.is_some_and(|d| Instant::now() >= d) {
            return Path {
                end: PathEnd::DeadlinePassed,
                tableau,
                pivots,
            };
        }
        let Some(row) = leaving_row(&tableau, entering, pivots == 0, &options.ratio) else {
            return Path {
                end: PathEnd::Ray,
                tableau,
                pivots,
            };
        };
        let leaving = tableau.pivot(row, entering);
        pivots += 1;
        if options.refactor_every > 0 && pivots % options.refactor_every == 0 {
            tableau.refactor(m, d, q);
        }
        log::trace!("lemke pivot {pivots}: {entering} enters in row {row}, {leaving} leaves");
        if leaving == tableau.z0() {
            return Path {
                end: PathEnd::Complementary,
                tableau,
                pivots,
            };
        }
        entering = complement(leaving, n);
    }
}

/// `z` read from the tableau (zero for nonbasic `z_i`).
pub fn z_from_tableau(tableau: &Tableau) -> DVector<f64> {
    let n = tableau.n();
    let mut z = DVector::zeros(n);
    for (r, &v) in tableau.basis.iter().enumerate() {
        if (n..2 * n).contains(&v) {
            z[v - n] = tableau.rhs(r);
        }
    }
    z
}

/// `z` from a fresh LU solve `B x = q` with the basis columns of the
/// original `[I | -M]` (no `z0`): removes the rounding that the pivots
/// accumulated, and, after a regularized run, re-solves the unregularized
/// problem in the same basis. `None` if `z0` is basic or `B` is singular.
///
/// With `S` the rows whose `w_i` is basic and `T` the indices of the basic
/// `z_j`, `B` is, up to the order of its columns and rows, the block
/// triangle `[I_S, -M_ST; 0, -M_RT]` (`R` the rows outside `S`, as many as
/// `T` has entries), so `B x = q` is `M_RT z_T = -q_R` and then
/// `w_S = q_S + M_ST z_T`: one LU of the `|T| x |T|` block instead of the
/// `n x n` basis, singular exactly when `B` is.
pub fn z_from_basis(basis: &[usize], m: &DMatrix<f64>, q: &DVector<f64>) -> Option<DVector<f64>> {
    let n = q.len();
    if basis.contains(&(2 * n)) {
        return None;
    }
    let mut w_basic = vec![false; n];
    let mut z_basic = Vec::new();
    for &v in basis {
        if v < n {
            w_basic[v] = true;
        } else if v < 2 * n {
            z_basic.push(v - n);
        }
    }
    let rows: Vec<usize> = (0..n).filter(|&i| !w_basic[i]).collect();
    if rows.len() != z_basic.len() {
        // Not a basis of n distinct columns of [I | -M].
        return None;
    }
    let mut z = DVector::zeros(n);
    if z_basic.is_empty() {
        return Some(z);
    }
    let k = z_basic.len();
    let block = DMatrix::from_fn(k, k, |r, c| m[(rows[r], z_basic[c])]);
    let rhs = DVector::from_fn(k, |r, _| -q[rows[r]]);
    let x = block.lu().solve(&rhs)?;
    if !x.iter().all(|v| v.is_finite()) {
        return None;
    }
    for (c, &j) in z_basic.iter().enumerate() {
        z[j] = x[c];
    }
    Some(z)
}
