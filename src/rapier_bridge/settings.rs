//! [`BridgeSettings`]: the stabilizer's settings and how a call couples
//! with the engine ([`CouplingMode`]).
//!
//! Rapier resolves contacts softly: its solver leaves resting contacts
//! penetrating by up to its *allowed linear error*
//! (`IntegrationParameters::allowed_linear_error()`,
//! `normalized_allowed_linear_error * length_unit`, 5 mm by default) and
//! pushes deeper ones out over several steps. Removing every penetration
//! after each step (positions only) fights that: the next step sinks the
//! contact again. [`CouplingMode::RespectAllowedPenetration`] removes only
//! the penetration beyond the engine's allowed error
//! ([`crate::Settings::allowed_penetration`]), so the engine's soft
//! contacts keep their slop.

use crate::settings::{FrictionRows, ResolvedLengths, Settings};
use crate::stabilizer::VelocityFriction;

/// How a bridge call couples with the engine.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum CouplingMode {
    /// Remove every penetration beyond the tolerance, correct positions
    /// only (velocities untouched). The stabilizer's own
    /// `allowed_penetration` applies as set.
    PositionsOnly,
    /// Accept penetrations up to Rapier's allowed linear error (read from
    /// the `IntegrationParameters` of each call, in world length): the
    /// stabilizer's `allowed_penetration` is set to it (or kept if larger),
    /// so a contact sunk by less is not touched and a deeper one is brought
    /// back to about that depth, not to zero. Positions only.
    RespectAllowedPenetration,
    /// Positions as [`CouplingMode::PositionsOnly`], then velocity
    /// consistency: the approach velocities at the contacts of the islands
    /// the call moved are removed by the mass-weighted projection at the
    /// velocity level ([`crate::Stabilizer::project_velocities`], with the
    /// step's time step for speculative contacts, friction as
    /// [`BridgeSettings::velocity_friction`], none by default), and the
    /// new velocities are written back. Without it a heavy body lifted out
    /// of the bodies it crushed keeps its velocity and sinks again at every
    /// step. With the colliders' friction, it and
    /// [`CouplingMode::ClosedContacts`] are the modes under which stacks
    /// of four light boxes under a box 100 and 1,000 times heavier stand;
    /// `ClosedContacts` drifts less (`benchmarks/results/coupling.md`).
    VelocityConsistency,
    /// Velocity consistency with the corrected contacts left *closed*: as
    /// [`CouplingMode::VelocityConsistency`], but the call's rows aim at a
    /// depth of one tolerance instead of a gap of the target margin (the
    /// call's allowed penetration is raised to its target margin plus its
    /// tolerance, [`closed_contact_allowance`]), so every contact the call
    /// corrects starts Rapier's next step touching, not separated.
    ///
    /// Why: Rapier (0.36, `contact_with_twist_friction.rs`, `update`)
    /// solves a contact point that is separated (`dist > 0`) rigidly and a
    /// penetrating one softly (`cfm_factor` only where `dist <= 0`). A
    /// contact opened to `+target_margin` sits on that switch, and the
    /// corners of a box cross it at different substeps of the next step:
    /// the box is pushed out unevenly, tilts, and its face slides on its
    /// support; with the contacts closed the slide is about ten times
    /// smaller (probed with `examples/probes/slide_probe.rs`:
    /// `benchmarks/results/coupling.md`, "What drives the stacks' drift").
    ///
    /// The default, chosen by measurement (`examples/with_and_without.rs`:
    /// `benchmarks/results/coupling.md`): the heavy stacks stand and drift
    /// a quarter to a sixth of what they drift under
    /// [`CouplingMode::VelocityConsistency`], every call converging. Its
    /// cost: the contacts it corrects are left sunk by about one tolerance,
    /// within the tolerance each call states.
    ///
    /// Its *resting calls* ([`BridgeSettings::resting_calls`],
    /// `rapier_bridge/rest.rs`): when every awake body moved in Rapier's
    /// last three steps by less than Rapier's sleep test allows, the call accepts
    /// Rapier's allowed linear error instead, so a scene Rapier holds at
    /// rest is not written and falls asleep.
    #[default]
    ClosedContacts,
}

impl CouplingMode {
    /// Whether the mode projects the velocities after the positions.
    pub fn projects_velocities(self) -> bool {
        matches!(
            self,
            CouplingMode::VelocityConsistency | CouplingMode::ClosedContacts
        )
    }
}

/// The allowed penetration that makes a call of
/// [`CouplingMode::ClosedContacts`] aim at a depth of one tolerance: its
/// rows aim at the gap `target_margin - allowed` (see
/// [`crate::Settings::allowed_penetration`]), so `allowed = target_margin +
/// tolerance` aims at the depth `tolerance`, half of what the call then
/// accepts (`allowed + tolerance`). `lengths` are the call's before any
/// allowed penetration ([`super::round_off`]); f32 rounding of the written
/// poses moves a contact by at most an eighth of the tolerance, so a
/// corrected contact stays closed.
pub fn closed_contact_allowance(lengths: &ResolvedLengths) -> f64 {
    lengths.target_margin + lengths.tolerance
}

