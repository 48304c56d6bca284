//! A sparse Cholesky factor `H = L L^T` of the body-space matrix by 6x6
//! body blocks.
//!
//! `H = M + J^T D J` couples body `k` with body `l` exactly when a row has
//! both, so its nonzeros come in dense 6x6 blocks on a graph of bodies.
//! The factor is computed on that graph: an approximate minimum degree
//! order of the bodies (faer's AMD on the block graph, 36 times fewer
//! entries than the scalar pattern), the block elimination tree and the
//! block fill of `L` once per pattern ([`BlockSymbolic`]), then per
//! numeric factorization, for every block column `p` in order (right
//! looking):
//!
//! ```text
//! L_pp L_pp^T = A_pp                      (a 6x6 Cholesky)
//! L_ip        = A_ip L_pp^-T              (every row block i of column p)
//! A_ij       -= L_ip L_jp^T               (every pair i >= j of those rows)
//! ```
//!
//! where the updated pairs and their places are resolved once by the
//! symbolic analysis, so that a factorization is a flat loop of 6x6 kernels
//! with no search. The solve is the block forward substitution
//! `L y = P b` and the backward one `L^T x = y`.
//!
//! faer's supernodal factor treats the same matrix as columns of scalars:
//! on these patterns (supernodes of about one body, 6 columns wide) its
//! dense kernels were called on blocks of a few rows, and a factorization
//! of the Bullet bin's island of 157 bodies (942 entries of `dq`, 41,000
//! entries of `L`) cost about 3 million instructions, about six times its
//! floating-point work (`benchmarks/results/call_cost.md`).
//!
//! A pivot block that is not positive definite in floating point (a pivot
//! not positive and finite) fails the factorization; the caller retries or
//! falls back as for any Cholesky. Not part of the stable API (public for
//! the tests).

use faer::sparse::SymbolicSparseColMatRef;

use super::kept_analyses::amd_order;

/// Entries of a body's block side.
const SIDE: usize = 6;
/// Entries of a block (column-major: entry `(r, c)` at `r + 6 c`).
const BLOCK: usize = SIDE * SIDE;

/// The block structure of `L` for one pattern of `H` (module docs).
#[derive(Debug, Clone)]
pub struct BlockSymbolic {
    /// `order[p]`: the body eliminated `p`-th.
    order: Vec<usize>,
    /// Per block column `p`, its off-diagonal slots
    /// `col_start[p]..col_start[p + 1]` (length `n + 1`).
    col_start: Vec<usize>,
    /// The row block (elimination position, greater than the column's) of
    /// each slot, ascending within a column. Slot `s` is stored at
    /// `(n + s) * 36`, diagonal block `p` at `p * 36`.
    rows: Vec<usize>,
    /// Per block column `p`, its updates
    /// `update_start[p]..update_start[p + 1]` (length `n + 1`).
    update_start: Vec<usize>,
    /// `(target, a, b)`: the block stored at `target` loses
    /// `L_a L_b^T` (slots `a`, `b` of one column, `rows[a] >= rows[b]`).
    updates: Vec<(usize, usize, usize)>,
    /// For each entry of `H`'s lower triangle in the caller's compressed
    /// columns, its place in the block storage.
    gather: Vec<usize>,
    /// The most off-diagonal blocks of one column.
    widest_column: usize,
}

