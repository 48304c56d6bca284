//! Resting calls: when Rapier holds every awake body still, a call of the
//! default coupling accepts Rapier's own resting depth.
//!
//! # Why
//!
//! Rapier's contacts are soft: from a contact the call left closed (depth
//! about one tolerance, ~1e-6 m) Rapier's next step sinks it again by
//! about 1.5e-4 m on the settled pyramid of 55 (`examples/probes/rest_probe.rs`),
//! towards its own resting depth (about 1.5 mm there, below its allowed
//! linear error of 5 mm). A call that corrects that sink writes every body
//! at every step, and Rapier treats a written pose as a user change: its
//! narrow phase wakes the body and every body touching it *strongly*
//! (sleep timer reset). Nothing can fall asleep, and the correction and the
//! sink alternate for ever: the settled scene creeps.
//!
//! # The rule
//!
//! A call is *resting* when every awake dynamic body moved, in Rapier's
//! step since the pose the last call left it at (kept by the bridge,
//! whatever was read in between), by less than Rapier's own sleep test
//! allows in one step: with `d = |t' - t| + 2 |sin(theta / 2)| r` the
//! displacement of its farthest point (`r` the reach of its shape from
//! its shape-frame origin, `theta` the rotation angle),
//!
//! ```text
//! d / 2 < normalized_linear_threshold * length_unit * dt
//! ```
//!
//! (`RigidBodyActivation`, 0.05 m/s by default: `d` below 1.67 mm at 60
//! Hz), in [`RESTING_STREAK`] consecutive steps (one step let the 1:100
//! heavy stack of `examples/with_and_without.rs` alternate between resting
//! and closing calls: 17.1 mm of drift against 11.3 with three; ten
//! delayed the compound pile's sleep from step 125 to 213). A resting call of [`super::CouplingMode::ClosedContacts`] takes
//! Rapier's allowed linear error as its allowed penetration (so its stated
//! tolerance includes it): contacts within it are left as Rapier holds
//! them, deeper ones are brought back to it. Nothing is written while
//! Rapier's resting depth stays within its allowed error, so the scene is
//! a fixed point and falls asleep when Rapier alone would. A body that
//! moves more (falling, sliding, pushed) makes the call an ordinary one.
//! A body appearing since the last call makes it ordinary too.
//!
//! # Held cycles
//!
//! Where Rapier cannot hold a scene (a 1,000 kg box on four 1 kg ones:
//! Rapier alone crushes it), every ordinary call lifts back what Rapier's
//! step sank, and the two alternate in a cycle. That cycle is deterministic
//! (`examples/probes/slide_probe.rs --ratio 1000 --verbose 200 201` prints the same
//! step twice): from the same corrected state Rapier's step sinks the stack
//! by the same ~1 mm, unevenly (its contact solver's order), tilting each
//! box by ~6e-4 rad about a point above its contact; the call, a
//! mass-weighted projection with friction rows that hold its contacts,
//! levels each box about its contact instead. Each cycle leaves every box
//! displaced sideways by the same ~2.3e-5 m: 7.4 mm in 300 steps.
//!
//! The corrected state is a fixed point of the cycle only if the call
//! returns to it. So in an ordinary call of
//! [`super::CouplingMode::ClosedContacts`], when *every* body the call
//! moved ends, over Rapier's step and the call together, within Rapier's
//! sleep test of the pose `P` the last non-resting call left it at (the
//! same test as above, on the net motion), the call puts those bodies back
//! at `P` and solves again from there ([`held_poses`]). The answer from
//! `P` is kept only if its depth, rounded to f32, stays within the call's
//! stated tolerance; otherwise the first answer stands. Per island, all
//! or nothing ([`whole_islands`]): if one body of an island the call solved
//! is not at rest in the cycle (something is falling, sliding, being
//! pushed), nothing of that island is held, so real motion is never undone
//! (held per body, a pile's bodies held in place while their neighbours in
//! the same island moved kept the compound pile of 60 awake to the end; held
//! only when every moved body of the call is at rest, the pile of 200,
//! where some body always moves, crept 58 mm after settling). The anchor `P` is not
//! moved by resting calls: on the 1:100 stack a resting call every fourth
//! step left the sunk pose as the anchor and the ratchet came back (1.8
//! mm in 300 steps against 0.43 with the anchor kept).
//!
//! A held cycle puts the pose back, not the velocity: the velocity Rapier
//! gave the body in its step stays (less the approach the velocity
//! projection removes), so a body can gather speed under a pose held
//! still and move off once released (a tumbling box of the pile of 200:
//! 3.1 rad/s under its held pose, a 6 mm slide).
//! [`super::BridgeSettings::zero_held_velocities`] zeroes the velocities
//! of the bodies put back; off by default (measured: its docs).

use std::collections::{HashMap, HashSet};

use nalgebra::Isometry3;
use rapier3d::dynamics::{IntegrationParameters, RigidBodySet};
use rapier3d::geometry::ColliderHandle;

use super::body_map::BodyMap;
use crate::scene::Scene;
use crate::stabilizer::Report;

/// Consecutive steps that must pass the rest test before a call rests
/// (measured: module docs).
pub(crate) const RESTING_STREAK: usize = 3;

/// The user poses of the dynamic scene bodies, by collider (kept from one
/// call to the next).
pub(crate) type RestPoses = HashMap<ColliderHandle, Isometry3<f64>>;

