//! The constraint provider of one island: contacts between the bodies that
//! move and between them and the bodies that hold still (fixed bodies, and
//! dynamic bodies outside the region being solved).
//!
//! The configuration holds the moving bodies in ascending order of scene
//! index; every other body keeps the pose it had when the island was
//! formed. The narrow phase runs once per configuration: the answers of the
//! configuration the island starts from come from the detection (no query),
//! a measurement and a linearization at the same configuration share one
//! set of answers, and each line-search trial queries every pair once,
//! warm-started from the pair's previous answer (trials differ little, so
//! these queries are nearly O(1)). The answers of the last configuration
//! measured (the accepted one, when the line search accepts) are handed
//! back for the next detection ([`IslandContacts::answers`]).

use std::sync::Arc;
use std::time::Instant;

use nalgebra::Isometry3;

use super::memo::PosedQuery;
use super::scene_parts::SceneParts;
use super::{BodyGeometry, ContactFriction, PairQuery, contact_rows, query};
use crate::broad_phase::BodyPair;
use crate::geometry::ConvexPolyhedron;
use crate::rows::{BodyState, ConstraintProvider, ConstraintRow, Measurement};
use crate::settings::Settings;
use crate::vclip::{FeaturePair, VClip};

/// Signed value reported for a pair whose query failed (a non-finite trial
/// pose): it makes the merit infinite, so the line search rejects the trial.
const FAILED_QUERY_VALUE: f64 = f64::NEG_INFINITY;

/// Shapes and poses of every convex part of the scene (its bodies' parts,
/// [`SceneParts`]), shared read-only by islands.
#[derive(Debug, Clone, Copy)]
pub struct SceneGeometry<'a> {
    /// The parts: polyhedra and owners.
    pub parts: &'a SceneParts,
    /// World pose of each part when the island was formed.
    pub poses: &'a [Isometry3<f64>],
}

impl<'a> SceneGeometry<'a> {
    /// Polyhedron of each part.
    pub fn shapes(&self) -> &'a [Arc<ConvexPolyhedron>] {
        self.parts.shapes()
    }

    /// Part `part` at its pose in the scene, as a body that does not move.
    pub fn held(&self, part: usize) -> BodyGeometry<'a> {
        BodyGeometry::convex(&self.parts.shapes()[part], self.poses[part], None)
            .rounded(self.parts.rounding(part))
            .curved(self.parts.curved(part))
    }
}

/// Contacts of one island.
pub struct IslandContacts<'a> {
    scene: SceneGeometry<'a>,
    /// Moving bodies, ascending scene indices (configuration order).
    bodies: Vec<usize>,
    /// Part pairs ([`SceneParts`]).
    pairs: Vec<BodyPair>,
    /// Friction coefficient of each pair.
    friction: Vec<f64>,
    /// Answers at `answered_at` (`None` for a failed query).
    answers: Vec<Option<PairQuery>>,
    answered_at: Vec<BodyState>,
    warm_starts: Vec<Option<FeaturePair>>,
    /// Pair index of each row of the last linearization.
    row_pairs: Vec<usize>,
    /// The call's settings (manifolds, V-Clip).
    settings: &'a Settings,
    /// V-Clip with the settings' parameters.
    vclip: VClip,
    /// Separated pairs closer than this give rows.
    margin: f64,
    queries: usize,
    query_seconds: f64,
}

