//! The testbed (feature `testbed`): what the command-line tool, the tests,
//! the benchmarks and the examples use around the library, and a library
//! user's build without default features leaves out.
//!
//! - [`demo`]: the built-in demonstration scene, a seeded random pile;
//! - [`render`]: SVG pictures of a scene and its contacts;
//! - [`verify`]: parry3d-f64's contact query as an independent check of
//!   the exact depths.

pub mod demo;
pub mod render;
pub mod verify;
