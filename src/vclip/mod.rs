//! V-Clip (B. Mirtich, "V-Clip: Fast and Robust Polyhedral Collision
//! Detection", ACM TOG 17(3), 1998) with the deepest-vertex search of
//! docs/design.md section 4.
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
//! other in the region's body frame (`pair` keeps the relative transforms,
//! like parry's `pos12`), so a query transforms O(1) points per visited
//! feature, never a whole body.
//!
//! Robustness: the walk decides with exact sign tests (no tolerance), with
//! every comparison between an edge and a face computed from the same
//! numbers in every state; a repeated state (a rounding tie) is resolved by
//! Theorem 1 with a tolerance or by a re-walk with slack; the iteration cap
//! ends in an exhaustive, correct fallback, and the result says so. A done
//! state at distance ~0 is classified touching or penetrating.
//!
//! Files: `clip` (edge clipping), `derivative` (derivative checks),
//! `vertex_states` and `edge_states` (the handlers), `local_min`, `state`
//! (dispatch), `deepest` (deepest vertex, face refinement), `witness`,
//! `closest` and `polish` (closest points), `touching` (distance ~0),
//! `verify` (Theorem 1 with tolerance), `fallback` (exhaustive answer),
//! `query` (driver), `pair` (frames), `types` and `settings` (public API).
//!
//! Example:
//!
//! ```
//! use constraint_stabilization::internals::geometry::ConvexPolyhedron;
//! use constraint_stabilization::internals::vclip::{vclip, Outcome};
//! use nalgebra::{Isometry3, Vector3};
//!
//! let cube = ConvexPolyhedron::cuboid(Vector3::new(1.0, 1.0, 1.0)).unwrap();
//! let a = Isometry3::identity();
//! let b = Isometry3::translation(3.0, 0.0, 0.0);
//! let first = vclip(&cube, &a, &cube, &b, None).unwrap();
//! let Outcome::Separated { distance, .. } = first.outcome else { panic!() };
//! assert!((distance - 1.0).abs() < 1e-12);
//! // Next query of the same pair: start from the cached features.
//! let next = vclip(&cube, &a, &cube, &b, Some(first.final_pair)).unwrap();
//! assert_eq!(next.iterations, 0);
//! ```

pub mod clip;
pub mod closest;
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

pub(crate) use deepest::descend;
pub use query::{CYCLE_CHECK_AFTER, HISTORY, ROTATION_NORM_TOLERANCE, VClip, vclip};
pub use settings::{
    DEFAULT_ITERATIONS_PER_FEATURE, DEFAULT_MIN_ITERATIONS, DEFAULT_TIE_TOLERANCE,
    DEFAULT_TOUCH_TOLERANCE, VClipError, VClipSettings,
};
pub use types::{BodyRole, DeepestVertex, FallbackReason, FeaturePair, Outcome, VClipResult};
