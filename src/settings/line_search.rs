//! Settings of the backtracking line search ([`crate::projector`]'s
//! `line_search`): accept the first `alpha = 1, beta, beta^2, ...` whose
//! true merit falls by `sigma alpha` of the merit before it and that pushes
//! no clear constraint in by more than `rho d`.

use super::SettingsError;
use super::error::check;

/// Settings of the backtracking line search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineSearchSettings {
    /// Factor `beta` by which a rejected step is shrunk. Default 0.5.
    pub shrink: f64,
    /// Smallest step `alpha_min` tried. Default 2^-10 (11 trials at most).
    pub min_step: f64,
    /// Fraction `sigma` of the linear decrease that must be achieved.
    /// Default 1e-4 (the customary Armijo constant).
    pub sufficient_decrease: f64,
    /// A constraint that was clear may end a step penetrating by at most
    /// `max(tolerance, new_penetration_fraction * d)`, with `d` the deepest
    /// penetration before the step. The linearization holds a clear contact
    /// at its place only to first order: a rotation by `theta` moves it by
    /// about `theta^2 r / 2`, which a strict tolerance would turn into a
    /// stall. Default 0.1: a neighbour is never pushed in by more than a
    /// tenth of the depth being removed. With an allowed penetration the
    /// test is measured from it (`crate::projector`'s line search).
    pub new_penetration_fraction: f64,
}

impl Default for LineSearchSettings {
    fn default() -> Self {
        LineSearchSettings {
            shrink: 0.5,
            min_step: 1.0 / 1024.0,
            sufficient_decrease: 1e-4,
            new_penetration_fraction: 0.1,
        }
    }
}

impl LineSearchSettings {
    /// Checks every factor's range (NaN is outside each).
    pub(crate) fn validate(&self) -> Result<(), SettingsError> {
        check(
            "line_search.shrink",
            self.shrink,
            self.shrink > 0.0 && self.shrink < 1.0,
            "in (0, 1)",
        )?;
        check(
            "line_search.min_step",
            self.min_step,
            self.min_step > 0.0 && self.min_step <= 1.0,
            "in (0, 1]",
        )?;
        check(
            "line_search.sufficient_decrease",
            self.sufficient_decrease,
            (0.0..1.0).contains(&self.sufficient_decrease),
            "in [0, 1)",
        )?;
        check(
            "line_search.new_penetration_fraction",
            self.new_penetration_fraction,
            (0.0..1.0).contains(&self.new_penetration_fraction),
            "in [0, 1)",
        )
    }
}
