"""MuJoCo models for the adapter's tests and examples: a bin on a plane
with free objects of every handled type, placed to overlap."""

from __future__ import annotations

import numpy as np


def hull_points(rng: np.random.Generator, count: int, size: float) -> np.ndarray:
    """Points on a squashed sphere: a random convex mesh."""
    p = rng.normal(size=(count, 3))
    p /= np.linalg.norm(p, axis=1, keepdims=True)
    return p * size * rng.uniform(0.6, 1.0, size=3)


def bin_xml(kinds, seed: int, extras: str = "", size: float = 0.05) -> str:
    """A 0.6 m square bin on a plane and one free body per entry of
    ``kinds`` (``box``, ``mesh``, ``sphere``, ``capsule``, ``cylinder``,
    ``pair`` (a box and a sphere on one body), ``ellipsoid``)."""
    rng = np.random.default_rng(seed)
    assets, bodies = [], []
    for i, kind in enumerate(kinds):
        s = size * rng.uniform(0.7, 1.3)
        if kind == "box":
            h = s * rng.uniform(0.5, 1.0, size=3)
            geom = f'<geom type="box" size="{h[0]} {h[1]} {h[2]}"/>'
        elif kind == "mesh":
            pts = hull_points(rng, 14, s)
            assets.append(f'<mesh name="m{i}" vertex="{" ".join(map(str, pts.ravel()))}"/>')
            geom = f'<geom type="mesh" mesh="m{i}"/>'
        elif kind == "sphere":
            geom = f'<geom type="sphere" size="{s * 0.7}"/>'
        elif kind == "capsule":
            geom = f'<geom type="capsule" size="{s * 0.4} {s * 0.8}"/>'
        elif kind == "cylinder":
            geom = f'<geom type="cylinder" size="{s * 0.6} {s * 0.5}"/>'
        elif kind == "pair":
            geom = (
                f'<geom type="box" size="{s * 0.5} {s * 0.4} {s * 0.3}" pos="{s * 0.4} 0 0" euler="0 0 20"/>'
                f'<geom type="sphere" size="{s * 0.4}" pos="{-s * 0.5} 0 0.01"/>'
            )
        elif kind == "ellipsoid":
            geom = f'<geom type="ellipsoid" size="{s} {s * 0.6} {s * 0.5}"/>'
        else:
            raise ValueError(kind)
        bodies.append(f'<body name="obj{i}"><freejoint name="j{i}"/>{geom}</body>')
    return f"""
<mujoco>
  <option timestep="0.002"/>
  <asset>{"".join(assets)}</asset>
  <worldbody>
    <geom name="floor" type="plane" size="2 2 0.1"/>
    <geom name="wall_px" type="box" size="0.02 0.32 0.15" pos="0.32 0 0.15"/>
    <geom name="wall_nx" type="box" size="0.02 0.32 0.15" pos="-0.32 0 0.15"/>
    <geom name="wall_py" type="box" size="0.32 0.02 0.15" pos="0 0.32 0.15"/>
    <geom name="wall_ny" type="box" size="0.32 0.02 0.15" pos="0 -0.32 0.15"/>
    <geom name="decor" type="sphere" size="0.05" pos="1 1 0.5" contype="0" conaffinity="0"/>
    {"".join(bodies)}
    {extras}
  </worldbody>
</mujoco>
"""


def random_overlapping_state(model, data, seed: int, spread: float = 0.2, height: float = 0.15) -> None:
    """Puts every free body at a random pose in a small region of the bin
    (so that they overlap each other, the floor and the walls)."""
    import mujoco

    rng = np.random.default_rng(seed)
    for j in range(model.njnt):
        if model.jnt_type[j] != mujoco.mjtJoint.mjJNT_FREE:
            continue
        a = model.jnt_qposadr[j]
        data.qpos[a : a + 2] = rng.uniform(-spread, spread, size=2)
        data.qpos[a + 2] = rng.uniform(0.0, height)
        q = rng.normal(size=4)
        data.qpos[a + 3 : a + 7] = q / np.linalg.norm(q)
    data.qvel[:] = rng.normal(size=model.nv)
    mujoco.mj_forward(model, data)
