"""Example 2: 40 random mesh and box objects dropped into a MuJoCo bin
with overlaps. MuJoCo alone from the raw layout against MuJoCo from the
layout stabilized by the adapter: kinetic energy over time, objects thrown
out of the bin, as numbers and (with matplotlib) a plot.

    python python/examples/mujoco_bin.py [--seeds 5] [--objects 40] [--plot bin.png]
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass
from typing import List

import mujoco
import numpy as np

from constraint_stabilization.mujoco import stabilize_mujoco

BIN_HALF = 0.25  # inner half width of the bin, m
WALL_HEIGHT = 0.2
SIMULATED_SECONDS = 1.5


def bin_model(objects: int, seed: int) -> mujoco.MjModel:
    """A bin on a plane and ``objects`` free bodies, every other one a
    random convex mesh, the rest boxes, 2-4 cm across."""
    rng = np.random.default_rng(seed)
    assets, bodies = [], []
    for i in range(objects):
        s = rng.uniform(0.02, 0.04)
        if i % 2:
            p = rng.normal(size=(16, 3))
            p = p / np.linalg.norm(p, axis=1, keepdims=True) * s * rng.uniform(0.6, 1.0, size=3)
            assets.append(f'<mesh name="m{i}" vertex="{" ".join(f"{v:.6f}" for v in p.ravel())}"/>')
            geom = f'<geom type="mesh" mesh="m{i}" density="800"/>'
        else:
            h = s * rng.uniform(0.5, 1.0, size=3)
            geom = f'<geom type="box" size="{h[0]:.6f} {h[1]:.6f} {h[2]:.6f}" density="800"/>'
        bodies.append(f'<body name="obj{i}"><freejoint/>{geom}</body>')
    w, t, hgt = BIN_HALF, 0.01, WALL_HEIGHT / 2
    walls = "".join(
        f'<geom type="box" size="{sx} {sy} {hgt}" pos="{px} {py} {hgt}"/>'
        for sx, sy, px, py in [(t, w + t, w + t, 0), (t, w + t, -w - t, 0), (w + t, t, 0, w + t), (w + t, t, 0, -w - t)]
    )
    xml = f"""<mujoco><option timestep="0.002"/><asset>{"".join(assets)}</asset>
      <worldbody><geom name="floor" type="plane" size="2 2 0.1"/>{walls}{"".join(bodies)}</worldbody></mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def drop_layout(model: mujoco.MjModel, data: mujoco.MjData, seed: int) -> None:
    """Every object at a random pose in the bin, low enough that many
    overlap each other, the floor and the walls; at rest."""
    rng = np.random.default_rng(1000 + seed)
    mujoco.mj_resetData(model, data)
    for j in range(model.njnt):
        a = model.jnt_qposadr[j]
        data.qpos[a : a + 2] = rng.uniform(-BIN_HALF, BIN_HALF, size=2)
        data.qpos[a + 2] = rng.uniform(0.0, 0.06)
        q = rng.normal(size=4)
        data.qpos[a + 3 : a + 7] = q / np.linalg.norm(q)
    data.qvel[:] = 0.0
    mujoco.mj_forward(model, data)


def kinetic_energy(model: mujoco.MjModel, data: mujoco.MjData) -> float:
    """MuJoCo's own kinetic energy (``mj_energyVel``), J."""
    mujoco.mj_energyVel(model, data)
    return float(data.energy[1])


# The depenetration burst: the first BURST_SECONDS of the run.
BURST_SECONDS = 0.1


@dataclass
class Run:
    energy: np.ndarray  # kinetic energy per step, J
    ejected: int  # objects outside the bin at the end
    peak_speed: float  # fastest object over the run, m/s
    deepest_start: float  # MuJoCo's deepest contact at the start (m, negative = penetration)
    stabilize_ms: float = 0.0
    status: str = ""


