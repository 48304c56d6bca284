//! [`RapierBridge`]: read the world into the kept scene, stabilize, write
//! the corrected poses back.
//!
//! One call, after `PhysicsPipeline::step`:
//! 1. read every collider ([`super::collider_shape`]): the ones the scene
//!    can hold, and the skipped ones with their reason;
//! 2. keep the scene ([`super::body_map`]): remove the bodies of mapped
//!    colliders that vanished or changed (the stabilizer carries the warm
//!    starts of the others to their new indices), append the new ones; then
//!    set every scene body's user pose to its collider's world pose
//!    `U = B P`, in one batch;
//! 3. hold the bodies Rapier put to sleep still (obstacles, not written
//!    unless they wedge an awake body the call cannot solve, `super::wedged`);
//!    choose the call's lengths ([`super::round_off`], and the allowed
//!    penetration of the coupling mode, [`super::settings`], Rapier's
//!    allowed linear error in a resting call, `super::rest`) and stabilize
//!    with the kept [`Stabilizer`] (warm starts from the previous call); on
//!    error nothing is written;
//! 4. write back the dynamic bodies whose pose changed, `B' = U' P^-1`,
//!    rounded to f32, without waking bodies, and move their colliders with
//!    them; in the velocity modes, project and write the velocities.

use std::collections::HashMap;

use nalgebra::{Isometry3, Vector3};
use rapier3d::dynamics::{
    ImpulseJointSet, IntegrationParameters, MultibodyJointSet, RigidBody, RigidBodyHandle,
    RigidBodySet,
};
use rapier3d::geometry::ColliderSet;
use rapier3d::math::Vector;
use rapier3d::pipeline::PhysicsWorld;

use super::body_map::{BodyMap, MappedCollider};
use super::collider_shape::{
    ReadCollider, compound_parent, read_collider, read_compound, shape_of_read,
};
use super::convert::{pose_from_f64, pose_to_f64, xyzw};
use super::error::BridgeError;
use super::joints::{JointReadReport, JointSkipReason, RapierJoint, SkippedJoint, read_joints};
use super::limbo::{Limbo, SleepPoses};
use super::report::{BridgeReport, SkipReason, SkippedCollider, SyncReport, WriteBackRoundOff};
use super::rest::{
    RESTING_STREAK, RestPoses, dynamic_poses, held_poses, is_resting, whole_islands,
};
use super::round_off::{
    ROUNDING_DEPTH_FACTOR, lowered_for_round_off, own_lengths, raised_lengths,
    write_back_round_off_bound,
};
use super::settings::{
    BridgeSettings, CouplingMode, FAST_BODY_REACH_FRACTION, closed_contact_allowance,
};
use super::sleep::{SleepClock, overlap_groups};
use super::wedged::{RELEASE_ROUNDS, held_near_left_islands};
use crate::body::{BodyDesc, MassSpec};
use crate::joints::JointError;
use crate::scene::{Scene, SceneError};
use crate::settings::{ResolvedLengths, Settings};
use crate::stabilizer::{BodyVelocity, Stabilizer, VelocityReport};

/// Stabilizes a Rapier world after each step; keeps the scene, the handle
/// map and the stabilizer (with its warm starts) from call to call.
#[derive(Debug, Clone)]
pub struct RapierBridge {
    settings: BridgeSettings,
    stabilizer: Stabilizer,
    scene: Scene,
    map: BodyMap,
    /// The awake dynamic bodies' poses as the last call left them
    /// (`super::rest`).
    last_output: RestPoses,
    /// The awake dynamic bodies' poses as the last call that was not a
    /// resting one left them: where a held cycle puts them back
    /// (`super::rest`).
    hold_anchor: RestPoses,
    /// Consecutive calls whose step passed the rest test.
    rest_streak: usize,
    /// Rapier's sleep timers on the poses the calls leave (`super::sleep`).
    clock: SleepClock,
    /// Where the bridge put bodies to sleep (`super::limbo`).
    sleep_poses: SleepPoses,
}

/// A user pose as stored: translation and `[x, y, z, w]`, compared bit for
/// bit to find the bodies the stabilizer moved.
type UserPose = (Vector3<f64>, [f64; 4]);

