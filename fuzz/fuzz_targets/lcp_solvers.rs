//! Fuzz target `lcp_solvers`: see `tests/it/fuzz_regressions/fuzz_checks/lcp_solvers.rs` for what it checks.
#![no_main]

#[path = "../../tests/it/fuzz_regressions/fuzz_checks/lcp_solvers.rs"]
mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| check::check(data));
