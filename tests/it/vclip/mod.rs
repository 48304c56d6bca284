//! V-Clip: separated distance, the deepest vertex, warm starts, Mirtich's
//! experiments, and property tests on random hulls.

mod clip;
mod deepest;
mod distance;
mod mirtich;
mod properties;
mod segment_closest;
mod warm;
