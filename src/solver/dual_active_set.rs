//! The dual active-set method of Goldfarb and Idnani ("A numerically
//! stable dual method for solving strictly convex quadratic programs",
//! Math. Programming 27, 1983) for the projection QP of a small island,
//! dense in body space.
//!
//! The problem is `minimize 1/2 dq^T M dq` subject to `s_i = a_i^T dq + b_i
//! >= 0` (`a_i = J_i^T`, `b = phi - target`, inequality rows only). The
//! method starts at the unconstrained minimum `dq = 0` and adds violated
//! rows one at a time, keeping every iterate the minimizer over its
//! active set `A` (rows held as equalities) with multipliers `u >= 0`: it
//! is dual feasible throughout and primal feasible at the end, where it is
//! the answer. Its state is `Jm = L^-T Q` and the upper triangle `R` of
//! the QR factorization `L^-1 N_A = Q [R; 0]` (`M = L L^T`, `N_A` the
//! active rows' gradients): then `Jm^T M Jm = I`, and for a row `a`,
//! `d = Jm^T a` splits into `d_1` (the first `q = |A|` entries) and `d_2`.
//!
//! **One step** toward a violated row `p` (`s_p < 0`):
//!
//! ```text
//! z = Jm_2 d_2               (the primal direction: moves s_p, keeps A tight)
//! r = R^-1 d_1               (how A's multipliers change: u <- u - t r, u_p <- u_p + t)
//! t_full = -s_p / (z^T a_p) = -s_p / |d_2|^2          (row p becomes tight)
//! t_part = min over r_j > 0 of u_j / r_j              (multiplier j reaches 0)
//! ```
//!
//! With `t = min(t_full, t_part)`, `dq <- dq + t z`. A full step adds `p`
//! to `A` (Givens rotations zero `d_2` below its first entry, the same
//! rotations applied to `Jm`'s columns, and `d`'s first `q + 1` entries
//! become `R`'s new column); a partial step drops the row whose multiplier
//! reached zero (rotations restore `R`'s triangle, applied to `Jm` too)
//! and steps toward `p` again. When `a_p` is a combination of the active
//! rows (`|d_2|` at rounding, [`DEPENDENT_REL`]) only the multipliers move
//! (`t = t_part`), and a row is dropped: redundant contact rows (four
//! corners on a face) are handled so, the active rows always independent.
//! When, in addition, no `r_j` is positive, no step exists: `a_p` is a
//! non-positive combination of tight rows, which certifies that the rows
//! cannot all hold; that is reported as [`DualActiveSetFailure::Infeasible`]
//! and left to the solvers that certify with a tolerance of their own
//! ([`crate::solver::FailureReason::certifies_infeasibility`] does not take
//! it).
//!
//! **Cost.** `M` is block diagonal (`L` per body: `sqrt(m) I_3` and the
//! inertia's Cholesky factor). A step costs `O(n (n - q))` for `z` and the
//! rotations, `O(q^2)` for `r`, `12 n` for `d` (a row has two bodies) and
//! `12 m` to measure every row after a primal step (`n = 6 bodies`, `m`
//! rows); the number of steps is about the size of the final active set
//! plus the drops. Dense in `n`: for islands of a few bodies with many
//! rows (a stack with its friction pyramids, 100-250 rows on 30-42
//! entries of `dq`), where the interior point's 16-20 factorizations cost
//! more (`benchmarks/results/solvers.md`).
//!
//! **Order.** The most violated row, measured in `M^-1` lengths
//! (`s_i / |a_i|_{M^-1}`), is added first. A row counts as violated while
//! `s_i < -VIOLATION_OF_ACCEPTANCE tol_residual L` (`L` the acceptance
//! length, `super::residuals`): the answer's feasibility is then well
//! within the acceptance test that every answer passes.

use std::time::Instant;

use nalgebra::{DMatrix, DVector, Matrix3, Vector6};

use super::metric::BlockMetric;
use super::outcome::Candidate;
use super::projection::ProjectionQp;
use super::residuals::{acceptance_length, row_diagonal};

/// `|d_2| <= DEPENDENT_REL |a_p|_{M^-1}`: the row is a combination of the
/// active rows (module docs), at rounding.
pub const DEPENDENT_REL: f64 = 1e-10;

/// A row counts as violated while `s_i` is below `-VIOLATION_OF_ACCEPTANCE
/// tol_residual L` (module docs).
pub const VIOLATION_OF_ACCEPTANCE: f64 = 1e-3;

