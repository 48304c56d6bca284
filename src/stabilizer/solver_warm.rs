//! The solver's warm starts: the multipliers of the last answer of every
//! body pair, kept across the passes of a call and across calls, for the
//! solvers that take them (the dual active-set method, the interior point,
//! the augmented Lagrangian; [`crate::solver::solve_projection_warm`],
//! [`crate::solver::SolverSettings::warm_starts`]).
//!
//! **Key.** The multipliers of one part pair are kept as one vector, in the
//! order of the projection QP: the pair's contact rows, then its friction
//! rows. An entry belongs to the two shape objects it was recorded for
//! (held as `Weak` references, as V-Clip's warm starts,
//! [`crate::contact::WarmStartCache`]), and fits a problem only when that
//! problem has as many multipliers for the pair. Bodies added, removed,
//! reordered or replaced (another shape object under the pair's indices),
//! shapes changed (a new shape object) and contact features changed (a
//! different number of rows) all make the entry miss: it is dropped from
//! the warm start, whose row then starts at 0. Within a pair of the same
//! row count the rows are matched by position; a row that moved to
//! another feature is still only a hint.
//!
//! **Why it cannot change an answer.** A warm start is where the solver
//! starts, not what it returns: every answer passes the same acceptance
//! test as a cold one (the KKT residuals of `dq` within the tolerance), and
//! the minimizer in `dq` is unique. A stale entry can cost iterations,
//! never the answer beyond the tolerance.
//!
//! **Size.** Entries of shapes that no longer exist are removed once per
//! call ([`SolverWarmCache::forget_dropped_shapes`]), and the cache is
//! cleared when bodies are removed from a scene through the stabilizer;
//! [`SolverWarmCache::multipliers`] counts what is kept (in the report).

use std::sync::Arc;

use nalgebra::DVector;

use crate::broad_phase::{BodyPair, PairMap};
use crate::contact::ShapeIdentity;
use crate::geometry::ConvexPolyhedron;

/// Multipliers of earlier answers per part pair (module docs).
#[derive(Debug, Clone, Default)]
pub struct SolverWarmCache {
    entries: PairMap<PairMultipliers>,
}

#[derive(Debug, Clone)]
struct PairMultipliers {
    shapes: ShapeIdentity,
    lambda: Vec<f64>,
}

/// The part pair of every multiplier of a problem (`None`: a joint's row,
/// never warm-started), grouped by pair, and the shapes of the parts.
/// Built once per solved problem: the same keys read its warm start and
/// record its answer.
pub struct MultiplierPairs<'a> {
    /// The multipliers of each pair, by position in the problem, in order.
    positions: PairMap<Vec<usize>>,
    /// Number of multipliers of the problem.
    len: usize,
    /// The scene's shapes, by part.
    shapes: &'a [Arc<ConvexPolyhedron>],
}

impl<'a> MultiplierPairs<'a> {
    /// Keys of a problem whose multiplier `i` belongs to `pairs[i]`.
    pub fn new(pairs: &[Option<BodyPair>], shapes: &'a [Arc<ConvexPolyhedron>]) -> Self {
        let mut positions: PairMap<Vec<usize>> = PairMap::default();
        for (i, pair) in pairs.iter().enumerate() {
            if let Some(pair) = pair {
                positions.entry(*pair).or_default().push(i);
            }
        }
        Self {
            positions,
            len: pairs.len(),
            shapes,
        }
    }

    fn shapes_of(&self, pair: BodyPair) -> Option<[&Arc<ConvexPolyhedron>; 2]> {
        Some([self.shapes.get(pair.body_a)?, self.shapes.get(pair.body_b)?])
    }
}

/// The warm starts a pass sees: the entries recorded by this call's later
/// passes over those of the kept cache (the last calls' first passes and
/// this call's first), newer first. Layers instead of a merged copy: a
/// pass reads the kept cache in place, nothing is copied per call.
#[derive(Debug, Clone, Copy)]
pub struct WarmLayers<'a> {
    /// The entries of this call's passes after the first.
    pub newer: &'a SolverWarmCache,
    /// The kept cache.
    pub older: &'a SolverWarmCache,
}

impl WarmLayers<'_> {
    /// The warm start of a problem whose multipliers belong to `keys`:
    /// every pair's newest kept multipliers where they fit (module docs),
    /// 0 elsewhere; `None` when no pair fits.
    pub fn warm_start(&self, keys: &MultiplierPairs<'_>) -> Option<DVector<f64>> {
        let mut lambda = DVector::zeros(keys.len);
        let (mut fitting, mut missing) = (0, 0);
        for (pair, positions) in &keys.positions {
            let Some(entry) = self
                .newer
                .entries
                .get(pair)
                .or_else(|| self.older.entries.get(pair))
            else {
                missing += 1;
                continue;
            };
            let fits = entry.lambda.len() == positions.len()
                && keys
                    .shapes_of(*pair)
                    .is_some_and(|shapes| entry.shapes.belongs_to(shapes));
            if !fits {
                continue;
            }
            for (&i, &value) in positions.iter().zip(&entry.lambda) {
                lambda[i] = value;
            }
            fitting += 1;
        }
        log::trace!(
            "warm start: {fitting} of {} pairs fit ({missing} without an entry)",
            keys.positions.len()
        );
        (fitting > 0).then_some(lambda)
    }
}

impl SolverWarmCache {
    /// Records the multipliers `lambda` of a problem with `keys`.
    pub fn record(&mut self, keys: &MultiplierPairs<'_>, lambda: &DVector<f64>) {
        if lambda.len() != keys.len {
            return;
        }
        for (&pair, positions) in &keys.positions {
            let Some(shapes) = keys.shapes_of(pair) else {
                continue;
            };
            let values = positions.iter().map(|&i| lambda[i]).collect();
            self.entries.insert(
                pair,
                PairMultipliers {
                    shapes: ShapeIdentity::of(shapes),
                    lambda: values,
                },
            );
        }
    }

    /// Takes over every entry of `other` (newer answers win).
    pub fn merge(&mut self, other: SolverWarmCache) {
        self.entries.extend(other.entries);
    }

    /// Removes the entries of shapes that have been dropped.
    pub fn forget_dropped_shapes(&mut self) {
        self.entries.retain(|_, entry| entry.shapes.alive());
    }

    /// Removes every entry.
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// Number of multipliers kept.
    pub fn multipliers(&self) -> usize {
        self.entries.values().map(|entry| entry.lambda.len()).sum()
    }
}
