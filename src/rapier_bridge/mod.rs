//! The Rapier bridge (feature `rapier`): stabilizes a Rapier 3D world after
//! `PhysicsPipeline::step` (or `PhysicsWorld::step`).
//!
//! [`RapierBridge::stabilize`] reads the world's convex colliders into a
//! [`Scene`](crate::scene::Scene) that it keeps across steps, removes their
//! interpenetration with a [`Stabilizer`](crate::Stabilizer) that it also
//! keeps (so that V-Clip starts from the features of the previous step), and
//! writes the corrected poses of the dynamic bodies back to Rapier.
//! Velocities, sleep states and everything else in the world are untouched.
//!
//! # What is read
//!
//! | Rapier | scene body |
//! |---|---|
//! | dynamic body with exactly one enabled, non-sensor collider, a cuboid or a convex polyhedron | a body of mass `RigidBody::mass()` (uniform density over the shape) |
//! | each such collider of a fixed or kinematic body (any number per body) | a fixed body (kinematic bodies are never moved) |
//! | each such collider without a parent body | a fixed body |
//! | anything else (balls, capsules, round shapes, meshes, ..., sensors, disabled colliders or bodies, dynamic bodies with several colliders) | skipped, and counted in [`BridgeReport::skipped`] |
//!
//! A dynamic body with several convex colliders is skipped whole: the
//! library's bodies are one convex shape each (a compound body needs a
//! scene API that does not exist yet).
//!
//! # Frames
//!
//! Rapier places a rigid body by its *body frame* `B` (world from body,
//! not the centre of mass) and a collider by `P = position_wrt_parent`
//! (body from collider), so the collider's world pose is `C = B P`. A
//! Rapier cuboid is centred on the collider frame and a convex polyhedron's
//! points are given in it: the collider frame is exactly the scene body's
//! *shape frame* (its user pose, see [`crate::body`]), so
//!
//! ```text
//! read:   U = B P                (f32 -> f64, composed in f64)
//! write:  B' = U' P^-1           (composed in f64, then rounded to f32)
//! ```
//!
//! The library works about the centre of mass internally; that is its own
//! business ([`crate::body::Body::set_user_pose`] derives it). A collider
//! without a parent has `C = Collider::position()`.
//!
//! # Kept across steps
//!
//! [`BodyMap`] maps Rapier collider and body handles to scene indices.
//! From one call to the next only poses are updated; colliders that appear
//! are appended (their shapes are built once). When a mapped collider
//! disappears or changes (shape, parent, body type, mass, offset), the scene
//! cannot drop a body, so the scene is rebuilt and the stabilizer restarted
//! (its warm starts are lost for that one call; reported as
//! [`BridgeReport::rebuilt`]).
//!
//! # Rounding
//!
//! Rapier stores poses in f32. A corrected pose written back is rounded to
//! f32; the largest rounding of a written translation and rotation is
//! reported ([`BridgeReport::write_back_round_off`]), since it can leave
//! a penetration of that order after the call.
//!
//! Files:
//! - `convert.rs`: f32 Rapier poses to f64 nalgebra isometries and back.
//! - `collider_shape.rs`: which colliders are read, and their shapes.
//! - `body_map.rs`: the map from Rapier handles to scene bodies, and the
//!   decision to append or rebuild.
//! - `bridge.rs`: [`RapierBridge`]: read, stabilize, write back.
//! - `report.rs`: [`BridgeReport`], [`SkippedCollider`], [`SkipReason`].
//! - `error.rs`: [`BridgeError`].
//! - `world.rs`: [`world_from_scene`]: the Rapier world of a scene (the
//!   inverse of the read), for comparing a call with a Rapier step of the
//!   same scene.

mod body_map;
mod bridge;
mod collider_shape;
mod convert;
mod error;
mod report;
pub mod round_off;
mod settings;
mod world;

pub use body_map::{BodyMap, MappedCollider};
pub use bridge::RapierBridge;
pub use convert::{pose_from_f64, pose_to_f64};
pub use error::BridgeError;
pub use report::{BridgeReport, SkipReason, SkippedCollider, SyncReport, WriteBackRoundOff};
pub use settings::{BridgeSettings, CouplingMode};
pub use world::{GRAVITY_Z_UP, SceneWorld, world_from_scene};