/// Steps (full, partial or dual) per row and per entry of `dq` before the
/// method gives up: it adds each row at most once between drops, and
/// about `|A| + drops` steps answer a problem (module docs); the limit
/// guards against cycling through degenerate ties.
pub const STEPS_PER_SIZE: usize = 4;

/// Problems of more entries of `dq` are refused (`NotApplicable`): its
/// two dense `n x n` matrices (5.8 MB at this size) and `O(n^2)` steps
/// are for islands of a few bodies, and a user naming it for a large
/// island gets the next solver of the chain, not a huge allocation.
/// `Auto` takes it up to 132 entries
/// ([`crate::solver::SolverSettings::auto_dual_active_set_max_dofs`]).
pub const MAX_DOFS: usize = 600;

/// Why the dual active-set method gave no answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum DualActiveSetFailure {
    /// Equality rows, friction cones or rows of more than two bodies,
    /// which it does not take, or more than [`MAX_DOFS`] entries of `dq`.
    NotApplicable,
    /// A violated row that no step can satisfy (module docs).
    Infeasible,
    /// [`STEPS_PER_SIZE`] `(m + n)` steps, or a value that is not finite.
    NotConverged,
    /// The deadline passed.
    Deadline,
}

/// Solves `qp` (module docs). `Candidate::iterations` counts the steps,
/// `Candidate::factorizations` is 0 (the factors are updated, never made
/// again).
pub fn solve(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    tol_residual: f64,
    deadline: Option<Instant>,
) -> Result<Candidate, DualActiveSetFailure> {
    if qp.num_equalities > 0 || !qp.cones.is_empty() || qp.num_dofs() > MAX_DOFS {
        return Err(DualActiveSetFailure::NotApplicable);
    }
    let rows = packed_rows(qp).ok_or(DualActiveSetFailure::NotApplicable)?;
    let n = qp.num_dofs();
    let m = qp.num_rows();
    let b = qp.b();
    let lengths: Vec<f64> = row_diagonal(qp, metric)
        .into_iter()
        .map(f64::sqrt)
        .collect();
    // A row no body moves (length 0) is never added: it holds or the
    // problem was rejected before (`super::solve`).
    let inverse_lengths: Vec<f64> = lengths
        .iter()
        .map(|&len| if len > 0.0 { 1.0 / len } else { 0.0 })
        .collect();
    let violated_below = -VIOLATION_OF_ACCEPTANCE * tol_residual * acceptance_length(qp);
    let mut state = State::new(n, metric).ok_or(DualActiveSetFailure::NotApplicable)?;
    let mut dq = DVector::zeros(n);
    let mut slack = b;
    let mut active: Vec<usize> = Vec::new();
    let mut u: Vec<f64> = Vec::new();
    let mut is_active = vec![false; m];
    let limit = STEPS_PER_SIZE * (m + n);
    let mut steps = 0;
    // The most violated row, in M^-1 lengths; none: the answer.
    while let Some(p) = most_violated(&slack, &inverse_lengths, &is_active, violated_below) {
        let mut u_p = 0.0;
        loop {
            steps += 1;
            if steps > limit {
                return Err(DualActiveSetFailure::NotConverged);
            }
            if deadline.is_some_and(|d| Instant::now() >= d) {
                return Err(DualActiveSetFailure::Deadline);
            }
            let d = state.project(&rows[p]);
            let q = active.len();
            let r = state.active_coefficients(&d, q);
            let d2_norm_sq: f64 = d.rows(q, n - q).norm_squared();
            // The partial step: the first active multiplier to reach zero.
            let mut partial: Option<(f64, usize)> = None;
            for (j, &rj) in r.iter().enumerate() {
                if rj > 0.0 {
                    let t = u[j] / rj;
                    if partial.is_none_or(|(best, _)| t < best) {
                        partial = Some((t, j));
                    }
                }
            }
            let dependent = d2_norm_sq.sqrt() <= DEPENDENT_REL * lengths[p];
            let full = (!dependent).then(|| -slack[p] / d2_norm_sq);
            let (t, drop) = match (full, partial) {
                (None, None) => return Err(DualActiveSetFailure::Infeasible),
                (Some(t_full), Some((t_part, j))) if t_part < t_full => (t_part, Some(j)),
                (Some(t_full), _) => (t_full, None),
                (None, Some((t_part, j))) => (t_part, Some(j)),
            };
            if !t.is_finite() {
                return Err(DualActiveSetFailure::NotConverged);
            }
            for (uj, rj) in u.iter_mut().zip(r.iter()) {
                *uj -= t * rj;
            }
            u_p += t;
            if !dependent {
                // The primal direction, only where the step moves `dq`.
                let z = state.direction(&d, q);
                dq.axpy(t, &z, 1.0);
                // s <- s + t J z (every row, the active ones stay at 0).
                let z_slice = z.as_slice();
                for (s_i, row) in slack.iter_mut().zip(&rows) {
                    *s_i += t * row.dot(z_slice);
                }
            }
            match drop {
                Some(j) => {
                    state.drop_active(j, q);
                    is_active[active.remove(j)] = false;
                    u.remove(j);
                }
                None => {
                    state.add_active(d, q);
                    active.push(p);
                    is_active[p] = true;
                    u.push(u_p);
                    break;
                }
            }
        }
    }
    let mut lambda = DVector::zeros(m);
    for (&i, &ui) in active.iter().zip(&u) {
        lambda[i] = ui.max(0.0);
    }
    if !(dq.iter().all(|x| x.is_finite()) && lambda.iter().all(|x| x.is_finite())) {
        return Err(DualActiveSetFailure::NotConverged);
    }
    Ok(Candidate {
        dq,
        lambda,
        iterations: steps,
        factorizations: 0,
    })
}

