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

use crate::stabilizer::{Settings, VelocityFriction};

/// How a bridge call couples with the engine.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum CouplingMode {
    /// Remove every penetration beyond the tolerance, correct positions
    /// only (velocities untouched): the seed's behaviour. The stabilizer's
    /// own `allowed_penetration` applies as set.
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
    /// step. The default, chosen by measurement
    /// (`examples/with_and_without.rs`, README): with the colliders'
    /// friction it is the only mode under which the stacks of four light
    /// boxes under a box 100 and 1,000 times heavier stand for 300 steps.
    #[default]
    VelocityConsistency,
    /// Velocity consistency with Rapier's allowed linear error respected:
    /// positions as [`CouplingMode::RespectAllowedPenetration`] (a contact
    /// sunk by less than the allowed error is not touched, a deeper one is
    /// brought back to about that depth), then the approach velocities of
    /// the islands the call moved removed as in
    /// [`CouplingMode::VelocityConsistency`]. Contacts stay closed at
    /// Rapier's own depth instead of being opened to a gap every step.
    VelocityAllowedPenetration,
}

impl CouplingMode {
    /// Whether the mode leaves Rapier its allowed linear error.
    pub fn respects_allowed_penetration(self) -> bool {
        matches!(
            self,
            CouplingMode::RespectAllowedPenetration | CouplingMode::VelocityAllowedPenetration
        )
    }

    /// Whether the mode projects the velocities after the positions.
    pub fn projects_velocities(self) -> bool {
        matches!(
            self,
            CouplingMode::VelocityConsistency | CouplingMode::VelocityAllowedPenetration
        )
    }
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
    /// ([`crate::projector::friction`]). Default true (with
    /// [`CouplingMode::VelocityConsistency`], measured); false gives the
    /// seed's frictionless projection.
    pub collider_friction: bool,
    /// Friction of the velocity projection of
    /// [`CouplingMode::VelocityConsistency`]
    /// ([`crate::stabilizer::VelocityFriction`], with the colliders'
    /// coefficients when [`BridgeSettings::collider_friction`], else the
    /// stabilizer's `friction`). Default [`VelocityFriction::None`], by
    /// measurement (`examples/with_and_without.rs`, README): with the cone
    /// on the velocity ([`VelocityFriction::OnVelocity`]) the light boxes
    /// of the heavy stacks leave each call without sideways velocity, yet
    /// the stacks drift as much (41.8 and 44.4 mm on the 1:100 and 1:1000
    /// stacks against 28.6 and 46.4: Rapier's next step gives the
    /// velocity back), worse on the 1:100 stack, while the pile (51 mm of
    /// creep against 94), the thrown box and the pyramid are somewhat
    /// better; calls cost a little more. With friction on the change the
    /// 1:1000 stack falls.
    pub velocity_friction: VelocityFriction,
    /// Experimental: velocities of moved bodies from their displacement
    /// since the last call.
    pub displacement_velocity: bool,
    /// Experimental: write back the corrected centre of mass with the
    /// engine's rotation.
    pub keep_engine_rotation: bool,
}

impl Default for BridgeSettings {
    fn default() -> Self {
        BridgeSettings::with_stabilizer(Settings::default())
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
            displacement_velocity: false,
            keep_engine_rotation: false,
        }
    }

    /// The allowed penetration of a call, given the engine's allowed
    /// linear error (world length).
    pub(crate) fn allowed_penetration(&self, engine_allowed: f64) -> f64 {
        let own = self.stabilizer.allowed_penetration;
        if self.coupling.respects_allowed_penetration() {
            own.max(engine_allowed)
        } else {
            own
        }
    }
}