impl RapierBridge {
    /// A bridge with validated stabilizer settings, the default coupling
    /// ([`super::CouplingMode::ClosedContacts`], with the colliders'
    /// friction) and an empty scene.
    ///
    /// The stabilizer settings are taken as given: `Settings::default()`
    /// here is not [`BridgeSettings::default`]'s stabilizer, which keeps the
    /// target margin at [`super::BRIDGE_TARGET_MARGIN_RELATIVE`] and the
    /// dual active-set method off (the settings with which the bridge's
    /// coupling and rest were measured). For the bridge's defaults use
    /// [`RapierBridge::with_settings`]`(BridgeSettings::default())`.
    pub fn new(settings: Settings) -> Result<Self, BridgeError> {
        Self::with_settings(BridgeSettings::with_stabilizer(settings))
    }

    /// A bridge with validated settings and an empty scene.
    pub fn with_settings(settings: BridgeSettings) -> Result<Self, BridgeError> {
        Ok(RapierBridge {
            stabilizer: Stabilizer::new(settings.stabilizer.clone())?,
            settings,
            scene: Scene::new(),
            map: BodyMap::default(),
            last_output: RestPoses::default(),
            hold_anchor: RestPoses::default(),
            rest_streak: 0,
            clock: SleepClock::default(),
            sleep_poses: SleepPoses::default(),
        })
    }

    /// The bridge's settings, as given.
    pub fn settings(&self) -> &BridgeSettings {
        &self.settings
    }

    /// The scene as of the last call (poses as read, or as corrected by
    /// the last [`RapierBridge::stabilize`]).
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Rapier handles of the scene bodies.
    pub fn body_map(&self) -> &BodyMap {
        &self.map
    }

    /// The stabilizer; its settings are those of the last call (derived
    /// from [`RapierBridge::settings`], see [`super::round_off`]).
    pub fn stabilizer(&self) -> &Stabilizer {
        &self.stabilizer
    }

    /// Reads the world into the scene (step 1 and 2 above) without
    /// stabilizing or writing anything.
    pub fn sync(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
    ) -> Result<SyncReport, BridgeError> {
        let (read, mut skipped) = read_world(bodies, colliders);
        let mut report = SyncReport::default();
        let plan = self.map.plan(&read);
        if !plan.remove.is_empty() {
            let removed = self
                .stabilizer
                .remove_bodies(&mut self.scene, &plan.remove)?;
            self.map.remove(&removed);
            report.removed = plan.remove.len();
        }
        for i in plan.append {
            match self.append(&read[i], bodies, colliders) {
                Ok(()) => report.appended += 1,
                Err(reason) => skipped.push(SkippedCollider {
                    collider: read[i].collider,
                    reason,
                }),
            }
        }
        self.update_poses(bodies, colliders)?;
        report.skipped = skipped;
        report.scene_bodies = self.scene.len();
        Ok(report)
    }

    /// Reads the joints into the scene's joints, replacing those of the
    /// last call (`super::joints`: which joints are read, which are
    /// skipped and why). Call after [`RapierBridge::sync`].
    pub fn sync_joints(
        &mut self,
        impulse_joints: &ImpulseJointSet,
        multibody_joints: &MultibodyJointSet,
    ) -> Result<JointReadReport, BridgeError> {
        let (joints, mut report) = read_joints(impulse_joints, multibody_joints, &self.map);
        let all: Vec<usize> = (0..self.scene.joints().len()).collect();
        self.scene
            .remove_joints(&all)
            .map_err(|e| BridgeError::Stabilize(e.into()))?;
        for (handle, joint) in joints {
            let reason = match self.scene.add_joint(joint) {
                Ok(_) => {
                    report.read += 1;
                    continue;
                }
                // Both bodies held still (asleep) or static: a reason of its
                // own, without the message that every call on a sleeping
                // figure would otherwise format for each of its joints.
                Err(SceneError::Joint {
                    source: JointError::BothFixed { .. },
                    ..
                }) => JointSkipReason::BothBodiesFixed,
                Err(error) => JointSkipReason::Invalid(error.to_string()),
            };
            report.skipped.push(SkippedJoint {
                joint: RapierJoint::Impulse(handle),
                reason,
            });
        }
        Ok(report)
    }

    /// [`RapierBridge::stabilize`] on a [`PhysicsWorld`], after
    /// `world.step()`: its bodies, colliders, joints and integration
    /// parameters.
    pub fn stabilize_world(
        &mut self,
        world: &mut PhysicsWorld,
    ) -> Result<BridgeReport, BridgeError> {
        self.stabilize(
            &mut world.bodies,
            &mut world.colliders,
            &world.impulse_joints,
            &world.multibody_joints,
            &world.integration_parameters,
        )
    }

