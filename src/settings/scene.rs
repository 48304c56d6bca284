//! The settings a scene file may carry, every field optional: a partial
//! [`Settings`] whose lengths are absolute, in the scene's length unit.
//! [`Settings::with_scene_settings`] puts each field that is set in its
//! place.

use super::error::{at_least, non_negative, positive};
use super::{FrictionModel, FrictionRows, Method, Settings, SettingsError};
use crate::solver::SolverChoice;

/// Settings carried by a scene; `None` means "the stabilizer's default".
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SceneSettings {
    /// Deepest penetration left at the end (length, > 0).
    pub tolerance: Option<f64>,
    /// Pairs closer than this enter the problem as near contacts (length, >= 0).
    pub contact_margin: Option<f64>,
    /// Separation the correction aims for (length, >= 0).
    pub target_margin: Option<f64>,
    /// Limit on projection passes (>= 1).
    pub max_passes: Option<u32>,
    /// Solver for every island, or `auto`.
    pub solver: Option<SolverChoice>,
    /// Solve every island with two solvers and report the difference.
    pub cross_check: Option<bool>,
    /// The correction method (`projection` or `gauss_seidel`, with the
    /// Gauss–Seidel defaults).
    pub method: Option<Method>,
    /// How rows with friction bound their sliding (`pyramid` or `cone`).
    pub friction_model: Option<FrictionModel>,
    /// How the friction rows enter the problem (`all`, `implied` or
    /// `generated`: the same minimizer).
    pub friction_rows: Option<FrictionRows>,
}

impl SceneSettings {
    /// Checks signs and finiteness of the fields that are present.
    pub fn validate(&self) -> Result<(), SettingsError> {
        if let Some(tolerance) = self.tolerance {
            positive("tolerance", tolerance)?;
        }
        if let Some(margin) = self.contact_margin {
            non_negative("contact_margin", margin)?;
        }
        if let Some(margin) = self.target_margin {
            non_negative("target_margin", margin)?;
        }
        if let Some(passes) = self.max_passes {
            at_least("max_passes", passes as usize, 1)?;
        }
        Ok(())
    }

    /// Whether no field is set.
    pub fn is_empty(&self) -> bool {
        *self == SceneSettings::default()
    }
}

impl Settings {
    /// These settings overridden by those a scene file carries: its lengths
    /// are absolute (in the scene's unit).
    pub fn with_scene_settings(mut self, scene: &SceneSettings) -> Self {
        if let Some(tolerance) = scene.tolerance {
            self.tolerance_absolute = Some(tolerance);
        }
        if let Some(margin) = scene.contact_margin {
            self.contact_margin_absolute = Some(margin);
        }
        if let Some(margin) = scene.target_margin {
            self.target_margin_absolute = Some(margin);
        }
        if let Some(passes) = scene.max_passes {
            self.max_passes = passes as usize;
        }
        if let Some(choice) = scene.solver {
            self.solver.choice = choice;
        }
        if let Some(cross_check) = scene.cross_check {
            self.solver.cross_check = cross_check;
        }
        if let Some(method) = scene.method {
            self.method = method;
        }
        if let Some(model) = scene.friction_model {
            self.friction_model = model;
        }
        if let Some(rows) = scene.friction_rows {
            self.friction_rows = rows;
        }
        self
    }
}
