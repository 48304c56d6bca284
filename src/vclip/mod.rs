//! V-Clip (B. Mirtich, "V-Clip: Fast and Robust Polyhedral Collision
//! Detection", ACM TOG 17(3), 1998) with the deepest-vertex search of
//! DESIGN.md section 4.
//!
//! The walk keeps a pair of features (vertex, edge or face), one per body,
//! and moves one of them to a neighbour until the closest points of the two
//! features lie in each other's Voronoi regions (then they are the closest
//! points of the bodies, Theorem 1) or a penetration is certain (an edge
//! crossing a face inside its Voronoi prism, or a vertex below every face
//! plane of the other body). On penetration, a descent over the vertex
//! graph finds the vertex deepest below the witness face.
//!
//! Frames: a feature of one body is tested against a Voronoi region of the
//! other in the region's body frame ([`pair`](self) keeps the relative
//! transforms), so a query transforms O(1) points per visited feature.
//!
//! Files: `clip` (edge clipping), `derivative` (derivative checks),
//! `vertex_states` and `edge_states` (the handlers), `local_min`, `state`
//! (dispatch), `deepest` (deepest vertex), `witness` and `closest` (closest
//! points), `fallback` (exhaustive answer), `query` (driver), `types` and
//! `settings` (public API).

mod clip;
mod closest;
mod deepest;
mod derivative;
mod edge_states;
mod fallback;
mod local_min;
mod pair;
mod polish;
mod query;
mod settings;
mod state;
mod touching;
mod types;
mod verify;
mod vertex_states;
mod witness;

pub use query::{CYCLE_CHECK_AFTER, HISTORY, ROTATION_NORM_TOLERANCE, VClip, vclip};
pub use settings::{
    DEFAULT_ITERATIONS_PER_FEATURE, DEFAULT_MIN_ITERATIONS, DEFAULT_TIE_TOLERANCE,
    DEFAULT_TOUCH_TOLERANCE, VClipError, VClipSettings,
};
pub use types::{BodyRole, DeepestVertex, FallbackReason, FeaturePair, Outcome, VClipResult};
