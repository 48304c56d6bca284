//! # constraint-stabilization
//!
//! Removes interpenetration between convex polyhedral rigid bodies after a
//! simulation step, by the smallest mass-weighted correction of their poses.
//!
//! The pipeline (see `DESIGN.md` of the project):
//! 1. [`vclip`] (Mirtich 1998) finds, for each pair of bodies, the closest
//!    features or a penetration; a deepest-vertex search turns a penetration
//!    into the deepest vertex–face pair.
//! 2. Each penetrating or near pair becomes a linearized non-penetration
//!    constraint `phi + J dq >= target`.
//! 3. [`solver`] computes the smallest correction in the metric of the mass
//!    matrix `M`: `min 1/2 dq^T M dq` subject to the constraints, a convex QP
//!    equivalent to the LCP `A = J M^-1 J^T, b = phi - target`.
//!
//! [`Settings::method`] chooses that projection (the default) or
//! [`gauss_seidel`], the game-engine baseline (Box2D's nonlinear
//! Gauss–Seidel position correction) on the same detection.
//!
//! All arithmetic is in `f64`.

pub mod body;
pub mod broad_phase;
pub mod contact;
#[cfg(feature = "demo")]
pub mod demo;
pub mod error;
pub mod gauss_seidel;
pub mod geometry;
pub mod io;
pub mod island;
mod parallel;
pub mod projector;
#[cfg(feature = "rapier")]
pub mod rapier_bridge;
pub mod render;
pub mod scene;
pub mod scene_parts;
pub mod solver;
pub mod stabilizer;
pub mod vclip;
pub mod verify;

pub use error::Error;
pub use projector::friction::FrictionModel;
pub use stabilizer::{GaussSeidelSettings, Method, Report, Settings, Stabilizer, Status};

/// The README's examples, compiled and run as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
