//! The query driver: validation, the walk with warm start and iteration
//! cap, and the conversion of its end state to an [`Outcome`].
//!
//! The walk starts from the warm-start pair (or vertex 0 of each body),
//! applies [`step`] until a handler reports done or a penetration, and
//! gives up after [`VClipSettings::iteration_cap`] transitions, in which
//! case the exhaustive [`fallback`](super::fallback) answers and the
//! result says so. Any start converges (Mirtich 1998, Theorem 2), so a
//! warm start changes the cost, not the answer: the distance and closest
//! points of a separated pair, and the penetration verdict, are the same
//! from any start. The deepest vertex–face pair of a penetration is not:
//! its face refinement is a local search from the face where the walk
//! detected the penetration. It is only the seed of the exact depth search
//! (`crate::contact::penetration`), whose answer is the same from any seed
//! (tested in `tests/it/vclip/warm.rs`).
//!
//! Rounding ties. In exact arithmetic no state repeats (each move lowers
//! the inter-feature distance, or keeps it and lowers the dimension). In
//! floating point, features at equal distance (parallel faces with aligned
//! edges, Mirtich's degeneracy test) can make predicates that are exactly
//! zero come out with either sign in different states, and the walk can
//! cycle among pairs at the same distance. The driver remembers the last
//! [`HISTORY`] states; when a state repeats, the remembered pairs are
//! tried in order of distance and the first that passes Theorem 1 with the
//! tolerance [`VClipSettings::tie_tolerance`] is the answer
//! (`resolved_cycle` is set). If none passes, the exhaustive fallback
//! answers.

use nalgebra::{Isometry3, Point3, UnitQuaternion};

use super::deepest::deepest_vertex;
use super::fallback::exhaustive;
use super::pair::Pair;
use super::polish::polish;
use super::settings::{VClipError, VClipSettings};
use super::state::{Step, Witness, step};
use super::touching::classify_contact;
use super::types::{BodyRole, FallbackReason, FeaturePair, Outcome, VClipResult};
use super::verify::is_closest_pair;
use super::witness::closest_points;

/// Largest accepted `| |q| - 1 |` of a pose's rotation quaternion; within
/// it the quaternion is renormalized.
pub const ROTATION_NORM_TOLERANCE: f64 = 1e-6;

/// Number of recent states remembered to detect a cycle.
pub const HISTORY: usize = 32;

/// Transitions of a walk before states are remembered: cycle detection
/// costs nothing in the common short walk (a warm query takes a few
/// transitions, a cold one on a 642-vertex sphere about a hundred; a
/// cycle found later is found all the same, and the iteration cap bounds
/// the delay).
pub const CYCLE_CHECK_AFTER: usize = 64;
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
        let refine = self.settings.refine_face;
        self.query_refining(poly_a, pose_a, poly_b, pose_b, warm_start, refine)
    }

    /// [`VClip::query`], with the face refinement of a penetration's
    /// deepest vertex–face pair on or off for this query
    /// ([`VClipSettings::refine_face`] is the default of `query`): the
    /// narrow phase, whose exact depth search only needs some vertex–face
    /// pair as its start, asks for it where it pays.
    pub fn query_refining(
        &self,
        poly_a: &ConvexPolyhedron,
        pose_a: &Isometry3<f64>,
        poly_b: &ConvexPolyhedron,
        pose_b: &Isometry3<f64>,
        warm_start: Option<FeaturePair>,
        refine: bool,
    ) -> Result<VClipResult, VClipError> {
        let pose_a = &normalized_pose(pose_a, BodyRole::A)?;
        let pose_b = &normalized_pose(pose_b, BodyRole::B)?;
        let start = warm_start.unwrap_or_else(FeaturePair::cold);
        check_feature(poly_a, start.a, BodyRole::A)?;
        check_feature(poly_b, start.b, BodyRole::B)?;
        let pair = Pair::new(poly_a, pose_a, poly_b, pose_b);
        let poses = [pose_a, pose_b];
        let cap = self
            .settings
            .iteration_cap(poly_a.feature_count(), poly_b.feature_count());
        Ok(match self.walk(&pair, start.to_array(), 0, cap) {
            WalkEnd::Done(features, iterations) => self.done(&pair, poses, features, iterations),
            WalkEnd::Penetration(witness, features, iterations) => {
                penetrating(&pair, poses, witness, features, iterations, refine)
            }
            WalkEnd::Cycle(states, iterations) => {
                self.resolve_cycle(&pair, poses, &states, iterations, cap, refine)
            }
            WalkEnd::Cap => {
                log::debug!("v-clip: iteration cap {cap} reached; exhaustive fallback");
                fall_back(&pair, poses, cap, FallbackReason::IterationCap)
            }
        })
    }

    /// Runs the state machine from `features` until done, penetration, a
    /// repeated state or `cap` transitions in all.
    fn walk(&self, pair: &Pair, mut features: [Feature; 2], first: usize, cap: usize) -> WalkEnd {
        // Filled only after `CYCLE_CHECK_AFTER` transitions: a normal walk
        // ends long before, and a cycle, once entered, repeats forever.
        let mut history: Vec<[Feature; 2]> = Vec::new();
        for iterations in first..cap {
            match step(pair, features) {
                Step::Move { body, to } => {
                    log::trace!("v-clip: {features:?}: body {body} -> {to:?}");
                    features[body] = to;
                    if iterations - first >= CYCLE_CHECK_AFTER {
                        if history.contains(&features) {
                            log::debug!("v-clip: state {features:?} repeats");
                            return WalkEnd::Cycle(history, iterations);
                        }
                        if history.len() == HISTORY {
                            history.remove(0);
                        }
                        history.push(features);
                    }
                }
                Step::Done => return WalkEnd::Done(features, iterations),
                Step::Penetration(witness) => {
                    log::trace!("v-clip: penetration {witness:?}");
                    return WalkEnd::Penetration(witness, features, iterations);
                }
            }
        }
        WalkEnd::Cap
    }
}

