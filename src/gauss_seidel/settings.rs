//! Settings of the nonlinear Gauss–Seidel position correction, with Box2D
//! v2.4's defaults (`b2_baumgarte`, `b2_linearSlop`,
//! `b2_maxLinearCorrection` in `b2_settings.h`, three position iterations in
//! the testbed's `b2World::Step`).
//!
//! Box2D's lengths are in metres for bodies of about a metre; here they are
//! relative to the scene's length scale `L` (the circumradius of the
//! smallest dynamic body, [`crate::stabilizer::scene_scale`]), so one Box2D
//! metre is one `L`, and a scene scaled by `s` is corrected the same way up
//! to the scale.

use thiserror::Error;

/// Box2D's `b2_baumgarte`: the fraction of a contact's error removed per
/// visit.
pub const DEFAULT_BAUMGARTE: f64 = 0.2;

/// Box2D's `b2_linearSlop` (0.005 m), relative to `L`: depth left alone.
pub const DEFAULT_SLOP_RELATIVE: f64 = 0.005;

/// Box2D's `b2_maxLinearCorrection` (0.2 m), relative to `L`: the largest
/// correction of one contact point in one visit.
pub const DEFAULT_MAX_CORRECTION_RELATIVE: f64 = 0.2;

/// Box2D's position iterations per step in its testbed (`b2World::Step(dt,
/// 8, 3)`).
pub const DEFAULT_ITERATIONS: usize = 3;

/// Settings of [`crate::stabilizer::Method::GaussSeidel`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaussSeidelSettings {
    /// Largest number of sweeps (one sweep: detect, then visit every contact
    /// point once). At least 1. Default 3 (Box2D's position iterations).
    pub iterations: usize,
    /// Fraction `beta` of a contact's error `s + slop` removed per visit, in
    /// `(0, 1]`. Default 0.2 (`b2_baumgarte`).
    pub baumgarte: f64,
    /// Depth left alone (length relative to `L`, finite, >= 0): a contact is
    /// pushed only while its separation is below `-slop`. Default 0.005
    /// (`b2_linearSlop`). With a slop above the tolerance a call can never
    /// report a resolved scene.
    pub slop_relative: f64,
    /// Largest correction `|C|` of one contact point per visit (length
    /// relative to `L`, positive; `f64::INFINITY` for no cap). Default 0.2
    /// (`b2_maxLinearCorrection`).
    pub max_correction_relative: f64,
    /// Detect the contacts again before every sweep (true, the default:
    /// new contacts are found and stale ones dropped as bodies move), or
    /// once per call (false: Box2D exactly, whose position iterations
    /// re-measure the points found by the step's collision detection; a
    /// sweep then costs a visit of the stored points, and the call measures
    /// the result once at the end).
    pub detect_every_sweep: bool,
}

impl Default for GaussSeidelSettings {
    fn default() -> Self {
        GaussSeidelSettings {
            iterations: DEFAULT_ITERATIONS,
            baumgarte: DEFAULT_BAUMGARTE,
            slop_relative: DEFAULT_SLOP_RELATIVE,
            max_correction_relative: DEFAULT_MAX_CORRECTION_RELATIVE,
            detect_every_sweep: true,
        }
    }
}

/// An invalid [`GaussSeidelSettings`] field.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GaussSeidelSettingsError {
    /// `iterations` is 0.
    #[error("setting `gauss_seidel.iterations` is 0: at least one sweep is needed")]
    ZeroIterations,
    /// `baumgarte` is outside `(0, 1]` or NaN.
    #[error("setting `gauss_seidel.baumgarte` is {0}: it must be in (0, 1]")]
    Baumgarte(f64),
    /// `slop_relative` is negative or not finite.
    #[error("setting `gauss_seidel.slop_relative` is {0}: it must be finite and non-negative")]
    Slop(f64),
    /// `max_correction_relative` is zero, negative or NaN.
    #[error(
        "setting `gauss_seidel.max_correction_relative` is {0}: it must be positive (infinite for no cap)"
    )]
    MaxCorrection(f64),
}

/// The absolute lengths of one call.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaussSeidelLengths {
    /// Depth left alone.
    pub slop: f64,
    /// Largest correction of one point per visit.
    pub max_correction: f64,
}

impl GaussSeidelSettings {
    /// Checks every field (NaN fails every check).
    pub fn validate(&self) -> Result<(), GaussSeidelSettingsError> {
        if self.iterations == 0 {
            return Err(GaussSeidelSettingsError::ZeroIterations);
        }
        if !(self.baumgarte > 0.0 && self.baumgarte <= 1.0) {
            return Err(GaussSeidelSettingsError::Baumgarte(self.baumgarte));
        }
        if !(self.slop_relative.is_finite() && self.slop_relative >= 0.0) {
            return Err(GaussSeidelSettingsError::Slop(self.slop_relative));
        }
        // `> 0` is false for NaN: NaN is rejected.
        let positive = self.max_correction_relative > 0.0;
        if !positive {
            return Err(GaussSeidelSettingsError::MaxCorrection(
                self.max_correction_relative,
            ));
        }
        Ok(())
    }

    /// The lengths for a scene of length scale `scale`.
    pub fn resolve(&self, scale: f64) -> GaussSeidelLengths {
        GaussSeidelLengths {
            slop: self.slop_relative * scale,
            max_correction: self.max_correction_relative * scale,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_box2d_and_valid() {
        let settings = GaussSeidelSettings::default();
        assert_eq!(settings.iterations, 3);
        assert_eq!(settings.baumgarte, 0.2);
        assert_eq!(settings.slop_relative, 0.005);
        assert_eq!(settings.max_correction_relative, 0.2);
        assert_eq!(settings.validate(), Ok(()));
    }

    #[test]
    fn each_invalid_field_has_its_error() {
        let with = |change: fn(&mut GaussSeidelSettings)| {
            let mut settings = GaussSeidelSettings::default();
            change(&mut settings);
            settings.validate()
        };
        use GaussSeidelSettingsError as E;
        assert_eq!(with(|s| s.iterations = 0), Err(E::ZeroIterations));
        assert_eq!(with(|s| s.baumgarte = 0.0), Err(E::Baumgarte(0.0)));
        assert_eq!(with(|s| s.baumgarte = 1.5), Err(E::Baumgarte(1.5)));
        assert!(matches!(
            with(|s| s.baumgarte = f64::NAN),
            Err(E::Baumgarte(_))
        ));
        assert_eq!(with(|s| s.slop_relative = -1e-3), Err(E::Slop(-1e-3)));
        assert!(matches!(
            with(|s| s.slop_relative = f64::INFINITY),
            Err(E::Slop(_))
        ));
        assert_eq!(
            with(|s| s.max_correction_relative = 0.0),
            Err(E::MaxCorrection(0.0))
        );
        assert!(matches!(
            with(|s| s.max_correction_relative = f64::NAN),
            Err(E::MaxCorrection(_))
        ));
        assert_eq!(with(|s| s.max_correction_relative = f64::INFINITY), Ok(()));
        assert_eq!(with(|s| s.baumgarte = 1.0), Ok(()));
    }

    #[test]
    fn lengths_scale_with_the_scene() {
        let lengths = GaussSeidelSettings::default().resolve(2.0);
        assert_eq!(lengths.slop, 0.01);
        assert_eq!(lengths.max_correction, 0.4);
    }
}