    /// Reads the world (bodies, colliders and joints, the sets
    /// `PhysicsPipeline::step` takes), removes interpenetration and joint
    /// drift, writes the corrected poses of dynamic bodies back (and, in
    /// the velocity modes, their velocities). `parameters` are the ones of
    /// the step just taken (the coupling mode may read them). On error
    /// nothing is written.
    pub fn stabilize(
        &mut self,
        bodies: &mut RigidBodySet,
        colliders: &mut ColliderSet,
        impulse_joints: &ImpulseJointSet,
        multibody_joints: &MultibodyJointSet,
        parameters: &IntegrationParameters,
    ) -> Result<BridgeReport, BridgeError> {
        let sync = self.sync(bodies, colliders)?;
        // The joints after this call's holds of sleeping bodies: a joint is
        // skipped as joining two fixed bodies by the holds of the call that
        // solves it (one part of a held figure woken: its joints are read
        // in the call that releases it).
        let (asleep, woken) =
            self.hold_sleeping(bodies, f64::from(parameters.allowed_linear_error()));
        let joints = self.sync_joints(impulse_joints, multibody_joints)?;
        let previous = std::mem::take(&mut self.last_output);
        let sleepers = match self.settings.sleep_held_groups && self.clock.has_pending() {
            true => {
                let sleepers =
                    self.clock
                        .take_sleepers(&previous, &self.scene, &self.map, parameters);
                for &i in &sleepers {
                    if let Some(body) = self.scene.bodies_mut().get_mut(i) {
                        body.hold_fixed();
                    }
                }
                sleepers
            }
            false => Vec::new(),
        };
        let struck = match self.settings.hold_struck_bodies {
            true => self.hold_struck(bodies, parameters),
            false => Vec::new(),
        };
        self.rest_streak = match is_resting(&previous, &self.scene, &self.map, bodies, parameters) {
            true => self.rest_streak + 1,
            false => 0,
        };
        let resting = self.settings.resting_calls && self.rest_streak >= RESTING_STREAK;
        let own = own_lengths(&self.settings.stabilizer, &self.scene);
        let round_off_bound = write_back_round_off_bound(&self.scene, &self.map, &own);
        let mut report = BridgeReport {
            sync,
            joints,
            stabilizer: None,
            bodies_written: 0,
            bodies_left_asleep: asleep,
            resting: false,
            bodies_held: 0,
            bodies_struck_held: struck.len(),
            bodies_released: 0,
            bodies_put_to_sleep: sleepers.len(),
            bodies_woken_falling: woken,
            velocities_zeroed: 0,
            write_back_round_off: WriteBackRoundOff::default(),
            round_off_bound,
            stated_tolerance: None,
            velocities: None,
            velocities_written: 0,
        };
        if self.scene.bodies().iter().all(|b| b.is_fixed()) {
            self.put_to_sleep(bodies, &sleepers);
            self.clock.record_asleep(&self.scene, &self.map);
            return Ok(report);
        }
        let allowed = self
            .settings
            .allowed_penetration(f64::from(parameters.allowed_linear_error()));
        let raised = raised_lengths(&own, round_off_bound);
        let engine_allowed = f64::from(parameters.allowed_linear_error());
        let allowed = match self.settings.coupling {
            CouplingMode::ClosedContacts if resting => allowed.max(engine_allowed),
            CouplingMode::ClosedContacts => allowed.max(closed_contact_allowance(&raised)),
            _ => allowed,
        };
        report.resting = resting;
        let stated = raised.allowing(allowed);
        let solved_to = match self.settings.coupling {
            CouplingMode::ClosedContacts => stated,
            _ => lowered_for_round_off(stated, round_off_bound),
        };
        self.stabilizer.set_call_lengths(Some(solved_to));
        report.stated_tolerance = Some(stated.tolerance);
        let before: Vec<UserPose> = self.scene.bodies().iter().map(user_pose_of).collect();
        report.stabilizer = Some(self.stabilizer.stabilize(&mut self.scene)?);
        if !struck.is_empty() {
            // The struck group released and the call solved again from the
            // first answer: the contacts inside the group, which the first
            // solve could not move, are corrected too.
            for &i in &struck {
                if let Some(body) = self.scene.bodies_mut().get_mut(i) {
                    body.release();
                }
            }
            report.stabilizer = Some(self.stabilizer.stabilize(&mut self.scene)?);
        }
        report.bodies_released =
            self.released_near_left_islands(&mut report, stated.contact_margin)?;
        if self.settings.coupling == CouplingMode::ClosedContacts {
            self.checked_after_rounding(&mut report, &before, stated)?;
        }
        let mut held = Vec::new();
        if self.settings.hold_cycles
            && !resting
            && self.settings.coupling == CouplingMode::ClosedContacts
        {
            let anchor = std::mem::take(&mut self.hold_anchor);
            held = self.hold_cycle(&mut report, &anchor, &before, bodies, parameters)?;
        }
        let (moved, round_off) = self.write_back(bodies, &before);
        bodies.propagate_modified_body_positions_to_colliders(colliders);
        self.last_output = dynamic_poses(&self.scene, &self.map);
        if !resting {
            self.hold_anchor = self.last_output.clone();
        }
        report.bodies_written = moved.len();
        report.write_back_round_off = round_off;
        if self.settings.coupling.projects_velocities() && !moved.is_empty() {
            let (velocities, count) = self.project_velocities(bodies, &moved, parameters)?;
            report.velocities = Some(velocities);
            report.velocities_written = count;
        }
        if self.settings.zero_held_velocities {
            report.velocities_zeroed += self.zero_velocities(bodies, &held);
        }
        self.put_to_sleep(bodies, &sleepers);
        self.clock.advance(
            &previous,
            &self.last_output,
            &self.scene,
            &self.map,
            bodies,
            parameters,
        );
        if self.settings.sleep_held_groups {
            let prepared = self
                .clock
                .prepare(&self.scene, &self.map, bodies, parameters);
            report.velocities_zeroed = self.zero_velocities(bodies, &prepared);
        }
        Ok(report)
    }

