//! The constraint provider of one island: contacts from V-Clip between the
//! island's dynamic bodies and between them and fixed bodies.
//!
//! The configuration holds the island's dynamic bodies in ascending order
//! of scene index; every other body keeps the pose it had when the island
//! was formed. Each measurement and linearization re-runs V-Clip on the
//! island's pairs, warm-started from the last query of the same pair (the
//! line search's trial configurations differ little, so these queries are
//! nearly O(1)).

use std::sync::Arc;

use nalgebra::Isometry3;

use crate::broad_phase::BodyPair;
use crate::contact::PairQuery;
use crate::contact::{self, BodyGeometry, WarmStartCache};
use crate::geometry::ConvexPolyhedron;
use crate::projector::{BodyState, ConstraintProvider, ConstraintRow, Measurement};
use crate::vclip::{FeaturePair, VClip};

/// Signed value reported for a pair whose query failed (a non-finite trial
/// pose): it makes the merit infinite, so the line search rejects the trial.
const FAILED_QUERY_VALUE: f64 = f64::NEG_INFINITY;

/// Shapes and poses of every body of the scene, shared read-only by islands.
#[derive(Debug, Clone, Copy)]
pub struct SceneGeometry<'a> {
    /// Polyhedron of each body.
    pub shapes: &'a [Arc<ConvexPolyhedron>],
    /// Centre-of-mass pose of each body when the island was formed.
    pub poses: &'a [Isometry3<f64>],
}

/// Contacts of one island.
pub struct IslandProvider<'a> {
    scene: SceneGeometry<'a>,
    /// Dynamic bodies, ascending scene indices (configuration order).
    bodies: &'a [usize],
    pairs: Vec<BodyPair>,
    warm_starts: Vec<Option<FeaturePair>>,
    vclip: VClip,
    margin: f64,
    manifold: bool,
}

impl<'a> IslandProvider<'a> {
    /// The provider of `pairs` between `bodies` (and fixed bodies).
    pub fn new(
        scene: SceneGeometry<'a>,
        bodies: &'a [usize],
        pairs: Vec<BodyPair>,
        cache: &WarmStartCache,
        vclip: VClip,
        margin: f64,
        manifold: bool,
    ) -> Self {
        let warm_starts = pairs
            .iter()
            .map(|&pair| cache.get(pair, shape_pair(scene.shapes, pair)))
            .collect();
        IslandProvider {
            scene,
            bodies,
            pairs,
            warm_starts,
            vclip,
            margin,
            manifold,
        }
    }

    /// The last feature pairs, to merge into the stabilizer's cache.
    pub fn record_warm_starts(&self, cache: &mut WarmStartCache) {
        for (&pair, start) in self.pairs.iter().zip(&self.warm_starts) {
            if let Some(features) = start {
                cache.insert(pair, shape_pair(self.scene.shapes, pair), *features);
            }
        }
    }

    fn geometry(&self, body: usize, configuration: &[BodyState]) -> BodyGeometry<'a> {
        let configuration_index = self.bodies.binary_search(&body).ok();
        let pose = match configuration_index {
            Some(index) => configuration[index].isometry(),
            None => self.scene.poses[body],
        };
        BodyGeometry {
            shape: &self.scene.shapes[body],
            pose,
            configuration_index,
        }
    }

    /// V-Clip on pair `k`, warm-started and recording the new start.
    fn query(
        &mut self,
        k: usize,
        configuration: &[BodyState],
    ) -> Option<(PairQuery, BodyGeometry<'a>, BodyGeometry<'a>)> {
        let pair = self.pairs[k];
        let a = self.geometry(pair.body_a, configuration);
        let b = self.geometry(pair.body_b, configuration);
        match contact::query(&self.vclip, &a, &b, self.warm_starts[k]) {
            Ok(result) => {
                self.warm_starts[k] = Some(result.vclip.final_pair);
                Some((result, a, b))
            }
            Err(error) => {
                log::warn!("island pair {pair:?}: V-Clip query failed: {error}");
                None
            }
        }
    }
}

impl ConstraintProvider for IslandProvider<'_> {
    fn linearize(&mut self, configuration: &[BodyState]) -> Vec<ConstraintRow> {
        let mut rows = Vec::new();
        for k in 0..self.pairs.len() {
            if let Some((result, a, b)) = self.query(k, configuration) {
                let pair_rows = contact::contact_rows(&result, &a, &b, self.margin, self.manifold);
                if let Some(penetration) = &result.penetration {
                    let pair = self.pairs[k];
                    let (exact, reference) = (&penetration.exact, &penetration.reference);
                    log::trace!(
                        "  pair ({}, {}): {} depth {:.3e}, normal {:.3?}; {} rows on {} {:.3e}",
                        pair.body_a,
                        pair.body_b,
                        exact.features.kind(),
                        exact.depth,
                        exact.normal_world.as_slice(),
                        pair_rows.len(),
                        reference.features.kind(),
                        reference.depth,
                    );
                }
                rows.extend(pair_rows);
            }
        }
        rows
    }

    fn measure(&mut self, configuration: &[BodyState]) -> Measurement {
        let values = (0..self.pairs.len())
            .map(|k| match self.query(k, configuration) {
                Some((result, _, _)) => result.signed_value(),
                None => FAILED_QUERY_VALUE,
            })
            .collect();
        Measurement { values }
    }
}

/// The shapes of a pair, the key of its warm start.
pub fn shape_pair(shapes: &[Arc<ConvexPolyhedron>], pair: BodyPair) -> [&Arc<ConvexPolyhedron>; 2] {
    [&shapes[pair.body_a], &shapes[pair.body_b]]
}
