#!/usr/bin/env bash
# The Rapier pile of 200's settle under the bridge's default with its
# friction rows as `all` (the bridge's default) and as `implied` (the
# stabilizer's default), over the 64 drop-height perturbations E (m) of
# the twentieth session's ensemble (`benchmarks/results/call_cost.md`),
# alternated per drop: one run of `probes settle` (300 steps) each,
# printing "E rows asleep_from drift_mm" (asleep_from `never` when the
# pile never sleeps), then per variant the drops within issue 22's limits
# (asleep by step 176, drift from step 150 at most 1 mm).
#
#   cargo build --release --features rapier,serde --example probes
#   bash benchmarks/scripts/friction_rows_settle.sh > settle.txt
set -euo pipefail
cd "$(dirname "$0")/../.."
probe=target/release/examples/probes
out=$(mktemp)
for E in 0 1e-7 -1e-7 5e-7 -5e-7 1e-6 -1e-6 2e-6 -2e-6 3e-6 -3e-6 5e-6 -5e-6 1e-5 -1e-5 2e-5 \
  1.5e-7 -1.5e-7 3e-7 -3e-7 7e-7 -7e-7 1.5e-6 -1.5e-6 2.5e-6 -2.5e-6 4e-6 -4e-6 7e-6 -7e-6 1.5e-5 -1.5e-5 \
  2e-7 -2e-7 4e-7 -4e-7 6e-7 -6e-7 8e-7 -8e-7 1.2e-6 -1.2e-6 1.8e-6 -1.8e-6 2.2e-6 -2.2e-6 3.5e-6 -3.5e-6 \
  4.5e-6 -4.5e-6 6e-6 -6e-6 8e-6 -8e-6 9e-6 -9e-6 1.2e-5 -1.2e-5 1.8e-5 -1.8e-5 2.5e-5 -2.5e-5 3e-5 -3e-5; do
  for rows in all implied; do
    summary=$("$probe" settle --perturb "$E" --friction-rows "$rows" --from 9999 --steps 300 2>&1 | grep '^summary')
    asleep=$(sed -nE 's/.*all asleep from Some\(([0-9]+)\).*/\1/p' <<<"$summary")
    drift=$(sed -nE 's/.*drift from step 150 ([0-9.]+) mm.*/\1/p' <<<"$summary")
    echo "$E $rows ${asleep:-never} $drift" | tee -a "$out"
  done
done
awk '{ n[$2]++; if ($3 != "never" && $3 <= 176 && $4 <= 1.0) ok[$2]++; if ($3 == "never") never[$2]++ }
  END { for (v in n) printf "%s: %d of %d within the limits, %d never asleep\n", v, ok[v], n[v], never[v] }' "$out"
rm -f "$out"
