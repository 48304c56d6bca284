//! The LCP as a dual QP for clarabel:
//!
//! ```text
//! minimize 1/2 z^T A z + b^T z   s.t.   z >= 0
//! ```
//!
//! whose KKT conditions are exactly the LCP `z >= 0, w = A z + b >= 0,
//! z^T w = 0` when `A` is symmetric positive semidefinite (`w` is the
//! multiplier of `z >= 0`). clarabel form: `P = triu(A~)`, `c = b~`,
//! `-z~ + s = 0`, `s >= 0`, on the Jacobi-scaled problem of
//! [`crate::solver::scaling`] (unit diagonal, `||b~||_inf = 1`). `P` is
//! dense: `n (n + 1) / 2` entries.

use nalgebra::DVector;

use super::{ClarabelPoint, ClarabelSettings, csc_from_triplets, run};
use crate::solver::lcp::Lcp;
use crate::solver::outcome::FailureReason;
use crate::solver::scaling::LcpScaling;

/// A solution of the LCP from clarabel on its dual QP.
#[derive(Debug, Clone, PartialEq)]
pub struct DualSolution {
    /// `z`.
    pub z: DVector<f64>,
    /// `w = M z + q`, recomputed from `z` on the original data.
    pub w: DVector<f64>,
    /// Interior-point iterations.
    pub iterations: usize,
}

/// Solves a symmetric positive semidefinite LCP with clarabel. Fails with
/// [`FailureReason::NotApplicable`] when `M` is not symmetric PSD.
pub fn solve_lcp(lcp: &Lcp, settings: &ClarabelSettings) -> Result<DualSolution, FailureReason> {
    if !lcp.is_symmetric_psd() {
        return Err(FailureReason::NotApplicable);
    }
    solve_lcp_unchecked(lcp, settings)
}

/// As [`solve_lcp`], for a matrix known to be symmetric PSD by construction
/// (`J M^-1 J^T`): skips the eigenvalue check.
pub fn solve_lcp_unchecked(
    lcp: &Lcp,
    settings: &ClarabelSettings,
) -> Result<DualSolution, FailureReason> {
    let n = lcp.n();
    if lcp.q().iter().all(|&x| x >= 0.0) {
        return Ok(DualSolution {
            z: DVector::zeros(n),
            w: lcp.q().clone(),
            iterations: 0,
        });
    }
    let scaling = LcpScaling::jacobi(lcp.m(), lcp.q());
    let m = scaling.scale_m(lcp.m());
    let q = scaling.scale_q(lcp.q());
    let mut p_triplets = Vec::with_capacity(n * (n + 1) / 2);
    for j in 0..n {
        for i in 0..=j {
            // Symmetrize: the average of the two triangles.
            p_triplets.push((i, j, 0.5 * (m[(i, j)] + m[(j, i)])));
        }
    }
    let p = csc_from_triplets(n, n, p_triplets);
    let a = csc_from_triplets(n, n, (0..n).map(|i| (i, i, -1.0)).collect());
    let point: ClarabelPoint =
        run(&p, q.as_slice(), &a, &vec![0.0; n], settings).map_err(FailureReason::Clarabel)?;
    let z_scaled = DVector::from_vec(point.x);
    let z = scaling.unscale_z(&z_scaled);
    let w = lcp.w(&z);
    Ok(DualSolution {
        z,
        w,
        iterations: point.iterations,
    })
}
