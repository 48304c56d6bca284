//! Lemke's method on a projection with equality rows (joints), the
//! equality block eliminated through a **sparse** factor of its Delassus
//! block, without assembling the dense LCP.
//!
//! The dual of the projection is the mixed LCP of [`super::lemke::mixed`]
//! with `A = J M^-1 J^T`, the `e` equality rows `E` first:
//!
//! ```text
//! A_EE z_E + A_EI z_I + b_E = 0                   (z_E free)
//! w_I = A_IE z_E + A_II z_I + b_I >= 0  _|_  z_I >= 0,
//! ```
//!
//! and with a generalized inverse `G` of `A_EE` the LCP that remains is
//! `S = A_II - A_IE G A_EI`, `q = b_I - A_IE G b_E`, after which
//! `z_E = -G (b_E + A_EI z_I)` (the derivation is in
//! [`super::lemke::mixed`]). There `G` comes from a dense pivoted Cholesky
//! factor, `O(e^3)`; here from a sparse one. `A_EE` is as sparse as the
//! joint graph: entry `(i, j)` is nonzero only when rows `i` and `j` share
//! a body, so a chain's block is banded and a tree's has no fill under a
//! minimum-degree order. `(A_EE)_ij = sum_k J_ik M_k^-1 J_jk^T` is summed
//! over the bodies `k` the rows share, `A_EI` and `A_II` likewise (`A_EI`
//! dense `e x (m - e)`, `A_II` dense; Lemke pivots on `S` alone, whose size
//! is the inequality rows').
//!
//! **The generalized inverse.** With the Jacobi scaling `D` of `A_EE`
//! (unit diagonal), faer's sparse `L L^T` of `X = D A_EE D` under an AMD
//! order, every pivot below [`super::lemke::mixed::EQUALITY_RANK_TOL_REL`]
//! replaced by [`DROPPED_PIVOT`]: a row dependent on the rows eliminated
//! before it (a closed loop of joints lists more rows than it removes
//! degrees of freedom) has a vanishing pivot in exact arithmetic, and with
//! the huge replacement its column of `L` and its entry of every solve
//! vanish to rounding, which is the truncated factor of the dense
//! pivoted path (`G = D X^- D` with that row's multiplier set to zero) in
//! this order. Inconsistent equalities (`b_E` outside the range of
//! `A_EE`) are reported as
//! [`super::lemke::LemkeStatus::InconsistentEqualities`] with the part outside,
//! `|b_E - A_EE G b_E|_inf` relative to `|b|_inf`, as by the dense path.
//!
//! **The check.** The answer is checked on the whole mixed problem, its
//! natural map relative to `max(|b|_inf, max_i A_ii |z|_inf)` (for a
//! positive semidefinite `A` its largest entry is on the diagonal), with
//! `w = b + J M^-1 J^T z` computed through `J` (`O(nnz(J))`), against
//! [`LemkeSettings::tol_residual_unscaled`], the dense path's test.
//!
//! Cost: one symbolic analysis (kept by the caller's
//! [`super::kept_analyses::KeptAnalyses`] with its pattern and reused while
//! the pattern holds: a scene's joints repeat it in every pass and call)
//! and one numeric factorization of an `e x e`
//! sparse matrix, `1 + (m - e)` solves with it, and Lemke on `m -
//! e` rows; the dense path's `O(e^3)` factorization and `O(m^2)` matrix are
//! gone.

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::SparseColMatRef;
use faer::{Conj, Mat, Par};
use nalgebra::{DMatrix, DVector};

use super::kept_analyses::{AnalysisKind, KeptAnalyses, KeptAnalysis};
use super::lcp::Lcp;
use super::lemke::mixed::{EQUALITY_RANK_TOL_REL, check_range, failure, inaccurate};
use super::lemke::{self, LemkeFailure, LemkeSettings};
use super::metric::BlockMetric;
use super::projection::ProjectionQp;
use super::projection_lcp::{Incidence, dq_from_lambda};
use super::residuals::natural_map_abs;