    /// Held cycles (`super::rest`): for each island all of whose moved
    /// bodies are at rest over Rapier's step and the call, puts them back
    /// at their poses
    /// in `anchor` (where the last call that was not a resting one left
    /// them) and solves again from there; keeps that answer only
    /// if its depth, rounded to f32, stays within the call's stated
    /// tolerance (`depth_after + 2 delta <= tolerance`), else restores the
    /// first answer. Returns the scene indices of the bodies held.
    fn hold_cycle(
        &mut self,
        report: &mut BridgeReport,
        anchor: &RestPoses,
        read: &[UserPose],
        bodies: &RigidBodySet,
        parameters: &IntegrationParameters,
    ) -> Result<Vec<usize>, BridgeError> {
        let moved: Vec<usize> = (0..read.len())
            .filter(|&i| user_pose_of(&self.scene.bodies()[i]) != read[i])
            .collect();
        let Some(first_report) = report.stabilizer.as_ref() else {
            return Ok(Vec::new());
        };
        let held = held_poses(anchor, &self.scene, &self.map, &moved, bodies, parameters);
        // Per island, all or nothing (module docs of `rest`).
        let held = whole_islands(first_report, &moved, held);
        if held.is_empty() {
            return Ok(Vec::new());
        }
        let indices: Vec<usize> = held.iter().map(|(i, _)| *i).collect();
        let scene_error = |e: SceneError| BridgeError::Stabilize(e.into());
        let first: Vec<(usize, Isometry3<f64>)> = self
            .scene
            .bodies()
            .iter()
            .map(|b| b.user_pose())
            .enumerate()
            .collect();
        let count = held.len();
        self.scene.set_user_poses(held).map_err(scene_error)?;
        let second = self.stabilizer.stabilize(&mut self.scene)?;
        if second.depth_after + 2.0 * report.round_off_bound <= second.tolerance {
            log::debug!(
                "held cycle: {count} bodies back at their anchor, depth after {:.3e}",
                second.depth_after
            );
            report.stabilizer = Some(second);
            report.bodies_held = count;
            return Ok(indices);
        } else {
            log::debug!(
                "held cycle rejected: depth after {:.3e} from the anchor, tolerance {:.3e}",
                second.depth_after,
                second.tolerance
            );
            self.scene.set_user_poses(first).map_err(scene_error)?;
        }
        Ok(Vec::new())
    }

