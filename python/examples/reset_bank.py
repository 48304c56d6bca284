"""Example 3: a reset bank. 1,000 random layouts of one scene (boxes and
convex hulls spawned into a bin, overlapping each other and the bin)
repaired with one batch call instead of rejected and re-sampled: the time
per layout and the fraction converged.

    python python/examples/reset_bank.py [--layouts 1000] [--objects 20] [--threads 2]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import constraint_stabilization as cs

BIN_HALF = 0.25  # inner half width, m
WALL = 0.01


def bank_scene(objects: int, seed: int = 0) -> cs.Scene:
    """A fixed bin (floor and four walls) and ``objects`` dynamic bodies,
    boxes and random convex hulls of 2-4 cm alternately."""
    rng = np.random.default_rng(seed)
    scene = cs.Scene()
    scene.add_body(cs.box([BIN_HALF + 2 * WALL, BIN_HALF + 2 * WALL, WALL]), fixed=True, name="floor")
    for _ in range(2):
        scene.add_body(cs.box([WALL, BIN_HALF + 2 * WALL, 0.1]), fixed=True, name="wall x")
        scene.add_body(cs.box([BIN_HALF + 2 * WALL, WALL, 0.1]), fixed=True, name="wall y")
    for i in range(objects):
        s = rng.uniform(0.02, 0.04)
        if i % 2:
            p = rng.normal(size=(16, 3))
            p = p / np.linalg.norm(p, axis=1, keepdims=True) * s * rng.uniform(0.6, 1.0, size=3)
            scene.add_body(cs.hull(p), density=800.0, name=f"hull {i}")
        else:
            scene.add_body(cs.box(s * rng.uniform(0.5, 1.0, size=3)), density=800.0, name=f"box {i}")
    return scene


def fixed_poses() -> np.ndarray:
    """The bin's five bodies, wxyz."""
    c = BIN_HALF + WALL
    return np.array(
        [
            [0, 0, -WALL, 1, 0, 0, 0],
            [c, 0, 0.1, 1, 0, 0, 0],
            [0, c, 0.1, 1, 0, 0, 0],
            [-c, 0, 0.1, 1, 0, 0, 0],
            [0, -c, 0.1, 1, 0, 0, 0],
        ],
        dtype=float,
    )


def random_layouts(scene: cs.Scene, count: int, seed: int) -> np.ndarray:
    """``(count, n, 7)`` wxyz layouts: the bin fixed, every object at a
    uniformly random pose in the lower part of the bin."""
    rng = np.random.default_rng(seed)
    n = len(scene)
    layouts = np.zeros((count, n, 7))
    layouts[:, :5] = fixed_poses()
    objects = n - 5
    layouts[:, 5:, :2] = rng.uniform(-BIN_HALF + 0.02, BIN_HALF - 0.02, size=(count, objects, 2))
    layouts[:, 5:, 2] = rng.uniform(0.0, 0.06, size=(count, objects))
    q = rng.normal(size=(count, objects, 4))
    layouts[:, 5:, 3:] = q / np.linalg.norm(q, axis=2, keepdims=True)
    return layouts


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--layouts", type=int, default=1000)
    parser.add_argument("--objects", type=int, default=20)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    scene = bank_scene(args.objects)
    layouts = random_layouts(scene, args.layouts, seed=1)
    start = time.perf_counter()
    bank = cs.stabilize_batch(scene, layouts, quaternion_order="wxyz", threads=args.threads)
    wall = time.perf_counter() - start
    overlapping = np.mean(bank.depth_before > bank.tolerance)
    print(f"{args.layouts} layouts of {args.objects} objects in a bin, {args.threads} threads: "
          f"{wall:.2f} s, {wall / args.layouts * 1e3:.2f} ms per layout")
    print(f"overlapping before: {overlapping:.1%} (median deepest {np.median(bank.depth_before) * 1e3:.1f} mm); "
          f"converged: {np.mean(bank.converged):.1%}; passes median {np.median(bank.passes):.0f}, max {bank.passes.max()}")
    statuses, counts = np.unique(bank.status, return_counts=True)
    print("status: " + ", ".join(f"{s} {c}" for s, c in zip(statuses, counts)))


if __name__ == "__main__":
    main()
