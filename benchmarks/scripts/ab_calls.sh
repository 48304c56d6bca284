#!/usr/bin/env bash
# Two builds of the command-line tool on the same scene files, alternated
# run by run (the machine is shared: side by side, never one after the
# other), and the median of each build's call time as its `info` log line
# reports it (the call alone, not reading or writing the files).
#
# usage: benchmarks/scripts/ab_calls.sh OLD_BIN NEW_BIN RUNS SCENE.json...
#   e.g. build `cargo build --release` at each commit, copy
#   target/release/stabilize aside as OLD_BIN and NEW_BIN, then
#   benchmarks/scripts/ab_calls.sh /tmp/old /tmp/new 9 tests/data/engine/*.json
set -euo pipefail
old=$1 new=$2 runs=$3
shift 3
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
call_ms() {
  RUST_LOG=constraint_stabilization=info "$1" scene "$2" -o "$out/out.json" 2>&1 |
    grep -o '[0-9.]* ms$' | cut -d' ' -f1
}
median() { sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
echo "| scene | old ms | new ms | new / old |"
echo "|---|---:|---:|---:|"
for scene in "$@"; do
  : >"$out/old" && : >"$out/new"
  for _ in $(seq "$runs"); do
    call_ms "$old" "$scene" >>"$out/old"
    call_ms "$new" "$scene" >>"$out/new"
  done
  a=$(median <"$out/old") b=$(median <"$out/new")
  echo "| $(basename "$scene" .json) | $a | $b | $(awk -v a="$a" -v b="$b" 'BEGIN {printf "%.2f", b / a}') |"
done