/// Settings of [`super::RapierBridge`].
#[derive(Debug, Clone, PartialEq)]
pub struct BridgeSettings {
    /// The stabilizer's settings. Each call derives its own from them: the
    /// tolerance and target margin are raised to cover the f32 rounding of
    /// the written poses ([`super::round_off`]) and the allowed
    /// penetration follows [`BridgeSettings::coupling`].
    pub stabilizer: Settings,
    /// How a call couples with the engine.
    pub coupling: CouplingMode,
    /// Give each scene body its collider's friction coefficient
    /// (`Collider::friction()`, Rapier's default 0.5; a pair's coefficient
    /// is the mean of its two bodies', as Rapier's default combine rule), so
    /// that the position projection is friction-aware
    /// ([`crate::projector::friction`]). Default true, chosen by
    /// measurement with the velocity modes
    /// (`benchmarks/results/coupling.md`); false leaves the bodies without
    /// a coefficient of their own, so the stabilizer's
    /// [`friction`](crate::Settings::friction) applies (default 0:
    /// frictionless).
    pub collider_friction: bool,
    /// Friction of the velocity projection of
    /// [`CouplingMode::VelocityConsistency`] and
    /// [`CouplingMode::ClosedContacts`]
    /// ([`crate::stabilizer::VelocityFriction`], with the colliders'
    /// coefficients when [`BridgeSettings::collider_friction`], else the
    /// stabilizer's `friction`). Default [`VelocityFriction::None`], chosen
    /// by measurement (`benchmarks/results/coupling.md`): with the cone on
    /// the velocity ([`VelocityFriction::OnVelocity`]) the light boxes of
    /// the heavy stacks leave each call without sideways velocity, yet the
    /// stacks drift as much (Rapier's next step gives the velocity back)
    /// and calls cost more; with friction on the change the 1:1000 stack
    /// falls.
    pub velocity_friction: VelocityFriction,
    /// Resting calls (`rapier_bridge/rest.rs`): when every awake body
    /// passed Rapier's own sleep test in Rapier's last three steps, a call
    /// of [`CouplingMode::ClosedContacts`] accepts Rapier's allowed linear
    /// error, so that a scene Rapier holds at rest is not written and
    /// falls asleep. Default true.
    pub resting_calls: bool,
    /// Held cycles (`rapier_bridge/rest.rs`): in a call of
    /// [`CouplingMode::ClosedContacts`] that is not a resting one, a body
    /// the call moved whose net motion over Rapier's step and the call,
    /// from where the last call that was not a resting one left it, passes
    /// Rapier's sleep test is put back there (all of them or none, and the
    /// call solved again from those poses; kept if the depth, rounded to
    /// f32, stays within the stated tolerance), so that a stack Rapier
    /// sinks and the call lifts is a fixed point of the (step, call) cycle
    /// instead of a ratchet: the 1:100 and 1:1000 stacks of
    /// `examples/with_and_without.rs` drift 0.43 and 0.32 mm in 300 steps
    /// instead of 11.3 and 7.4 (`benchmarks/results/coupling.md`). Default
    /// true.
    pub hold_cycles: bool,
    /// Struck bodies (`rapier_bridge/bridge.rs`): in a call, a dynamic
    /// body that Rapier's step moved, at its speed, by more than
    /// [`FAST_BODY_REACH_FRACTION`] times its reach (a body that may have
    /// passed into another within one step) is *fast*. The struck group is
    /// every dynamic body a fast one reaches through overlapping bounding
    /// boxes of dynamic bodies; if every body of it other than the fast
    /// ones was at rest when the last call ended (asleep, or its pose as
    /// the last call left it within Rapier's sleep test of the one before:
    /// `rapier_bridge/sleep.rs`), it is held still for the call's first
    /// solve, so the correction of a deep, fast penetration moves the fast
    /// body only, not the stack it struck (the minimal mass-weighted
    /// correction of a box tunnelled into another pushes both apart
    /// sideways); then it is released and the call solved again from that
    /// answer, so the contacts inside the group are corrected too. A group
    /// still moving (a pile settling, whose falling bodies strike each
    /// other) is not held. Default true, chosen by measurement
    /// (`benchmarks/results/coupling.md`, "The thrown box"): the thrown
    /// box's stack of `examples/with_and_without.rs` drifts 0.32 mm
    /// instead of 59.42 (Rapier alone 17.91), the other scenes as without.
    pub hold_struck_bodies: bool,
    /// Held groups put to sleep (`rapier_bridge/sleep.rs`): a group of
    /// awake bodies (overlapping bounding boxes) whose poses, as the calls
    /// leave them, have passed Rapier's sleep test for Rapier's
    /// `time_until_sleep` gets its velocities zeroed, and at the next call,
    /// if Rapier's step moved it by less than that test allows, is held
    /// still (not written) and put to sleep with `RigidBody::sleep`. A held
    /// cycle writes its bodies at every call, and Rapier wakes a written
    /// body and its neighbours at its next step, so without this a scene
    /// the calls hold still never sleeps. Default true.
    pub sleep_held_groups: bool,
    /// Held velocities zeroed (`rapier_bridge/rest.rs`, "Held cycles"): a
    /// body a held cycle puts back at its anchor also gets its velocity
    /// zeroed (written without waking), so the cycle is a fixed point in
    /// velocity too. Without it the pose is reset at every call while
    /// Rapier's velocity keeps what each step adds: on the pile of 200 a
    /// tumbling box held at steps 140 and 144 reached 3.1 rad/s under its
    /// held pose and slid 6 mm once released (`examples/probes/settle_probe.rs`).
    /// Default false: measured on the pile of 200 it settles more often
    /// within issue 22's limits (5 of 11 runs with perturbed drop heights
    /// or solver tolerances, against 1 of 11) but with heavier tails (up to
    /// 67 mm of drift, against 54), so not a clear improvement
    /// (`benchmarks/results/coupling.md`, "The pile of 200's settle").
    pub zero_held_velocities: bool,
}

