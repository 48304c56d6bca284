//! Detection over the whole scene: broad phase, then the narrow phase on
//! every candidate pair, classified against the tolerance and the contact
//! margin.
//!
//! A pair whose two bodies have not moved since its last answer in this call
//! (the [`QueryMemo`]) is not queried again; nor is a pair whose last exact
//! answer, in this call or an earlier one, certifies that it is still
//! separated beyond the contact margin, whatever its parts did since
//! ([`SeparationCertificates`], when
//! [`crate::vclip::VClipSettings::motion_certificates`] is on): it would
//! give no row and no penetration. With the same setting, a pair whose
//! parts have not moved since an earlier call's answer reuses it. Every
//! other pair runs V-Clip, warm-started from the pair's last feature pair
//! ([`WarmStartCache`]).

use std::borrow::Cow;
use std::time::Instant;

use super::certificate::SeparationCertificates;
use super::island::Island;
use super::island_contacts::{SceneGeometry, shape_pair};
use super::memo::{PosedQuery, QueryMemo};
use super::{PairQuery, PenetrationFeatures, WarmStartCache, query};
use crate::broad_phase::{BodyPair, BroadPhaseError, IncrementalBroadPhase};
use crate::parallel;
use crate::scene::Scene;
use crate::settings::ResolvedLengths;
use crate::vclip::{FeaturePair, VClip, VClipError};

/// The queries of a pass are spread over the thread pool from this many
/// on, and made on the calling thread below: one query costs 5-7 us on
/// the engine states (a call's narrow-phase time over its queries: the
/// Bullet pyramid, the MuJoCo thrown box), and handing work to the pool
/// and waiting for it costs a few tens of microseconds in thread switches.
pub const PARALLEL_MIN_QUERIES: usize = 16;

/// Why a detection failed: invalid broad-phase input (a margin, a box) or
/// an invalid V-Clip query (a pose). [`crate::Error`] has a variant for
/// each.
#[derive(Debug, Clone, PartialEq)]
pub enum DetectionError {
    /// The broad phase rejected its input.
    BroadPhase(BroadPhaseError),
    /// A V-Clip query rejected its input.
    VClip(VClipError),
}

impl From<BroadPhaseError> for DetectionError {
    fn from(error: BroadPhaseError) -> Self {
        DetectionError::BroadPhase(error)
    }
}

impl From<VClipError> for DetectionError {
    fn from(error: VClipError) -> Self {
        DetectionError::VClip(error)
    }
}

/// One penetrating pair as a detection found it: the feature pair of its
/// minimum translation and its exact depth. Two compound bodies may have
/// several (one per pair of penetrating parts).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairPenetration {
    /// First body (scene index, the smaller).
    pub body_a: usize,
    /// Second body (scene index).
    pub body_b: usize,
    /// The penetrating parts, as indices into each body's
    /// [`crate::body::Body::parts`] (0 for a convex body).
    pub parts: [usize; 2],
    /// Vertex–face (either body's face) or edge–edge.
    pub features: PenetrationFeatures,
    /// Exact penetration depth (separating axes).
    pub depth: f64,
}

/// The pairs that matter after one detection.
#[derive(Debug, Clone, Default)]
pub struct Detection {
    /// Candidate pairs from the broad phase.
    pub candidates: usize,
    /// Candidate pairs queried (the others were answered by the memo or
    /// certified separated).
    pub queried: usize,
    /// Candidate pairs certified separated beyond the margin (not queried,
    /// [`SeparationCertificates`]).
    pub certified: usize,
    /// Candidate pairs answered by an earlier call's answer at the same
    /// poses ([`SeparationCertificates::answer_at`]).
    pub reused: usize,
    /// Part pairs (`contact::scene_parts::SceneParts`) penetrating or
    /// within the contact margin, ascending (body pairs in a scene of
    /// convex bodies).
    pub active_pairs: Vec<BodyPair>,
    /// The body pair of each active pair (islands are formed over them).
    pub active_bodies: Vec<BodyPair>,
    /// Signed value (distance, or minus depth) of each active pair.
    pub active_values: Vec<f64>,
    /// Narrow-phase answer of each active pair, at the detection's poses.
    pub active_queries: Vec<PairQuery>,
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
    /// Whether some pair of `island` (formed over
    /// [`Detection::active_pairs`]) penetrates deeper than `tolerance`.
    pub fn island_penetrates(&self, island: &Island, tolerance: f64) -> bool {
        island
            .pairs
            .iter()
            .any(|&k| -self.active_values[k] > tolerance)
    }

