//! Fuzz target `vclip_depth`: see `tests/fuzz_checks/vclip_depth.rs` for what it checks.
#![no_main]

#[path = "../../tests/fuzz_checks/vclip_depth.rs"]
mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| check::check(data));