/// How a walk ended.
enum WalkEnd {
    Done([Feature; 2], usize),
    Penetration(Witness, [Feature; 2], usize),
    /// A state repeated; the remembered states (oldest first) and the
    /// iteration count.
    Cycle(Vec<[Feature; 2]>, usize),
    Cap,
}

/// The answer of a walk that found a penetration: the deepest vertex–face
/// pair from its witness, refined or not.
fn penetrating(
    pair: &Pair,
    poses: [&Isometry3<f64>; 2],
    witness: Witness,
    features: [Feature; 2],
    iterations: usize,
    refine: bool,
) -> VClipResult {
    let deepest = deepest_vertex(pair, poses, witness, refine);
    VClipResult {
        outcome: Outcome::Penetrating(deepest),
        final_pair: FeaturePair::from_array(features),
        iterations,
        fallback: None,
        resolved_cycle: false,
    }
}

impl VClip {
    /// The answer after a repeated state: the remembered pair of smallest
    /// distance that passes Theorem 1 up to the tie tolerance, else the
    /// exhaustive fallback (`refine`: as in [`VClip::query_refining`]).
    fn resolve_cycle(
        &self,
        pair: &Pair,
        poses: [&Isometry3<f64>; 2],
        states: &[[Feature; 2]],
        iterations: usize,
        cap: usize,
        refine: bool,
    ) -> VClipResult {
        let tol = self.settings.tie_tolerance * pair_scale(pair);
        let mut candidates: Vec<([Feature; 2], [Point3<f64>; 2], f64)> = states
            .iter()
            .filter_map(|&f| closest_points(pair, f).map(|p| (f, p, (p[0] - p[1]).norm())))
            .collect();
        candidates.sort_by(|x, y| x.2.total_cmp(&y.2));
        for (f, p, d) in &candidates {
            log::debug!(
                "v-clip: tie candidate {f:?} at {d:e}: closest pair {}",
                is_closest_pair(pair, *f, p, tol)
            );
        }
        match candidates
            .into_iter()
            .find(|(f, p, _)| is_closest_pair(pair, *f, p, tol))
        {
            Some((features, points, _)) => VClipResult {
                resolved_cycle: true,
                ..self.finish(pair, poses, features, points, iterations)
            },
            None => self.tolerant_walk(pair, poses, states, iterations, cap, refine),
        }
    }

