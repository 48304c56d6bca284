//! The condensed tableau of Lemke's method and its pivot.
//!
//! The system `I w - M z - d z0 = q` has `2n + 1` variables, numbered
//! `w_i = i`, `z_i = n + i`, `z0 = 2n`. With `B` the columns of the `n`
//! basic variables and `N` those of the `n + 1` nonbasic ones, the full
//! tableau is `B^-1 [I | -M | -d | q]`; its basic columns are unit vectors,
//! so only `D = B^-1 N` and `rhs = B^-1 q` are stored (Tucker's condensed
//! form): `n` rows of `n + 2` entries, row-major. [`Tableau::at`] and
//! [`Tableau::column`] answer for any variable, basic or not; columns
//! `0..n` of the full tableau are `B^-1`, which the lexicographic ratio
//! test reads.
//!
//! A pivot (variable `e` enters in row `r`, `l = basis[r]` leaves) costs
//! `n (n + 2)` multiply-adds, half of the full tableau's `n (2n + 2)`:
//!
//! ```text
//! p = D[r][c]                      (c: the column of e)
//! D'[r][j] = D[r][j] / p,          D'[r][c] = 1 / p
//! D'[i][j] = D[i][j] - D[i][c] D[r][j] / p,   D'[i][c] = -D[i][c] / p
//! ```
//!
//! and column `c` then belongs to `l`. Refactorizing from scratch (an LU
//! of `B`, `O(n^3)`) is [`Tableau::refactor`], for comparison and
//! clean-up; `benchmarks/solvers.rs` measures both.

use nalgebra::{DMatrix, DVector};

/// The condensed tableau and its basis.
#[derive(Debug, Clone)]
pub struct Tableau {
    n: usize,
    /// `n + 2`: `n + 1` nonbasic columns and `rhs`.
    stride: usize,
    data: Vec<f64>,
    /// `basis[r]` = the variable basic in row `r`.
    pub basis: Vec<usize>,
    /// `nonbasic[c]` = the variable of column `c`.
    nonbasic: Vec<usize>,
    /// Column of each variable, if nonbasic.
    column_of: Vec<Option<usize>>,
}

impl Tableau {
    /// The starting tableau: basis `w`, `D = [-M | -d]`, `rhs = q`.
    pub fn new(m: &DMatrix<f64>, d: &DVector<f64>, q: &DVector<f64>) -> Self {
        let n = q.len();
        let stride = n + 2;
        let mut data = vec![0.0; n * stride];
        for r in 0..n {
            let row = &mut data[r * stride..(r + 1) * stride];
            for j in 0..n {
                row[j] = -m[(r, j)];
            }
            row[n] = -d[r];
            row[n + 1] = q[r];
        }
        let nonbasic: Vec<usize> = (n..=2 * n).collect();
        let mut column_of = vec![None; 2 * n + 1];
        for (c, &v) in nonbasic.iter().enumerate() {
            column_of[v] = Some(c);
        }
        Self {
            n,
            stride,
            data,
            basis: (0..n).collect(),
            nonbasic,
            column_of,
        }
    }

    /// Problem size.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Variable index of `z0`.
    pub fn z0(&self) -> usize {
        2 * self.n
    }

    /// Entry `(r, v)` of the full tableau `B^-1 [I | -M | -d]`.
    pub fn at(&self, r: usize, v: usize) -> f64 {
        match self.column_of[v] {
            Some(c) => self.data[r * self.stride + c],
            None => f64::from(u8::from(self.basis[r] == v)),
        }
    }

    /// Value of the basic variable of row `r`.
    pub fn rhs(&self, r: usize) -> f64 {
        self.data[r * self.stride + self.stride - 1]
    }

    /// Column of variable `v` of the full tableau (all rows).
    pub fn column(&self, v: usize) -> Vec<f64> {
        (0..self.n).map(|r| self.at(r, v)).collect()
    }

    /// Pivots nonbasic variable `e` into the basis in row `r`; returns the
    /// variable that left. `e` must be nonbasic.
    pub fn pivot(&mut self, r: usize, e: usize) -> usize {
        let Some(c) = self.column_of[e] else {
            // The path enters z0 first, then always the complement of the
            // variable that just left: nonbasic by construction (a basis
            // holds one variable of each complementary pair but one).
            debug_assert!(false, "entering variable {e} is basic");
            return e;
        };
        let stride = self.stride;
        let (before, rest) = self.data.split_at_mut(r * stride);
        let (pivot_row, after) = rest.split_at_mut(stride);
        let inv = 1.0 / pivot_row[c];
        pivot_row.iter_mut().for_each(|x| *x *= inv);
        pivot_row[c] = inv;
        for row in before
            .chunks_exact_mut(stride)
            .chain(after.chunks_exact_mut(stride))
        {
            let f = row[c];
            if f != 0.0 {
                row.iter_mut()
                    .zip(pivot_row.iter())
                    .for_each(|(x, p)| *x -= f * p);
                row[c] = -f * inv;
            }
        }
        let leaving = std::mem::replace(&mut self.basis[r], e);
        self.nonbasic[c] = leaving;
        self.column_of[leaving] = Some(c);
        self.column_of[e] = None;
        leaving
    }

    /// Recomputes `D = B^-1 N` and `rhs = B^-1 q` from the original data
    /// with an LU factorization of the current basis. Returns `false`
    /// (tableau unchanged) when `B` is numerically singular.
    pub fn refactor(&mut self, m: &DMatrix<f64>, d: &DVector<f64>, q: &DVector<f64>) -> bool {
        let n = self.n;
        if n == 0 {
            return true;
        }
        let full = original_columns(m, d, q);
        let b = DMatrix::from_fn(n, n, |i, r| full[(i, self.basis[r])]);
        let rhs_cols = DMatrix::from_fn(n, self.stride, |i, c| {
            if c < n + 1 {
                full[(i, self.nonbasic[c])]
            } else {
                q[i]
            }
        });
        let Some(solved) = b.lu().solve(&rhs_cols) else {
            return false;
        };
        if !solved.iter().all(|x| x.is_finite()) {
            return false;
        }
        for r in 0..n {
            for c in 0..self.stride {
                self.data[r * self.stride + c] = solved[(r, c)];
            }
        }
        true
    }
}

/// `[I | -M | -d | q]` as a dense `n x (2n + 2)` matrix.
pub fn original_columns(m: &DMatrix<f64>, d: &DVector<f64>, q: &DVector<f64>) -> DMatrix<f64> {
    let n = q.len();
    DMatrix::from_fn(n, 2 * n + 2, |i, c| match c {
        c if c < n => f64::from(u8::from(i == c)),
        c if c < 2 * n => -m[(i, c - n)],
        c if c == 2 * n => -d[i],
        _ => q[i],
    })
}
