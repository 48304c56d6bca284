//! Settings of the Gauss–Seidel baseline (`Method::GaussSeidel`).

use constraint_stabilization::Settings;

use crate::methods::GaussSeidelPreset;

/// The library's settings for `iterations` sweeps of `preset`.
pub fn settings(preset: &GaussSeidelPreset, iterations: usize) -> Settings {
    // Placeholder until the method lands: the library's own solver.
    let _ = (preset, iterations);
    Settings::default()
}
