//! A trust region per body per step: the linearized constraints hold only
//! near the configuration where they were taken, so a step moves no body
//! further than where the linearization is trusted.
//!
//! A body's size is its radius of gyration about the centre of mass,
//!
//! ```text
//! s_i = sqrt(tr(I_i^body) / (2 m_i))
//! ```
//!
//! (for uniform density `tr(I) = 2 sum m |r|^2`, so `s_i` is the RMS
//! distance of the body's mass from its centre: `h` for a cube of
//! half-edge `h`). With limits `theta_max` (radians) and `tau` (relative to
//! the size), body `i` allows the factor
//!
//! ```text
//! c_i = min(1, theta_max / |dtheta_i|, max(tau s_i, d) / |dx_i|)
//! ```
//!
//! with `d` the deepest penetration of the island before the step: a body
//! may always translate by `d`, since removing a penetration by a
//! translation needs no more and the rows are exact for a translation while
//! the contact features stay (a small box deep inside a big one must leave
//! it by a translation of many times its own size; the size limit alone
//! would take as many passes).
//!
//! and the island's whole correction is scaled by `c = min_i c_i`: the
//! direction stays the solver's (a scaled minimal correction still
//! satisfies every row it satisfied to first order by a fraction `c` of the
//! penetration), only its length is limited. Why this matters: a rotation
//! by `theta` moves a contact point by `theta r` to first order and by
//! `theta^2 r / 2` more, which the rows ignore; a light body squeezed
//! under a heavy one gets a large, cheap (mass-weighted) rotation whose
//! second-order error flings it. The line search then backtracks from the
//! limited step, and the next pass linearizes again where the body now is.

use nalgebra::DVector;

use crate::rows::BodyInertia;
use crate::settings::Settings;

/// Limits of one step, per body. Infinite limits turn the region off.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrustRegion {
    /// Largest rotation of a body in one step, radians.
    pub max_rotation: f64,
    /// Largest translation of a body's centre of mass in one step, relative
    /// to the body's radius of gyration.
    pub max_translation_relative: f64,
}

impl TrustRegion {
    /// The limits of [`Settings::step_max_rotation`] and
    /// [`Settings::step_max_translation_relative`].
    pub fn of(settings: &Settings) -> Self {
        TrustRegion {
            max_rotation: settings.step_max_rotation,
            max_translation_relative: settings.step_max_translation_relative,
        }
    }

    /// No limit: the solver's correction is used whole.
    pub const UNLIMITED: TrustRegion = TrustRegion {
        max_rotation: f64::INFINITY,
        max_translation_relative: f64::INFINITY,
    };

    /// The factor `c` in (0, 1] by which `dq` (6 entries per body, in the
    /// order of `inertias`) must be scaled to stay in the region, for an
    /// island whose deepest penetration is `depth`.
    pub fn scale(&self, dq: &DVector<f64>, inertias: &[BodyInertia], depth: f64) -> f64 {
        inertias
            .iter()
            .enumerate()
            .map(|(i, inertia)| {
                let dx = dq.fixed_rows::<3>(6 * i).norm();
                let dtheta = dq.fixed_rows::<3>(6 * i + 3).norm();
                let max_dx =
                    (self.max_translation_relative * radius_of_gyration(inertia)).max(depth);
                limit_factor(max_dx, dx).min(limit_factor(self.max_rotation, dtheta))
            })
            .fold(1.0, f64::min)
    }
}

impl Default for TrustRegion {
    fn default() -> Self {
        TrustRegion::UNLIMITED
    }
}

/// `min(1, limit / length)`; 1 for a zero length.
fn limit_factor(limit: f64, length: f64) -> f64 {
    if length > limit { limit / length } else { 1.0 }
}

/// `sqrt(tr(I_body) / (2 m))`.
pub fn radius_of_gyration(inertia: &BodyInertia) -> f64 {
    (inertia.inertia_body.trace() / (2.0 * inertia.mass)).sqrt()
}
