//! The inputs kept from fuzzing (`tests/data/fuzz/TARGET/`, one file per
//! input: those that found a bug, and a few seeds), run through the same
//! checks as the fuzz targets ([`fuzz_checks`], included by the targets
//! of `fuzz/` from `tests/it/fuzz_regressions/fuzz_checks/`), so that a bug the
//! fuzzer found once stays fixed without the fuzzer. See docs/reliability.md
//! and benchmarks/results/fuzzing.md for the fuzzing runs.

mod fuzz_checks;

use std::path::Path;

/// Runs `check` on every file under `tests/data/fuzz/target/`; returns how
/// many there were.
fn replay(target: &str, check: fn(&[u8])) -> usize {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/fuzz")
        .join(target);
    let mut entries: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.expect("readable directory").path())
        .collect();
    entries.sort();
    for path in &entries {
        println!("{target}: {}", path.display());
        check(&std::fs::read(path).expect("readable input"));
    }
    entries.len()
}

#[test]
fn scene_file_inputs() {
    assert!(replay("scene_file", fuzz_checks::scene_file::check) > 0);
}

#[test]
fn lcp_solvers_inputs() {
    assert!(replay("lcp_solvers", fuzz_checks::lcp_solvers::check) > 0);
}

#[test]
fn vclip_depth_inputs() {
    assert!(replay("vclip_depth", fuzz_checks::vclip_depth::check) > 0);
}
