//! Fuzz target `scene_file`: see `tests/it/fuzz_regressions/fuzz_checks/scene_file.rs` for what it checks.
#![no_main]

#[path = "../../tests/it/fuzz_regressions/fuzz_checks/scene_file.rs"]
mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| check::check(data));
