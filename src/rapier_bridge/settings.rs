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

use crate::stabilizer::Settings;

/// How a bridge call couples with the engine.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum CouplingMode {
    /// Remove every penetration beyond the tolerance, correct positions
    /// only (velocities untouched). The stabilizer's own
    /// `allowed_penetration` applies as set. Default: the seed's
    /// behaviour (the default is not yet chosen by measurement against the
    /// other modes).
    #[default]
    PositionsOnly,
    /// Accept penetrations up to Rapier's allowed linear error (read from
    /// the `IntegrationParameters` of each call, in world length): the
    /// stabilizer's `allowed_penetration` is set to it (or kept if larger),
    /// so a contact sunk by less is not touched and a deeper one is brought
    /// back to about that depth, not to zero. Positions only.
    RespectAllowedPenetration,
}

/// Settings of [`super::RapierBridge`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BridgeSettings {
    /// The stabilizer's settings. Each call derives its own from them: the
    /// tolerance and target margin are raised to cover the f32 rounding of
    /// the written poses ([`super::round_off`]) and the allowed
    /// penetration follows [`BridgeSettings::coupling`].
    pub stabilizer: Settings,
    /// How a call couples with the engine.
    pub coupling: CouplingMode,
}

impl BridgeSettings {
    /// The bridge settings with these stabilizer settings and the default
    /// coupling.
    pub fn with_stabilizer(stabilizer: Settings) -> Self {
        BridgeSettings {
            stabilizer,
            coupling: CouplingMode::default(),
        }
    }

    /// The allowed penetration of a call, given the engine's allowed
    /// linear error (world length).
    pub(crate) fn allowed_penetration(&self, engine_allowed: f64) -> f64 {
        let own = self.stabilizer.allowed_penetration;
        match self.coupling {
            CouplingMode::PositionsOnly => own,
            CouplingMode::RespectAllowedPenetration => own.max(engine_allowed),
        }
    }
}
