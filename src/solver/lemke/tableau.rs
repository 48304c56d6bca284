//! The dense tableau of Lemke's method and its pivot (Gauss-Jordan update).
//!
//! The system `I w - M z - d z0 = q` has `2n + 1` variables, numbered
//! `w_i = i`, `z_i = n + i`, `z0 = 2n`. The tableau stores
//! `B^-1 [I | -M | -d | q]`, row-major, `n` rows of `2n + 2` entries, where
//! `B` holds the columns of the basic variables (`basis[r]` is basic in row
//! `r`, its value `rhs(r)`). Columns `0..n` are therefore `B^-1` itself: the
//! lexicographic ratio test reads them.
//!
//! A pivot on `(r, c)` costs `O(n^2)`: divide row `r` by `T[r][c]`, then
//! eliminate column `c` from the other rows. Refactorizing from scratch
//! (an LU of `B`, `O(n^3)`) is available as [`Tableau::refactor`] for
//! comparison and periodic clean-up.

use nalgebra::{DMatrix, DVector};

/// The tableau and its basis.
#[derive(Debug, Clone)]
pub struct Tableau {
    n: usize,
    stride: usize,
    data: Vec<f64>,
    /// `basis[r]` = the variable basic in row `r`.
    pub basis: Vec<usize>,
}

impl Tableau {
    /// The starting tableau: basis `w`, data `[I | -M | -d | q]`.
    pub fn new(m: &DMatrix<f64>, d: &DVector<f64>, q: &DVector<f64>) -> Self {
        let n = q.len();
        let stride = 2 * n + 2;
        let mut data = vec![0.0; n * stride];
        for r in 0..n {
            let row = &mut data[r * stride..(r + 1) * stride];
            row[r] = 1.0;
            for j in 0..n {
                row[n + j] = -m[(r, j)];
            }
            row[2 * n] = -d[r];
            row[2 * n + 1] = q[r];
        }
        Self {
            n,
            stride,
            data,
            basis: (0..n).collect(),
        }
    }

    /// Problem size.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Column index of `z0`.
    pub fn z0(&self) -> usize {
        2 * self.n
    }

    /// Entry `(r, c)`.
    pub fn at(&self, r: usize, c: usize) -> f64 {
        self.data[r * self.stride + c]
    }

    /// Value of the basic variable of row `r`.
    pub fn rhs(&self, r: usize) -> f64 {
        self.at(r, self.stride - 1)
    }

    /// Column `c` (all rows).
    pub fn column(&self, c: usize) -> Vec<f64> {
        (0..self.n).map(|r| self.at(r, c)).collect()
    }

    /// Pivots variable `c` into the basis in row `r`; returns the variable
    /// that left.
    pub fn pivot(&mut self, r: usize, c: usize) -> usize {
        let stride = self.stride;
        let pivot = self.at(r, c);
        let (before, rest) = self.data.split_at_mut(r * stride);
        let (pivot_row, after) = rest.split_at_mut(stride);
        pivot_row.iter_mut().for_each(|x| *x /= pivot);
        pivot_row[c] = 1.0;
        for row in before
            .chunks_exact_mut(stride)
            .chain(after.chunks_exact_mut(stride))
        {
            let f = row[c];
            if f != 0.0 {
                row.iter_mut()
                    .zip(pivot_row.iter())
                    .for_each(|(x, p)| *x -= f * p);
                row[c] = 0.0;
            }
        }
        std::mem::replace(&mut self.basis[r], c)
    }

    /// Recomputes the whole tableau as `B^-1 [I | -M | -d | q]` from the
    /// original data with an LU factorization of the current basis. Returns
    /// `false` (tableau unchanged) when `B` is numerically singular.
    pub fn refactor(&mut self, m: &DMatrix<f64>, d: &DVector<f64>, q: &DVector<f64>) -> bool {
        let n = self.n;
        if n == 0 {
            return true;
        }
        let full = original_columns(m, d, q);
        let b = DMatrix::from_fn(n, n, |i, r| full[(i, self.basis[r])]);
        let Some(solved) = b.lu().solve(&full) else {
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
