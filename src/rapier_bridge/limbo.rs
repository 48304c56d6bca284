//! Bodies put to sleep that Rapier still integrates: the limbo between
//! `RigidBody::sleep` and Rapier's island manager committing the sleep.
//!
//! # Why
//!
//! `super::sleep` puts a held group to sleep with `RigidBody::sleep`
//! (rapier3d 0.36.1): the body is flagged asleep and its velocity zeroed,
//! but it stays in Rapier's awake island until the island manager commits
//! the sleep at the end of a later step (`IslandManager::update_islands`;
//! an island that lost constraints is split first). Meanwhile the narrow
//! phase qualifies a contact pair for the solver only if one side is an
//! awake dynamic body (`pair_update.rs`: `!rb.activation.sleeping`), so a
//! pair of two flagged bodies, or of a flagged body and the ground, is not
//! solved, while the bodies are still integrated: they fall freely through
//! each other and the ground. With Rapier's four substeps that is 1.7 mm in
//! the first step and 4.4 mm in the second (`examples/probes/settle_probe.rs`:
//! every body of the pile of 200 after the bridge put it to sleep); on the
//! pile of 200 dropped 5e-6 m higher the commit came only after eight
//! steps, the pile had sunk 9 cm into itself and the ground, and it woke
//! up in an avalanche (213 mm of drift).
//!
//! # The rule
//!
//! The bridge remembers the pose at which it put each body to sleep. A
//! call that finds a body flagged asleep with a velocity that is not zero
//! (Rapier's commit zeroes it, so the body is still being integrated):
//! - if the body's farthest point is within Rapier's allowed linear error
//!   of that pose, zeroes its velocity again (no wake: a velocity write
//!   flags no change), so the next step moves it by one step of gravity
//!   from rest, not by an accumulated fall;
//! - else wakes it (`RigidBody::wake_up`, strong): Rapier solves its
//!   contacts again and the call corrects it as an awake body.
//!
//! A body found committed (asleep, at rest) or awake leaves the limbo.

use std::collections::{HashMap, HashSet};

use nalgebra::Isometry3;
use rapier3d::dynamics::RigidBody;
use rapier3d::geometry::ColliderHandle;
use rapier3d::math::Vector;

use super::body_map::BodyMap;
use super::rest::farthest_point_motion;

/// What a call does with a body flagged asleep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Limbo {
    /// Asleep and committed (or put to sleep by Rapier itself): held still.
    Asleep,
    /// Flagged asleep, still integrated, within the allowed error: its
    /// velocity zeroed again, held still.
    Stopped,
    /// Flagged asleep, still integrated, beyond the allowed error: woken.
    Woken,
}

/// The poses at which the bridge put bodies to sleep (module docs).
#[derive(Debug, Clone, Default)]
pub(crate) struct SleepPoses(HashMap<ColliderHandle, Isometry3<f64>>);

impl SleepPoses {
    /// Remembers that the body was put to sleep at `pose` (its user pose).
    pub(crate) fn record(&mut self, collider: ColliderHandle, pose: Isometry3<f64>) {
        self.0.insert(collider, pose);
    }

    /// Forgets a body that is awake.
    pub(crate) fn forget(&mut self, collider: ColliderHandle) {
        self.0.remove(&collider);
    }

    /// Keeps only the bodies of `mapped` (colliders still read).
    pub(crate) fn retain_mapped(&mut self, mapped: &BodyMap) {
        if self.0.is_empty() {
            return;
        }
        let read: HashSet<ColliderHandle> = mapped.entries().iter().map(|e| e.collider).collect();
        self.0.retain(|collider, _| read.contains(collider));
    }

    /// The limbo rule (module docs) for a Rapier body flagged asleep whose
    /// scene body `body` holds its current user pose; `allowed` is
    /// Rapier's allowed linear error.
    pub(crate) fn check(
        &mut self,
        collider: ColliderHandle,
        body: &crate::body::Body,
        rigid_body: &mut RigidBody,
        allowed: f64,
    ) -> Limbo {
        let moving = rigid_body.linvel() != Vector::ZERO || rigid_body.angvel() != Vector::ZERO;
        let Some(at_sleep) = self.0.get(&collider) else {
            return Limbo::Asleep;
        };
        if !moving {
            self.0.remove(&collider);
            return Limbo::Asleep;
        }
        if farthest_point_motion(body, &body.user_pose(), at_sleep) <= allowed {
            rigid_body.set_linvel(Vector::ZERO, false);
            rigid_body.set_angvel(Vector::ZERO, false);
            return Limbo::Stopped;
        }
        self.0.remove(&collider);
        rigid_body.wake_up(true);
        Limbo::Woken
    }
}
