//! Held islands put to sleep: a group of bodies the calls have kept still
//! for Rapier's `time_until_sleep` is put to sleep through Rapier's API.
//!
//! # Why
//!
//! A held cycle (`super::rest`) makes the corrected state `P` a fixed
//! point of (Rapier's step, the call): Rapier's step moves the bodies from
//! `P` to `S`, the call puts them back at `P`, and every step ends at the
//! same `S`. Rapier's own sleep test, the drift of each body's farthest
//! point between two consecutive steps (`RigidBodyActivation::update_energy`
//! in rapier3d 0.36.1), would then pass. But the call writes `P` at every
//! step, and Rapier treats a written pose as a user change:
//! `RigidBody::set_position` flags `RigidBodyChanges::POSITION` even with
//! `wake_up = false`; at its next step, `handle_user_changes_to_rigid_bodies`
//! (`pipeline/user_changes.rs`) moves the body's colliders and flags them
//! `ColliderChanges::POSITION`, and the narrow phase's
//! `handle_user_changes_on_colliders` (`geometry/narrow_phase/pair_management.rs`)
//! wakes the parent body and every body in its contact graph *strongly*
//! (`IslandManager::wake_up(.., true)`: sleep timer reset to 0). Rapier
//! offers no way to move a body without that: a written body never sleeps.
//!
//! # The rule
//!
//! The bridge keeps, per awake dynamic body, Rapier's sleep timer applied
//! to the poses the calls *leave*: with `d` the displacement of the body's
//! farthest point between the pose the last call left it at and the pose
//! this call leaves it at (the test of `super::rest`), the timer grows by
//! `dt` while `d / 2 < normalized_linear_threshold * length_unit * dt` and
//! restarts at 0 otherwise. A held body's `d` is 0.
//!
//! A *group* is a connected component of the awake dynamic bodies whose
//! bounding boxes, grown by Rapier's broad-phase margin ([`group_margin`]),
//! overlap, or that a joint the bridge read links: a superset of the
//! bodies Rapier's contact graph and joints join (Rapier wakes the contact
//! graph neighbours of a written body, and its islands hold touching and
//! jointed bodies), so a group never splits one of Rapier's islands and no
//! written body wakes it (with Rapier's default broad phase: its adaptive
//! margin, off by default, can be larger). When every body of a
//! group has a timer of at least its `time_until_sleep` (and Rapier's own
//! timers do not already say so), the call zeroes their velocities (a
//! velocity write does not wake: no change flag). At the next call, if the
//! group is the same (all of it prepared, nothing added), and every body of
//! it moved in Rapier's step by at most Rapier's allowed linear error, its
//! bodies are held still (not solved, not written) and put to sleep with
//! `RigidBody::sleep` (no pose write, so no wake): Rapier pins their sleep
//! eligibility and its island manager puts their island to sleep within
//! its next steps (until it does, Rapier integrates the bodies without
//! their contacts: `super::limbo`). Two calls, because a call that writes
//! a pose cannot put that body to sleep (the write wakes it at the next
//! step).
//!
//! Why the margin: with boxes grown by the prediction distance only, the
//! pile of 200 was put to sleep at step 161 as a group of 196 and four
//! single bodies the calls still wrote; Rapier woke the group's bodies
//! near them at the next steps, and the pile crept 28 mm.
//!
//! The check at the second call allows each body to have moved, in
//! Rapier's step from the corrected state at rest, by up to Rapier's
//! allowed linear error: with Rapier's sleep test instead, the pile of 200
//! of `examples/with_and_without.rs` never slept (one body of 196 failed
//! it in that step at every try: 1.57 mm by `examples/probes/rest_probe.rs`'s
//! measure, above 1.67 mm by the bridge's larger bound on the farthest
//! point). The sleeping group is left
//! where Rapier's steps from the corrected state at rest put it before its
//! island manager commits the sleep (two or three steps: an island that
//! lost contacts is split first): on that pile 6.3 mm deep at most, where
//! Rapier alone sleeps at 10.0 mm. A body that wakes it (an awake body
//! touching it in Rapier's step) wakes its island, and the call corrects
//! it again.

use std::collections::{HashMap, HashSet};

use rapier3d::dynamics::{IntegrationParameters, RigidBodySet};
use rapier3d::geometry::ColliderHandle;

