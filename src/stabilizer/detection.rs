//! Detection over the whole scene: broad phase, then V-Clip on every
//! candidate pair (warm-started), classified against the tolerance and the
//! contact margin.

use std::time::Instant;

use nalgebra::Isometry3;

use crate::broad_phase::{self, BodyPair};
use crate::contact::PairQuery;
use crate::contact::{self, BodyGeometry, WarmStartCache};
use crate::scene::Scene;
use crate::vclip::VClip;

use super::island_provider::{SceneGeometry, shape_pair};
use super::report::PairPenetration;
use super::settings::ResolvedLengths;
use super::{StabilizeError, parallel};

/// The pairs that matter after one detection.
#[derive(Debug, Clone, Default)]
pub struct Detection {
    /// Candidate pairs from the broad phase.
    pub candidates: usize,
    /// Pairs penetrating or within the contact margin, ascending.
    pub active_pairs: Vec<BodyPair>,
    /// Signed value (distance, or minus depth) of each active pair.
    pub active_values: Vec<f64>,
    /// Deepest penetration over all pairs (0 if none).
    pub deepest: f64,
    /// The pairs penetrating deeper than the tolerance, ascending.
    pub penetrations: Vec<PairPenetration>,
    /// Broad-phase wall time, seconds.
    pub broad_phase_seconds: f64,
    /// Narrow-phase wall time, seconds.
    pub narrow_phase_seconds: f64,
}

impl Detection {
    /// Number of active pairs penetrating deeper than `tolerance`.
    pub fn penetrating(&self, tolerance: f64) -> usize {
        self.active_values
            .iter()
            .filter(|&&v| -v > tolerance)
            .count()
    }
}

/// Broad and narrow phase at the scene's current poses; updates the cache.
pub fn detect(
    scene: &Scene,
    geometry: SceneGeometry,
    cache: &mut WarmStartCache,
    vclip: &VClip,
    lengths: &ResolvedLengths,
) -> Result<Detection, StabilizeError> {
    let broad_start = Instant::now();
    let candidates = broad_phase::candidate_pairs(scene, lengths.contact_margin)?;
    let broad_phase_seconds = broad_start.elapsed().as_secs_f64();
    let narrow_start = Instant::now();
    let results = parallel::map(&candidates, |&pair| {
        let start = cache.get(pair, shape_pair(geometry.shapes, pair));
        query_pair(geometry, pair, vclip, start)
    });
    let mut detection = Detection {
        candidates: candidates.len(),
        broad_phase_seconds,
        ..Detection::default()
    };
    for (pair, result) in candidates.into_iter().zip(results) {
        let result = result?;
        cache.insert(
            pair,
            shape_pair(geometry.shapes, pair),
            result.vclip.final_pair,
        );
        let value = result.signed_value();
        detection.deepest = detection.deepest.max(-value);
        if let Some(penetration) = result.penetration.filter(|p| p.depth() > lengths.tolerance) {
            log::debug!(
                "penetration ({}, {}): {} depth {:.3e}",
                pair.body_a,
                pair.body_b,
                penetration.features().kind(),
                penetration.depth()
            );
            detection.penetrations.push(PairPenetration {
                body_a: pair.body_a,
                body_b: pair.body_b,
                features: penetration.features(),
                depth: penetration.depth(),
            });
        }
        if value < lengths.contact_margin {
            detection.active_pairs.push(pair);
            detection.active_values.push(value);
        }
    }
    detection.narrow_phase_seconds = narrow_start.elapsed().as_secs_f64();
    Ok(detection)
}

fn query_pair(
    geometry: SceneGeometry,
    pair: BodyPair,
    vclip: &VClip,
    start: Option<crate::vclip::FeaturePair>,
) -> Result<PairQuery, StabilizeError> {
    let body = |index: usize, pose: &Isometry3<f64>| BodyGeometry {
        shape: &geometry.shapes[index],
        pose: *pose,
        configuration_index: None,
    };
    let a = body(pair.body_a, &geometry.poses[pair.body_a]);
    let b = body(pair.body_b, &geometry.poses[pair.body_b]);
    Ok(contact::query(vclip, &a, &b, start)?)
}