impl BlockSymbolic {
    /// The analysis of the pattern of `H` given as its lower triangle in
    /// compressed columns (`col_ptr`, `row_idx`, `6 n_bodies` columns,
    /// every entry of a coupled pair of bodies present, rows ascending), and
    /// `neighbours[l]`: the bodies `k > l` coupled with `l`, ascending.
    /// `None` when the two disagree or faer's ordering fails.
    pub fn new(neighbours: &[Vec<usize>], col_ptr: &[usize], row_idx: &[usize]) -> Option<Self> {
        let n = neighbours.len();
        let covers_every_entry = col_ptr.first() == Some(&0)
            && col_ptr.last() == Some(&row_idx.len())
            && col_ptr.windows(2).all(|w| w[0] <= w[1]);
        if col_ptr.len() != SIDE * n + 1 || !covers_every_entry {
            return None;
        }
        let order = block_order(neighbours)?;
        let mut position = vec![0usize; n];
        for (p, &k) in order.iter().enumerate() {
            position[k] = p;
        }
        // The lower adjacency in elimination positions.
        let mut below: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (l, list) in neighbours.iter().enumerate() {
            for &k in list {
                let (pk, pl) = (*position.get(k)?, position[l]);
                if pk == pl {
                    return None;
                }
                below[pk.min(pl)].push(pk.max(pl));
            }
        }
        // Block fill by the elimination tree: the structure of column p is
        // its own rows and its children's, less p; its parent is its first
        // row.
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut col_start = Vec::with_capacity(n + 1);
        let mut rows: Vec<usize> = Vec::new();
        let mut mark = vec![usize::MAX; n];
        col_start.push(0);
        for p in 0..n {
            let start = rows.len();
            for &q in &below[p] {
                if mark[q] != p {
                    mark[q] = p;
                    rows.push(q);
                }
            }
            for &c in &children[p] {
                for s in col_start[c]..col_start[c + 1] {
                    let q = rows[s];
                    if q != p && mark[q] != p {
                        mark[q] = p;
                        rows.push(q);
                    }
                }
            }
            rows[start..].sort_unstable();
            col_start.push(rows.len());
            if let Some(&parent) = rows.get(start) {
                children[parent].push(p);
            }
        }
        let slot_of = |column: usize, row: usize| -> Option<usize> {
            let slots = &rows[col_start[column]..col_start[column + 1]];
            slots
                .binary_search(&row)
                .ok()
                .map(|s| col_start[column] + s)
        };
        let place = |row: usize, column: usize| -> Option<usize> {
            if row == column {
                Some(row * BLOCK)
            } else {
                slot_of(column, row).map(|s| (n + s) * BLOCK)
            }
        };
        let mut update_start = Vec::with_capacity(n + 1);
        let mut updates = Vec::new();
        update_start.push(0);
        for p in 0..n {
            for a in col_start[p]..col_start[p + 1] {
                for b in col_start[p]..=a {
                    updates.push((place(rows[a], rows[b])?, a, b));
                }
            }
            update_start.push(updates.len());
        }
        let mut gather = vec![0usize; row_idx.len()];
        for j in 0..SIDE * n {
            let (l, c) = (j / SIDE, j % SIDE);
            let column = col_ptr[j]..col_ptr[j + 1];
            for (e, &i) in column.clone().zip(row_idx.get(column)?) {
                let (k, r) = (i / SIDE, i % SIDE);
                let (pk, pl) = (*position.get(k)?, position[l]);
                gather[e] = if pk >= pl {
                    place(pk, pl)? + r + SIDE * c
                } else {
                    // Entry (k, l) of H is entry (l, k) of its transpose:
                    // block (pl, pk) at row c, column r.
                    place(pl, pk)? + c + SIDE * r
                };
            }
        }
        let widest_column = col_start.windows(2).map(|w| w[1] - w[0]).max().unwrap_or(0);
        Some(Self {
            widest_column,
            order,
            col_start,
            rows,
            update_start,
            updates,
            gather,
        })
    }

    /// Bodies.
    fn bodies(&self) -> usize {
        self.order.len()
    }

    /// Entries of the block storage of `L`.
    pub fn len_val(&self) -> usize {
        (self.bodies() + self.rows.len()) * BLOCK
    }

    /// Bytes held by the analysis.
    pub fn bytes(&self) -> usize {
        let words = self.order.len()
            + self.col_start.len()
            + self.rows.len()
            + self.update_start.len()
            + 3 * self.updates.len()
            + self.gather.len();
        words * std::mem::size_of::<usize>()
    }