/// The user poses of the awake dynamic bodies of the scene, by collider.
pub(crate) fn dynamic_poses(scene: &Scene, map: &BodyMap) -> RestPoses {
    map.entries()
        .iter()
        .zip(scene.bodies())
        .filter(|(entry, body)| entry.is_dynamic() && !body.is_fixed())
        .map(|(entry, body)| (entry.collider, body.user_pose()))
        .collect()
}

/// Whether every awake dynamic body passes Rapier's sleep test on its
/// motion since `previous` (module docs); false when there is none.
pub(crate) fn is_resting(
    previous: &RestPoses,
    scene: &Scene,
    map: &BodyMap,
    bodies: &RigidBodySet,
    parameters: &IntegrationParameters,
) -> bool {
    let mut awake = map
        .entries()
        .iter()
        .zip(scene.bodies())
        .filter(|(entry, body)| entry.is_dynamic() && !body.is_fixed())
        .peekable();
    if awake.peek().is_none() {
        return false;
    }
    awake.all(|(entry, body)| {
        previous.get(&entry.collider).is_some_and(|before| {
            passes_sleep_test(entry, body, &body.user_pose(), before, bodies, parameters)
        })
    })
}

/// The bodies of `moved` (scene indices) whose net motion since their
/// pose in `anchor`, over Rapier's step and this call together, passes
/// Rapier's sleep test, with that pose: the call may put them back there
/// (module docs, "Held cycles").
pub(crate) fn held_poses(
    anchor: &RestPoses,
    scene: &Scene,
    map: &BodyMap,
    moved: &[usize],
    bodies: &RigidBodySet,
    parameters: &IntegrationParameters,
) -> Vec<(usize, Isometry3<f64>)> {
    moved
        .iter()
        .filter_map(|&index| {
            let entry = map.entries().get(index)?;
            let body = scene.bodies().get(index)?;
            let before = anchor.get(&entry.collider)?;
            (entry.is_dynamic()
                && !body.is_fixed()
                && passes_sleep_test(entry, body, &body.user_pose(), before, bodies, parameters))
            .then_some((index, *before))
        })
        .collect()
}

/// Whether the body's motion from `before` to its current user pose passes
/// Rapier's sleep test for one step (module docs); false without a Rapier
/// body.
pub(crate) fn passes_sleep_test(
    entry: &super::body_map::MappedCollider,
    body: &crate::body::Body,
    now: &Isometry3<f64>,
    before: &Isometry3<f64>,
    bodies: &RigidBodySet,
    parameters: &IntegrationParameters,
) -> bool {
    let Some(rigid_body) = entry.body.and_then(|h| bodies.get(h)) else {
        return false;
    };
    let dt = f64::from(parameters.dt);
    let length_unit = f64::from(parameters.length_unit);
    let threshold = f64::from(rigid_body.activation().normalized_linear_threshold);
    let motion = farthest_point_motion(body, now, before);
    threshold >= 0.0 && 0.5 * motion < threshold * length_unit * dt
}

/// A bound on how far any point of the body moves from user pose `before`
/// to `now`: the translation plus the chord `2 |sin(theta / 2)| r` of the
/// farthest point (`r` the reach from the shape-frame origin, about which
/// the user pose turns).
pub(crate) fn farthest_point_motion(
    body: &crate::body::Body,
    now: &Isometry3<f64>,
    before: &Isometry3<f64>,
) -> f64 {
    let reach = body.reach() + body.com_offset().norm();
    let half_angle = before.rotation.angle_to(&now.rotation) / 2.0;
    (now.translation.vector - before.translation.vector).norm()
        + 2.0 * half_angle.sin().abs() * reach
}

/// The entries of `held` whose island holds no moved body left out of
/// `held`: per island, all or nothing. An island is the bodies the
/// stabilizer solved together in any pass of `report` (islands of
/// different passes that share a body are one).
pub(crate) fn whole_islands(
    report: &Report,
    moved: &[usize],
    held: Vec<(usize, Isometry3<f64>)>,
) -> Vec<(usize, Isometry3<f64>)> {
    let n = moved.iter().max().map_or(0, |&m| m + 1);
    let mut sets = DisjointSets::new(n);
    for island in report.pass_reports.iter().flat_map(|p| &p.solved) {
        let mut members = island.bodies.iter().filter(|&&b| b < n);
        if let Some(&first) = members.next() {
            for &other in members {
                sets.join(first, other);
            }
        }
    }
    let is_held: HashSet<usize> = held.iter().map(|(i, _)| *i).collect();
    let moving: HashSet<usize> = moved
        .iter()
        .filter(|i| !is_held.contains(i))
        .map(|&i| sets.root(i))
        .collect();
    held.into_iter()
        .filter(|(i, _)| !moving.contains(&sets.root(*i)))
        .collect()
}

/// Union-find over `0..n` (path halving).
pub(crate) struct DisjointSets(Vec<usize>);

impl DisjointSets {
    pub(crate) fn new(n: usize) -> Self {
        DisjointSets((0..n).collect())
    }

    pub(crate) fn root(&mut self, mut i: usize) -> usize {
        while self.0[i] != i {
            self.0[i] = self.0[self.0[i]];
            i = self.0[i];
        }
        i
    }

    pub(crate) fn join(&mut self, a: usize, b: usize) {
        let (a, b) = (self.root(a), self.root(b));
        self.0[a] = b;
    }
}
