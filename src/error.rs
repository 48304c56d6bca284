//! Typed errors returned at the library's boundary. No NaN and no panic
//! leaves the library on any user input: invalid input becomes one of these.

use thiserror::Error;

pub use crate::body::BodyError;
pub use crate::broad_phase::BroadPhaseError;
pub use crate::contact::IslandError;
pub use crate::geometry::GeometryError;
#[cfg(feature = "serde")]
pub use crate::io::scene_file::SceneFileError;
pub use crate::scene::SceneError;
pub use crate::settings::SettingsError;
pub use crate::solver::SolverError;
pub use crate::vclip::VClipError;

impl From<crate::contact::DetectionError> for Error {
    fn from(error: crate::contact::DetectionError) -> Self {
        match error {
            crate::contact::DetectionError::BroadPhase(error) => Error::BroadPhase(error),
            crate::contact::DetectionError::VClip(error) => Error::VClip(error),
        }
    }
}

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
    /// A stabilizer setting is invalid.
    #[error("settings: {0}")]
    Settings(#[from] SettingsError),
    /// Every solver failed on an island (the poses are as they were).
    #[error("solver: {0}")]
    Solver(#[from] SolverError),
    /// A V-Clip query was given invalid input.
    #[error("V-Clip: {0}")]
    VClip(#[from] VClipError),
    /// A corrected pose was rejected by its body (the poses are as they were).
    #[error("body: {0}")]
    Body(#[from] BodyError),
    /// A velocity projection was given a velocity list of the wrong length.
    #[error("{velocities} velocities for a scene of {bodies} bodies")]
    VelocityCount {
        /// Velocities given.
        velocities: usize,
        /// Bodies of the scene.
        bodies: usize,
    },
    /// A time step is zero, negative or not finite.
    #[error("time step {0}: it must be finite and positive")]
    InvalidTimeStep(f64),
    /// A velocity component is NaN or infinite.
    #[error("the velocity of body {body} is not finite")]
    NonFiniteVelocity {
        /// The body's scene index.
        body: usize,
    },
}