    /// Releases the held bodies that wedge an island the call could not
    /// solve and solves again (`super::wedged`); returns how many were
    /// released.
    fn released_near_left_islands(
        &mut self,
        report: &mut BridgeReport,
        margin: f64,
    ) -> Result<usize, BridgeError> {
        let mut released = 0;
        for _ in 0..RELEASE_ROUNDS {
            let Some(last) = report.stabilizer.as_ref() else {
                break;
            };
            let near = held_near_left_islands(&self.scene, last, margin);
            if near.is_empty() {
                break;
            }
            log::debug!(
                "{} islands left unsolved: {} held bodies near them released",
                last.islands_left.len(),
                near.len()
            );
            for &i in &near {
                if let Some(body) = self.scene.bodies_mut().get_mut(i) {
                    body.release();
                }
            }
            released += near.len();
            report.stabilizer = Some(self.stabilizer.stabilize(&mut self.scene)?);
        }
        Ok(released)
    }

    /// In closed contacts the call is solved to its stated lengths, and
    /// rounding the written poses to f32 can add up to `2 delta` to a depth
    /// (`super::round_off`). When the call resolved with its exact depth
    /// after within `2 delta` of the stated tolerance, a copy of the scene
    /// with the moved bodies at their poses as written (rounded to f32 and
    /// read back) is measured by a copy of the stabilizer, so that neither
    /// the scene nor the stabilizer's warm state changes; only if the
    /// rounding took a pair beyond the stated tolerance is the call solved
    /// again, from its answer, to the tolerance lowered by `2 delta`. The
    /// stabilizer is left at `stated`.
    fn checked_after_rounding(
        &mut self,
        report: &mut BridgeReport,
        read: &[UserPose],
        stated: ResolvedLengths,
    ) -> Result<(), BridgeError> {
        let Some(first) = report.stabilizer.as_ref() else {
            return Ok(());
        };
        let bound = ROUNDING_DEPTH_FACTOR * report.round_off_bound;
        if !first.status.is_resolved() || first.depth_after + bound <= stated.tolerance {
            return Ok(());
        }
        let first_depth = first.depth_after;
        let rounded: Vec<(usize, Isometry3<f64>)> = self
            .map
            .entries()
            .iter()
            .zip(self.scene.bodies())
            .zip(read)
            .enumerate()
            .filter(|(_, ((entry, body), old))| entry.is_dynamic() && user_pose_of(body) != **old)
            .map(|(i, ((entry, body), _))| (i, as_written(entry, &body.user_pose())))
            .collect();
        let mut written = self.scene.clone();
        written
            .set_user_poses(rounded)
            .map_err(|e| BridgeError::Stabilize(e.into()))?;
        let over = self.stabilizer.clone().penetrations(&written)?;
        log::debug!(
            "depth after {first_depth:.4e} within 2 delta ({bound:.3e}) of the tolerance {:.4e}: as written, {} pairs beyond it",
            stated.tolerance,
            over.len()
        );
        if over.is_empty() {
            return Ok(());
        }
        let lowered = lowered_for_round_off(stated, report.round_off_bound);
        self.stabilizer.set_call_lengths(Some(lowered));
        let again = self.stabilizer.stabilize(&mut self.scene);
        self.stabilizer.set_call_lengths(Some(stated));
        report.stabilizer = Some(again?);
        Ok(())
    }

    /// Puts the Rapier bodies of `sleepers` (scene indices) to sleep
    /// (`super::sleep`): velocities zeroed, sleep eligibility pinned, no
    /// pose written.
    fn put_to_sleep(&mut self, bodies: &mut RigidBodySet, sleepers: &[usize]) {
        for &i in sleepers {
            if let (Some(entry), Some(body)) =
                (self.map.entries().get(i), self.scene.bodies().get(i))
            {
                self.sleep_poses.record(entry.collider, body.user_pose());
            }
            let handle = self.map.entries().get(i).and_then(|e| e.body);
            if let Some(rigid_body) = handle.and_then(|h| bodies.get_mut(h)) {
                rigid_body.sleep();
            }
        }
        if !sleepers.is_empty() {
            log::debug!("held groups put to sleep: {} bodies", sleepers.len());
        }
    }

    /// Zeroes the velocities of the Rapier bodies of `indices` (scene
    /// indices) without waking them (`super::sleep`); returns how many.
    fn zero_velocities(&self, bodies: &mut RigidBodySet, indices: &[usize]) -> usize {
        let mut zeroed = 0;
        for &i in indices {
            let handle = self.map.entries().get(i).and_then(|e| e.body);
            if let Some(rigid_body) = handle.and_then(|h| bodies.get_mut(h)) {
                rigid_body.set_linvel(Vector::ZERO, false);
                rigid_body.set_angvel(Vector::ZERO, false);
                zeroed += 1;
            }
        }
        if zeroed > 0 {
            log::debug!(
                "held groups at rest for Rapier's time until sleep: {zeroed} velocities zeroed"
            );
        }
        zeroed
    }

