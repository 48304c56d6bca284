"""The Python package's benchmark (results in benchmarks/results/python.md):

1. the binding's overhead on a 40-body layout: the wall time of
   ``cs.stabilize`` seen from Python against the library's own time of the
   same call (``report.times["total"]``, measured inside the Rust call),
   interleaved call by call;
2. batch throughput: 1,000 layouts of the reset bank with 1 and 2
   threads, interleaved;
3. example 2's comparison (MuJoCo from the raw layout against MuJoCo from
   the stabilized layout), 5 seeds.

Run with the release build (``pip install ./python``):

    python python/benchmarks/bench_python.py [--quick]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import constraint_stabilization as cs

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "examples"))
from reset_bank import bank_scene, random_layouts  # noqa: E402


def overhead(repeats: int) -> None:
    scene = bank_scene(40, seed=3)
    layouts = random_layouts(scene, repeats, seed=5)
    walls, inners = [], []
    for layout in layouts:
        start = time.perf_counter()
        _, report = cs.stabilize(scene, layout, quaternion_order="wxyz")
        walls.append(time.perf_counter() - start)
        inners.append(report.times["total"])
    ratios = [(w - i) / i for w, i in zip(walls, inners)]
    gaps = [w - i for w, i in zip(walls, inners)]
    print(f"## 1. Overhead on a 40-body layout ({repeats} layouts, one call each)\n")
    print("| | median | min | max |\n|---|---|---|---|")
    print(f"| wall time of cs.stabilize (ms) | {statistics.median(walls) * 1e3:.3f} | {min(walls) * 1e3:.3f} | {max(walls) * 1e3:.3f} |")
    print(f"| library's own time (ms) | {statistics.median(inners) * 1e3:.3f} | {min(inners) * 1e3:.3f} | {max(inners) * 1e3:.3f} |")
    print(f"| binding overhead (ms) | {statistics.median(gaps) * 1e3:.3f} | {min(gaps) * 1e3:.3f} | {max(gaps) * 1e3:.3f} |")
    print(f"| overhead / library time | {statistics.median(ratios):.2%} | {min(ratios):.2%} | {max(ratios):.2%} |\n")


def throughput(count: int, rounds: int) -> None:
    scene = bank_scene(20)
    layouts = random_layouts(scene, count, seed=1)
    times = {1: [], 2: []}
    cpu = {1: [], 2: []}
    converged = {}
    for _ in range(rounds):
        for threads in (1, 2):
            start, start_cpu = time.perf_counter(), time.process_time()
            bank = cs.stabilize_batch(scene, layouts, quaternion_order="wxyz", threads=threads)
            times[threads].append(time.perf_counter() - start)
            cpu[threads].append(time.process_time() - start_cpu)
            converged[threads] = (float(np.mean(bank.converged)), bank.poses)
    same = np.array_equal(converged[1][1], converged[2][1])
    print(f"## 2. Batch throughput: {count} layouts of 20 objects in a bin ({rounds} rounds, interleaved)\n")
    print("| threads | median wall (s) | per layout (ms) | layouts/s | converged | cores obtained (CPU time / wall) |\n|---|---|---|---|---|---|")
    for threads in (1, 2):
        m = statistics.median(times[threads])
        cores = statistics.median(c / w for c, w in zip(cpu[threads], times[threads]))
        print(f"| {threads} | {m:.2f} | {m / count * 1e3:.2f} | {count / m:.0f} | {converged[threads][0]:.1%} | {cores:.2f} |")
    speedup = statistics.median(times[1]) / statistics.median(times[2])
    print(f"\nSpeed-up 2 threads / 1: {speedup:.2f}; poses of the two runs bit-identical: {same}.\n")


def example_two(seeds: int) -> None:
    try:
        import mujoco_bin
    except ImportError as error:
        print(f"## 3. Example 2: skipped ({error})")
        return
    print(f"## 3. Example 2: 40 objects dropped into a MuJoCo bin, {seeds} seeds\n")
    burst = int(mujoco_bin.BURST_SECONDS / 0.002)
    print("| seed | deepest raw (mm) | raw: KE at 10 ms (J) | raw: peak KE first 0.1 s (J) | raw: fastest (m/s) | raw: out of bin | stabilize (ms) | stabilized: KE at 10 ms (J) | stabilized: peak KE first 0.1 s (J) | stabilized: fastest (m/s) | stabilized: out of bin |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for seed in range(seeds):
        raw, fixed = mujoco_bin.compare(40, seed)
        print(f"| {seed} | {-raw.deepest_start * 1e3:.1f} | {raw.energy[4]:.3g} | {raw.energy[:burst].max():.3g} | {raw.peak_speed:.2f} | {raw.ejected} | "
              f"{fixed.stabilize_ms:.1f} ({fixed.status}) | {fixed.energy[4]:.3g} | {fixed.energy[:burst].max():.3g} | {fixed.peak_speed:.2f} | {fixed.ejected} |")
    print()


def main() -> None:
    parser = argparse.ArgumentParser(description="The Python package's benchmark")
    parser.add_argument("--quick", action="store_true", help="small counts, to check that it runs")
    args = parser.parse_args()
    overhead(5 if args.quick else 60)
    throughput(50 if args.quick else 1000, 1 if args.quick else 3)
    example_two(1 if args.quick else 5)


if __name__ == "__main__":
    main()
