//! Friction cones in the whitened, unit-scaled variables of [`super::primal`].
//!
//! A cone `w = (b + J_n dq, mu J_t1 dq, mu J_t2 dq) in K`
//! ([`crate::solver::friction_cone`]) has three rows `R_j` (`J_n`,
//! `mu J_t1`, `mu J_t2`). With `y = L^T dq = s y^` they become
//! `G_j = L^-1 R_j^T`, and the cone is divided by one factor `g`, the norm
//! of the normal row `|G_0|` (of the largest tangent row when no body moves
//! the normal one): `K` is invariant under a common positive scaling of its
//! three components, not under one per component. In clarabel's form
//! `A x + sigma = b, sigma in K`:
//!
//! ```text
//! sigma = (b / (g s) + G^_0 y^,  G^_1 y^,  G^_2 y^),    G^_j = G_j / g,
//! A = -[G^_0; G^_1; G^_2],   b = (b / (g s), 0, 0),   SecondOrderConeT(3).
//! ```
//!
//! The dual `z^ in K` maps back as a row's does: `z = s z^ / g` (all three
//! components, so `|z_t| <= z_0` is kept). A violated cone (`b < 0`) counts
//! in the variable scale `s` as a violated row: `-b / g`, the distance in
//! `y` of its normal row's half-space, which the cone lies in.

use nalgebra::Vector6;

use crate::solver::friction_cone::{CONE_DIM, FrictionCone};
use crate::solver::metric::BlockMetric;
use crate::solver::projection::JacobianRow;

/// A row in whitened variables: `L_k^-1 g` per block.
pub(super) fn whitened_blocks(
    row: &JacobianRow,
    metric: &[BlockMetric],
) -> Vec<(usize, Vector6<f64>)> {
    row.blocks
        .iter()
        .map(|(k, g)| (*k, metric[*k].solve_l(g)))
        .collect()
}

/// `|G|` of whitened blocks.
pub(super) fn blocks_norm(blocks: &[(usize, Vector6<f64>)]) -> f64 {
    blocks
        .iter()
        .map(|(_, v)| v.norm_squared())
        .sum::<f64>()
        .sqrt()
}

/// Whitened blocks divided by `g`, as `(variable, value)` without zeros.
pub(super) fn scaled_entries(blocks: &[(usize, Vector6<f64>)], g: f64) -> Vec<(usize, f64)> {
    blocks
        .iter()
        .flat_map(|(k, v)| v.iter().enumerate().map(move |(e, x)| (6 * k + e, x / g)))
        .filter(|(_, x)| *x != 0.0)
        .collect()
}

/// One cone in whitened variables (module docs), before the variable
/// scale `s` is known.
pub(super) struct WhiteCone {
    /// Index of the cone in the problem.
    pub index: usize,
    /// The common factor `g`.
    pub norm: f64,
    /// `G^_0, G^_1, G^_2` as `(variable, value)`.
    pub rows: [Vec<(usize, f64)>; CONE_DIM],
    /// `b` of the cone.
    pub b: f64,
}

/// The whitened cone, or `None` when no body moves any of its rows (then
/// `dq` cannot change it; the caller rejects it when it is violated).
pub(super) fn whiten_cone(
    index: usize,
    cone: &FrictionCone,
    metric: &[BlockMetric],
) -> Option<WhiteCone> {
    let blocks = cone.rows().map(|row| whitened_blocks(&row, metric));
    let norms = blocks.each_ref().map(|b| blocks_norm(b));
    let norm = if norms[0] > 0.0 {
        norms[0]
    } else {
        norms[1].max(norms[2])
    };
    (norm > 0.0 && norm.is_finite()).then(|| WhiteCone {
        index,
        norm,
        rows: blocks.each_ref().map(|b| scaled_entries(b, norm)),
        b: cone.b(),
    })
}