    /// Holds every dynamic scene body whose Rapier body sleeps still (an
    /// obstacle for the awake ones, never read as moving nor written) and
    /// releases the awake ones; returns how many are held. Rapier wakes a
    /// sleeping body that an awake one touches during its step, so a
    /// sleeping body is touched only by sleeping or fixed ones, unless the
    /// user moved a body into it without waking it.
    fn hold_sleeping(&mut self, bodies: &mut RigidBodySet, allowed: f64) -> (usize, usize) {
        let (mut held, mut woken) = (0, 0);
        for (entry, body) in self.map.entries().iter().zip(self.scene.bodies_mut()) {
            let rigid_body = entry
                .body
                .filter(|_| entry.is_dynamic())
                .and_then(|h| bodies.get_mut(h));
            let state = match rigid_body {
                Some(rb) if rb.is_sleeping() => {
                    self.sleep_poses.check(entry.collider, body, rb, allowed)
                }
                _ => {
                    self.sleep_poses.forget(entry.collider);
                    body.release();
                    continue;
                }
            };
            match state {
                Limbo::Asleep | Limbo::Stopped => {
                    body.hold_fixed();
                    held += 1;
                }
                Limbo::Woken => {
                    body.release();
                    woken += 1;
                }
            }
        }
        self.sleep_poses.retain_mapped(&self.map);
        if woken > 0 {
            log::debug!("bodies put to sleep but still falling, woken: {woken}");
        }
        (held, woken)
    }

    /// Struck bodies ([`BridgeSettings::hold_struck_bodies`]): holds still
    /// every dynamic body that is not fast and that a fast body reaches
    /// through overlapping bounding boxes of dynamic bodies; returns their
    /// scene indices.
    fn hold_struck(
        &mut self,
        bodies: &RigidBodySet,
        parameters: &IntegrationParameters,
    ) -> Vec<usize> {
        let dt = f64::from(parameters.dt).max(0.0);
        let fast: Vec<bool> = self
            .map
            .entries()
            .iter()
            .zip(self.scene.bodies())
            .map(|(entry, body)| {
                let speed = entry
                    .body
                    .filter(|_| entry.is_dynamic() && !body.is_held())
                    .and_then(|h| bodies.get(h))
                    .map_or(0.0, |b| f64::from(b.linvel().length()));
                speed * dt > FAST_BODY_REACH_FRACTION * body.reach()
            })
            .collect();
        if !fast.contains(&true) {
            return Vec::new();
        }
        // Every dynamic body reached from a fast one through overlapping
        // bounding boxes of dynamic bodies (fixed ones do not pass it on):
        // the whole group a fast body struck, held as one.
        let movable: Vec<usize> = (0..fast.len())
            .filter(|&i| !self.scene.bodies()[i].is_fixed())
            .collect();
        // Only a group that was at rest when the last call ended (its bodies
        // other than the fast ones asleep or passing Rapier's sleep test):
        // a struck standing stack, not a pile still settling, whose bodies
        // strike each other as they fall.
        let at_rest = |i: usize| {
            self.map
                .entry(i)
                .is_some_and(|e| self.clock.was_at_rest(e.collider))
        };
        let struck: Vec<usize> = overlap_groups(&self.scene, &movable, 0.0)
            .into_iter()
            .filter(|group| {
                group.iter().any(|&i| fast[i])
                    && group.iter().filter(|&&i| !fast[i]).all(|&i| at_rest(i))
            })
            .flatten()
            .filter(|&i| !fast[i])
            .collect();
        for &i in &struck {
            if let Some(body) = self.scene.bodies_mut().get_mut(i) {
                body.hold_fixed();
            }
        }
        log::debug!("struck bodies held: {}", struck.len());
        struck
    }