def simulate(model: mujoco.MjModel, data: mujoco.MjData) -> Run:
    deepest = min((c.dist for c in data.contact[: data.ncon]), default=0.0)
    steps = int(SIMULATED_SECONDS / model.opt.timestep)
    energy = np.zeros(steps)
    peak_speed = 0.0
    dofs = [model.jnt_dofadr[j] for j in range(model.njnt)]
    for k in range(steps):
        mujoco.mj_step(model, data)
        energy[k] = kinetic_energy(model, data)
        peak_speed = max(peak_speed, max(float(np.linalg.norm(data.qvel[d : d + 3])) for d in dofs))
    ejected = 0
    for j in range(model.njnt):
        x, y, z = data.qpos[model.jnt_qposadr[j] : model.jnt_qposadr[j] + 3]
        ejected += int(max(abs(x), abs(y)) > BIN_HALF or z < -0.05)
    return Run(energy=energy, ejected=ejected, peak_speed=peak_speed, deepest_start=float(deepest))


def compare(objects: int, seed: int):
    model = bin_model(objects, seed)
    data = mujoco.MjData(model)
    drop_layout(model, data, seed)
    raw = simulate(model, data)
    drop_layout(model, data, seed)
    start = time.perf_counter()
    result = stabilize_mujoco(model, data)
    ms = (time.perf_counter() - start) * 1e3
    fixed = simulate(model, data)
    fixed.stabilize_ms, fixed.status = ms, result.report.status
    return raw, fixed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--objects", type=int, default=40)
    parser.add_argument("--plot", default="", help="write a PNG of the kinetic energy (needs matplotlib)")
    args = parser.parse_args()
    rows: List[str] = []
    runs = []
    burst = int(BURST_SECONDS / 0.002)
    print("| seed | deepest raw (mm) | raw: KE at 10 ms (J) | raw: peak KE first 0.1 s (J) | raw: fastest (m/s) | raw: out of bin | stabilize (ms, status) | deepest after (mm) | stabilized: KE at 10 ms (J) | stabilized: peak KE first 0.1 s (J) | stabilized: fastest (m/s) | stabilized: out of bin |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for seed in range(args.seeds):
        raw, fixed = compare(args.objects, seed)
        runs.append((raw, fixed))
        row = (
            f"| {seed} | {-raw.deepest_start * 1e3:.1f} | {raw.energy[4]:.3g} | {raw.energy[:burst].max():.3g} | {raw.peak_speed:.2f} | {raw.ejected} | "
            f"{fixed.stabilize_ms:.1f} ({fixed.status}) | {max(0.0, -fixed.deepest_start) * 1e3:.2g} | {fixed.energy[4]:.3g} | {fixed.energy[:burst].max():.3g} | {fixed.peak_speed:.2f} | {fixed.ejected} |"
        )
        rows.append(row)
        print(row, flush=True)
    peak_raw = np.median([r.energy[:burst].max() for r, _ in runs])
    peak_fixed = np.median([f.energy[:burst].max() for _, f in runs])
    print(f"median peak kinetic energy in the first {BURST_SECONDS} s: raw {peak_raw:.3g} J, stabilized {peak_fixed:.3g} J; "
          f"ejected in all: raw {sum(r.ejected for r, _ in runs)}, stabilized {sum(f.ejected for _, f in runs)} "
          f"of {args.seeds * args.objects}")
    if args.plot:
        try:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            print("matplotlib is not installed: no plot (pip install matplotlib)")
            return
        raw, fixed = runs[0]
        t = np.arange(1, raw.energy.size + 1) * 0.002
        plt.figure(figsize=(6, 3.5))
        plt.semilogy(t, np.maximum(raw.energy, 1e-9), label="MuJoCo from the raw layout")
        plt.semilogy(t, np.maximum(fixed.energy, 1e-9), label="MuJoCo from the stabilized layout")
        plt.xlabel("time (s)")
        plt.ylabel("kinetic energy (J)")
        plt.title(f"{args.objects} objects dropped into a bin (seed 0)")
        plt.legend()
        plt.tight_layout()
        plt.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
