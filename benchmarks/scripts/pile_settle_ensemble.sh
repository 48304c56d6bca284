#!/usr/bin/env bash
# The Rapier pile of 200's settle over perturbed drops (issue 21 / 22):
# for each drop-height perturbation E (m) and each variant, one run of
# `probes settle` (300 steps), printing "E variant asleep_from drift_mm"
# (asleep_from empty when the pile never sleeps). Variants: Rapier alone,
# the bridge with clarabel above Lemke's range (the interior point off),
# the bridge with the interior point from 41 rows (the default), and both
# with `BridgeSettings::zero_held_velocities`.
#
#   cargo build --release --features rapier,serde --example probes
#   bash benchmarks/scripts/pile_settle_ensemble.sh > ensemble.txt
set -euo pipefail
cd "$(dirname "$0")/../.."
probe=target/release/examples/probes
for E in 0 1e-7 -1e-7 5e-7 -5e-7 1e-6 -1e-6 2e-6 -2e-6 3e-6 -3e-6 5e-6 -5e-6 1e-5 -1e-5 2e-5; do
  for variant in plain clarabel ip41 ip41z clarabelz; do
    case $variant in
      plain) args=(--plain) ;;
      clarabel) args=(--ip-min-rows 99999999) ;;
      ip41) args=(--ip-min-rows 41) ;;
      ip41z) args=(--ip-min-rows 41 --zero-held-velocities) ;;
      clarabelz) args=(--ip-min-rows 99999999 --zero-held-velocities) ;;
    esac
    summary=$("$probe" settle --perturb "$E" "${args[@]}" --from 9999 --steps 300 2>&1 | grep '^summary')
    asleep=$(sed -nE 's/.*all asleep from Some\(([0-9]+)\).*/\1/p' <<<"$summary")
    drift=$(sed -nE 's/.*drift from step 150 ([0-9.]+) mm.*/\1/p' <<<"$summary")
    echo "$E $variant ${asleep:-never} $drift"
  done
done
