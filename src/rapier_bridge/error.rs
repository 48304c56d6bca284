//! Why a bridge call failed. On any error nothing is written to Rapier.

use rapier3d::geometry::ColliderHandle;
use thiserror::Error;

use crate::scene::SceneError;

/// A failed bridge call.
#[derive(Debug, Error)]
pub enum BridgeError {
    /// A collider could not become a scene body: a pose that is not finite
    /// (a simulation that blew up), a degenerate hull, a mass that is zero
    /// or not finite.
    #[error("collider {collider:?}: {source}")]
    Body {
        /// The collider.
        collider: ColliderHandle,
        /// What is wrong with it.
        source: SceneError,
    },
    /// A scene body has no Rapier counterpart ([`super::world_from_scene`]):
    /// a pose or shape that does not fit in f32, a hull Rapier cannot build.
    #[error("scene body {index} ({name}): {reason}")]
    SceneBody {
        /// Its index in the scene.
        index: usize,
        /// Its name.
        name: String,
        /// What is wrong with it.
        reason: String,
    },
    /// The stabilizer failed (its settings, or no solver succeeded); the
    /// world is as it was.
    #[error("stabilizer: {0}")]
    Stabilize(#[from] crate::Error),
}
