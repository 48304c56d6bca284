//! The Rapier bridge (feature `rapier`): stabilizes a Rapier 3D world after
//! `PhysicsPipeline::step` (or `PhysicsWorld::step`).
//!
//! [`RapierBridge::stabilize`] reads the world's convex colliders into a
//! [`Scene`](crate::scene::Scene) that it keeps across steps, removes their
//! interpenetration with a [`Stabilizer`](crate::Stabilizer) that it also
//! keeps (so that V-Clip starts from the features of the previous step), and
//! writes the corrected poses of the dynamic bodies back to Rapier. In the
//! default coupling ([`CouplingMode::ClosedContacts`]) it then removes
//! the approach velocities of the contacts it corrected and writes those
//! velocities back; in the position modes velocities are untouched. The
//! written bodies' colliders are moved with them before the call returns
//! (`RigidBodySet::propagate_modified_body_positions_to_colliders`), so
//! scene queries between the call and the next step see the corrected
//! world. Bodies Rapier has put to sleep are held still: obstacles, never
//! written (`rest.rs`, "At rest" below). Sleep states and everything else
//! in the world are never touched.
//! How a call couples with the engine is chosen in [`BridgeSettings`]
//! ([`CouplingMode`]); [`RapierBridge::new`] takes the stabilizer's
//! settings alone and the default coupling.
//!
//! # What is read
//!
//! | Rapier | scene body |
//! |---|---|
//! | dynamic body with exactly one enabled, non-sensor collider, a cuboid, a convex polyhedron, a ball, a capsule, a rounded cuboid or convex polyhedron, a cylinder or a cone (`round_collider`) | a body with Rapier's mass properties: `RigidBody::mass()`, the centre of mass and inertia of `RigidBody::mass_properties()` (`engine_mass.rs`) |
//! | dynamic body with several enabled, non-sensor colliders, each of those shapes | one compound body ([`crate::body::Shape::Compound`]) in the rigid body's frame, a part per collider at its offset `P_i`, with Rapier's mass properties (from the colliders' densities); its friction coefficient is the mean of its colliders' |
//! | each such collider of a fixed or kinematic (position- or velocity-based) body (any number per body) | a fixed body: an obstacle, never written; its pose is read again each call |
//! | each such collider without a parent body | a fixed body |
//! | anything else (rounded cylinders and cones, meshes, heightfields, ..., sensors, disabled colliders or bodies) | skipped, and counted in [`BridgeReport::skipped`]; a dynamic body with one such collider among several is skipped whole |
//!
//! A compound moves as one body: its parts never collide with each other,
//! its rows act on the rigid body's six degrees of freedom about the
//! compound's centre of mass (Rapier's), and the rigid body's pose is
//! written back.
//!
//! # At rest
//!
//! A dynamic body Rapier has put to sleep is held still for the call
//! ([`crate::body::Body::hold_fixed`]): never solved as moving nor written,
//! left asleep ([`BridgeReport::bodies_left_asleep`]); with every body
//! asleep the stabilizer is not called. Rapier wakes (strongly) every body
//! whose pose the user writes and the bodies touching it, so a settled
//! scene sleeps only if the calls stop writing it: in the default coupling
//! a *resting call* (every awake body passed Rapier's own sleep test in
//! its last three steps) accepts Rapier's allowed linear error (`rest.rs`,
//! [`BridgeSettings::resting_calls`]). Where Rapier cannot hold a scene
//! and the calls hold it still by writing it back (held cycles,
//! [`BridgeSettings::hold_cycles`]), a group of bodies held for Rapier's
//! `time_until_sleep` is put to sleep by the bridge: velocities zeroed,
//! then `RigidBody::sleep` at the next call, with no pose written
//! (`sleep.rs`, [`BridgeSettings::sleep_held_groups`]).
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
//! [`BodyMap`] maps Rapier collider and body handles to scene indices and
//! back ([`BodyMap::scene_index`], [`BodyMap::scene_index_of_body`],
//! [`BodyMap::collider_of`], [`BodyMap::body_of`]). From one call to the
//! next the poses are updated in one batch
//! ([`Scene::set_user_poses`](crate::scene::Scene::set_user_poses));
//! colliders that appear are appended (their shapes are built once); the
//! bodies of mapped colliders that disappear or change (shape, parent, body
//! type, mass, offset; for a compound, any of its colliders, or a collider
//! added to or removed from its body) are removed
//! ([`Stabilizer::remove_bodies`](crate::Stabilizer::remove_bodies): the
//! order of the others is kept, their indices shift down, and their V-Clip
//! warm starts follow them), a changed one appended again. The scene is
//! never rebuilt ([`SyncReport::removed`], [`SyncReport::appended`]).
//!
//! # Coupling
//!
//! [`CouplingMode`] (the design: `docs/coupling.md`; what each mode does
//! to a simulation: `benchmarks/results/coupling.md`):
//! - [`CouplingMode::PositionsOnly`] removes every penetration beyond the
//!   tolerance, positions only (velocities untouched);
//! - [`CouplingMode::RespectAllowedPenetration`] leaves Rapier its allowed
//!   linear error (`IntegrationParameters::allowed_linear_error()`, read at
//!   each call): it becomes the stabilizer's
//!   [`allowed_penetration`](crate::Settings::allowed_penetration), so a
//!   contact sunk by less is not touched and a deeper one is brought back
//!   to about that depth; positions only;
//! - [`CouplingMode::VelocityConsistency`] corrects positions as the first,
//!   then removes the approach velocities of the contacts of the islands it
//!   moved ([`crate::Stabilizer::project_velocities`]);
//! - [`CouplingMode::ClosedContacts`] does the same but aims the corrected
//!   contacts at a depth of one tolerance instead of a gap of the target
//!   margin ([`closed_contact_allowance`]), so that Rapier's next step
//!   starts with them touching: Rapier solves separated contact points
//!   rigidly and penetrating ones softly, and a contact opened to a tiny
//!   gap sits on that switch (the heavy stacks' sideways drift,
//!   `docs/coupling.md`). The default; its resting calls accept Rapier's
//!   allowed linear error (`rest.rs`).
//!
//! # Rounding
//!
//! Rapier stores poses in f32. A corrected pose written back is rounded to
//! f32, which moves a collider point by at most `delta = u (|t| + 4 r)`
//! (`u = 2^-24`; [`round_off`] derives it). Each call raises the
//! stabilizer's tolerance to at least `8 delta` and its target margin to at
//! least `4 delta`, so that the rounding cannot take a corrected contact
//! beyond the tolerance (at most a quarter of it in the worst case). The
//! bound is reported ([`BridgeReport::round_off_bound`]) with the largest
//! rounding measured ([`BridgeReport::write_back_round_off`]).
//!
//! Files:
//! - `convert.rs`: f32 Rapier poses to f64 nalgebra isometries and back.
//! - `collider_shape.rs`: which colliders are read, and their shapes.
//! - `body_map.rs`: the map from Rapier handles to scene bodies and back,
//!   and the plan of a call: bodies to remove, colliders to append.
//! - `settings.rs`: [`BridgeSettings`], [`CouplingMode`].
//! - `round_off.rs`: the f32 write-back bound and the call's lengths.
//! - `bridge.rs`: [`RapierBridge`]: read, stabilize, write back.
//! - `engine_mass.rs`: Rapier's mass properties in the scene body's frame.
//! - `rest.rs`: resting calls (Rapier's sleep test on the step's motion).
//! - `report.rs`: [`BridgeReport`], [`SkippedCollider`], [`SkipReason`].
//! - `error.rs`: [`BridgeError`].
//! - `world.rs`: [`world_from_scene`]: the Rapier world of a scene (the
//!   inverse of the read), for comparing a call with a Rapier step of the
//!   same scene.

mod body_map;
mod bridge;
mod collider_shape;
mod convert;
mod engine_mass;
mod error;
mod joints;
mod limbo;
mod report;
mod rest;
mod round_collider;
pub mod round_off;
mod settings;
mod sleep;
mod wedged;
pub(crate) mod world;

pub use body_map::{BodyMap, MappedCollider};
pub use bridge::RapierBridge;
pub use convert::{pose_from_f64, pose_to_f64};
pub use engine_mass::ENGINE_COM_ROUNDING;
pub use error::BridgeError;
pub use joints::{JointReadReport, JointSkipReason, RapierJoint, SkippedJoint};
pub use report::{BridgeReport, SkipReason, SkippedCollider, SyncReport, WriteBackRoundOff};
pub use settings::{
    BRIDGE_TARGET_MARGIN_RELATIVE, BridgeSettings, CouplingMode, FAST_BODY_REACH_FRACTION,
    closed_contact_allowance,
};
pub use world::{GRAVITY_Z_UP, SceneWorld, world_from_scene};
