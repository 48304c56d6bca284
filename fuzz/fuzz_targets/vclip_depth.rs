//! Fuzz target `vclip_depth`: see `tests/it/fuzz_regressions/fuzz_checks/vclip_depth.rs` for what it checks.
#![no_main]

#[path = "../../tests/it/fuzz_regressions/fuzz_checks/vclip_depth.rs"]
mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| check::check(data));