/// The value that replaces a pivot of the scaled `A_EE` below the rank
/// tolerance (module docs): `1e20` against a unit diagonal, so that the
/// dropped row's column of `L` is below `1e-15` of the others' and its
/// multiplier below `1e-20` of `b`.
pub const DROPPED_PIVOT: f64 = 1e20;

/// Lemke's answer from the elimination: the multipliers `z` (equality
/// rows first) and Lemke's pivots on the reduced problem.
#[derive(Debug, Clone)]
pub struct EliminatedSolution {
    /// One multiplier per row of the projection.
    pub z: DVector<f64>,
    /// The correction `dq = M^-1 J^T z` (computed for the final check).
    pub dq: DVector<f64>,
    /// Lemke's pivots on `S` (0 without inequality rows).
    pub pivots: usize,
    /// Numeric factorizations of `A_EE` (one; none without equality rows).
    pub factorizations: usize,
}

/// Solves the dual of `qp` (which has equality rows) by the sparse
/// elimination of the module docs and Lemke's method on what remains.
pub fn solve(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    settings: &LemkeSettings,
    kept: Option<&KeptAnalyses>,
) -> Result<EliminatedSolution, LemkeFailure> {
    let (e, m) = (qp.num_equalities, qp.num_rows());
    let ni = m - e;
    let blocks = DelassusBlocks::new(qp, metric);
    let b = qp.b();
    let b_e = b.rows(0, e).into_owned();
    let b_i = b.rows(e, ni).into_owned();
    let not_finite = || failure(inaccurate(f64::INFINITY));
    // Right-hand sides: b_E, then the columns of A_EI.
    let mut rhs = Mat::<f64>::from_fn(e, 1 + ni, |r, c| match c {
        0 => b_e[r],
        _ => blocks.a_ei[(r, c - 1)],
    });
    blocks
        .apply_inverse(&mut rhs, kept)
        .ok_or_else(not_finite)?;
    let g_b = DVector::from_fn(e, |r, _| rhs[(r, 0)]);
    let g_a = DMatrix::from_fn(e, ni, |r, c| rhs[(r, c + 1)]);
    if !g_b.iter().chain(g_a.iter()).all(|v| v.is_finite()) {
        return Err(not_finite());
    }
    check_range(&(&b_e - blocks.apply_a_ee(&g_b)), &b, settings)?;
    let (z_i, pivots) = if ni == 0 {
        (DVector::zeros(0), 0)
    } else {
        let s = &blocks.a_ii - blocks.a_ei.transpose() * &g_a;
        let q_i = &b_i - blocks.a_ei.transpose() * &g_b;
        let reduced = Lcp::new(s, q_i).map_err(|_| not_finite())?;
        let inner = lemke::solve(&reduced, settings)?;
        (inner.z, inner.pivots)
    };
    let z_e = -(g_b + g_a * &z_i);
    let mut z = DVector::zeros(m);
    z.rows_mut(0, e).copy_from(&z_e);
    z.rows_mut(e, ni).copy_from(&z_i);
    let dq = dq_from_lambda(qp, metric, &z);
    let w = &b + qp.apply_j(&dq);
    let size = b.amax().max(blocks.max_diagonal * z.amax());
    let natural = natural_map_abs(&z, &w, e);
    let relative = if size > 0.0 { natural / size } else { natural };
    if relative.is_nan() || relative > settings.tol_residual_unscaled {
        return Err(LemkeFailure {
            status: inaccurate(relative),
            attempts: Vec::new(),
            pivots,
        });
    }
    log::trace!(
        "lemke: {e} equality rows eliminated by a sparse factor, {ni} rows pivoted ({pivots} pivots)"
    );
    Ok(EliminatedSolution {
        z,
        dq,
        pivots,
        factorizations: usize::from(e > 0),
    })
}

