#!/usr/bin/env python3
"""Summarize `ENGINE_QPS_PER_QP=1 cargo bench --bench engine_qps` output
(its stderr) by size of `dq`: per bin of entries, the QPs, each variant's
summed median time (ms), and how often the first variant was faster than
the second; then the QPs above 132 entries one per line, with the rows
violated at `dq = 0` against the entries (`Auto`'s rule for the dual
active-set method).

    ENGINE_QPS_PER_QP=1 cargo bench --bench engine_qps --features serde -- \
        --min-rows 2 --rounds 3 --variants das,ip,lemke 2> per_qp.txt >/dev/null
    python3 benchmarks/scripts/engine_qps_bins.py per_qp.txt das,ip,lemke
"""
import sys

BINS = [(0, 24), (25, 60), (61, 132), (133, 240), (241, 400), (401, 600), (601, 10**9)]


def read(path):
    rows = []
    for line in open(path):
        if not line.startswith("per-qp"):
            continue
        t = line.split()
        # per-qp NAME dofs D rows R violated V ms t1 t2 ... iterations i1 i2 ...
        at_ms = t.index("ms")
        at_it = t.index("iterations")
        rows.append(
            {
                "state": t[1],
                "dofs": int(t[3]),
                "rows": int(t[5]),
                "violated": int(t[7]),
                "ms": [float(x) for x in t[at_ms + 1 : at_it]],
                "iterations": [int(x) for x in t[at_it + 1 :]],
            }
        )
    return rows


def main():
    path = sys.argv[1]
    names = sys.argv[2].split(",") if len(sys.argv) > 2 else None
    rows = read(path)
    if not rows:
        sys.exit("no per-qp lines")
    k = len(rows[0]["ms"])
    names = names or [f"v{i}" for i in range(k)]
    print("| entries of dq | QPs | " + " | ".join(f"{n} ms" for n in names) + f" | {names[0]} faster than {names[1]} |")
    print("|---|---:|" + "---:|" * k + "---:|")
    for lo, hi in BINS:
        sel = [r for r in rows if lo <= r["dofs"] <= hi]
        if not sel:
            continue
        sums = [sum(r["ms"][i] for r in sel) for i in range(k)]
        wins = sum(1 for r in sel if r["ms"][0] < r["ms"][1])
        label = f"{lo}-{hi}" if hi < 10**9 else f"above {lo - 1}"
        print(f"| {label} | {len(sel)} | " + " | ".join(f"{s:.2f}" for s in sums) + f" | {wins} of {len(sel)} |")
    print()
    print("| state | entries | rows | violated | violated <= entries | " + " | ".join(f"{n} ms" for n in names) + f" | {names[0]} / {names[1]} |")
    print("|---|---:|---:|---:|---|" + "---:|" * k + "---:|")
    for r in sorted((r for r in rows if r["dofs"] > 132), key=lambda r: (r["dofs"], r["state"])):
        ratio = r["ms"][0] / r["ms"][1] if r["ms"][1] > 0 else float("nan")
        rule = "yes" if r["violated"] <= r["dofs"] else "no"
        print(
            f"| {r['state']} | {r['dofs']} | {r['rows']} | {r['violated']} | {rule} | "
            + " | ".join(f"{x:.3f}" for x in r["ms"])
            + f" | {ratio:.2f} |"
        )


if __name__ == "__main__":
    main()
