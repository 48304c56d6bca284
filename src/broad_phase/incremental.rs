//! The broad phase kept from one detection to the next, so that a pass
//! pays only for the bodies that moved since the last one.
//!
//! A stabilization call detects contacts once per pass, and after the
//! first pass only the bodies of the islands it solved have moved: late
//! passes move a handful of bodies in a scene of thousands. Rebuilding the
//! hierarchy and recomputing every body's box each pass would make the
//! broad phase `O(passes * n log n)`, the only part of a late pass that
//! grows with the scene (measured on a pile of 2,000 bodies:
//! `CHANGELOG.md`, 2026-12-02, "Incremental broad phase").
//!
//! The state kept: each body's enlarged box (its world AABB grown by
//! `margin / 2`, as in [`super::candidate_pairs`]), the pose it was
//! computed at, parry's hierarchy over those boxes and the candidate pairs.
//! An update finds the moved bodies (centre-of-mass pose not bit-identical
//! to the stored one), recomputes only their boxes, writes them into the
//! hierarchy's leaves and refits it (`O(n)` without rebuilding), keeps the
//! stored pairs of two unmoved bodies (neither box changed, so neither did
//! their overlap) and asks the hierarchy for the leaves overlapping each
//! moved box. The overlap test is the hierarchy's own closed-interval test
//! on the same enlarged boxes as a full build's self-traversal, so the
//! pairs are exactly those of [`super::candidate_pairs`] at the same poses
//! (checked against it and against brute force in
//! `tests/it/scene/broad_phase.rs`).
//!
//! A full build is made instead on the first update, when the number of
//! bodies, their fixed flags or the margin changed, and when more than
//! [`REBUILD_MOVED_FRACTION`] of the bodies moved (a refit keeps the tree's
//! topology, whose quality decays when everything moves).

use nalgebra::Isometry3;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};

use super::{BodyPair, BroadPhaseError, body_aabb, check_inputs, overlapping_pairs};
use crate::scene::Scene;

/// Above this fraction of moved bodies an update rebuilds the hierarchy
/// instead of refitting it: when most boxes change, recomputing all of them
/// costs the same and a fresh build keeps the tree tight.
pub const REBUILD_MOVED_FRACTION: f64 = 0.5;

/// Candidate pairs of a scene, updated from the bodies that moved since the
/// last call of [`IncrementalBroadPhase::candidate_pairs`].
#[derive(Debug, Clone, Default)]
pub struct IncrementalBroadPhase {
    state: Option<State>,
}

/// What the last update left: boxes, the poses they were computed at, the
/// hierarchy over them, the pairs.
#[derive(Debug, Clone)]
struct State {
    margin: f64,
    fixed: Vec<bool>,
    poses: Vec<Isometry3<f64>>,
    enlarged: Vec<Aabb>,
    bvh: Bvh,
    pairs: Vec<BodyPair>,
}

/// How the last update was made (for tests and logs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BroadPhaseUpdate {
    /// The hierarchy was built over every body.
    Rebuilt,
    /// This many moved bodies were updated in the kept hierarchy.
    Refitted(usize),
}

impl IncrementalBroadPhase {
    /// An empty state: the first update is a full build.
    pub fn new() -> Self {
        Self::default()
    }

