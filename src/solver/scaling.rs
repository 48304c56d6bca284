//! Symmetric diagonal scaling of an LCP, so that tolerances can be absolute
//! in the scaled problem and relative in the original one.
//!
//! With `D = diag(d)`, `d > 0`, and `s > 0`, the LCP `(M, q)` is equivalent to
//!
//! ```text
//! M~ = D M D,   q~ = D q / s,   z = s D z~,   w = s D^-1 w~
//! ```
//!
//! since `w~ = M~ z~ + q~ = D (M z + q) / s`. Signs and complementarity are
//! unchanged. Jacobi scaling `d_i = 1/sqrt(M_ii)` gives `M~` a unit diagonal
//! (for a contact LCP `A = J M^-1 J^T` this removes the spread of masses and
//! lengths); `s = ||D q||_inf` makes `||q~||_inf = 1`.

use nalgebra::{DMatrix, DVector};

/// Diagonal entries below this fraction of `max|M|` are treated as zero for
/// the Jacobi scale: that row gets `1/sqrt(r_i)`, `r_i` the largest entry of
/// its row and column, or `1/sqrt(max|M|)` if `r_i` is below
/// [`JACOBI_MIN_ROW_REL`] of `max|M|`.
///
/// The row's own magnitude, not `max|M|`: with the global one a row with a
/// zero diagonal among large entries gets a scale far below its
/// neighbours', which hides its violation in the scaled problem (the kept
/// fuzz input `tests/data/fuzz/lcp_solvers/crash-lemke-natural-map`;
/// `benchmarks/results/fuzzing.md`).
pub const JACOBI_MIN_DIAG_REL: f64 = 1e-14;

/// A row (with its column) whose largest entry is below this fraction of
/// `max|M|` is zero for the scaling (about `eps^2`: far below any entry that
/// a pivot can resolve, far above underflow).
pub const JACOBI_MIN_ROW_REL: f64 = 1e-30;

/// The scaling `(d, s)` of an LCP.
#[derive(Debug, Clone, PartialEq)]
pub struct LcpScaling {
    /// Diagonal of `D`, all positive.
    pub d: DVector<f64>,
    /// Scale `s > 0` of `q`.
    pub s: f64,
}

impl LcpScaling {
    /// Jacobi scaling of `M`, then normalization of `q`.
    pub fn jacobi(m: &DMatrix<f64>, q: &DVector<f64>) -> Self {
        let size = m.amax();
        let fallback = if size > 0.0 { 1.0 / size.sqrt() } else { 1.0 };
        let floor = JACOBI_MIN_DIAG_REL * size;
        let d = DVector::from_iterator(
            q.len(),
            (0..q.len()).map(|i| {
                let mii = m[(i, i)];
                if mii > floor {
                    return 1.0 / mii.sqrt();
                }
                // Only a row with a (near) zero diagonal reads its row and
                // column.
                let own = m.row(i).amax().max(m.column(i).amax());
                if own > JACOBI_MIN_ROW_REL * size {
                    1.0 / own.sqrt()
                } else {
                    fallback
                }
            }),
        );
        let dq_norm = d.component_mul(q).amax();
        let s = if dq_norm > 0.0 { dq_norm } else { 1.0 };
        Self { d, s }
    }

    /// `D M D`.
    pub fn scale_m(&self, m: &DMatrix<f64>) -> DMatrix<f64> {
        let mut out = m.clone();
        for j in 0..m.ncols() {
            for i in 0..m.nrows() {
                out[(i, j)] *= self.d[i] * self.d[j];
            }
        }
        out
    }

    /// `D q / s`.
    pub fn scale_q(&self, q: &DVector<f64>) -> DVector<f64> {
        self.d.component_mul(q) / self.s
    }

    /// `z = s D z~`.
    pub fn unscale_z(&self, z_scaled: &DVector<f64>) -> DVector<f64> {
        self.d.component_mul(z_scaled) * self.s
    }
}