/// A body whose speed times the step's time step exceeds this fraction of
/// its reach (largest distance of a vertex from its centre of mass) is a
/// fast body for [`BridgeSettings::hold_struck_bodies`].
pub const FAST_BODY_REACH_FRACTION: f64 = 2.0;

/// The stabilizer's target margin under [`BridgeSettings::default`],
/// relative to `L`: one tolerance, the gap with which the bridge's coupling
/// modes and its rest were measured (`benchmarks/results/coupling.md`),
/// rather than the stabilizer's own default
/// ([`crate::settings::DEFAULT_TARGET_MARGIN_RELATIVE`]). Under
/// [`CouplingMode::ClosedContacts`] the accepted depth is the target margin
/// plus two tolerances ([`closed_contact_allowance`]), so a larger margin
/// would leave contacts sunk deeper between steps.
pub const BRIDGE_TARGET_MARGIN_RELATIVE: f64 = 1e-6;

impl Default for BridgeSettings {
    /// The default coupling, and the stabilizer's default settings but
    /// for the dual active-set method, which is off
    /// (`SolverSettings::auto_dual_active_set_max_dofs = 0`): the interior
    /// point and Lemke answer the bridge's islands as before it. Over 64
    /// perturbed drops of the Rapier pile of 200 (`probes settle`), 15
    /// settled within issue 22's limits (asleep by step 176, drift at most
    /// 1 mm) with it off and 6 with it on (`benchmarks/results/
    /// call_cost.md`, eighteenth session); its answers are the same
    /// minimizer within the tolerance, but the settle follows them. The
    /// target margin stays at [`BRIDGE_TARGET_MARGIN_RELATIVE`], and the
    /// friction rows at [`FrictionRows::All`] (every contact row with its
    /// pyramid's facets, where the stabilizer's default leaves the implied
    /// row out), for the same reason: over the same kind of 64 drops, 15
    /// settled within the limits with them and 11 without
    /// (`benchmarks/results/engine_friction.md`).
    fn default() -> Self {
        let mut stabilizer = Settings {
            target_margin_relative: BRIDGE_TARGET_MARGIN_RELATIVE,
            ..Settings::default()
        };
        stabilizer.solver.auto_dual_active_set_max_dofs = 0;
        stabilizer.solver.auto_dual_active_set_violated_max_dofs = 0;
        stabilizer.friction_rows = FrictionRows::All;
        BridgeSettings::with_stabilizer(stabilizer)
    }
}

impl BridgeSettings {
    /// The bridge settings with these stabilizer settings and the default
    /// coupling.
    pub fn with_stabilizer(stabilizer: Settings) -> Self {
        BridgeSettings {
            stabilizer,
            coupling: CouplingMode::default(),
            collider_friction: true,
            velocity_friction: VelocityFriction::None,
            resting_calls: true,
            hold_cycles: true,
            hold_struck_bodies: true,
            sleep_held_groups: true,
            zero_held_velocities: false,
        }
    }

    /// The allowed penetration of a call, given the engine's allowed
    /// linear error (world length).
    pub(crate) fn allowed_penetration(&self, engine_allowed: f64) -> f64 {
        let own = self.stabilizer.allowed_penetration;
        match self.coupling {
            CouplingMode::RespectAllowedPenetration => own.max(engine_allowed),
            _ => own,
        }
    }
}