/// The blocks of `A = J M^-1 J^T`: `A_EE` sparse (its lower triangle,
/// compressed by columns), `A_EI` and `A_II` dense.
struct DelassusBlocks {
    e: usize,
    /// Column pointers of `A_EE`'s lower triangle.
    col_ptr: Vec<usize>,
    /// Row indices, ascending within a column (the diagonal first).
    row_idx: Vec<usize>,
    /// Values of `A_EE` (unscaled).
    values: Vec<f64>,
    a_ei: DMatrix<f64>,
    a_ii: DMatrix<f64>,
    /// `max_i A_ii` over every row.
    max_diagonal: f64,
}

impl DelassusBlocks {
    /// The blocks of `A`, `A_EE` column by column: for equality row `c`,
    /// the terms `J_jk M_k^-1 J_ck^T` over the bodies `k` of row `c` and
    /// the equality rows `j >= c` touching them, summed in a dense
    /// accumulator and written in ascending rows (the diagonal first, and
    /// present even for a zero row, so that the factorization sees every
    /// column). `O(sum_k deg_k^2)` as the whole matrix, with no sort of
    /// the terms.
    fn new(qp: &ProjectionQp, metric: &[BlockMetric]) -> Self {
        let (e, m) = (qp.num_equalities, qp.num_rows());
        let ni = m - e;
        let incidence = Incidence::of(qp, metric);
        let mut max_diagonal = 0.0_f64;
        let mut col_ptr = Vec::with_capacity(e + 1);
        // At most one entry per pair of equality rows sharing a body.
        let bound: usize = (0..metric.len())
            .map(|k| {
                let entries = incidence.of_body(k);
                let n = incidence.row[entries].partition_point(|&i| i < e);
                n * (n + 1) / 2
            })
            .sum::<usize>()
            .max(e);
        let mut row_idx = Vec::with_capacity(bound);
        let mut values = Vec::with_capacity(bound);
        let mut accumulator = vec![0.0; e];
        let mut touched: Vec<usize> = Vec::new();
        // `seen[j] == c + 1`: row `j` is in `touched` for column `c`.
        let mut seen = vec![0_usize; e];
        // Position of row `c` in each body's entries: the entries of body
        // `k` with rows below `c` are passed (rows ascend within a body).
        let mut first = incidence.start[..metric.len()].to_vec();
        col_ptr.push(0);
        for c in 0..e {
            touched.push(c);
            seen[c] = c + 1;
            for (k, _) in &qp.rows[c].blocks {
                let entries = incidence.of_body(*k);
                while incidence.row[first[*k]] < c {
                    first[*k] += 1;
                }
                let own = first[*k];
                let u_c = incidence.u[own];
                for p in own..entries.end {
                    let j = incidence.row[p];
                    if j >= e {
                        break;
                    }
                    if seen[j] != c + 1 {
                        seen[j] = c + 1;
                        touched.push(j);
                    }
                    accumulator[j] += incidence.g[p].dot(&u_c);
                }
            }
            touched.sort_unstable();
            for &j in &touched {
                row_idx.push(j);
                values.push(accumulator[j]);
                accumulator[j] = 0.0;
            }
            touched.clear();
            max_diagonal = max_diagonal.max(values[col_ptr[c]]);
            col_ptr.push(row_idx.len());
        }
        let mut a_ei = DMatrix::zeros(e, ni);
        let mut a_ii = DMatrix::zeros(ni, ni);
        for k in 0..metric.len() {
            let entries = incidence.of_body(k);
            let split = entries.start + incidence.row[entries.clone()].partition_point(|&i| i < e);
            for x in entries.clone() {
                let (i, u_i) = (incidence.row[x], incidence.u[x]);
                for y in split.max(x)..entries.end {
                    let j = incidence.row[y];
                    let v = incidence.g[y].dot(&u_i);
                    if i < e {
                        a_ei[(i, j - e)] += v;
                    } else {
                        a_ii[(j - e, i - e)] += v;
                        if i != j {
                            a_ii[(i - e, j - e)] += v;
                        }
                    }
                }
            }
        }
        for r in 0..ni {
            max_diagonal = max_diagonal.max(a_ii[(r, r)]);
        }
        Self {
            e,
            col_ptr,
            row_idx,
            values,
            a_ei,
            a_ii,
            max_diagonal,
        }
    }

