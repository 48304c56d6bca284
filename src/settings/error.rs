//! The one error of every setting: which field (its path, as in code and
//! scene files: `tolerance_relative`, `line_search.shrink`,
//! `gauss_seidel.iterations`), the value given and what it must be.

use thiserror::Error;

/// An invalid setting, named by its path.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum SettingsError {
    /// A real-valued setting is outside its range (NaN is outside every
    /// range).
    #[error("setting `{field}` is {value}: it must be {requirement}")]
    OutOfRange {
        /// The setting's path.
        field: &'static str,
        /// The value given.
        value: f64,
        /// What it must be.
        requirement: &'static str,
    },
    /// A count is below its least value.
    #[error("setting `{field}` is {value}: it must be at least {least}")]
    TooFew {
        /// The setting's path.
        field: &'static str,
        /// The value given.
        value: usize,
        /// The least value allowed.
        least: usize,
    },
}

impl SettingsError {
    /// The path of the setting the error is about.
    pub fn field(&self) -> &'static str {
        match self {
            SettingsError::OutOfRange { field, .. } | SettingsError::TooFew { field, .. } => field,
        }
    }
}

/// `value` finite and `> 0`.
pub(crate) fn positive(field: &'static str, value: f64) -> Result<(), SettingsError> {
    check(
        field,
        value,
        value.is_finite() && value > 0.0,
        "finite and positive",
    )
}

/// `value` finite and `>= 0`.
pub(crate) fn non_negative(field: &'static str, value: f64) -> Result<(), SettingsError> {
    check(
        field,
        value,
        value.is_finite() && value >= 0.0,
        "finite and non-negative",
    )
}

/// `value > 0`, possibly infinite (no limit), never NaN.
pub(crate) fn positive_or_infinite(field: &'static str, value: f64) -> Result<(), SettingsError> {
    check(
        field,
        value,
        value > 0.0,
        "positive (infinite for no limit)",
    )
}

/// `ok`, or the error that `value` is not `requirement`.
pub(crate) fn check(
    field: &'static str,
    value: f64,
    ok: bool,
    requirement: &'static str,
) -> Result<(), SettingsError> {
    match ok {
        true => Ok(()),
        false => Err(SettingsError::OutOfRange {
            field,
            value,
            requirement,
        }),
    }
}

/// `value >= least`.
pub(crate) fn at_least(
    field: &'static str,
    value: usize,
    least: usize,
) -> Result<(), SettingsError> {
    match value >= least {
        true => Ok(()),
        false => Err(SettingsError::TooFew {
            field,
            value,
            least,
        }),
    }
}
