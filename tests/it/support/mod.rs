//! Helpers of several test areas (not needed by the benchmarks or the
//! examples, whose shared helpers are in `dev_support`): the proptest
//! configuration, the LCP and projection-QP oracles, the Siconos files,
//! the engine states.

#[cfg(feature = "serde")]
pub mod engine_states;
pub mod proptest_config;
pub mod siconos;
pub mod solver_oracle;
