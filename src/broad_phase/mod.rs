//! Broad phase: candidate body pairs from enlarged axis-aligned boxes.
//!
//! Each body's world AABB (the bounds of its transformed vertices, exact for
//! a polyhedron) is enlarged by `margin / 2` on every side. Two boxes
//! overlap (closed intervals on all three axes) exactly when the gap between
//! the original boxes is at most `margin` on every axis; since the distance
//! of two bodies is at least their largest per-axis AABB gap, every pair at
//! distance `<= margin` (touching, near, or penetrating) is a candidate.
//!
//! The overlapping leaf pairs come from a self-traversal of parry3d-f64's
//! bounding volume hierarchy ([`Bvh`], binned SAH build, Wald 2007). The
//! output is normalized so that it does not depend on the tree's shape:
//! pairs `(i, j)` with `i < j`, sorted, without duplicates, and without
//! pairs of two fixed bodies (which never move, so need no constraint).

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Vector;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};
use thiserror::Error;

use crate::body::Body;
use crate::scene::Scene;

mod incremental;

pub use incremental::{BroadPhaseUpdate, IncrementalBroadPhase, REBUILD_MOVED_FRACTION};

/// A map keyed by body (or part) pair, hashed by foldhash with a fixed
/// seed: the narrow phase's memo, V-Clip's and the solver's warm starts and
/// the separation certificates are looked up for every candidate pair of
/// every pass, where the standard library's SipHash was a measurable part
/// of the call's sequential work. The fixed seed keeps every run's
/// iteration order the same.
pub type PairMap<V> = std::collections::HashMap<BodyPair, V, foldhash::fast::FixedState>;

/// Two bodies, by index, with `body_a < body_b`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct BodyPair {
    /// The smaller index.
    pub body_a: usize,
    /// The larger index.
    pub body_b: usize,
}

impl BodyPair {
    /// The pair of two distinct indices, in increasing order; `None` if equal.
    pub fn new(i: usize, j: usize) -> Option<Self> {
        match i.cmp(&j) {
            std::cmp::Ordering::Less => Some(BodyPair {
                body_a: i,
                body_b: j,
            }),
            std::cmp::Ordering::Greater => Some(BodyPair {
                body_a: j,
                body_b: i,
            }),
            std::cmp::Ordering::Equal => None,
        }
    }
}

/// Why the broad phase could not run.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum BroadPhaseError {
    /// The margin is NaN, infinite or negative.
    #[error("margin is {0}: it must be finite and non-negative")]
    InvalidMargin(f64),
    /// Boxes and fixed flags differ in number.
    #[error("{aabbs} boxes but {flags} fixed flags")]
    LengthMismatch {
        /// Number of boxes.
        aabbs: usize,
        /// Number of fixed flags.
        flags: usize,
    },
    /// A box has a non-finite bound or `mins > maxs` on some axis.
    #[error("box {0} is not finite or has min > max")]
    InvalidAabb(usize),
    /// More bodies than the hierarchy can index (`u32`).
    #[error("{0} bodies: the broad phase handles at most 2^32 - 1")]
    TooManyBodies(usize),
}

/// Candidate pairs of a scene: every pair (not both fixed) whose world AABBs
/// come within `margin` of each other on every axis.
pub fn candidate_pairs(scene: &Scene, margin: f64) -> Result<Vec<BodyPair>, BroadPhaseError> {
    let aabbs: Vec<Aabb> = scene.bodies().iter().map(body_aabb).collect();
    candidate_pairs_of_aabbs(&aabbs, &scene.fixed_flags(), margin)
}

/// Every body's world box grown by `margin / 2` on each side (two such
/// boxes overlap when the bodies' boxes are within `margin`), index =
/// body index: the leaves of [`candidate_pairs`]' hierarchy, after its
/// input checks.
pub fn grown_boxes(scene: &Scene, margin: f64) -> Result<Vec<Aabb>, BroadPhaseError> {
    let aabbs: Vec<Aabb> = scene.bodies().iter().map(body_aabb).collect();
    check_inputs(aabbs.as_slice(), &scene.fixed_flags(), margin)?;
    Ok(aabbs.iter().map(|a| a.loosened(margin / 2.0)).collect())
}