    /// Factors `H` from its lower-triangle values (in the order of the
    /// caller's compressed columns) into `factor` (length
    /// [`BlockSymbolic::len_val`]); `false` when a pivot is not positive
    /// and finite.
    pub fn factorize(&self, values: &[f64], factor: &mut [f64]) -> bool {
        if values.len() != self.gather.len() || factor.len() != self.len_val() {
            return false;
        }
        factor.fill(0.0);
        for (&value, &place) in values.iter().zip(&self.gather) {
            factor[place] = value;
        }
        // The kernels compiled for the CPU's widest vector instructions
        // (pulp's runtime dispatch; every kernel below is inlined into it).
        pulp::Arch::new().dispatch(
            #[inline(always)]
            || self.factorize_blocks(factor),
        )
    }

    /// The right-looking block elimination (module docs) on the gathered
    /// storage.
    #[inline(always)]
    fn factorize_blocks(&self, factor: &mut [f64]) -> bool {
        let n = self.bodies();
        let mut panel = vec![0.0; self.widest_column * BLOCK];
        for p in 0..n {
            let (head, tail) = factor.split_at_mut(n * BLOCK);
            let diagonal = &mut head[p * BLOCK..(p + 1) * BLOCK];
            if !cholesky6(diagonal) {
                return false;
            }
            let first = self.col_start[p];
            let slots = first..self.col_start[p + 1];
            for s in slots.clone() {
                let l = &mut tail[s * BLOCK..(s + 1) * BLOCK];
                right_solve_transpose(diagonal, l);
                panel[(s - first) * BLOCK..(s - first + 1) * BLOCK].copy_from_slice(l);
            }
            for &(target, a, b) in &self.updates[self.update_start[p]..self.update_start[p + 1]] {
                let la = &panel[(a - first) * BLOCK..(a - first + 1) * BLOCK];
                let lb = &panel[(b - first) * BLOCK..(b - first + 1) * BLOCK];
                subtract_product(&mut factor[target..target + BLOCK], la, lb);
            }
        }
        true
    }

    /// `H^-1 rhs` (in the caller's body order) with a factor from
    /// [`BlockSymbolic::factorize`].
    pub fn solve(&self, factor: &[f64], rhs: &[f64], out: &mut [f64]) {
        let n = self.bodies();
        let mut y = vec![0.0; SIDE * n];
        for (p, &k) in self.order.iter().enumerate() {
            y[SIDE * p..SIDE * p + SIDE].copy_from_slice(&rhs[SIDE * k..SIDE * k + SIDE]);
        }
        // L y = P rhs.
        for p in 0..n {
            let diagonal = &factor[p * BLOCK..(p + 1) * BLOCK];
            let mut yp = [0.0; SIDE];
            yp.copy_from_slice(&y[SIDE * p..SIDE * p + SIDE]);
            forward6(diagonal, &mut yp);
            y[SIDE * p..SIDE * p + SIDE].copy_from_slice(&yp);
            for s in self.col_start[p]..self.col_start[p + 1] {
                let l = &factor[(n + s) * BLOCK..(n + s + 1) * BLOCK];
                let q = self.rows[s];
                let yq = &mut y[SIDE * q..SIDE * q + SIDE];
                for c in 0..SIDE {
                    let x = yp[c];
                    for (r, value) in yq.iter_mut().enumerate() {
                        *value -= l[r + SIDE * c] * x;
                    }
                }
            }
        }
        // L^T x = y.
        for p in (0..n).rev() {
            let mut xp = [0.0; SIDE];
            xp.copy_from_slice(&y[SIDE * p..SIDE * p + SIDE]);
            for s in self.col_start[p]..self.col_start[p + 1] {
                let l = &factor[(n + s) * BLOCK..(n + s + 1) * BLOCK];
                let q = self.rows[s];
                let xq = &y[SIDE * q..SIDE * q + SIDE];
                for (c, value) in xp.iter_mut().enumerate() {
                    let column = &l[SIDE * c..SIDE * c + SIDE];
                    *value -= column.iter().zip(xq).map(|(a, b)| a * b).sum::<f64>();
                }
            }
            backward6(&factor[p * BLOCK..(p + 1) * BLOCK], &mut xp);
            y[SIDE * p..SIDE * p + SIDE].copy_from_slice(&xp);
        }
        for (p, &k) in self.order.iter().enumerate() {
            out[SIDE * k..SIDE * k + SIDE].copy_from_slice(&y[SIDE * p..SIDE * p + SIDE]);
        }
    }
}