/// The row with the most negative `s_i / |a_i|_{M^-1}` among the inactive
/// rows violated beyond `violated_below` (`inverse_lengths`: `1 /
/// |a_i|_{M^-1}`, 0 for a row no body moves).
fn most_violated(
    slack: &DVector<f64>,
    inverse_lengths: &[f64],
    is_active: &[bool],
    violated_below: f64,
) -> Option<usize> {
    let mut best: Option<(f64, usize)> = None;
    for (i, (&s, &inverse)) in slack.iter().zip(inverse_lengths).enumerate() {
        if s >= violated_below || is_active[i] || inverse == 0.0 {
            continue;
        }
        let measure = s * inverse;
        if best.is_none_or(|(b, _)| measure < b) {
            best = Some((measure, i));
        }
    }
    best.map(|(_, i)| i)
}

/// A row's gradient as at most two blocks of six entries of `dq` (a
/// contact's two bodies; an absent second block is zeros at offset 0).
struct PackedRow {
    offsets: [usize; 2],
    gradients: [Vector6<f64>; 2],
}

impl PackedRow {
    /// `a^T v`.
    fn dot(&self, v: &[f64]) -> f64 {
        self.offsets
            .iter()
            .zip(&self.gradients)
            .map(|(&offset, g)| Vector6::from_column_slice(&v[offset..offset + 6]).dot(g))
            .sum()
    }
}

/// The rows packed; `None` when a row has more than two bodies (not a
/// contact's: the other solvers take that problem).
fn packed_rows(qp: &ProjectionQp) -> Option<Vec<PackedRow>> {
    qp.rows
        .iter()
        .map(|row| {
            let mut packed = PackedRow {
                offsets: [0; 2],
                gradients: [Vector6::zeros(); 2],
            };
            if row.blocks.len() > 2 {
                return None;
            }
            for (slot, (k, g)) in row.blocks.iter().enumerate() {
                packed.offsets[slot] = 6 * k;
                packed.gradients[slot] = *g;
            }
            Some(packed)
        })
        .collect()
}

/// `Jm` and `R` (module docs), dense, column-major.
struct State {
    n: usize,
    /// `n x n`, `Jm^T M Jm = I`.
    jm: DMatrix<f64>,
    /// `n x n`, upper triangle of the first `q` columns used.
    r: DMatrix<f64>,
}

impl State {
    /// `Jm = L^-T`: per body `I_3 / sqrt(m)` and `C^-T` (`C` the inertia's
    /// lower Cholesky factor); `R` empty. `None` when a factor is singular
    /// (a validated metric's never is).
    fn new(n: usize, metric: &[BlockMetric]) -> Option<Self> {
        let mut jm = DMatrix::zeros(n, n);
        for (k, block) in metric.iter().enumerate() {
            let scale = 1.0 / block.mass.sqrt();
            for c in 0..3 {
                jm[(6 * k + c, 6 * k + c)] = scale;
            }
            let c_inv_t: Matrix3<f64> = block.inertia_chol.transpose().try_inverse()?;
            jm.fixed_view_mut::<3, 3>(6 * k + 3, 6 * k + 3)
                .copy_from(&c_inv_t);
        }
        Some(Self {
            n,
            jm,
            r: DMatrix::zeros(n, n),
        })
    }

