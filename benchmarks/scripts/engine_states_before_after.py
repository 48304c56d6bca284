#!/usr/bin/env python3
"""Side-by-side run of two builds of the `stabilize` tool on the engine states.

Usage: engine_states_before_after.py BEFORE_BIN AFTER_BIN [REPEATS] > table.md

For each scene file of tests/data/engine/, the two binaries run
`stabilize scene FILE -o OUT` alternately REPEATS times (default 5); the
table gives the exit code, status, passes, mass-weighted displacement and the
median of the call's own total time (`report.times_s.total`) of each. The
penetration left in each output is measured by the AFTER binary with a
tolerance above every depth (the call then only measures): its depth is the
exact separating-axis depth (checked against a brute force in
tests/it/contact/manifold.rs), never the depth a build reports about itself.
"""
import glob, json, os, statistics, subprocess, sys, tempfile

def run(binary, scene, out):
    proc = subprocess.run([binary, "scene", scene, "-o", out], capture_output=True, text=True)
    report = None
    if os.path.exists(out):
        report = json.load(open(out)).get("report")
    return proc.returncode, report, proc.stderr.strip().splitlines()[-1:] if proc.stderr else []

def exact_depth(measurer, out):
    data = json.load(open(out))
    data.pop("report", None)
    data["settings"] = {"tolerance": 1e3}
    with tempfile.TemporaryDirectory() as tmp:
        src, dst = os.path.join(tmp, "in.json"), os.path.join(tmp, "out.json")
        json.dump(data, open(src, "w"))
        subprocess.run([measurer, "scene", src, "-o", dst], capture_output=True)
        return json.load(open(dst))["report"]["penetration_before"]

def main():
    before, after = sys.argv[1], sys.argv[2]
    repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    root = os.path.join(os.path.dirname(__file__), "..", "..", "tests", "data", "engine")
    print("| state | before: exit, status, passes | after: exit, status, passes | depth in | exact depth left before / after | displacement before / after | median time before / after (ms) |")
    print("|---|---|---|---:|---|---|---|")
    for scene in sorted(glob.glob(os.path.join(root, "*.json"))):
        name = os.path.basename(scene)[:-5]
        rows = {"before": [], "after": []}
        with tempfile.TemporaryDirectory() as tmp:
            outs = {k: os.path.join(tmp, k + ".json") for k in rows}
            for _ in range(repeats):
                for label, binary in (("before", before), ("after", after)):
                    if os.path.exists(outs[label]):
                        os.remove(outs[label])
                    rows[label].append(run(binary, scene, outs[label]))
            cells = {}
            for label in rows:
                code, report, err = rows[label][-1]
                if report is None:
                    cells[label] = (f"{code}, failed: {' '.join(err)[:60]}", "-", "-", "-")
                    continue
                times = [r[1]["times_s"]["total"] * 1e3 for r in rows[label] if r[1]]
                left = exact_depth(after, outs[label])
                cells[label] = (f"{code}, {report['status']}, {report['passes']}", f"{left:.2e}",
                                f"{report['displacement']:.4g}", f"{statistics.median(times):.1f}")
                depth_in = report["penetration_before"] if label == "after" else None
            d_in = exact_depth(after, scene)
        b, a = cells["before"], cells["after"]
        print(f"| {name} | {b[0]} | {a[0]} | {d_in:.2e} | {b[1]} / {a[1]} | {b[2]} / {a[2]} | {b[3]} / {a[3]} |")

if __name__ == "__main__":
    main()