    /// The walk again from the nearest remembered state, with every sign
    /// test given a slack of the tie tolerance, so that rounding noise no
    /// longer moves it; a second cycle or the cap ends in the fallback.
    fn tolerant_walk(
        &self,
        pair: &Pair,
        poses: [&Isometry3<f64>; 2],
        states: &[[Feature; 2]],
        iterations: usize,
        cap: usize,
        refine: bool,
    ) -> VClipResult {
        let tolerant = Pair {
            polys: pair.polys,
            to_other: pair.to_other,
            slack: self.settings.tie_tolerance * pair_scale(pair),
        };
        let start = states.last().copied().unwrap_or([Feature::Vertex(0); 2]);
        let result = match self.walk(&tolerant, start, iterations, cap) {
            WalkEnd::Done(features, iterations) => self.done(pair, poses, features, iterations),
            WalkEnd::Penetration(witness, features, iterations) => {
                penetrating(pair, poses, witness, features, iterations, refine)
            }
            WalkEnd::Cycle(..) | WalkEnd::Cap => {
                log::debug!("v-clip: the tolerant walk did not end; exhaustive fallback");
                return fall_back(pair, poses, iterations, FallbackReason::Cycle);
            }
        };
        VClipResult {
            resolved_cycle: true,
            ..result
        }
    }
}

/// The length scale of rounding in a query: both bodies' scales plus the
/// distance between their centres (the size of transformed coordinates).
fn pair_scale(pair: &Pair) -> f64 {
    let offset = pair.to_other[1]
        .point(&nalgebra::Point3::origin())
        .coords
        .norm();
    pair.polys[0].scale() + pair.polys[1].scale() + offset
}

impl VClip {
    /// The result of a done state.
    fn done(
        &self,
        pair: &Pair,
        poses: [&Isometry3<f64>; 2],
        features: [Feature; 2],
        iterations: usize,
    ) -> VClipResult {
        match closest_points(pair, features) {
            Some(points) => {
                let (features, points) = polish(pair, features, points);
                self.finish(pair, poses, features, points, iterations)
            }
            // Never reached: no handler returns done on an edge–face or
            // face–face pair. Answer correctly all the same.
            None => fall_back(pair, poses, iterations, FallbackReason::IterationCap),
        }
    }

    /// Separated with these closest points (`[on A, on B]`, A's frame),
    /// unless they coincide within the touch tolerance and the bodies
    /// overlap (see [`classify_contact`]).
    fn finish(
        &self,
        pair: &Pair,
        poses: [&Isometry3<f64>; 2],
        features: [Feature; 2],
        points: [Point3<f64>; 2],
        iterations: usize,
    ) -> VClipResult {
        let [p_a, p_b] = points;
        let distance = (p_a - p_b).norm();
        let tol = self.settings.touch_tolerance * pair_scale(pair);
        let outcome = match (distance <= tol)
            .then(|| classify_contact(pair, poses, features, &points, tol))
            .flatten()
        {
            Some(deepest) => Outcome::Penetrating(deepest),
            None => Outcome::Separated {
                distance,
                witness_a_world: poses[0] * p_a,
                witness_b_world: poses[0] * p_b,
            },
        };
        VClipResult {
            outcome,
            final_pair: FeaturePair::from_array(features),
            iterations,
            fallback: None,
            resolved_cycle: false,
        }
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
        resolved_cycle: false,
    }
}

/// The pose with its quaternion renormalized, or an error if it is not
/// finite or not unit within [`ROTATION_NORM_TOLERANCE`]. A quaternion off
/// unit by `δ` scales every transformed length by `1 + O(δ)`, which would
/// show directly in the distances; interpolated rotations (slerp) drift by
/// about 1e-9.
fn normalized_pose(pose: &Isometry3<f64>, body: BodyRole) -> Result<Isometry3<f64>, VClipError> {
    let finite = pose.translation.vector.iter().all(|c| c.is_finite())
        && pose.rotation.coords.iter().all(|c| c.is_finite());
    if !finite {
        return Err(VClipError::NonFinitePose { body });
    }
    let norm = pose.rotation.coords.norm();
    if (norm - 1.0).abs() > ROTATION_NORM_TOLERANCE {
        return Err(VClipError::NonUnitRotation { body, norm });
    }
    let rotation = UnitQuaternion::new_unchecked(pose.rotation.into_inner() / norm);
    Ok(Isometry3::from_parts(pose.translation, rotation))
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
