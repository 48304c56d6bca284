//! What a bridge call did: the stabilizer's report, the colliders skipped
//! and why, how the scene was kept, and the f32 rounding of the write-back.

use rapier3d::geometry::ColliderHandle;

use crate::stabilizer::Report;

/// Why a collider is not in the scene.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SkipReason {
    /// Its shape is none the bridge reads (`collider_shape`; the name of
    /// Rapier's `ShapeType`, e.g. `"TriMesh"`, `"RoundCylinder"`).
    Shape(String),
    /// A sensor: it does not collide.
    Sensor,
    /// The collider or its parent body is disabled (or the parent is gone).
    Disabled,
    /// The scene rejected it (a degenerate hull, a mass that is zero or not
    /// finite): the message says why. It is tried again next call.
    Invalid(String),
}

/// A collider that is not in the scene.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SkippedCollider {
    /// The collider.
    pub collider: ColliderHandle,
    /// Why it is skipped.
    pub reason: SkipReason,
}

/// How the world was read into the scene ([`super::RapierBridge::sync`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SyncReport {
    /// Colliders not read, in the collider set's order.
    pub skipped: Vec<SkippedCollider>,
    /// Scene bodies after the call.
    pub scene_bodies: usize,
    /// Bodies appended by this call (new colliders, and changed ones).
    pub appended: usize,
    /// Bodies removed by this call (colliders that vanished or changed);
    /// the others keep their shapes and warm starts.
    pub removed: usize,
}

/// Largest f32 rounding of the poses written back (0 when none was).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WriteBackRoundOff {
    /// Largest distance between a body-frame origin computed in f64 and as
    /// written in f32 (length).
    pub translation: f64,
    /// Largest rotation angle between a body rotation computed in f64 and as
    /// written in f32 (radians).
    pub rotation: f64,
}

/// The report of [`super::RapierBridge::stabilize`].
#[derive(Debug, Clone)]
pub struct BridgeReport {
    /// How the world was read.
    pub sync: SyncReport,
    /// How the joints were read.
    pub joints: super::joints::JointReadReport,
    /// The stabilizer's report; `None` when the scene has no dynamic body
    /// (nothing to do, the stabilizer is not called).
    pub stabilizer: Option<Report>,
    /// Rapier bodies whose pose was written back (awake bodies the call
    /// moved; none when nothing awake penetrates beyond the tolerance).
    pub bodies_written: usize,
    /// Dynamic bodies Rapier had put to sleep: held still as obstacles,
    /// neither solved nor written (unless released,
    /// [`BridgeReport::bodies_released`]), and left asleep.
    pub bodies_left_asleep: usize,
    /// Whether the call was a resting one (`rapier_bridge/rest.rs`): every
    /// awake body passed Rapier's sleep test in Rapier's last three steps,
    /// and Rapier's allowed linear error was accepted.
    pub resting: bool,
    /// Bodies a held cycle put back where the last call that was not a
    /// resting one left them ([`super::BridgeSettings::hold_cycles`],
    /// `rapier_bridge/rest.rs`); 0 when the call held nothing.
    pub bodies_held: usize,
    /// Bodies struck by a fast body and held still for the call's first
    /// solve ([`super::BridgeSettings::hold_struck_bodies`]); 0 when none.
    pub bodies_struck_held: usize,
    /// Bodies held still (asleep, or put to sleep) that the call released
    /// because an island next to them could not be solved with them held
    /// (`rapier_bridge/wedged.rs`); solved, and written if moved; 0 when
    /// none.
    pub bodies_released: usize,
    /// Awake bodies this call put to sleep (`rapier_bridge/sleep.rs`,
    /// [`super::BridgeSettings::sleep_held_groups`]): held still, not
    /// written, and `RigidBody::sleep` called; 0 when none.
    pub bodies_put_to_sleep: usize,
    /// Bodies the bridge had put to sleep that Rapier still integrated
    /// without their contacts and that had fallen beyond Rapier's allowed
    /// linear error: woken and corrected as awake bodies
    /// (`rapier_bridge/limbo.rs`); 0 when none.
    pub bodies_woken_falling: usize,
    /// Awake bodies whose velocities this call zeroed to put them to sleep
    /// at the next call (`rapier_bridge/sleep.rs`), and with
    /// [`super::BridgeSettings::zero_held_velocities`] the bodies a held
    /// cycle put back; 0 when none.
    pub velocities_zeroed: usize,
    /// f32 rounding of the written poses, as measured.
    pub write_back_round_off: WriteBackRoundOff,
    /// `delta`: the most any collider point of a dynamic body can move when
    /// its pose is rounded to f32 (a bound, see `rapier_bridge/round_off.rs`);
    /// the depth of a pair in the f32 world exceeds its depth in the
    /// stabilizer's f64 scene by at most `2 delta`. The call's tolerance is
    /// at least `8 delta`.
    pub round_off_bound: f64,
    /// The tolerance this call states for the world as written (f32
    /// poses); `None` when the stabilizer was not called. Outside
    /// [`super::CouplingMode::ClosedContacts`] the stabilizer solves to it
    /// lowered by `2 delta`; in closed contacts to it, and when the
    /// answer's depth is within `2 delta` of it, the answer is checked as
    /// written in f32 and solved again to it lowered by `2 delta` if the
    /// rounding took a pair beyond it (module docs of
    /// `rapier_bridge/round_off.rs`): a resolved call leaves the f32 world
    /// within it.
    pub stated_tolerance: Option<f64>,
    /// The velocity projection of [`super::CouplingMode::VelocityConsistency`]
    /// and [`super::CouplingMode::ClosedContacts`]
    /// (`None` in the other modes, or when nothing moved).
    pub velocities: Option<crate::stabilizer::VelocityReport>,
    /// Rapier bodies whose velocity was written back.
    pub velocities_written: usize,
}

impl BridgeReport {
    /// The colliders not in the scene.
    pub fn skipped(&self) -> &[SkippedCollider] {
        &self.sync.skipped
    }

    /// An upper bound on the deepest penetration of the world as written
    /// (f32 poses): the stabilizer's exact depth after the call plus the
    /// `2 delta` that rounding can add to a pair ([`BridgeReport::round_off_bound`]).
    /// `None` when the stabilizer was not called (no dynamic body).
    pub fn written_depth_bound(&self) -> Option<f64> {
        let report = self.stabilizer.as_ref()?;
        Some(report.depth_after + super::round_off::ROUNDING_DEPTH_FACTOR * self.round_off_bound)
    }
}
