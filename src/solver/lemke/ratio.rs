//! The lexicographic minimum-ratio test (Cottle, Pang and Stone 1992,
//! section 4.9), which makes Lemke's method terminate on degenerate problems.
//!
//! For an entering column `a = B^-1 A_c`, the candidate rows are those with
//! `a_r > 0`; the leaving row minimizes, lexicographically, the row vector
//!
//! ```text
//! (rhs_r, (B^-1)_r0, (B^-1)_r1, ...) / a_r
//! ```
//!
//! Rows of `B^-1` are linearly independent, so the minimum is unique: no
//! basis repeats and the method cannot cycle. Floating-point ties are ties
//! within [`super::LemkeSettings::tol_tie`], relative to the size of the
//! compared values. When `z0` can leave it is chosen at once (the path ends
//! there).
//!
//! The first step is special: `z0` enters with column `-d` (all negative)
//! and must leave every row feasible, so the row is the lexicographic
//! minimum of `(q_r, e_r) / d_r` over all rows: the most negative `q_r / d_r`.

use super::tableau::Tableau;

/// Tolerances of the ratio test.
#[derive(Debug, Clone, Copy)]
pub struct RatioTolerances {
    /// A pivot element must exceed this fraction of the column's largest
    /// magnitude.
    pub pivot_rel: f64,
    /// A column whose largest magnitude is below this is zero (a ray).
    pub zero_column: f64,
    /// Relative tie width.
    pub tie: f64,
}

/// Leaving row for entering column `c`, or `None` when no entry qualifies
/// (a ray: the entering variable can grow without bound).
pub fn leaving_row(t: &Tableau, c: usize, first: bool, tol: &RatioTolerances) -> Option<usize> {
    let column = t.column(c);
    let col_max = column.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if col_max <= tol.zero_column {
        return None;
    }
    let sign = if first { -1.0 } else { 1.0 };
    let threshold = tol.pivot_rel * col_max;
    let candidates: Vec<(usize, f64)> = column
        .iter()
        .enumerate()
        .map(|(r, &a)| (r, sign * a))
        .filter(|&(_, a)| a > threshold)
        .collect();
    if candidates.is_empty() {
        return None;
    }
    let tied = keep_minimal(&candidates, |r, a| t.rhs(r) / a, tol.tie);
    if let Some(&(r, _)) = tied.iter().find(|(r, _)| t.basis[*r] == t.z0()) {
        return Some(r);
    }
    Some(lexicographic(t, tied, tol.tie))
}

/// Breaks ties with the columns of `B^-1`, in order.
fn lexicographic(t: &Tableau, mut tied: Vec<(usize, f64)>, tie: f64) -> usize {
    let mut j = 0;
    while tied.len() > 1 && j < t.n() {
        tied = keep_minimal(&tied, |r, a| t.at(r, j) / a, tie);
        j += 1;
    }
    tied[0].0
}

/// The candidates whose `key` is within the tie width of the minimum key.
fn keep_minimal(
    candidates: &[(usize, f64)],
    key: impl Fn(usize, f64) -> f64,
    tie: f64,
) -> Vec<(usize, f64)> {
    let keys: Vec<f64> = candidates.iter().map(|&(r, a)| key(r, a)).collect();
    let min = keys.iter().copied().fold(f64::INFINITY, f64::min);
    let width = tie * (1.0 + min.abs());
    candidates
        .iter()
        .zip(&keys)
        .filter(|&(_, k)| *k <= min + width)
        .map(|(c, _)| *c)
        .collect()
}