    /// The candidate pairs at the scene's current poses (exactly those of
    /// [`super::candidate_pairs`]), and how they were found.
    pub fn candidate_pairs(
        &mut self,
        scene: &Scene,
        margin: f64,
    ) -> Result<(&[BodyPair], BroadPhaseUpdate), BroadPhaseError> {
        let fixed = scene.fixed_flags();
        let reusable = self
            .state
            .as_ref()
            .is_some_and(|s| s.margin == margin && s.fixed == fixed);
        let moved: Vec<usize> = match (&self.state, reusable) {
            (Some(state), true) => moved_bodies(scene, &state.poses),
            _ => Vec::new(),
        };
        let update =
            if reusable && (moved.len() as f64) <= REBUILD_MOVED_FRACTION * fixed.len() as f64 {
                // `reusable` implies a stored state: this cannot fail.
                let state = self.state.as_mut().expect("a reusable state exists");
                state.refit(scene, &moved)?;
                BroadPhaseUpdate::Refitted(moved.len())
            } else {
                self.state = Some(State::build(scene, fixed, margin)?);
                BroadPhaseUpdate::Rebuilt
            };
        // Both branches above leave a state: this cannot fail.
        let state = self.state.as_ref().expect("the update stored a state");
        log::trace!(
            "  broad phase: {update:?}, {} bodies, {} candidate pairs",
            state.poses.len(),
            state.pairs.len()
        );
        Ok((&state.pairs, update))
    }
}

/// The bodies whose centre-of-mass pose differs from `poses` (bit for bit).
fn moved_bodies(scene: &Scene, poses: &[Isometry3<f64>]) -> Vec<usize> {
    scene
        .bodies()
        .iter()
        .zip(poses)
        .enumerate()
        .filter(|(_, (body, pose))| body.com_pose() != *pose)
        .map(|(index, _)| index)
        .collect()
}

impl State {
    /// A full build at the scene's poses.
    fn build(scene: &Scene, fixed: Vec<bool>, margin: f64) -> Result<Self, BroadPhaseError> {
        let aabbs: Vec<Aabb> = scene.bodies().iter().map(body_aabb).collect();
        check_inputs(&aabbs, &fixed, margin)?;
        let enlarged: Vec<Aabb> = aabbs.iter().map(|a| a.loosened(margin / 2.0)).collect();
        let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &enlarged);
        let pairs = overlapping_pairs(&bvh, &mut BvhWorkspace::default(), &fixed);
        Ok(State {
            margin,
            fixed,
            poses: scene.bodies().iter().map(|b| *b.com_pose()).collect(),
            enlarged,
            bvh,
            pairs,
        })
    }

    /// Updates the boxes of the `moved` bodies and the pairs that involve
    /// them. On error (a moved body's box is not finite) the state is left
    /// as it was.
    fn refit(&mut self, scene: &Scene, moved: &[usize]) -> Result<(), BroadPhaseError> {
        if moved.is_empty() {
            return Ok(());
        }
        let bodies = scene.bodies();
        let boxes: Vec<Aabb> = moved.iter().map(|&i| body_aabb(&bodies[i])).collect();
        if let Some(k) = boxes.iter().position(|a| !super::is_valid(a)) {
            return Err(BroadPhaseError::InvalidAabb(moved[k]));
        }
        let mut is_moved = vec![false; self.poses.len()];
        for (&i, aabb) in moved.iter().zip(&boxes) {
            is_moved[i] = true;
            self.poses[i] = *bodies[i].com_pose();
            self.enlarged[i] = aabb.loosened(self.margin / 2.0);
            // Leaf indices are body indices below 2^32 (checked by the
            // build), so the conversion is exact.
            self.bvh
                .insert_or_update_partially(self.enlarged[i], i as u32, 0.0);
        }
        self.bvh.refit(&mut BvhWorkspace::default());
        self.pairs
            .retain(|p| !is_moved[p.body_a] && !is_moved[p.body_b]);
        for &i in moved {
            for leaf in self.bvh.intersect_aabb(&self.enlarged[i]) {
                let j = leaf as usize;
                // A pair of two moved bodies is found from both sides:
                // keep it from its smaller index's query only.
                let found_twice = is_moved[j] && j < i;
                if found_twice || (self.fixed[i] && self.fixed[j]) {
                    continue;
                }
                if let Some(pair) = BodyPair::new(i, j) {
                    self.pairs.push(pair);
                }
            }
        }
        self.pairs.sort_unstable();
        self.pairs.dedup();
        Ok(())
    }
}
