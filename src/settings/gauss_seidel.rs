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

use super::SettingsError;
use super::error::{at_least, check, non_negative, positive_or_infinite};

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

/// Settings of [`super::Method::GaussSeidel`].
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

impl GaussSeidelSettings {
    /// Checks every field (NaN fails every check).
    pub fn validate(&self) -> Result<(), SettingsError> {
        at_least("gauss_seidel.iterations", self.iterations, 1)?;
        check(
            "gauss_seidel.baumgarte",
            self.baumgarte,
            self.baumgarte > 0.0 && self.baumgarte <= 1.0,
            "in (0, 1]",
        )?;
        non_negative("gauss_seidel.slop_relative", self.slop_relative)?;
        positive_or_infinite(
            "gauss_seidel.max_correction_relative",
            self.max_correction_relative,
        )
    }
}
