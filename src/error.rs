//! Typed errors returned at the library's boundary. No NaN and no panic
//! leaves the library on any user input: invalid input becomes one of these.

use thiserror::Error;

pub use crate::geometry::GeometryError;

/// Any error the library returns.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum Error {
    /// A shape could not be built.
    #[error("geometry: {0}")]
    Geometry(#[from] GeometryError),
}