impl<'a> IslandContacts<'a> {
    /// The contacts of the part pairs `pairs` (each with at least one part
    /// of a body in `bodies`),
    /// with friction coefficients `friction`, whose answers at
    /// `configuration` (the bodies' poses in `scene`) are `answers`;
    /// separated pairs closer than `margin` give rows.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        scene: SceneGeometry<'a>,
        bodies: Vec<usize>,
        pairs: Vec<BodyPair>,
        friction: Vec<f64>,
        answers: Vec<PairQuery>,
        configuration: Vec<BodyState>,
        settings: &'a Settings,
        margin: f64,
    ) -> Self {
        let warm_starts = answers.iter().map(|a| Some(a.vclip.final_pair)).collect();
        IslandContacts {
            scene,
            bodies,
            pairs,
            friction,
            answers: answers.into_iter().map(Some).collect(),
            answered_at: configuration,
            warm_starts,
            row_pairs: Vec::new(),
            settings,
            vclip: VClip::new(settings.vclip),
            margin,
            queries: 0,
            query_seconds: 0.0,
        }
    }

    /// The moving bodies, ascending scene indices (configuration order).
    pub fn bodies(&self) -> &[usize] {
        &self.bodies
    }

    /// The part pairs, in provider order.
    pub fn pairs(&self) -> &[BodyPair] {
        &self.pairs
    }

    /// The body pair of each part pair, in provider order.
    pub fn body_pairs(&self) -> Vec<BodyPair> {
        let parts = self.scene.parts;
        self.pairs
            .iter()
            .map(|&pair| parts.owner_pair(pair))
            .collect()
    }

    /// Pair index (into [`IslandContacts::pairs`]) of each row of the last
    /// linearization.
    pub fn row_pairs(&self) -> &[usize] {
        &self.row_pairs
    }

    /// Pair queries run so far (answers taken from the detection excluded).
    pub fn queries(&self) -> usize {
        self.queries
    }

    /// Wall time of those queries, seconds.
    pub fn query_seconds(&self) -> f64 {
        self.query_seconds
    }

    /// The last feature pair of every pair queried or answered, to record
    /// in the stabilizer's cache ([`WarmStartCache::insert`]).
    pub fn warm_starts(&self) -> Vec<(BodyPair, FeaturePair)> {
        self.pairs
            .iter()
            .zip(&self.warm_starts)
            .filter_map(|(&pair, start)| start.map(|features| (pair, features)))
            .collect()
    }

    /// The answers of the last configuration measured, with the poses they
    /// were computed at (failed queries left out).
    pub fn answers(&self) -> Vec<(BodyPair, PosedQuery)> {
        let configuration = &self.answered_at;
        self.pairs
            .iter()
            .zip(&self.answers)
            .filter_map(|(&pair, answer)| {
                let query = answer.clone()?;
                let poses = [
                    self.geometry(pair.body_a, configuration).pose,
                    self.geometry(pair.body_b, configuration).pose,
                ];
                Some((pair, PosedQuery { poses, query }))
            })
            .collect()
    }

    /// Part `part` at `configuration` (its body's state there if the body
    /// moves, else its pose in the scene).
    fn geometry(&self, part: usize, configuration: &[BodyState]) -> BodyGeometry<'a> {
        let parts = self.scene.parts;
        match self.bodies.binary_search(&parts.owner(part)) {
            Ok(index) => {
                let state = &configuration[index];
                BodyGeometry {
                    shape: &parts.shapes()[part],
                    pose: parts.pose(part, &state.isometry()),
                    configuration_index: Some(index),
                    com_world: state.position,
                    rounding: parts.rounding(part),
                    curved: parts.curved(part),
                }
            }
            Err(_) => self.scene.held(part),
        }
    }

    /// Makes the answers those of `configuration`, querying every pair
    /// (warm-started) unless they already are.
    fn answer_at(&mut self, configuration: &[BodyState]) {
        if self.answered_at.as_slice() == configuration {
            return;
        }
        let start = Instant::now();
        for k in 0..self.pairs.len() {
            let pair = self.pairs[k];
            let a = self.geometry(pair.body_a, configuration);
            let b = self.geometry(pair.body_b, configuration);
            self.answers[k] = match query(&self.vclip, &a, &b, self.warm_starts[k]) {
                Ok(result) => {
                    self.warm_starts[k] = Some(result.vclip.final_pair);
                    Some(result)
                }
                Err(error) => {
                    log::warn!("island pair {pair:?}: V-Clip query failed: {error}");
                    None
                }
            };
        }
        self.queries += self.pairs.len();
        self.answered_at = configuration.to_vec();
        self.query_seconds += start.elapsed().as_secs_f64();
    }
}

impl ConstraintProvider for IslandContacts<'_> {
    fn linearize(&mut self, configuration: &[BodyState]) -> Vec<ConstraintRow> {
        self.answer_at(configuration);
        let mut rows = Vec::new();
        self.row_pairs.clear();
        for (k, &pair) in self.pairs.iter().enumerate() {
            let Some(result) = &self.answers[k] else {
                continue;
            };
            let a = self.geometry(pair.body_a, configuration);
            let b = self.geometry(pair.body_b, configuration);
            let friction = ContactFriction {
                mu: self.friction[k],
            };
            let pair_rows = contact_rows(result, &a, &b, self.margin, self.settings, friction);
            if let (Some(penetration), None) = (&result.penetration, &result.round) {
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
            } else {
                log::trace!(
                    "  pair ({}, {}): separated by {:.3e}; {} rows",
                    pair.body_a,
                    pair.body_b,
                    result.signed_value(),
                    pair_rows.len(),
                );
            }
            self.row_pairs
                .extend(std::iter::repeat_n(k, pair_rows.len()));
            rows.extend(pair_rows);
        }
        rows
    }

    fn measure(&mut self, configuration: &[BodyState]) -> Measurement {
        self.answer_at(configuration);
        let values = self
            .answers
            .iter()
            .map(|answer| match answer {
                Some(result) => result.signed_value(),
                None => FAILED_QUERY_VALUE,
            })
            .collect();
        Measurement {
            values,
            equalities: Vec::new(),
        }
    }
}

/// The shapes of a pair, the key of its warm start.
pub fn shape_pair(shapes: &[Arc<ConvexPolyhedron>], pair: BodyPair) -> [&Arc<ConvexPolyhedron>; 2] {
    [&shapes[pair.body_a], &shapes[pair.body_b]]
}
