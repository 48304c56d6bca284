//! The `stabilize` command line (its binary needs feature `cli`, which
//! this module is compiled with): `stabilize scene`, `stabilize demo`,
//! `stabilize lcp`; jointed scenes.

mod lcp;
mod scene;
mod scene_joints;
