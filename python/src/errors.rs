//! Library errors as Python exceptions, and the guard that keeps panics
//! out of Python.
//!
//! The exception classes are defined in Python
//! (`constraint_stabilization/errors.py`, so that the input errors can
//! also be `ValueError` or `TypeError`); this module looks them up by name
//! when it raises one. Each library error family has its class, and the
//! message is the library's `Display` text.

use std::panic::{AssertUnwindSafe, catch_unwind};

use constraint_stabilization::Error;
use constraint_stabilization::error::{BodyError, SceneError};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyType;

/// The Python module that holds the exception classes.
const ERRORS_MODULE: &str = "constraint_stabilization.errors";

/// A Python exception of the package's class `class_name` with `message`.
pub fn package_error(class_name: &'static str, message: String) -> PyErr {
    Python::attach(|py| {
        let class = py
            .import(ERRORS_MODULE)
            .and_then(|module| module.getattr(class_name))
            .and_then(|class| class.cast_into::<PyType>().map_err(PyErr::from));
        match class {
            Ok(class) => PyErr::from_type(class, message),
            // Only if the package's own errors module is missing (a broken
            // install): still an exception, never a crash.
            Err(lookup) => PyRuntimeError::new_err(format!(
                "{message} (and {ERRORS_MODULE}.{class_name} could not be loaded: {lookup})"
            )),
        }
    })
}

/// A bad value in the input (an array's shape, a NaN, a bad name).
pub fn input_error(message: String) -> PyErr {
    package_error("InputError", message)
}

/// An input of the wrong type (a dtype, an unknown keyword).
pub fn input_type_error(message: String) -> PyErr {
    package_error("InputTypeError", message)
}

/// The class of a library error's family.
fn class_of(error: &Error) -> &'static str {
    match error {
        Error::Geometry(_) => "GeometryError",
        Error::Scene(SceneError::Body {
            source: BodyError::Shape(_),
            ..
        })
        | Error::Body(BodyError::Shape(_)) => "GeometryError",
        Error::Scene(SceneError::Body { .. }) | Error::Body(_) => "BodyError",
        Error::Scene(SceneError::Settings(_)) | Error::Settings(_) => "SettingsError",
        Error::Scene(_) => "SceneError",
        Error::Solver(_) => "SolverError",
        Error::BroadPhase(_) | Error::Island(_) | Error::VClip(_) => "DetectionError",
        _ => "StabilizationError",
    }
}

/// The Python exception of a library error.
pub fn library_error(error: Error) -> PyErr {
    package_error(class_of(&error), error.to_string())
}

/// Runs `f` so that a panic inside it becomes the package's
/// `InternalError` (a bug of the library, reported as such) instead of
/// pyo3's `PanicException`.
pub fn guarded<T>(what: &str, f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(result) => result,
        Err(payload) => Err(package_error(
            "InternalError",
            format!(
                "{what}: internal error (a panic): {}",
                panic_message(&payload)
            ),
        )),
    }
}

/// The text of a panic payload (`&str` or `String`, as `panic!` makes).
pub fn panic_message(payload: &Box<dyn std::any::Any + Send>) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic payload".to_owned())
}

/// Raises the exception that a library error of family `family` becomes,
/// or (`"panic"`) panics inside the guard: the tests check every class and
/// that no panic reaches Python. Not part of the API.
#[pyfunction]
#[pyo3(name = "_raise_for_test")]
pub fn raise_for_test(family: &str) -> PyResult<()> {
    use constraint_stabilization::error::{BroadPhaseError, GeometryError, SolverError};
    let error = match family {
        "geometry" => Error::Geometry(GeometryError::Empty),
        "body" => Error::Body(BodyError::InvalidMass(-1.0)),
        "scene" => Error::Scene(SceneError::NoSuchBody { index: 3, len: 1 }),
        "settings" => Error::Settings(constraint_stabilization::SettingsError::TooFew {
            field: "max_passes",
            value: 0,
            least: 1,
        }),
        "solver" => Error::Solver(SolverError::NonFinite {
            what: "b",
            index: 0,
        }),
        "detection" => Error::BroadPhase(BroadPhaseError::InvalidMargin(-1.0)),
        "other" => Error::InvalidTimeStep(0.0),
        "panic" => return guarded("test", || panic!("a panic raised on purpose")),
        _ => return Err(input_error(format!("no error family {family:?}"))),
    };
    Err(library_error(error))
}
