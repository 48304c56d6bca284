//! Keyword arguments as the library's [`Settings`]: each keyword is a
//! field of `Settings` with the same name and meaning (lengths relative to
//! the scene's scale unless `_absolute`, `time_budget` in seconds); an
//! omitted keyword keeps the library's default, an unknown one or a value
//! of the wrong type raises the package's `InputTypeError` (a
//! `TypeError`), an out-of-range value the library's `SettingsError`.

use std::time::Duration;

use constraint_stabilization::{Error, FrictionModel, FrictionRows, Method, Settings};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{input_error, input_type_error, library_error};

/// Every keyword accepted, in `Settings`' order.
pub const SETTING_NAMES: [&str; 22] = [
    "method",
    "tolerance_relative",
    "tolerance_absolute",
    "contact_margin_relative",
    "contact_margin_absolute",
    "target_margin_relative",
    "target_margin_absolute",
    "allowed_penetration",
    "time_budget",
    "max_passes",
    "contact_manifold",
    "near_pair_faces",
    "hold_open_gaps",
    "friction",
    "friction_directions",
    "friction_model",
    "friction_rows",
    "solve_whole_islands",
    "keep_penetrated_pairs",
    "joint_rotation_weight",
    "step_max_rotation",
    "step_max_translation_relative",
];

/// The keywords [`settings_from_kwargs`] accepts.
#[pyfunction]
pub fn setting_names() -> Vec<&'static str> {
    SETTING_NAMES.to_vec()
}

/// `value` as a `T`, or the package's type error naming the keyword.
fn typed<'py, T: FromPyObjectOwned<'py>>(name: &str, value: &Bound<'py, PyAny>) -> PyResult<T> {
    value.extract::<T>().map_err(|_| {
        let given = value
            .get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_else(|_| "?".to_owned());
        input_type_error(format!(
            "setting `{name}` must be a {}, got {given}",
            std::any::type_name::<T>()
                .rsplit("::")
                .next()
                .unwrap_or("value")
        ))
    })
}

/// A time budget in seconds as a duration (`Duration::from_secs_f64`
/// panics on a negative, NaN or huge value: those are range errors here).
fn budget(seconds: f64) -> PyResult<Duration> {
    Duration::try_from_secs_f64(seconds).map_err(|_| {
        input_error(format!(
            "setting `time_budget` is {seconds} s: it must be finite and nonnegative"
        ))
    })
}

/// A setting given by name (`method`, `friction_model`): the library's
/// value of that name, else an input error listing `choices`.
fn named<T>(
    name: &str,
    value: &Bound<'_, PyAny>,
    from_name: fn(&str) -> Option<T>,
    choices: &[&str],
) -> PyResult<T> {
    let text: String = typed(name, value)?;
    from_name(&text).ok_or_else(|| {
        input_error(format!(
            "setting `{name}` is {text:?}: it must be one of {choices:?}"
        ))
    })
}

/// The library's settings from keyword arguments (validated).
pub fn settings_from_kwargs(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Settings> {
    let mut s = Settings::default();
    let Some(kwargs) = kwargs else {
        return Ok(s);
    };
    for (key, value) in kwargs.iter() {
        let name: String = typed("(name)", &key)?;
        let v = &value;
        match name.as_str() {
            "method" => {
                s.method = named(&name, v, Method::from_name, &["projection", "gauss_seidel"])?
            }
            "tolerance_relative" => s.tolerance_relative = typed(&name, v)?,
            "tolerance_absolute" => s.tolerance_absolute = typed(&name, v)?,
            "contact_margin_relative" => s.contact_margin_relative = typed(&name, v)?,
            "contact_margin_absolute" => s.contact_margin_absolute = typed(&name, v)?,
            "target_margin_relative" => s.target_margin_relative = typed(&name, v)?,
            "target_margin_absolute" => s.target_margin_absolute = typed(&name, v)?,
            "allowed_penetration" => s.allowed_penetration = typed(&name, v)?,
            "time_budget" => {
                let seconds: Option<f64> = typed(&name, v)?;
                s.time_budget = seconds.map(budget).transpose()?;
            }
            "max_passes" => s.max_passes = typed(&name, v)?,
            "contact_manifold" => s.contact_manifold = typed(&name, v)?,
            "near_pair_faces" => s.near_pair_faces = typed(&name, v)?,
            "hold_open_gaps" => s.hold_open_gaps = typed(&name, v)?,
            "friction" => s.friction = typed(&name, v)?,
            "friction_directions" => s.friction_directions = typed(&name, v)?,
            "friction_model" => {
                s.friction_model = named(&name, v, FrictionModel::from_name, &["pyramid", "cone"])?
            }
            "friction_rows" => {
                s.friction_rows = named(
                    &name,
                    v,
                    FrictionRows::from_name,
                    &["all", "implied", "generated"],
                )?
            }
            "solve_whole_islands" => s.solve_whole_islands = typed(&name, v)?,
            "keep_penetrated_pairs" => s.keep_penetrated_pairs = typed(&name, v)?,
            "joint_rotation_weight" => s.joint_rotation_weight = typed(&name, v)?,
            "step_max_rotation" => s.step_max_rotation = typed(&name, v)?,
            "step_max_translation_relative" => s.step_max_translation_relative = typed(&name, v)?,
            _ => {
                return Err(input_type_error(format!(
                    "unknown setting `{name}`; the settings are: {}",
                    SETTING_NAMES.join(", ")
                )));
            }
        }
    }
    s.validate()
        .map_err(|e| library_error(Error::Settings(e)))?;
    Ok(s)
}
