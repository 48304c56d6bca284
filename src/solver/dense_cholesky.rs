//! A dense Cholesky factor `H = L L^T` of the small body-space matrices
//! (up to `dense_max_dofs`, 96 entries of `dq`), written for their size:
//! the right-looking (outer-product) elimination, whose inner loops run
//! down contiguous columns of the column-major array, and triangular solves
//! in place. The same arithmetic as any Cholesky; on these sizes nalgebra's
//! generic one spent most of its time outside the floating-point work
//! (perf on the thrown box's interior point: factor and solves a fifth of
//! the solve).
//!
//! For `j = 0..n` (`A` overwritten by `L`): `L_jj = sqrt(A_jj)`,
//! `L_ij = A_ij / L_jj` (`i > j`), then the trailing lower triangle
//! `A_rc -= L_rj L_cj` (`r >= c > j`). A pivot that is not
//! positive and finite fails the factorization (rounding on a matrix that
//! is positive definite in exact arithmetic; the caller retries or falls
//! back). Not part of the stable API (public for the tests).

use nalgebra::{DMatrix, DVector};

/// The factor `L` (lower triangle of a column-major `n x n` matrix; the
/// upper triangle holds what was there).
#[derive(Debug, Clone)]
pub struct DenseCholesky {
    l: DMatrix<f64>,
}

impl DenseCholesky {
    /// Factors the symmetric `h` (its lower triangle is read), or `None`
    /// when a pivot is not positive and finite.
    pub fn new(mut h: DMatrix<f64>) -> Option<Self> {
        let n = h.nrows();
        if h.ncols() != n {
            return None;
        }
        let a = h.as_mut_slice();
        for j in 0..n {
            let pivot = a[j * n + j];
            if !(pivot > 0.0 && pivot.is_finite()) {
                return None;
            }
            let d = pivot.sqrt();
            a[j * n + j] = d;
            for x in &mut a[j * n + j + 1..(j + 1) * n] {
                *x /= d;
            }
            // The trailing columns c > j: A[c.., c] -= L[c.., j] L[c, j].
            let (head, tail) = a.split_at_mut((j + 1) * n);
            let column_j = &head[j * n..];
            for c in j + 1..n {
                let l_cj = column_j[c];
                if l_cj == 0.0 {
                    continue;
                }
                let target = &mut tail[(c - j - 1) * n + c..(c - j) * n];
                for (t, &l_rj) in target.iter_mut().zip(&column_j[c..n]) {
                    *t -= l_rj * l_cj;
                }
            }
        }
        Some(Self { l: h })
    }

    /// `H^-1 b`.
    pub fn solve(&self, b: &DVector<f64>) -> DVector<f64> {
        let n = self.l.nrows();
        let l = self.l.as_slice();
        let mut x = b.clone();
        let y = x.as_mut_slice();
        // L y = b, column by column.
        for j in 0..n {
            let column = &l[j * n..(j + 1) * n];
            y[j] /= column[j];
            let yj = y[j];
            for (yi, &lij) in y[j + 1..].iter_mut().zip(&column[j + 1..]) {
                *yi -= lij * yj;
            }
        }
        // L^T x = y, from the last row up.
        for j in (0..n).rev() {
            let column = &l[j * n..(j + 1) * n];
            let dot: f64 = column[j + 1..]
                .iter()
                .zip(&y[j + 1..])
                .map(|(a, b)| a * b)
                .sum();
            y[j] = (y[j] - dot) / column[j];
        }
        x
    }
}