use super::body_map::BodyMap;
use super::rest::{DisjointSets, RestPoses, farthest_point_motion, passes_sleep_test};
use crate::broad_phase::{body_aabb, candidate_pairs_of_aabbs};
use crate::scene::Scene;
use parry3d_f64::bounding_volume::Aabb;

/// Per awake dynamic body, the time its poses as left by the calls have
/// passed Rapier's sleep test (module docs), and the bodies whose
/// velocities the last call zeroed before putting them to sleep.
#[derive(Debug, Clone, Default)]
pub(crate) struct SleepClock {
    timers: HashMap<ColliderHandle, f64>,
    pending: HashSet<ColliderHandle>,
    /// The dynamic bodies held still as asleep when the last call ended.
    asleep: HashSet<ColliderHandle>,
}

impl SleepClock {
    /// Whether the body was at rest when the last call ended: asleep, or
    /// its pose as left by the last call passed Rapier's sleep test against
    /// the one the call before left.
    pub(crate) fn was_at_rest(&self, collider: ColliderHandle) -> bool {
        self.asleep.contains(&collider) || self.timers.get(&collider).is_some_and(|t| *t > 0.0)
    }

    /// Remembers the dynamic bodies held still (asleep, or put to sleep)
    /// as the call ends.
    pub(crate) fn record_asleep(&mut self, scene: &Scene, map: &BodyMap) {
        self.asleep = map
            .entries()
            .iter()
            .zip(scene.bodies())
            .filter(|(entry, body)| entry.is_dynamic() && body.is_held())
            .map(|(entry, _)| entry.collider)
            .collect();
    }

    /// Whether a call zeroed velocities before a sleep decision.
    pub(crate) fn has_pending(&self) -> bool {
        !self.pending.is_empty()
    }

    /// The scene indices of the awake dynamic bodies to put to sleep in
    /// this call: the groups (module docs) all of whose bodies the last
    /// call prepared and moved, in Rapier's step since `previous` (the
    /// poses the last call left), by less than the sleep test allows.
    /// Clears the prepared set.
    pub(crate) fn take_sleepers(
        &mut self,
        previous: &RestPoses,
        scene: &Scene,
        map: &BodyMap,
        parameters: &IntegrationParameters,
    ) -> Vec<usize> {
        let pending = std::mem::take(&mut self.pending);
        if pending.is_empty() {
            return Vec::new();
        }
        let awake = awake_dynamic(scene, map);
        let margin = group_margin(parameters);
        let allowed = f64::from(parameters.allowed_linear_error());
        let groups = overlap_groups(scene, &awake, margin);
        groups
            .into_iter()
            .filter(|group| {
                group.iter().all(|&i| {
                    let entry = &map.entries()[i];
                    let body = &scene.bodies()[i];
                    pending.contains(&entry.collider)
                        && previous.get(&entry.collider).is_some_and(|before| {
                            farthest_point_motion(body, &body.user_pose(), before) <= allowed
                        })
                })
            })
            .flatten()
            .collect()
    }

    /// After a call: advances the timers from `previous` to `now` (the
    /// poses the last call and this call left) and remembers the bodies
    /// held as asleep.
    pub(crate) fn advance(
        &mut self,
        previous: &RestPoses,
        now: &RestPoses,
        scene: &Scene,
        map: &BodyMap,
        bodies: &RigidBodySet,
        parameters: &IntegrationParameters,
    ) {
        let dt = f64::from(parameters.dt).max(0.0);
        let awake = awake_dynamic(scene, map);
        let mut timers = HashMap::with_capacity(awake.len());
        for &i in &awake {
            let entry = &map.entries()[i];
            let body = &scene.bodies()[i];
            let (Some(before), Some(after)) =
                (previous.get(&entry.collider), now.get(&entry.collider))
            else {
                continue;
            };
            let at_rest = passes_sleep_test(entry, body, after, before, bodies, parameters);
            let time = match at_rest {
                true => self.timers.get(&entry.collider).copied().unwrap_or(0.0) + dt,
                false => 0.0,
            };
            timers.insert(entry.collider, time);
        }
        self.timers = timers;
        self.record_asleep(scene, map);
    }

