//! [`RapierBridge`]: read the world into the kept scene, stabilize, write
//! the corrected poses back.
//!
//! One call, after `PhysicsPipeline::step`:
//! 1. read every collider ([`super::collider_shape`]): the ones the scene
//!    can hold, and the skipped ones with their reason;
//! 2. keep the scene ([`super::body_map`]): append new colliders, or
//!    rebuild when a mapped one vanished or changed; then set every scene
//!    body's user pose to its collider's world pose `U = B P`;
//! 3. stabilize with the kept [`Stabilizer`] (warm starts from the previous
//!    call); on error nothing is written;
//! 4. write back the dynamic bodies whose pose changed, `B' = U' P^-1`,
//!    rounded to f32, without touching velocities or waking bodies.

use nalgebra::{Isometry3, Vector3};
use rapier3d::dynamics::RigidBodySet;
use rapier3d::geometry::ColliderSet;

use super::body_map::{BodyMap, MappedCollider, Plan};
use super::collider_shape::{ReadCollider, read_collider, shape_of};
use super::convert::{pose_from_f64, pose_to_f64, xyzw};
use super::error::BridgeError;
use super::report::{BridgeReport, SkipReason, SkippedCollider, SyncReport, WriteBackRoundOff};
use crate::body::{BodyDesc, MassSpec};
use crate::scene::Scene;
use crate::stabilizer::{Settings, Stabilizer};

/// Stabilizes a Rapier world after each step; keeps the scene, the handle
/// map and the stabilizer (with its warm starts) from call to call.
#[derive(Debug, Clone)]
pub struct RapierBridge {
    stabilizer: Stabilizer,
    scene: Scene,
    map: BodyMap,
}

/// A user pose as stored: translation and `[x, y, z, w]`, compared bit for
/// bit to find the bodies the stabilizer moved.
type UserPose = (Vector3<f64>, [f64; 4]);

impl RapierBridge {
    /// A bridge with validated stabilizer settings and an empty scene.
    pub fn new(settings: Settings) -> Result<Self, BridgeError> {
        Ok(RapierBridge {
            stabilizer: Stabilizer::new(settings)?,
            scene: Scene::new(),
            map: BodyMap::default(),
        })
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

    /// The stabilizer (its settings).
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
        let new = match self.map.plan(&read) {
            Plan::Append(new) => new,
            Plan::Rebuild => {
                self.restart()?;
                report.rebuilt = true;
                (0..read.len()).collect()
            }
        };
        for i in new {
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

    /// Reads the world, removes interpenetration, writes the corrected
    /// poses of dynamic bodies back (velocities untouched). On error
    /// nothing is written.
    pub fn stabilize(
        &mut self,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
    ) -> Result<BridgeReport, BridgeError> {
        let sync = self.sync(bodies, colliders)?;
        let mut report = BridgeReport {
            sync,
            stabilizer: None,
            bodies_written: 0,
            write_back_round_off: WriteBackRoundOff::default(),
        };
        if self.scene.bodies().iter().all(|b| b.is_fixed()) {
            return Ok(report);
        }
        let before: Vec<UserPose> = self.scene.bodies().iter().map(user_pose_of).collect();
        report.stabilizer = Some(self.stabilizer.stabilize(&mut self.scene)?);
        let (written, round_off) = self.write_back(bodies, &before);
        report.bodies_written = written;
        report.write_back_round_off = round_off;
        Ok(report)
    }

    /// Drops the scene and the map, and restarts the stabilizer with the
    /// same settings (its warm starts refer to scene indices).
    fn restart(&mut self) -> Result<(), BridgeError> {
        self.stabilizer = Stabilizer::new(self.stabilizer.settings().clone())?;
        self.scene = Scene::new();
        self.map.clear();
        Ok(())
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
        let collider = colliders.get(read.collider).ok_or(SkipReason::Disabled)?;
        let shape = shape_of(collider).ok_or(SkipReason::Disabled)?;
        let entry = MappedCollider::of(read);
        let pose = collider_world_pose(&entry, bodies, colliders).ok_or(SkipReason::Disabled)?;
        let desc = BodyDesc {
            name: format!("collider {}", read.collider.into_raw_parts().0),
            shape,
            translation: pose.translation.vector,
            rotation_xyzw: xyzw(&pose.rotation),
            mass: read.dynamic_mass.map_or(MassSpec::Fixed, MassSpec::Mass),
        };
        self.scene
            .add_body(desc)
            .map_err(|e| SkipReason::Invalid(e.to_string()))?;
        self.map.push(read);
        Ok(())
    }

    /// Sets every scene body's user pose to its collider's world pose.
    fn update_poses(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
    ) -> Result<(), BridgeError> {
        for (index, entry) in self.map.entries().iter().enumerate() {
            let Some(pose) = collider_world_pose(entry, bodies, colliders) else {
                continue;
            };
            let moved = self.scene.body_mut(index).and_then(|body| {
                body.set_user_pose(pose.translation.vector, xyzw(&pose.rotation))
                    .map_err(|source| crate::scene::SceneError::Body {
                        index,
                        name: body.name().to_owned(),
                        source,
                    })
            });
            moved.map_err(|source| BridgeError::Body {
                collider: entry.collider,
                source,
            })?;
        }
        Ok(())
    }

    /// Writes `B' = U' P^-1` to every dynamic body the stabilizer moved.
    fn write_back(
        &self,
        bodies: &mut RigidBodySet,
        before: &[UserPose],
    ) -> (usize, WriteBackRoundOff) {
        let mut written = 0;
        let mut round_off = WriteBackRoundOff::default();
        for ((entry, body), old) in self
            .map
            .entries()
            .iter()
            .zip(self.scene.bodies())
            .zip(before)
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
            written += 1;
        }
        (written, round_off)
    }
}

/// Every collider, read or skipped, in the collider set's order.
fn read_world(
    bodies: &RigidBodySet,
    colliders: &ColliderSet,
) -> (Vec<ReadCollider>, Vec<SkippedCollider>) {
    let mut read = Vec::new();
    let mut skipped = Vec::new();
    for (handle, collider) in colliders.iter() {
        match read_collider(handle, collider, bodies, colliders) {
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
