//! The lower Cholesky factor of the active rows' Delassus matrix, kept
//! by appending a row and by removing one with column rotations.

/// The lower Cholesky factor `L` of `W_A = N_A^T M^-1 N_A`, the active
/// rows' Delassus matrix, dense and row-major in a square of `capacity`
/// (at most `min(n, m)` independent rows are ever active).
pub(super) struct ActiveFactor {
    pub(super) capacity: usize,
    l: Vec<f64>,
    /// `1 / L_ii` (the solves multiply: a division per entry was a fifth
    /// of a step).
    inverse_diagonal: Vec<f64>,
}

impl ActiveFactor {
    pub(super) fn new(capacity: usize) -> Self {
        Self {
            capacity,
            l: vec![0.0; capacity * capacity],
            inverse_diagonal: vec![0.0; capacity],
        }
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.l[i * self.capacity + j]
    }

    /// `y = L^-1 w` (`q = w.len()`).
    pub(super) fn solve_lower(&self, w: &[f64]) -> Vec<f64> {
        let mut y = Vec::with_capacity(w.len());
        self.solve_lower_into(w, &mut y);
        y
    }

    /// `y = L^-1 w` into `y` (its contents replaced): the steps' solves
    /// reuse one buffer.
    pub(super) fn solve_lower_into(&self, w: &[f64], y: &mut Vec<f64>) {
        y.clear();
        y.extend_from_slice(w);
        for i in 0..y.len() {
            let row = &self.l[i * self.capacity..i * self.capacity + i + 1];
            let sum: f64 = row[..i].iter().zip(&y[..i]).map(|(a, b)| a * b).sum();
            y[i] = (y[i] - sum) * self.inverse_diagonal[i];
        }
    }

    /// `r = L^-T y`, by columns of `L^T` (rows of `L`).
    pub(super) fn solve_upper(&self, y: &[f64]) -> Vec<f64> {
        let mut r = Vec::with_capacity(y.len());
        self.solve_upper_into(y, &mut r);
        r
    }

    /// `r = L^-T y` into `r` (its contents replaced).
    pub(super) fn solve_upper_into(&self, y: &[f64], r: &mut Vec<f64>) {
        r.clear();
        r.extend_from_slice(y);
        for i in (0..r.len()).rev() {
            let row = &self.l[i * self.capacity..i * self.capacity + i + 1];
            r[i] *= self.inverse_diagonal[i];
            let ri = r[i];
            for (rj, lij) in r[..i].iter_mut().zip(&row[..i]) {
                *rj -= lij * ri;
            }
        }
    }

    /// Appends the row `[y^T, pivot]` (the new row's column of `W_A` was
    /// `w = L y`, its diagonal `|y|^2 + pivot^2`).
    pub(super) fn append(&mut self, y: &[f64], pivot: f64) {
        let q = y.len();
        let row = &mut self.l[q * self.capacity..q * self.capacity + q + 1];
        row[..q].copy_from_slice(y);
        row[q] = pivot;
        self.inverse_diagonal[q] = 1.0 / pivot;
    }

    /// Removes active row `k` of `q`: the rows after it move up one,
    /// which leaves one entry above the diagonal in each of them; a
    /// rotation of columns `(j, j + 1)` (`L <- L G`, so `L L^T` keeps)
    /// zeroes it, row by row.
    pub(super) fn remove(&mut self, k: usize, q: usize) {
        let cap = self.capacity;
        for i in k..q - 1 {
            let (upper, lower) = self.l.split_at_mut((i + 1) * cap);
            upper[i * cap..i * cap + i + 2].copy_from_slice(&lower[..i + 2]);
        }
        for j in 0..q {
            self.l[(q - 1) * cap + j] = 0.0;
        }
        for j in k..q - 1 {
            let (x, y) = (self.at(j, j), self.at(j, j + 1));
            if y == 0.0 {
                continue;
            }
            let h = (x * x + y * y).sqrt();
            let (c, s) = (x / h, y / h);
            for i in j..q - 1 {
                let (a, b) = (self.at(i, j), self.at(i, j + 1));
                self.l[i * cap + j] = c * a + s * b;
                self.l[i * cap + j + 1] = -s * a + c * b;
            }
        }
        for i in k..q - 1 {
            self.inverse_diagonal[i] = 1.0 / self.at(i, i);
        }
    }
}