    /// The Jacobi scaling `d_i = A_ii^-1/2` of `A_EE` (1 for a zero row).
    fn jacobi(&self) -> Vec<f64> {
        (0..self.e)
            .map(|c| {
                let diagonal = self.values[self.col_ptr[c]];
                if diagonal > 0.0 {
                    diagonal.sqrt().recip()
                } else {
                    1.0
                }
            })
            .collect()
    }

    /// `rhs <- G rhs` column by column (module docs), with the symbolic
    /// analysis kept in `kept` for this pattern (made and kept there when
    /// missing; made and dropped without a store); `None` when faer fails
    /// (out of memory).
    fn apply_inverse(&self, rhs: &mut Mat<f64>, kept: Option<&KeptAnalyses>) -> Option<()> {
        let e = self.e;
        if e == 0 {
            return Some(());
        }
        let d = self.jacobi();
        let scaled: Vec<f64> = (0..e)
            .flat_map(|c| (self.col_ptr[c]..self.col_ptr[c + 1]).map(move |p| (c, p)))
            .map(|(c, p)| d[c] * self.values[p] * d[self.row_idx[p]])
            .collect();
        let kind = AnalysisKind::Simplicial;
        let analysis = match kept {
            Some(kept) => kept.analysis(kind, &self.col_ptr, &self.row_idx)?,
            None => Arc::new(KeptAnalysis::new(kind, &self.col_ptr, &self.row_idx)?),
        };
        // Factored as `P A P^T` in the analysis's order, solved as
        // `(P A P^T) (P x) = P rhs` (`super::kept_analyses`).
        let mut permuted = vec![0.0; scaled.len()];
        analysis.permute_values(&scaled, &mut permuted);
        let matrix = SparseColMatRef::new(analysis.permuted_pattern(), &permuted);
        let order = analysis.order();
        let symbolic = analysis.symbolic();
        let k = rhs.ncols();
        let scratch = symbolic
            .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(k, Par::Seq));
        let mut workspace = MemBuffer::try_new(scratch).ok()?;
        let mut l_values = vec![0.0; symbolic.len_val()];
        let regularization = LltRegularization {
            dynamic_regularization_delta: DROPPED_PIVOT,
            dynamic_regularization_epsilon: EQUALITY_RANK_TOL_REL,
        };
        let llt = symbolic
            .factorize_numeric_llt(
                &mut l_values,
                matrix,
                analysis.permuted_side(),
                regularization,
                Par::Seq,
                MemStack::new(&mut workspace),
                Default::default(),
            )
            .ok()?;
        let mut rhs_permuted = Mat::from_fn(e, k, |r, c| d[order[r]] * rhs[(order[r], c)]);
        llt.solve_in_place_with_conj(
            Conj::No,
            rhs_permuted.as_mut(),
            Par::Seq,
            MemStack::new(&mut workspace),
        );
        for c in 0..k {
            for (r, &original) in order.iter().enumerate() {
                rhs[(original, c)] = d[original] * rhs_permuted[(r, c)];
            }
        }
        Some(())
    }

    /// `A_EE x` from the stored lower triangle.
    fn apply_a_ee(&self, x: &DVector<f64>) -> DVector<f64> {
        let mut y = DVector::zeros(self.e);
        for c in 0..self.e {
            for p in self.col_ptr[c]..self.col_ptr[c + 1] {
                let (r, v) = (self.row_idx[p], self.values[p]);
                y[r] += v * x[c];
                if r != c {
                    y[c] += v * x[r];
                }
            }
        }
        y
    }
}
