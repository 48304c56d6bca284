//! The sparse Cholesky by 6x6 body blocks (`solver::block_cholesky`)
//! against nalgebra's dense one on random symmetric positive definite
//! matrices with the block patterns of body-space matrices (chains, stars,
//! random graphs, disconnected bodies, one body), and its refusal of a
//! matrix that is not positive definite.

use constraint_stabilization::solver::block_cholesky::BlockSymbolic;
use nalgebra::{DMatrix, DVector};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Relative agreement of two backward-stable solves of a system whose
/// condition number is below about 1e4: rounding of order `n u kappa`.
const SOLVE_AGREEMENT_TOL: f64 = 1e-9;

/// Body-space entries per body.
const SIDE: usize = 6;

/// `neighbours[l]`: the bodies `k > l` coupled with `l`, ascending, for the
/// undirected `edges`.
fn neighbours(n: usize, edges: &[(usize, usize)]) -> Vec<Vec<usize>> {
    let mut list = vec![Vec::new(); n];
    for &(a, b) in edges {
        list[a.min(b)].push(a.max(b));
    }
    for l in &mut list {
        l.sort_unstable();
        l.dedup();
    }
    list
}

/// `M + sum_e G_e G_e^T`: `M` block diagonal and positive definite, each
/// edge a random rank-3 coupling of its two bodies (so every coupled
/// block is nonzero and the matrix positive definite).
fn random_matrix(n: usize, edges: &[(usize, usize)], rng: &mut ChaCha8Rng) -> DMatrix<f64> {
    let dofs = SIDE * n;
    let mut h = DMatrix::zeros(dofs, dofs);
    for k in 0..n {
        let b = DMatrix::from_fn(SIDE, SIDE, |_, _| rng.random_range(-1.0..1.0));
        let block = &b * b.transpose() + DMatrix::identity(SIDE, SIDE);
        h.view_mut((SIDE * k, SIDE * k), (SIDE, SIDE))
            .copy_from(&block);
    }
    for &(a, b) in edges {
        let mut g = DMatrix::zeros(dofs, 3);
        for c in 0..3 {
            for r in 0..SIDE {
                g[(SIDE * a + r, c)] = rng.random_range(-1.0..1.0);
                g[(SIDE * b + r, c)] = rng.random_range(-1.0..1.0);
            }
        }
        h += &g * g.transpose();
    }
    h
}

/// The lower triangle of `h` in the compressed columns of the body-space
/// pattern: column `6 l + c` holds rows `6 l + c .. 6 l + 6`, then the six
/// rows of each neighbour `k > l`.
fn lower_pattern(
    h: &DMatrix<f64>,
    neighbours: &[Vec<usize>],
) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let mut col_ptr = vec![0];
    let mut row_idx = Vec::new();
    let mut values = Vec::new();
    for (l, list) in neighbours.iter().enumerate() {
        for c in 0..SIDE {
            let j = SIDE * l + c;
            let rows =
                (j..SIDE * l + SIDE).chain(list.iter().flat_map(|&k| SIDE * k..SIDE * k + SIDE));
            for i in rows {
                row_idx.push(i);
                values.push(h[(i, j)]);
            }
            col_ptr.push(row_idx.len());
        }
    }
    (col_ptr, row_idx, values)
}

/// Factors and solves `h x = rhs` by blocks and checks the answer against
/// nalgebra's Cholesky and the residual.
fn check(n: usize, edges: &[(usize, usize)], rng: &mut ChaCha8Rng, what: &str) {
    let list = neighbours(n, edges);
    let h = random_matrix(n, edges, rng);
    let (col_ptr, row_idx, values) = lower_pattern(&h, &list);
    let symbolic = BlockSymbolic::new(&list, &col_ptr, &row_idx).expect("a valid pattern");
    let mut factor = vec![0.0; symbolic.len_val()];
    assert!(
        symbolic.factorize(&values, &mut factor),
        "{what}: factorization failed"
    );
    let rhs = DVector::from_fn(SIDE * n, |_, _| rng.random_range(-1.0..1.0));
    let mut x = DVector::zeros(SIDE * n);
    symbolic.solve(&factor, rhs.as_slice(), x.as_mut_slice());
    let y = h.clone().cholesky().expect("positive definite").solve(&rhs);
    let relative = (&x - &y).norm() / y.norm();
    assert!(
        relative <= SOLVE_AGREEMENT_TOL,
        "{what}: {relative:e} from nalgebra"
    );
    let residual = (&h * &x - &rhs).norm() / rhs.norm();
    assert!(
        residual <= SOLVE_AGREEMENT_TOL,
        "{what}: residual {residual:e}"
    );
}

#[test]
fn solves_as_nalgebra_on_body_space_patterns() {
    let mut rng = ChaCha8Rng::seed_from_u64(36);
    check(1, &[], &mut rng, "one body");
    check(5, &[], &mut rng, "five bodies, no coupling");
    let chain: Vec<_> = (1..30).map(|k| (k - 1, k)).collect();
    check(30, &chain, &mut rng, "chain of 30");
    let star: Vec<_> = (1..25).map(|k| (0, k)).collect();
    check(25, &star, &mut rng, "star of 25");
    let complete: Vec<_> = (0..12)
        .flat_map(|a| (a + 1..12).map(move |b| (a, b)))
        .collect();
    check(12, &complete, &mut rng, "complete graph of 12");
    for (n, degree) in [(20, 2.0), (60, 4.0), (157, 5.5)] {
        for _ in 0..3 {
            let p = degree / n as f64;
            let edges: Vec<_> = (0..n)
                .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
                .filter(|_| rng.random_bool(p))
                .collect();
            check(
                n,
                &edges,
                &mut rng,
                &format!("random graph of {n}, degree {degree}"),
            );
        }
    }
}

/// A pivot block that is not positive definite fails the factorization
/// instead of answering.
#[test]
fn refuses_a_matrix_that_is_not_positive_definite() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let edges = [(0, 1), (1, 2)];
    let list = neighbours(3, &edges);
    let mut h = random_matrix(3, &edges, &mut rng);
    h[(14, 14)] = -1.0;
    let (col_ptr, row_idx, values) = lower_pattern(&h, &list);
    let symbolic = BlockSymbolic::new(&list, &col_ptr, &row_idx).expect("a valid pattern");
    let mut factor = vec![0.0; symbolic.len_val()];
    assert!(!symbolic.factorize(&values, &mut factor));
    let mut nan = values.clone();
    nan[0] = f64::NAN;
    assert!(!symbolic.factorize(&nan, &mut factor));
}

/// A pattern whose columns do not match the bodies is refused.
#[test]
fn refuses_a_pattern_of_another_size() {
    let list = neighbours(2, &[(0, 1)]);
    assert!(BlockSymbolic::new(&list, &[0, 1], &[0]).is_none());
}
