//! The query driver: validation, the walk with warm start and iteration
//! cap, and the conversion of its end state to an [`Outcome`].
//!
//! The walk starts from the warm-start pair (or vertex 0 of each body),
//! applies [`step`] until a handler reports done or a penetration, and
//! gives up after [`VClipSettings::iteration_cap`] transitions, in which
//! case the exhaustive [`fallback`](super::fallback) answers and the
//! result says so. Any start converges (Mirtich 1998, Theorem 2), so a
//! warm start changes the cost, not the answer.

use nalgebra::Isometry3;

use super::deepest::deepest_vertex;
use super::fallback::exhaustive;
use super::pair::Pair;
use super::settings::{VClipError, VClipSettings};
use super::state::{Step, step};
use super::types::{BodyRole, FallbackReason, FeaturePair, Outcome, VClipResult};
use super::witness::closest_points;
use crate::geometry::{ConvexPolyhedron, Feature};

/// A V-Clip query engine with its settings.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct VClip {
    /// Iteration cap.
    pub settings: VClipSettings,
}

/// V-Clip with default settings; see [`VClip::query`].
pub fn vclip(
    poly_a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    poly_b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
    warm_start: Option<FeaturePair>,
) -> Result<VClipResult, VClipError> {
    VClip::default().query(poly_a, pose_a, poly_b, pose_b, warm_start)
}

impl VClip {
    /// V-Clip with these settings.
    pub fn new(settings: VClipSettings) -> Self {
        VClip { settings }
    }

    /// Closest features and distance of two polyhedra, or their deepest
    /// vertex–face pair if they interpenetrate. Poses map body frames
    /// (centre of mass) to the world frame. `warm_start` is the
    /// `final_pair` of an earlier query of the same two shapes.
    pub fn query(
        &self,
        poly_a: &ConvexPolyhedron,
        pose_a: &Isometry3<f64>,
        poly_b: &ConvexPolyhedron,
        pose_b: &Isometry3<f64>,
        warm_start: Option<FeaturePair>,
    ) -> Result<VClipResult, VClipError> {
        check_pose(pose_a, BodyRole::A)?;
        check_pose(pose_b, BodyRole::B)?;
        let start = warm_start.unwrap_or_else(FeaturePair::cold);
        check_feature(poly_a, start.a, BodyRole::A)?;
        check_feature(poly_b, start.b, BodyRole::B)?;
        let pair = Pair::new(poly_a, pose_a, poly_b, pose_b);
        let poses = [pose_a, pose_b];
        let cap = self
            .settings
            .iteration_cap(poly_a.feature_count(), poly_b.feature_count());
        let mut features = start.to_array();
        for iterations in 0..cap {
            match step(&pair, features) {
                Step::Move { body, to } => {
                    log::trace!("v-clip: {features:?}: body {body} -> {to:?}");
                    features[body] = to;
                }
                Step::Done => {
                    return Ok(separated(&pair, poses, features, iterations));
                }
                Step::Penetration(witness) => {
                    log::trace!("v-clip: penetration {witness:?}");
                    return Ok(VClipResult {
                        outcome: Outcome::Penetrating(deepest_vertex(&pair, poses, witness)),
                        final_pair: FeaturePair::from_array(features),
                        iterations,
                        fallback: None,
                    });
                }
            }
        }
        log::debug!("v-clip: iteration cap {cap} reached at {features:?}; exhaustive fallback");
        Ok(fall_back(&pair, poses, cap, FallbackReason::IterationCap))
    }
}

/// The separated outcome of a done state.
fn separated(
    pair: &Pair,
    poses: [&Isometry3<f64>; 2],
    features: [Feature; 2],
    iterations: usize,
) -> VClipResult {
    match closest_points(pair, features) {
        Some([p_a, p_b]) => VClipResult {
            outcome: Outcome::Separated {
                distance: (p_a - p_b).norm(),
                witness_a_world: poses[0] * p_a,
                witness_b_world: poses[0] * p_b,
            },
            final_pair: FeaturePair::from_array(features),
            iterations,
            fallback: None,
        },
        // Never reached: no handler returns done on an edge–face or
        // face–face pair. Answer correctly all the same.
        None => fall_back(pair, poses, iterations, FallbackReason::IterationCap),
    }
}

fn fall_back(
    pair: &Pair,
    poses: [&Isometry3<f64>; 2],
    iterations: usize,
    reason: FallbackReason,
) -> VClipResult {
    let (outcome, final_pair) = exhaustive(pair, poses);
    VClipResult {
        outcome,
        final_pair,
        iterations,
        fallback: Some(reason),
    }
}

fn check_pose(pose: &Isometry3<f64>, body: BodyRole) -> Result<(), VClipError> {
    let finite = pose.translation.vector.iter().all(|c| c.is_finite())
        && pose.rotation.coords.iter().all(|c| c.is_finite());
    if finite {
        Ok(())
    } else {
        Err(VClipError::NonFinitePose { body })
    }
}

fn check_feature(
    poly: &ConvexPolyhedron,
    feature: Feature,
    body: BodyRole,
) -> Result<(), VClipError> {
    let exists = match feature {
        Feature::Vertex(v) => v < poly.vertices().len(),
        Feature::Edge(e) => e < poly.edges().len(),
        Feature::Face(f) => f < poly.faces().len(),
    };
    if exists {
        Ok(())
    } else {
        Err(VClipError::InvalidWarmStart { body, feature })
    }
}
