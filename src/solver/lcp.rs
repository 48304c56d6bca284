//! A dense linear complementarity problem, possibly mixed.
//!
//! ```text
//! find z  with  z >= 0,  w = M z + q >= 0,  z^T w = 0.
//! ```
//!
//! A *mixed* LCP ([`Lcp::mixed`]) has `free` leading variables `z_E`
//! (`E = 0..free`) without a sign, whose rows hold with equality:
//!
//! ```text
//! w_E = 0 (z_E free),   z_I >= 0, w_I >= 0, z_I^T w_I = 0   (I = free..n).
//! ```
//!
//! It is the dual of a projection QP with equality rows
//! (`super::projection`); `free = 0` is the plain LCP.
//!
//! `M` is any real square matrix (Lemke's method handles the nonsymmetric
//! problems of the Siconos test set); the QP solvers apply only when `M` is
//! symmetric positive semidefinite, where the LCP is the optimality system of
//! `min 1/2 z^T M z + q^T z, z >= 0`.

use nalgebra::{DMatrix, DVector};

use super::error::SolverError;
use super::projection::check_finite;

/// Relative asymmetry `max|M - M^T| / max|M|` below which `M` counts as
/// symmetric. `J M^-1 J^T` formed in f64 is symmetric to a few ulps.
pub const SYMMETRY_TOL_REL: f64 = 1e-12;

/// Most negative eigenvalue of the symmetric part, relative to the largest
/// eigenvalue magnitude, that still counts as positive semidefinite. A
/// rank-deficient `J M^-1 J^T` has zero eigenvalues computed as +-1e-16
/// relative; anything far below is genuinely indefinite.
pub const PSD_TOL_REL: f64 = 1e-10;

/// A validated dense LCP `(M, q)`: square, finite; with `free` leading
/// free variables (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Lcp {
    m: DMatrix<f64>,
    q: DVector<f64>,
    free: usize,
}

impl Lcp {
    /// Checks that `M` is square, `q` matches it and every entry is finite.
    pub fn new(m: DMatrix<f64>, q: DVector<f64>) -> Result<Self, SolverError> {
        if m.nrows() != m.ncols() {
            return Err(SolverError::NotSquare {
                rows: m.nrows(),
                cols: m.ncols(),
            });
        }
        if q.len() != m.nrows() {
            return Err(SolverError::DimensionMismatch {
                what: "q",
                expected: m.nrows(),
                found: q.len(),
            });
        }
        check_finite("M", m.as_slice())?;
        check_finite("q", q.as_slice())?;
        Ok(Self { m, q, free: 0 })
    }

    /// The mixed LCP whose first `free` variables are free and whose first
    /// `free` rows hold with equality (module docs); checked as
    /// [`Lcp::new`], and `free <= n`.
    pub fn mixed(m: DMatrix<f64>, q: DVector<f64>, free: usize) -> Result<Self, SolverError> {
        let lcp = Self::new(m, q)?;
        if free > lcp.n() {
            return Err(SolverError::TooManyEqualities {
                num_equalities: free,
                rows: lcp.n(),
            });
        }
        Ok(Self { free, ..lcp })
    }

    /// The number of leading free variables (0 for a plain LCP).
    pub fn free(&self) -> usize {
        self.free
    }

    /// The matrix `M`.
    pub fn m(&self) -> &DMatrix<f64> {
        &self.m
    }

    /// The vector `q`.
    pub fn q(&self) -> &DVector<f64> {
        &self.q
    }

    /// Problem size `n`.
    pub fn n(&self) -> usize {
        self.q.len()
    }

    /// `w = M z + q`.
    pub fn w(&self, z: &DVector<f64>) -> DVector<f64> {
        &self.m * z + &self.q
    }

    /// Whether `M` is symmetric to `SYMMETRY_TOL_REL`.
    pub fn is_symmetric(&self) -> bool {
        let size = self.m.amax();
        (&self.m - self.m.transpose()).amax() <= SYMMETRY_TOL_REL * size
    }

    /// Smallest eigenvalue of the symmetric part `(M + M^T)/2`, relative to
    /// the largest eigenvalue magnitude (0 for the zero matrix).
    pub fn min_eigenvalue_sym_rel(&self) -> f64 {
        if self.n() == 0 {
            return 0.0;
        }
        let sym = (&self.m + self.m.transpose()) * 0.5;
        let eig = sym.symmetric_eigenvalues();
        let largest = eig.amax();
        if largest == 0.0 {
            0.0
        } else {
            eig.min() / largest
        }
    }

    /// Whether the symmetric part is positive semidefinite (then `M` is
    /// copositive-plus and Lemke's method solves the LCP or proves that it
    /// has no solution; Cottle, Pang and Stone 1992, section 4.4).
    pub fn is_psd(&self) -> bool {
        self.min_eigenvalue_sym_rel() >= -PSD_TOL_REL
    }

    /// Whether `M` is symmetric positive semidefinite: the QP forms apply.
    pub fn is_symmetric_psd(&self) -> bool {
        self.is_symmetric() && self.is_psd()
    }
}
