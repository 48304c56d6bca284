//! The lengths of one call, resolved once against the scene's length
//! scale `L` and passed down to every stage (detection, rows, projection,
//! the Gauss–Seidel baseline).
//!
//! A length `x_relative` resolves to `x_absolute` when that is set, else
//! to `x_relative * L`. An allowed penetration `a` is added to the
//! tolerance and taken from the target margin: depths up to `a +
//! tolerance` are accepted, and the rows aim at the gap `target_margin - a`.

use super::Settings;

/// The lengths of one call, in the scene's unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResolvedLengths {
    /// The scene's length scale `L`.
    pub scale: f64,
    /// Penetration tolerance (the allowed penetration included).
    pub tolerance: f64,
    /// Contact margin: separated pairs closer than this join the problem.
    pub contact_margin: f64,
    /// Target margin: the gap the linearized rows aim for (negative when
    /// an allowed penetration deeper than the plain margin is set).
    pub target_margin: f64,
    /// The allowed penetration, included in `tolerance` and subtracted
    /// from `target_margin`.
    pub allowed_penetration: f64,
    /// The Gauss–Seidel baseline's slop: depth it leaves alone.
    pub gauss_seidel_slop: f64,
    /// The Gauss–Seidel baseline's largest correction of one contact point
    /// per visit.
    pub gauss_seidel_max_correction: f64,
}

impl Settings {
    /// The lengths for a scene of length scale `scale`; the allowed
    /// penetration is added to the tolerance and taken from the target
    /// margin (both unchanged, bit for bit, when it is 0).
    pub fn resolve(&self, scale: f64) -> ResolvedLengths {
        let allowed = self.allowed_penetration;
        let tolerance = self
            .tolerance_absolute
            .unwrap_or(self.tolerance_relative * scale);
        let contact_margin = self
            .contact_margin_absolute
            .unwrap_or(self.contact_margin_relative * scale);
        let target_margin = self
            .target_margin_absolute
            .unwrap_or(self.target_margin_relative * scale);
        ResolvedLengths {
            scale,
            tolerance,
            contact_margin,
            target_margin,
            allowed_penetration: 0.0,
            gauss_seidel_slop: self.gauss_seidel.slop_relative * scale,
            gauss_seidel_max_correction: self.gauss_seidel.max_correction_relative * scale,
        }
        .allowing(allowed)
    }
}

impl ResolvedLengths {
    /// These lengths (with no allowed penetration yet) allowing the
    /// penetration `allowed`: added to the tolerance, taken from the target
    /// margin.
    pub fn allowing(self, allowed: f64) -> Self {
        ResolvedLengths {
            tolerance: self.tolerance + allowed,
            target_margin: self.target_margin - allowed,
            allowed_penetration: allowed,
            ..self
        }
    }
}