    /// Number of active pairs penetrating deeper than `tolerance`.
    pub fn penetrating(&self, tolerance: f64) -> usize {
        self.active_values
            .iter()
            .filter(|&&v| -v > tolerance)
            .count()
    }
}

/// What detection keeps from one pass (and call) to the next.
#[derive(Debug)]
pub struct DetectionState<'a> {
    /// The broad phase of the call's earlier passes.
    pub broad_phase: &'a mut IncrementalBroadPhase,
    /// V-Clip's last feature pair per body pair (across calls).
    pub cache: &'a mut WarmStartCache,
    /// The call's narrow-phase answers by pair and poses.
    pub memo: &'a mut QueryMemo,
    /// The separation certificates (across calls); `None`: none used.
    pub certificates: Option<&'a mut SeparationCertificates>,
    /// Part pairs kept active whatever their distance, ascending: queried
    /// even when the broad phase or a certificate would skip them, and
    /// recorded as active (with rows) even beyond the contact margin
    /// (`stabilizer::kept_pairs`). Empty: none.
    pub kept_pairs: &'a [BodyPair],
}

/// Broad and narrow phase at the scene's current poses; updates the broad
/// phase, the warm starts and the memo.
pub fn detect(
    scene: &Scene,
    geometry: SceneGeometry,
    state: DetectionState<'_>,
    vclip: &VClip,
    lengths: &ResolvedLengths,
) -> Result<Detection, DetectionError> {
    let DetectionState {
        broad_phase,
        cache,
        memo,
        mut certificates,
        kept_pairs,
    } = state;
    let broad_start = Instant::now();
    let (body_pairs, _) = broad_phase.candidate_pairs(scene, lengths.contact_margin)?;
    let mut candidates = match geometry.parts.all_convex() {
        true => Cow::Borrowed(body_pairs),
        false => Cow::Owned(geometry.parts.part_pairs(
            body_pairs,
            geometry.poses,
            lengths.contact_margin,
        )),
    };
    let kept = |pair: &BodyPair| kept_pairs.binary_search(pair).is_ok();
    if !kept_pairs.is_empty() {
        let all = candidates.to_mut();
        all.extend(kept_pairs.iter().copied());
        all.sort_unstable();
        all.dedup();
    }
    let candidates: &[BodyPair] = &candidates;
    let broad_phase_seconds = broad_start.elapsed().as_secs_f64();
    let narrow_start = Instant::now();
    let poses_of = |pair: BodyPair| [&geometry.poses[pair.body_a], &geometry.poses[pair.body_b]];
    let mut answers: Vec<Option<PairQuery>> = candidates
        .iter()
        .map(|&pair| memo.get(pair, poses_of(pair)).cloned())
        .collect();
    let mut certified = vec![false; candidates.len()];
    let mut reused = 0;
    if let Some(store) = certificates.as_deref_mut() {
        for (i, &pair) in candidates.iter().enumerate() {
            if answers[i].is_some() {
                continue;
            }
            answers[i] = store.answer_at(pair, geometry.parts, poses_of(pair));
            if answers[i].is_some() {
                reused += 1;
                continue;
            }
            certified[i] = !kept(&pair)
                && store.certifies(pair, geometry.parts, poses_of(pair), lengths.contact_margin);
        }
    }
    let to_query: Vec<usize> = (0..candidates.len())
        .filter(|&i| answers[i].is_none() && !certified[i])
        .collect();
    memo.reserve(to_query.len());
    let queried = parallel::map_from(&to_query, PARALLEL_MIN_QUERIES, |&i| {
        let pair = candidates[i];
        let start = cache.get(pair, shape_pair(geometry.shapes(), pair));
        query_pair(geometry, pair, vclip, start)
    });
    for (&i, result) in to_query.iter().zip(queried) {
        let result = result?;
        let pair = candidates[i];
        cache.insert(
            pair,
            shape_pair(geometry.shapes(), pair),
            result.vclip.final_pair,
        );
        let [pose_a, pose_b] = poses_of(pair);
        let poses = [*pose_a, *pose_b];
        if let Some(store) = certificates.as_deref_mut() {
            store.record(pair, geometry.parts, poses, &result);
        }
        memo.insert(
            pair,
            PosedQuery {
                poses,
                query: result.clone(),
            },
        );
        answers[i] = Some(result);
    }
    let mut detection = Detection {
        candidates: candidates.len(),
        queried: to_query.len(),
        certified: certified.iter().filter(|&&c| c).count(),
        reused,
        broad_phase_seconds,
        ..Detection::default()
    };
    for (&pair, answer) in candidates.iter().zip(answers) {
        // Every pair not certified has an answer: from the memo, from an
        // earlier call at the same poses, or queried just above.
        if let Some(result) = answer {
            let bodies = geometry.parts.owner_pair(pair);
            log_pair(scene, bodies, &result, lengths);
            detection.record(geometry, pair, result, lengths, kept(&pair));
        }
    }
    detection.narrow_phase_seconds = narrow_start.elapsed().as_secs_f64();
    Ok(detection)
}

