//! V-Clip: separated distance, the deepest vertex, warm starts, Mirtich's
//! experiments, and property tests on random hulls.

mod deepest;
mod distance;
mod mirtich;
mod properties;
mod warm;
