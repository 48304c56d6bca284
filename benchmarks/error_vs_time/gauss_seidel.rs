//! Settings of the Gauss–Seidel baseline (`Method::GaussSeidel`).

use constraint_stabilization::{GaussSeidelSettings, Method, Settings};

use crate::methods::GaussSeidelPreset;

/// The library's settings for `iterations` sweeps of `preset` (the
/// default tolerance, contact margin and manifold, as the library's runs).
pub fn settings(preset: &GaussSeidelPreset, iterations: usize) -> Settings {
    Settings {
        method: Method::GaussSeidel,
        gauss_seidel: GaussSeidelSettings {
            iterations,
            baumgarte: preset.baumgarte,
            slop_relative: preset.slop_relative,
            max_correction_relative: preset.max_correction_relative,
            detect_every_sweep: preset.detect_every_sweep,
        },
        ..Settings::default()
    }
}
