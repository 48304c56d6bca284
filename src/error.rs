//! Typed errors returned at the library's boundary. No NaN and no panic
//! leaves the library on any user input: invalid input becomes one of these.

use thiserror::Error;

pub use crate::broad_phase::BroadPhaseError;
pub use crate::geometry::GeometryError;
#[cfg(feature = "serde")]
pub use crate::io::scene_file::SceneFileError;
pub use crate::island::IslandError;
pub use crate::scene::SceneError;

/// Any error the library returns.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum Error {
    /// A shape could not be built.
    #[error("geometry: {0}")]
    Geometry(#[from] GeometryError),
    /// A scene or body description is invalid.
    #[error("scene: {0}")]
    Scene(#[from] SceneError),
    /// A scene file could not be read or written.
    #[cfg(feature = "serde")]
    #[error("scene file: {0}")]
    SceneFile(#[from] SceneFileError),
    /// Broad-phase input is invalid.
    #[error("broad phase: {0}")]
    BroadPhase(#[from] BroadPhaseError),
    /// Island input is invalid.
    #[error("islands: {0}")]
    Island(#[from] IslandError),
}
