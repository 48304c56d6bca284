"""Scenes and layouts shared by the tests: boxes on a fixed floor."""

from __future__ import annotations

import numpy as np

import constraint_stabilization as cs

FLOOR_HALF = np.array([4.0, 4.0, 0.5])


def random_unit_quaternions(rng: np.random.Generator, count: int) -> np.ndarray:
    q = rng.normal(size=(count, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def boxes_on_floor(count: int, seed: int):
    """A floor (fixed, top at z = 0) and ``count`` boxes; their half
    extents (floor first) and a scene."""
    rng = np.random.default_rng(seed)
    halves = [FLOOR_HALF] + [rng.uniform(0.15, 0.35, size=3) for _ in range(count)]
    scene = cs.Scene()
    scene.add_body(cs.box(FLOOR_HALF), fixed=True, name="floor")
    for i, h in enumerate(halves[1:]):
        scene.add_body(cs.box(h), mass=float(rng.uniform(0.5, 2.0)), name=f"box {i}")
    return halves, scene


def overlapping_layout(count: int, seed: int, spread: float = 0.6) -> np.ndarray:
    """``(1 + count, 7)`` xyzw poses: the floor, then boxes packed into a
    small region so that many overlap (and sink into the floor)."""
    rng = np.random.default_rng(seed)
    poses = np.zeros((count + 1, 7))
    poses[0] = [0, 0, -0.5, 0, 0, 0, 1]
    poses[1:, :2] = rng.uniform(-spread, spread, size=(count, 2))
    poses[1:, 2] = rng.uniform(0.0, 0.8, size=count)
    poses[1:, 3:] = random_unit_quaternions(rng, count)
    return poses