/// Whether body `i` forms a candidate pair with some other body: its grown
/// box (from [`grown_boxes`]) overlaps another's, the two not both fixed.
/// The same test as [`candidate_pairs`]' for the pairs of one body, by a
/// scan of every box: `O(n)` for the one body, no hierarchy.
pub fn has_candidate_pair(boxes: &[Aabb], fixed: &[bool], i: usize) -> bool {
    let (Some(own), Some(&own_fixed)) = (boxes.get(i), fixed.get(i)) else {
        return false;
    };
    boxes
        .iter()
        .zip(fixed)
        .enumerate()
        .any(|(j, (other, &other_fixed))| {
            j != i && !(own_fixed && other_fixed) && own.intersects(other)
        })
}

/// A body's world AABB as parry's type.
pub(crate) fn body_aabb(body: &Body) -> Aabb {
    let (min, max) = body.world_aabb();
    Aabb::new(
        Vector::new(min.x, min.y, min.z),
        Vector::new(max.x, max.y, max.z),
    )
}

/// Candidate pairs among boxes `aabbs` (index = body index), `fixed[i]`
/// telling whether body `i` is fixed.
pub fn candidate_pairs_of_aabbs(
    aabbs: &[Aabb],
    fixed: &[bool],
    margin: f64,
) -> Result<Vec<BodyPair>, BroadPhaseError> {
    check_inputs(aabbs, fixed, margin)?;
    let enlarged: Vec<Aabb> = aabbs.iter().map(|a| a.loosened(margin / 2.0)).collect();
    let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &enlarged);
    let mut workspace = BvhWorkspace::default();
    let pairs = overlapping_pairs(&bvh, &mut workspace, fixed);
    log::debug!(
        "  broad phase: {} bodies, AABBs grown by the contact margin {margin:.3e}, {} candidate pairs",
        aabbs.len(),
        pairs.len()
    );
    Ok(pairs)
}

/// The overlapping leaf pairs of `bvh` (leaf index = body index), not both
/// fixed, normalized: ascending, without duplicates.
fn overlapping_pairs(bvh: &Bvh, workspace: &mut BvhWorkspace, fixed: &[bool]) -> Vec<BodyPair> {
    let mut pairs = Vec::new();
    bvh.traverse_bvtt_single_tree::<false>(workspace, &mut |leaf_1, leaf_2| {
        let (i, j) = (leaf_1 as usize, leaf_2 as usize);
        if fixed[i] && fixed[j] {
            return;
        }
        if let Some(pair) = BodyPair::new(i, j) {
            pairs.push(pair);
        }
    });
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// The broad phase's input checks: a finite non-negative margin, a flag
/// per box, valid boxes, indices that fit the hierarchy's `u32` leaves.
fn check_inputs(aabbs: &[Aabb], fixed: &[bool], margin: f64) -> Result<(), BroadPhaseError> {
    if !(margin.is_finite() && margin >= 0.0) {
        return Err(BroadPhaseError::InvalidMargin(margin));
    }
    if aabbs.len() != fixed.len() {
        return Err(BroadPhaseError::LengthMismatch {
            aabbs: aabbs.len(),
            flags: fixed.len(),
        });
    }
    if let Some(index) = aabbs.iter().position(|a| !is_valid(a)) {
        return Err(BroadPhaseError::InvalidAabb(index));
    }
    if u32::try_from(aabbs.len()).is_err() {
        return Err(BroadPhaseError::TooManyBodies(aabbs.len()));
    }
    Ok(())
}

fn is_valid(aabb: &Aabb) -> bool {
    let finite = aabb.mins.is_finite() && aabb.maxs.is_finite();
    finite && aabb.mins.cmple(aabb.maxs).all()
}
