//! The checks of the fuzz targets (`fuzz/fuzz_targets/`), one function per
//! target, shared with the regression tests of `fuzz_regressions` (its `mod.rs`),
//! which runs them on the inputs kept under `tests/data/fuzz/TARGET/`.
//! Each check takes the fuzzer's raw bytes, returns early on input the
//! library rightly rejects (a typed error is an answer), and panics on a
//! wrong answer, judged by an oracle the library did not write.
//!
//! With `FUZZ_DEBUG` set, the V-Clip and LCP checks print their input as
//! decoded (`FUZZ_DEBUG=1 cargo test --test it fuzz_regressions:: -- --nocapture`).
//!
//! Every check is bounded in time: scenes, hulls and LCPs beyond the sizes
//! below are skipped (the fuzzer looks for wrong answers, not slow ones;
//! sizes are covered by `io::scene_file_limits`).
#![allow(dead_code)]

pub mod lcp_solvers;
pub mod scene_file;
pub mod vclip_depth;
