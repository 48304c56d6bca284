#!/usr/bin/env bash
# Times the Rust part of `.ci/run` but for fmt and the quick harness, in a
# clone: the lint-and-build step's two commands (the first with
# `--timings`, whose report lands in target/cargo-timings/), then the
# README's test command. Run it in a fresh clone to measure a fresh build.
#
# usage: benchmarks/scripts/ci_build_time.sh CLONE_DIR
# WRAP=clippy-driver measures a tree from before `.ci/lint-rustc`.
set -euo pipefail
cd "$1"
export CARGO_INCREMENTAL=0
export RUSTC_WORKSPACE_WRAPPER="${WRAP:-$PWD/.ci/lint-rustc}"
export CLIPPY_ARGS=-D__CLIPPY_HACKERY__warnings__CLIPPY_HACKERY__
workspace=(--workspace --exclude constraint-stabilization-python --features rapier)
start=$SECONDS
/usr/bin/time -f "build %e s wall, %U s user, %S s system" \
  cargo test "${workspace[@]}" --no-run --timings > build1.log 2>&1
/usr/bin/time -f "benchmarks' build %e s wall, %U s user, %S s system" \
  cargo test "${workspace[@]}" --benches --no-run > build2.log 2>&1
/usr/bin/time -f "tests %e s wall, %U s user, %S s system" \
  cargo test --features rapier > test.log 2>&1
tail -n 1 build1.log build2.log test.log
grep "finished in" test.log
echo "the three: $((SECONDS - start)) s"