/// faer's approximate minimum degree order of the body graph; `None` when
/// faer fails.
fn block_order(neighbours: &[Vec<usize>]) -> Option<Vec<usize>> {
    let n = neighbours.len();
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::new();
    col_ptr.push(0);
    for (l, list) in neighbours.iter().enumerate() {
        // Sorted and without repeats, as faer's checked pattern must be,
        // whatever the caller's list.
        let mut column: Vec<usize> = list.iter().copied().filter(|&k| k > l && k < n).collect();
        column.sort_unstable();
        column.dedup();
        row_idx.push(l);
        row_idx.extend(column);
        col_ptr.push(row_idx.len());
    }
    let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
    amd_order(pattern).map(|(order, _)| order)
}

/// The 6x6 Cholesky of the lower triangle of `a`, in place; `false` when a
/// pivot is not positive and finite.
#[inline(always)]
fn cholesky6(a: &mut [f64]) -> bool {
    for j in 0..SIDE {
        let pivot = a[j + SIDE * j];
        if !(pivot > 0.0 && pivot.is_finite()) {
            return false;
        }
        let d = pivot.sqrt();
        a[j + SIDE * j] = d;
        for r in j + 1..SIDE {
            a[r + SIDE * j] /= d;
        }
        for c in j + 1..SIDE {
            let l_cj = a[c + SIDE * j];
            for r in c..SIDE {
                a[r + SIDE * c] -= a[r + SIDE * j] * l_cj;
            }
        }
    }
    true
}

/// `x <- x L^-T` for the 6x6 lower factor `l` (row by row, `x L^T = b`
/// by forward substitution).
#[inline(always)]
fn right_solve_transpose(l: &[f64], x: &mut [f64]) {
    for c in 0..SIDE {
        let d = l[c + SIDE * c];
        for r in 0..SIDE {
            x[r + SIDE * c] /= d;
        }
        for t in c + 1..SIDE {
            let l_tc = l[t + SIDE * c];
            for r in 0..SIDE {
                x[r + SIDE * t] -= x[r + SIDE * c] * l_tc;
            }
        }
    }
}

/// `target -= a b^T` on 6x6 blocks.
#[inline(always)]
fn subtract_product(target: &mut [f64], a: &[f64], b: &[f64]) {
    for c in 0..SIDE {
        for t in 0..SIDE {
            let b_ct = b[c + SIDE * t];
            for r in 0..SIDE {
                target[r + SIDE * c] -= a[r + SIDE * t] * b_ct;
            }
        }
    }
}

/// `y <- L^-1 y` for the 6x6 lower factor `l`.
#[inline(always)]
fn forward6(l: &[f64], y: &mut [f64; SIDE]) {
    for c in 0..SIDE {
        y[c] /= l[c + SIDE * c];
        for r in c + 1..SIDE {
            y[r] -= l[r + SIDE * c] * y[c];
        }
    }
}

/// `x <- L^-T x` for the 6x6 lower factor `l`.
#[inline(always)]
fn backward6(l: &[f64], x: &mut [f64; SIDE]) {
    for c in (0..SIDE).rev() {
        let mut value = x[c];
        for r in c + 1..SIDE {
            value -= l[r + SIDE * c] * x[r];
        }
        x[c] = value / l[c + SIDE * c];
    }
}