    /// Velocity consistency: reads the velocities of the dynamic bodies,
    /// removes the approach velocities at the contacts of the islands of
    /// `moved`, writes back the velocities that changed (without waking
    /// bodies); returns the projection's report and the bodies written.
    fn project_velocities(
        &mut self,
        bodies: &mut RigidBodySet,
        moved: &[usize],
        parameters: &IntegrationParameters,
    ) -> Result<(VelocityReport, usize), BridgeError> {
        let handles: Vec<Option<RigidBodyHandle>> = self
            .map
            .entries()
            .iter()
            .map(|entry| entry.body.filter(|_| entry.is_dynamic()))
            .collect();
        let velocities: Vec<BodyVelocity> = handles
            .iter()
            .map(|handle| {
                handle
                    .and_then(|h| bodies.get(h))
                    .map_or_else(BodyVelocity::default, velocity_of)
            })
            .collect();
        let mut projected = velocities.clone();
        let time_step = Some(f64::from(parameters.dt)).filter(|dt| *dt > 0.0);
        let report = self.stabilizer.project_velocities(
            &self.scene,
            &mut projected,
            moved,
            time_step,
            self.settings.velocity_friction,
        )?;
        let mut written = 0;
        for ((handle, old), new) in handles.iter().zip(&velocities).zip(&projected) {
            let Some(body) = handle.and_then(|h| bodies.get_mut(h)) else {
                continue;
            };
            if old == new {
                continue;
            }
            let f32_of = |v: &Vector3<f64>| Vector::new(v.x as f32, v.y as f32, v.z as f32);
            body.set_linvel(f32_of(&new.linear), false);
            body.set_angvel(f32_of(&new.angular), false);
            written += 1;
        }
        Ok((report, written))
    }

    /// Builds the scene body of a read collider; an invalid one (a
    /// degenerate hull, a mass that is zero or not finite, a pose that is
    /// not finite) is skipped with the message.
    fn append(
        &mut self,
        read: &ReadCollider,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
    ) -> Result<(), SkipReason> {
        let shape = shape_of_read(read, colliders).ok_or(SkipReason::Disabled)?;
        let entry = MappedCollider::of(read);
        let pose = collider_world_pose(&entry, bodies, colliders).ok_or(SkipReason::Disabled)?;
        let name = match (read.parts.is_empty(), read.body) {
            (false, Some(body)) => format!("body {}", body.into_raw_parts().0),
            _ => format!("collider {}", read.collider.into_raw_parts().0),
        };
        let desc = BodyDesc {
            name,
            shape,
            translation: pose.translation.vector,
            rotation_xyzw: xyzw(&pose.rotation),
            mass: read.dynamic_mass.map_or(MassSpec::Fixed, MassSpec::Mass),
        };
        let index = self
            .scene
            .add_body(desc)
            .map_err(|e| SkipReason::Invalid(e.to_string()))?;
        if let Some(engine_mass) = &read.engine_mass {
            let body = self
                .scene
                .body_mut(index)
                .map_err(|e| SkipReason::Invalid(e.to_string()))?;
            engine_mass
                .apply(body, &read.collider_in_body)
                .map_err(|e| SkipReason::Invalid(e.to_string()))?;
        }
        if self.settings.collider_friction {
            // A compound's coefficient is the mean of its colliders'.
            let handles = entry.colliders();
            let coefficients: Vec<f64> = handles
                .iter()
                .filter_map(|&h| colliders.get(h))
                .map(|c| f64::from(c.friction()))
                .collect();
            let friction =
                Some(coefficients.iter().sum::<f64>() / coefficients.len().max(1) as f64);
            let body = self
                .scene
                .body_mut(index)
                .map_err(|e| SkipReason::Invalid(e.to_string()))?;
            body.set_friction(friction)
                .map_err(|e| SkipReason::Invalid(e.to_string()))?;
        }
        self.map.push(read);
        Ok(())
    }

    /// Sets every scene body's user pose to its collider's world pose, in
    /// one batch (all or nothing).
    fn update_poses(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
    ) -> Result<(), BridgeError> {
        let poses = self
            .map
            .entries()
            .iter()
            .enumerate()
            .filter_map(|(index, entry)| {
                collider_world_pose(entry, bodies, colliders).map(|pose| (index, pose))
            });
        let result = self.scene.set_user_poses(poses.collect::<Vec<_>>());
        result.map_err(|source| {
            // The indices are the map's own, so a body error always names a
            // mapped collider; anything else is passed on as the scene's.
            let collider = match source {
                SceneError::Body { index, .. } => self.map.collider_of(index),
                _ => None,
            };
            match collider {
                Some(collider) => BridgeError::Body { collider, source },
                None => BridgeError::Stabilize(source.into()),
            }
        })
    }

