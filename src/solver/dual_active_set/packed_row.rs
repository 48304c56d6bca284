//! A contact row's gradient packed as at most two blocks of six entries
//! of `dq`: the dual active-set method's rows and their `M^-1` images,
//! whose products cost a 6-product per shared body.

use nalgebra::Vector6;

use crate::solver::metric::BlockMetric;
use crate::solver::projection::ProjectionQp;

/// A row's gradient (or `M^-1` times it) as at most two blocks of six
/// entries of `dq` (a contact's two bodies; an absent second block is
/// zeros at the first block's offset).
pub(super) struct PackedRow {
    offsets: [usize; 2],
    blocks: [Vector6<f64>; 2],
}

impl PackedRow {
    /// `a^T v` for a dense `v`.
    pub(super) fn dot(&self, v: &[f64]) -> f64 {
        self.offsets
            .iter()
            .zip(&self.blocks)
            .map(|(&offset, g)| Vector6::from_column_slice(&v[offset..offset + 6]).dot(g))
            .sum()
    }

    /// `a^T x` for another packed row: the blocks of the bodies both have.
    pub(super) fn dot_packed(&self, other: &PackedRow) -> f64 {
        let mut sum = 0.0;
        for (&offset, g) in self.offsets.iter().zip(&self.blocks) {
            for (&other_offset, h) in other.offsets.iter().zip(&other.blocks) {
                if offset == other_offset {
                    sum += g.dot(h);
                }
            }
        }
        sum
    }

    /// `v <- v + c a`.
    pub(super) fn add_to(&self, c: f64, v: &mut [f64]) {
        for (&offset, g) in self.offsets.iter().zip(&self.blocks) {
            for (x, gi) in v[offset..offset + 6].iter_mut().zip(g.iter()) {
                *x += c * gi;
            }
        }
    }

    /// `M^-1 a` (`M` block diagonal, so the same bodies).
    pub(super) fn scaled(&self, metric: &[BlockMetric]) -> PackedRow {
        PackedRow {
            offsets: self.offsets,
            // A row of no body (zero blocks at offset 0) of a problem with
            // no body has no metric block: zeros.
            blocks: [0, 1].map(|slot| {
                metric
                    .get(self.offsets[slot] / 6)
                    .map_or_else(Vector6::zeros, |block| block.apply_inv(&self.blocks[slot]))
            }),
        }
    }
}

/// The rows packed; `None` when a row has more than two bodies (not a
/// contact's: the other solvers take that problem).
pub(super) fn packed_rows(qp: &ProjectionQp) -> Option<Vec<PackedRow>> {
    qp.rows
        .iter()
        .map(|row| {
            let mut packed = PackedRow {
                offsets: [0; 2],
                blocks: [Vector6::zeros(); 2],
            };
            match row.blocks.as_slice() {
                [] => {}
                [(k, g)] => {
                    packed.offsets = [6 * k, 6 * k];
                    packed.blocks[0] = *g;
                }
                [(k, g), (l, h)] => {
                    packed.offsets = [6 * k, 6 * l];
                    packed.blocks = [*g, *h];
                }
                _ => return None,
            }
            Some(packed)
        })
        .collect()
}
