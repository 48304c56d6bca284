//! Helpers shared by the integration tests (`tests/it`), the benchmarks
//! (`benchmarks/`) and the examples (`examples/`) of
//! `constraint-stabilization`; not published.
//!
//! - [`sat`]: the brute-force separating-axis oracle, the exact
//!   penetration depth of a pair of posed polyhedra and of a scene;
//! - [`random`]: random rotations, poses and convex hulls;
//! - [`scene`]: body descriptions, scenes, pose snapshots;
//! - [`vclip`]: the parry3d-f64 oracle of the V-Clip tests, a brute-force
//!   distance, and Mirtich's experiments;
//! - [`solver`]: random contact-like projection QPs.
//!
//! Helpers used by one test area only live in that area (`tests/it/AREA`),
//! helpers of several test areas in `tests/it/support`.

pub mod joints;
pub mod random;
pub mod sat;
pub mod scene;
pub mod solver;
pub mod support_oracle;
pub mod vclip;