    /// Writes `B' = U' P^-1` to every dynamic body the stabilizer moved;
    /// returns their scene indices and the rounding measured.
    fn write_back(
        &self,
        bodies: &mut RigidBodySet,
        before: &[UserPose],
    ) -> (Vec<usize>, WriteBackRoundOff) {
        let mut written = Vec::new();
        let mut round_off = WriteBackRoundOff::default();
        for (index, ((entry, body), old)) in self
            .map
            .entries()
            .iter()
            .zip(self.scene.bodies())
            .zip(before)
            .enumerate()
        {
            if !entry.is_dynamic() || user_pose_of(body) == *old {
                continue;
            }
            let Some(rigid_body) = entry.body.and_then(|h| bodies.get_mut(h)) else {
                continue;
            };
            let body_pose = body_pose_of(entry, &body.user_pose());
            let pose = pose_from_f64(&body_pose);
            record_round_off(&mut round_off, &body_pose, &pose_to_f64(&pose));
            rigid_body.set_position(pose, false);
            written.push(index);
        }
        (written, round_off)
    }
}

/// Every collider, read or skipped, in the collider set's order (a
/// compound at its first collider in that order).
fn read_world(
    bodies: &RigidBodySet,
    colliders: &ColliderSet,
) -> (Vec<ReadCollider>, Vec<SkippedCollider>) {
    let mut read = Vec::new();
    let mut skipped = Vec::new();
    // A compound is read once, at its first collider in the set's order;
    // its other colliders repeat that outcome (`None`: read).
    let mut compounds: HashMap<RigidBodyHandle, Option<SkipReason>> = HashMap::new();
    for (handle, collider) in colliders.iter() {
        let result = match compound_parent(collider, bodies, colliders) {
            Some(body) => match compounds.get(&body) {
                Some(None) => continue,
                Some(Some(reason)) => Err(reason.clone()),
                None => {
                    let result = read_compound(body, bodies, colliders);
                    compounds.insert(body, result.as_ref().err().cloned());
                    result
                }
            },
            None => read_collider(handle, collider, bodies),
        };
        match result {
            Ok(r) => read.push(r),
            Err(reason) => skipped.push(SkippedCollider {
                collider: handle,
                reason,
            }),
        }
    }
    (read, skipped)
}

/// `U = B P` for a collider with a parent, `Collider::position()` without;
/// `None` if the handles no longer exist.
fn collider_world_pose(
    entry: &MappedCollider,
    bodies: &RigidBodySet,
    colliders: &ColliderSet,
) -> Option<Isometry3<f64>> {
    match entry.body {
        Some(body) => Some(pose_to_f64(bodies.get(body)?.position()) * entry.collider_in_body),
        None => Some(pose_to_f64(colliders.get(entry.collider)?.position())),
    }
}

/// The user pose `U'` as Rapier will hold it once written: the body pose
/// `U' P^-1` rounded to f32, read back as the bridge reads it.
fn as_written(entry: &MappedCollider, user_pose: &Isometry3<f64>) -> Isometry3<f64> {
    pose_to_f64(&pose_from_f64(&body_pose_of(entry, user_pose))) * entry.collider_in_body
}

/// `B' = U' P^-1`: the Rapier body pose that puts the collider at `U'`.
fn body_pose_of(entry: &MappedCollider, user_pose: &Isometry3<f64>) -> Isometry3<f64> {
    user_pose * entry.collider_in_body.inverse()
}

fn user_pose_of(body: &crate::body::Body) -> UserPose {
    (*body.translation_user(), body.rotation_user_xyzw())
}

fn record_round_off(
    round_off: &mut WriteBackRoundOff,
    exact: &Isometry3<f64>,
    written: &Isometry3<f64>,
) {
    let translation = (written.translation.vector - exact.translation.vector).norm();
    let rotation = exact.rotation.angle_to(&written.rotation);
    round_off.translation = round_off.translation.max(translation);
    round_off.rotation = round_off.rotation.max(rotation);
}

/// A Rapier body's velocity in f64: of its centre of mass, and angular.
fn velocity_of(body: &RigidBody) -> BodyVelocity {
    let (v, w) = (body.linvel(), body.angvel());
    BodyVelocity {
        linear: Vector3::new(v.x.into(), v.y.into(), v.z.into()),
        angular: Vector3::new(w.x.into(), w.y.into(), w.z.into()),
    }
}
