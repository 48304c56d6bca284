//! The integration tests of `constraint-stabilization`, one test binary
//! (one link of the library) with a module per area:
//!
//! - [`architecture`]: the modules of `src/` point one way;
//! - [`geometry`]: convex polyhedra (hulls, faces, shapes, the parry bridge);
//! - [`vclip`]: V-Clip distance, deepest vertex, warm starts, Mirtich's
//!   experiments, property tests;
//! - [`contact`]: the narrow phase's exact depth and the contact manifold;
//! - [`scene`]: bodies, broad phase, islands, the demo scene;
//! - [`solver`]: the projection QP, Lemke, PGS, clarabel, the friction
//!   cone, the Siconos LCP files;
//! - [`round`]: round and curved shapes (closed forms, the support-function
//!   oracle, parry's contact query, mass properties);
//! - [`stabilize`]: `Stabilizer::stabilize` end to end, and the projector
//!   on analytic constraints;
//! - [`gauss_seidel`]: the Gauss-Seidel method (with joints: its `joints`);
//! - [`io`]: scene and LCP files, the SVG picture;
//! - [`cli`]: the `stabilize` command line (feature `cli`);
//! - [`rapier_bridge`]: the Rapier bridge (features `rapier` and `testbed`);
//! - [`fuzz_regressions`]: the inputs kept from fuzzing (feature `serde`).
//!
//! Helpers shared with the benchmarks and examples are in the
//! `dev-support` crate (`dev_support`); helpers of several areas in
//! [`support`]; helpers of one area in that area.
//!
//! One area: `cargo test --test it stabilize::` (a name filter: the test
//! paths are `AREA::FILE::TEST`); one file: `cargo test --test it
//! stabilize::scenes:: -- --nocapture`.

mod support;

mod architecture;

mod contact;
mod gauss_seidel;
mod geometry;
mod io;
mod joints;
mod round;
mod scene;
mod solver;
mod stabilize;
mod vclip;

#[cfg(feature = "cli")]
mod cli;
#[cfg(feature = "serde")]
mod fuzz_regressions;
#[cfg(all(feature = "rapier", feature = "testbed"))]
mod rapier_bridge;
