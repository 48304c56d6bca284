//! # constraint-stabilization
//!
//! Removes interpenetration between rigid bodies (convex polyhedra and
//! compounds of them) after a simulation step, by the smallest
//! mass-weighted correction of their poses. All arithmetic is in `f64`.
//!
//! ```
//! use constraint_stabilization::{BodyDesc, MassSpec, Scene, Settings, Shape, Stabilizer, Status};
//! use nalgebra::Vector3;
//!
//! let mut scene = Scene::new();
//! scene.add_body(BodyDesc {
//!     name: "ground".into(),
//!     shape: Shape::Cuboid { half_extents: Vector3::new(10.0, 0.5, 10.0) },
//!     translation: Vector3::new(0.0, -0.5, 0.0),
//!     rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
//!     mass: MassSpec::Fixed,
//! })?;
//! // A unit box sunk 1 cm into the ground.
//! scene.add_body(BodyDesc {
//!     name: "box".into(),
//!     shape: Shape::Cuboid { half_extents: Vector3::new(0.5, 0.5, 0.5) },
//!     translation: Vector3::new(0.0, 0.49, 0.0),
//!     rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
//!     mass: MassSpec::Mass(1.0),
//! })?;
//! let mut stabilizer = Stabilizer::new(Settings::default())?;
//! let report = stabilizer.stabilize(&mut scene)?;
//! assert_eq!(report.status, Status::Converged);
//! # Ok::<(), constraint_stabilization::Error>(())
//! ```
//!
//! A call ([`Stabilizer::stabilize`]) makes passes until no pair penetrates
//! deeper than the tolerance:
//! 1. **Detection.** A broad phase on the bodies' boxes grown by the
//!    contact margin; V-Clip (Mirtich 1998) on every candidate pair of
//!    convex parts, warm-started from the pair's last feature pair; where
//!    two parts overlap, a walk from V-Clip's deepest vertex to the exact
//!    penetration depth (the smallest translation that separates them) and
//!    a contact manifold on its normal.
//! 2. **Islands.** Bodies joined by penetrating or near pairs; fixed bodies
//!    never join. Only islands with a penetration beyond the tolerance are
//!    solved, in parallel (feature `parallel`), merged in a fixed order, and
//!    within an island only the region that must move.
//! 3. **Rows and projection.** Each contact becomes a linearized row
//!    `phi + J dq >= target`; the correction minimizes `1/2 dq^T M dq` (a
//!    convex QP, equivalent to the LCP `A = J M^-1 J^T, b = phi - target`),
//!    solved by clarabel or the built-in Lemke solver ([`solver`]), every
//!    answer checked by the same acceptance residuals.
//! 4. **Line search.** The correction, held in a per-body trust region, is
//!    scaled back until the merit on the true geometry falls and no clear
//!    pair is pushed in: the merit never rises, and the scene is never
//!    returned worse than it came.
//!
//! [`Settings::method`] chooses that projection (the default) or the
//! game-engine baseline (Box2D's nonlinear Gauss–Seidel position
//! correction) on the same detection. The design is in `docs/design.md`,
//! the module map in `ARCHITECTURE.md`.

pub mod body;
mod broad_phase;
mod contact;
pub mod error;
mod geometry;
pub mod io;
pub mod joints;
mod parallel;
mod projector;
#[cfg(feature = "rapier")]
pub mod rapier_bridge;
mod rows;
pub mod scene;
pub mod settings;
pub mod solver;
pub mod stabilizer;
#[cfg(feature = "testbed")]
pub mod testbed;
mod vclip;

pub use body::{Body, BodyDesc, BodyError, MassSpec, Shape, ShapePart};
pub use error::Error;
pub use joints::{Joint, JointKind};
pub use scene::{Scene, SceneError};
pub use settings::{FrictionModel, FrictionRows, Method, Settings, SettingsError};
pub use stabilizer::{Report, Stabilizer, Status};

/// The library's internals, for its own benchmarks and tests: geometry,
/// V-Clip, the narrow phase, rows and the projection loop. Not part of the
/// supported API: names and signatures here change without notice.
#[doc(hidden)]
pub mod internals {
    /// Broad phase on bounding boxes.
    pub mod broad_phase {
        pub use crate::broad_phase::*;
    }
    /// The narrow phase: exact depths, manifolds, contact rows, islands.
    pub mod contact {
        pub use crate::contact::*;
    }
    /// Convex polyhedra, hulls and features.
    pub mod geometry {
        pub use crate::geometry::*;
    }
    /// The projection loop: steps, line search, trust region, friction.
    pub mod projector {
        pub use crate::projector::*;
    }
    /// Linearized rows and configurations.
    pub mod rows {
        pub use crate::rows::*;
    }
    /// V-Clip and the deepest-vertex search.
    pub mod vclip {
        pub use crate::vclip::*;
    }
    /// Private parts of the public `stabilizer` module.
    pub mod stabilizer {
        /// The Gauss-Seidel method's sweeps, points and joint rows.
        pub mod gauss_seidel {
            pub use crate::stabilizer::gauss_seidel::{joints, point, sweep};
        }
        /// Regions of an island.
        pub mod region {
            pub use crate::stabilizer::region::*;
        }
        /// One island's pass.
        pub mod solve_island {
            pub use crate::stabilizer::solve_island::*;
        }
    }
    /// Private parts of the public `rapier_bridge` module.
    #[cfg(feature = "rapier")]
    pub mod rapier_bridge {
        /// Round-off of poses written to Rapier.
        pub mod round_off {
            pub use crate::rapier_bridge::round_off::*;
        }
        /// A Rapier world built from a scene.
        pub mod world {
            pub use crate::rapier_bridge::world::*;
        }
    }
}

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
