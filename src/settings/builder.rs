//! [`SettingsBuilder`]: the defaults, changed field by field, validated once
//! at [`SettingsBuilder::build`].

use std::time::Duration;

use super::{
    FrictionModel, FrictionRows, GaussSeidelSettings, LineSearchSettings, Method, Settings,
    SettingsError,
};
use crate::solver::SolverSettings;
use crate::vclip::VClipSettings;

/// Builds [`Settings`] from the defaults; [`SettingsBuilder::build`]
/// validates the result.
///
/// ```
/// use constraint_stabilization::Settings;
///
/// let settings = Settings::builder()
///     .tolerance_relative(1e-5)
///     .friction(0.5)
///     .build()?;
/// assert_eq!(settings.friction, 0.5);
/// assert!(Settings::builder().max_passes(0).build().is_err());
/// # Ok::<(), constraint_stabilization::SettingsError>(())
/// ```
#[derive(Debug, Clone, Default)]
pub struct SettingsBuilder {
    settings: Settings,
}

/// A setter per field: `name(value)` sets `settings.name = value`.
macro_rules! setters {
    ($($(#[$doc:meta])* $field:ident: $type:ty),* $(,)?) => {
        $(
            $(#[$doc])*
            pub fn $field(mut self, value: $type) -> Self {
                self.settings.$field = value;
                self
            }
        )*
    };
}

/// A setter per optional field: `name(value)` sets `settings.name =
/// Some(value)`.
macro_rules! optional_setters {
    ($($(#[$doc:meta])* $field:ident: $type:ty),* $(,)?) => {
        $(
            $(#[$doc])*
            pub fn $field(mut self, value: $type) -> Self {
                self.settings.$field = Some(value);
                self
            }
        )*
    };
}

impl SettingsBuilder {
    setters! {
        /// [`Settings::method`].
        method: Method,
        /// [`Settings::gauss_seidel`].
        gauss_seidel: GaussSeidelSettings,
        /// [`Settings::tolerance_relative`].
        tolerance_relative: f64,
        /// [`Settings::contact_margin_relative`].
        contact_margin_relative: f64,
        /// [`Settings::target_margin_relative`].
        target_margin_relative: f64,
        /// [`Settings::allowed_penetration`].
        allowed_penetration: f64,
        /// [`Settings::max_passes`].
        max_passes: usize,
        /// [`Settings::contact_manifold`].
        contact_manifold: bool,
        /// [`Settings::near_pair_faces`].
        near_pair_faces: bool,
        /// [`Settings::hold_open_gaps`].
        hold_open_gaps: bool,
        /// [`Settings::friction`].
        friction: f64,
        /// [`Settings::friction_directions`].
        friction_directions: usize,
        /// [`Settings::friction_model`].
        friction_model: FrictionModel,
        /// [`Settings::friction_rows`].
        friction_rows: FrictionRows,
        /// [`Settings::friction_max_iterations`].
        friction_max_iterations: usize,
        /// [`Settings::friction_max_correction`].
        friction_max_correction: f64,
        /// [`Settings::solve_whole_islands`].
        solve_whole_islands: bool,
        /// [`Settings::keep_penetrated_pairs`].
        keep_penetrated_pairs: bool,
        /// [`Settings::joint_rotation_weight`].
        joint_rotation_weight: f64,
        /// [`Settings::step_max_rotation`].
        step_max_rotation: f64,
        /// [`Settings::step_max_translation_relative`].
        step_max_translation_relative: f64,
        /// [`Settings::line_search`].
        line_search: LineSearchSettings,
        /// [`Settings::solver`].
        solver: SolverSettings,
        /// [`Settings::vclip`].
        vclip: VClipSettings,
    }

    optional_setters! {
        /// [`Settings::tolerance_absolute`].
        tolerance_absolute: f64,
        /// [`Settings::contact_margin_absolute`].
        contact_margin_absolute: f64,
        /// [`Settings::target_margin_absolute`].
        target_margin_absolute: f64,
        /// [`Settings::time_budget`].
        time_budget: Duration,
    }

    /// The settings, validated: the error names the first invalid field by
    /// its path.
    pub fn build(self) -> Result<Settings, SettingsError> {
        self.settings.validate()?;
        Ok(self.settings)
    }
}