    /// The scene indices of the groups all of whose timers reached their
    /// `time_until_sleep`, unless Rapier's own timers already all have;
    /// they are remembered as prepared for the next call.
    pub(crate) fn prepare(
        &mut self,
        scene: &Scene,
        map: &BodyMap,
        bodies: &RigidBodySet,
        parameters: &IntegrationParameters,
    ) -> Vec<usize> {
        let awake = awake_dynamic(scene, map);
        let ready = |i: usize| {
            let entry = &map.entries()[i];
            let rigid_body = entry.body.and_then(|h| bodies.get(h));
            let time = self.timers.get(&entry.collider).copied().unwrap_or(0.0);
            rigid_body.is_some_and(|rb| time >= f64::from(rb.activation().time_until_sleep))
        };
        let engine_ready = |i: usize| {
            map.entries()[i]
                .body
                .and_then(|h| bodies.get(h))
                .is_some_and(|rb| rb.activation().is_eligible_for_sleep())
        };
        // A group is prepared only if all its bodies are ready: with none
        // ready, no grouping is needed.
        if !awake.iter().any(|&i| ready(i)) {
            self.pending.clear();
            return Vec::new();
        }
        let margin = group_margin(parameters);
        let prepared: Vec<usize> = overlap_groups(scene, &awake, margin)
            .into_iter()
            .filter(|g| g.iter().all(|&i| ready(i)) && !g.iter().all(|&i| engine_ready(i)))
            .flatten()
            .collect();
        self.pending = prepared
            .iter()
            .map(|&i| map.entries()[i].collider)
            .collect();
        prepared
    }
}

/// Rapier's broad-phase skin (`BroadPhaseBvh::CHANGE_DETECTION_FACTOR` of
/// rapier3d 0.36.1, its default, non-adaptive margin), as a fraction of
/// the length unit: a leaf's box is fattened by it and refit only when the
/// collider leaves it.
pub(crate) const BROAD_PHASE_SKIN: f64 = 0.04;

/// How far, on every side, a body's box is grown to find its group: the
/// most by which Rapier's broad-phase box of it (half the prediction
/// distance, plus a skin the body may have moved within since its box was
/// fitted) can exceed its box, so that two bodies Rapier pairs (and so
/// wakes together when one is written) are always in one group.
fn group_margin(parameters: &IntegrationParameters) -> f64 {
    f64::from(parameters.prediction_distance())
        + 2.0 * BROAD_PHASE_SKIN * f64::from(parameters.length_unit)
}

/// Scene indices of the dynamic bodies that are neither fixed nor held.
fn awake_dynamic(scene: &Scene, map: &BodyMap) -> Vec<usize> {
    map.entries()
        .iter()
        .zip(scene.bodies())
        .enumerate()
        .filter(|(_, (entry, body))| entry.is_dynamic() && !body.is_fixed())
        .map(|(i, _)| i)
        .collect()
}

/// The connected components of `members` (scene indices) whose world
/// bounding boxes, grown by `margin` on every side, overlap, or that a
/// scene joint links (Rapier's islands join jointed bodies too): the
/// broad phase's pairs at twice the margin, then union-find.
pub(crate) fn overlap_groups(scene: &Scene, members: &[usize], margin: f64) -> Vec<Vec<usize>> {
    let boxes: Vec<Aabb> = members
        .iter()
        .map(|&i| body_aabb(&scene.bodies()[i]))
        .collect();
    let none_fixed = vec![false; members.len()];
    let mut sets = DisjointSets::new(members.len());
    match candidate_pairs_of_aabbs(&boxes, &none_fixed, 2.0 * margin) {
        Ok(pairs) => {
            for pair in pairs {
                sets.join(pair.body_a, pair.body_b);
            }
        }
        // Only a margin or a box that is not finite fails; then every
        // member is one group, which sleeps only when all of it is at rest.
        Err(_) => {
            for k in 1..members.len() {
                sets.join(0, k);
            }
        }
    }
    let position: HashMap<usize, usize> =
        members.iter().enumerate().map(|(k, &i)| (i, k)).collect();
    for joint in scene.joints() {
        if let (Some(&a), Some(&b)) = (position.get(&joint.body_a), position.get(&joint.body_b)) {
            sets.join(a, b);
        }
    }
    let mut groups: HashMap<usize, Vec<usize>> = HashMap::new();
    for (k, &i) in members.iter().enumerate() {
        groups.entry(sets.root(k)).or_default().push(i);
    }
    let mut groups: Vec<Vec<usize>> = groups.into_values().collect();
    groups.sort_unstable();
    groups
}