    /// `d = Jm^T a` (the row's two blocks only).
    fn project(&self, row: &PackedRow) -> DVector<f64> {
        let n = self.n;
        let data = self.jm.as_slice();
        DVector::from_fn(n, |j, _| row.dot(&data[j * n..j * n + n]))
    }

    /// `r = R^-1 d_1` by back substitution, column by column (`R` is
    /// stored by columns).
    fn active_coefficients(&self, d: &DVector<f64>, q: usize) -> Vec<f64> {
        let n = self.n;
        let data = self.r.as_slice();
        let mut r: Vec<f64> = d.as_slice()[..q].to_vec();
        for j in (0..q).rev() {
            let column = &data[j * n..j * n + j + 1];
            r[j] /= column[j];
            let rj = r[j];
            for (ri, rij) in r[..j].iter_mut().zip(column) {
                *ri -= rij * rj;
            }
        }
        r
    }

    /// `z = Jm_2 d_2`.
    fn direction(&self, d: &DVector<f64>, q: usize) -> DVector<f64> {
        let mut z = DVector::zeros(self.n);
        for j in q..self.n {
            z.axpy(d[j], &self.jm.column(j), 1.0);
        }
        z
    }

    /// Adds the row with `d = Jm^T a`: rotations zero `d[q + 1..]` from the
    /// bottom, applied to `Jm`'s columns; `d[..=q]` is `R`'s column `q`.
    fn add_active(&mut self, mut d: DVector<f64>, q: usize) {
        for j in (q + 1..self.n).rev() {
            if let Some((c, s, h)) = givens(d[j - 1], d[j]) {
                d[j - 1] = h;
                d[j] = 0.0;
                rotate_columns(&mut self.jm, j - 1, j, c, s);
            }
        }
        for i in 0..=q {
            self.r[(i, q)] = d[i];
        }
    }

    /// Drops active row `k` of `q`: `R`'s column `k` removed, the columns
    /// after it shifted left (upper Hessenberg), rotations on rows
    /// `(j, j + 1)` restore the triangle, applied to `Jm`'s columns too.
    fn drop_active(&mut self, k: usize, q: usize) {
        for j in k..q - 1 {
            for i in 0..=j + 1 {
                self.r[(i, j)] = self.r[(i, j + 1)];
            }
        }
        for i in 0..q {
            self.r[(i, q - 1)] = 0.0;
        }
        for j in k..q - 1 {
            if let Some((c, s, h)) = givens(self.r[(j, j)], self.r[(j + 1, j)]) {
                self.r[(j, j)] = h;
                self.r[(j + 1, j)] = 0.0;
                for col in j + 1..q - 1 {
                    let (top, bottom) = (self.r[(j, col)], self.r[(j + 1, col)]);
                    self.r[(j, col)] = c * top + s * bottom;
                    self.r[(j + 1, col)] = -s * top + c * bottom;
                }
                rotate_columns(&mut self.jm, j, j + 1, c, s);
            }
        }
    }
}

/// The rotation `G^T [x; y] = [h; 0]`, `G^T = [[c, s], [-s, c]]`; `None`
/// when `y` is already zero.
fn givens(x: f64, y: f64) -> Option<(f64, f64, f64)> {
    if y == 0.0 {
        return None;
    }
    // The entries are lengths in `M^-1` of rows and their parts: far from
    // overflow, so the plain root (hypot's scaling costs a tenth of the
    // solve).
    let h = (x * x + y * y).sqrt();
    Some((x / h, y / h, h))
}

/// `Jm <- Jm G` on columns `a`, `b` (`G = [[c, -s], [s, c]]`): the rotation
/// that [`givens`] applied to `Jm^T a`.
fn rotate_columns(jm: &mut DMatrix<f64>, a: usize, b: usize, c: f64, s: f64) {
    let n = jm.nrows();
    let data = jm.as_mut_slice();
    let (left, right) = data.split_at_mut(b * n);
    let col_a = &mut left[a * n..a * n + n];
    let col_b = &mut right[..n];
    for (x, y) in col_a.iter_mut().zip(col_b.iter_mut()) {
        let (t1, t2) = (*x, *y);
        *x = c * t1 + s * t2;
        *y = -s * t1 + c * t2;
    }
}