impl Detection {
    /// Classifies one part pair's answer; a `kept` pair is active whatever
    /// its distance.
    fn record(
        &mut self,
        geometry: SceneGeometry,
        pair: BodyPair,
        result: PairQuery,
        lengths: &ResolvedLengths,
        kept: bool,
    ) {
        let value = result.signed_value();
        self.deepest = self.deepest.max(-value);
        let parts = geometry.parts;
        let bodies = parts.owner_pair(pair);
        if let Some(depth) = result.depth().filter(|&d| d > lengths.tolerance) {
            let features = match (&result.penetration, &result.round) {
                (Some(penetration), None) => penetration.features(),
                _ => PenetrationFeatures::Round,
            };
            let first = |body: usize| parts.parts_of(body).start;
            self.penetrations.push(PairPenetration {
                body_a: bodies.body_a,
                body_b: bodies.body_b,
                parts: [
                    pair.body_a - first(bodies.body_a),
                    pair.body_b - first(bodies.body_b),
                ],
                features,
                depth,
            });
        }
        if value < lengths.contact_margin || kept {
            self.active_pairs.push(pair);
            self.active_bodies.push(bodies);
            self.active_values.push(value);
            self.active_queries.push(result);
        }
    }
}

/// The debug line of a penetrating pair (trace for a near one), by body.
fn log_pair(scene: &Scene, pair: BodyPair, result: &PairQuery, lengths: &ResolvedLengths) {
    let name = |i: usize| scene.bodies().get(i).map_or("?", |b| b.name());
    let (a, b) = (pair.body_a, pair.body_b);
    let kind = match (&result.penetration, &result.round) {
        (Some(p), None) => p.features().kind(),
        _ => PenetrationFeatures::Round.kind(),
    };
    match result.depth() {
        Some(depth) if depth > lengths.tolerance => log::debug!(
            "  penetrating: {a} {} and {b} {}, {kind} depth {depth:.3e}",
            name(a),
            name(b),
        ),
        _ => log::trace!(
            "  pair {a} {} and {b} {}: signed distance {:.3e}",
            name(a),
            name(b),
            result.signed_value()
        ),
    }
}

fn query_pair(
    geometry: SceneGeometry,
    pair: BodyPair,
    vclip: &VClip,
    start: Option<FeaturePair>,
) -> Result<PairQuery, VClipError> {
    let (a, b) = (geometry.held(pair.body_a), geometry.held(pair.body_b));
    query(vclip, &a, &b, start)
}
