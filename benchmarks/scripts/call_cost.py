#!/usr/bin/env python3
"""Issue 21's loop goal from a `with_and_without` results file.

Usage: call_cost.py DIR/with_and_without.md > table.md

Reads the rigid-body table of `examples/with_and_without.rs` (one row per
scene and run) and, for every row of the bridge's default run, prints the
median and worst call against Rapier's median step of the same run and
against its median step while some body is awake (a settled world sleeps
and steps in microseconds, so the ratio to its median step says little):
the goal is the median call at most 10x and the worst at most 50x the
step. The joint scenes' table already gives its calls in Rapier steps and
is printed as it is.
"""
import sys

MEDIAN_GOAL = 10.0
WORST_GOAL = 50.0


def rows(lines, header_start):
    """The rows of the table whose header starts with `header_start`."""
    out, inside, columns = [], False, []
    for line in lines:
        if line.startswith(header_start):
            inside, columns = True, [c.strip() for c in line.strip().strip("|").split("|")]
            continue
        if inside and line.startswith("|---"):
            continue
        if inside and line.startswith("|"):
            out.append(dict(zip(columns, [c.strip() for c in line.strip().strip("|").split("|")])))
        elif inside:
            inside = False
    return out


def ratio(value, step):
    return value / step if step > 0 else float("inf")


def main(path):
    lines = open(path).read().splitlines()
    print("| scene | call ms (median / max) | step ms | awake step ms | median / awake step | worst / awake step | goals (10x / 50x) |")
    print("|---|---|---|---|---|---|---|")
    for row in rows(lines, "| scene | run | deepest after step 1"):
        awake_column = "call ms while all asleep / Rapier step ms while awake (medians)"
        if "default" not in row.get("run", "") or awake_column not in row:
            continue
        median_ms, max_ms = (float(x) for x in row["call ms (median / max)"].split("/"))
        step = float(row["Rapier step ms (median)"])
        awake = row[awake_column].split("/")[1].strip()
        awake = float(awake) if awake not in ("-", "") else step
        median_ratio, worst_ratio = ratio(median_ms, awake), ratio(max_ms, awake)
        goals = "{} / {}".format(
            "met" if median_ratio <= MEDIAN_GOAL else "missed",
            "met" if worst_ratio <= WORST_GOAL else "missed",
        )
        print(f"| {row['scene']} | {median_ms:.2f} / {max_ms:.1f} | {step:.3f} | {awake:.4f} | {median_ratio:.2f}x | {worst_ratio:,.0f}x | {goals} |")
    joints = rows(lines, "| scene | run | worst joint separation")
    if joints:
        print()
        print("| scene | run | call ms (median / max) | call in Rapier steps (median / worst) |")
        print("|---|---|---|---|")
        for row in joints:
            if "default" in row.get("run", ""):
                print(f"| {row['scene']} | {row['run']} | {row['call ms (median / max)']} | {row['call in Rapier steps (median / worst)']} |")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
