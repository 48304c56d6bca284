//! Settings of the Gauss–Seidel baseline (`Method::GaussSeidel`).

use constraint_stabilization::settings::GaussSeidelSettings;
use constraint_stabilization::{Method, Settings};

use crate::methods::GaussSeidelPreset;

/// The library's settings for `iterations` sweeps of `preset` (the
/// default tolerance, contact margin and manifold, as the library's runs).
pub fn settings(preset: &GaussSeidelPreset, iterations: usize) -> Settings {
    {
        let mut settings = Settings::default();
        settings.method = Method::GaussSeidel;
        settings.gauss_seidel = GaussSeidelSettings {
            iterations,
            baumgarte: preset.baumgarte,
            slop_relative: preset.slop_relative,
            max_correction_relative: preset.max_correction_relative,
            detect_every_sweep: preset.detect_every_sweep,
        };
        settings
    }
}
