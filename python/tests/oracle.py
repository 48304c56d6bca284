"""An independent depth oracle for the tests: the exact penetration depth
of two boxes by separating axes (the three face normals of each and the
nine edge-edge cross products; for convex polytopes the smallest overlap
over these axes is the depth), written here in numpy, not taken from the
library."""

from __future__ import annotations

import itertools

import numpy as np


def rotation_xyzw(q: np.ndarray) -> np.ndarray:
    x, y, z, w = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def box_vertices(half: np.ndarray, pose_xyzw: np.ndarray) -> np.ndarray:
    corners = np.array(list(itertools.product([-1, 1], repeat=3)), dtype=float) * half
    return corners @ rotation_xyzw(pose_xyzw[3:]).T + pose_xyzw[:3]


def box_depth(half_a, pose_a, half_b, pose_b) -> float:
    """Penetration depth of two boxes (0 if they are apart)."""
    va, vb = box_vertices(np.asarray(half_a), pose_a), box_vertices(np.asarray(half_b), pose_b)
    ra, rb = rotation_xyzw(pose_a[3:]), rotation_xyzw(pose_b[3:])
    axes = [ra[:, i] for i in range(3)] + [rb[:, i] for i in range(3)]
    for i in range(3):
        for j in range(3):
            c = np.cross(ra[:, i], rb[:, j])
            if np.linalg.norm(c) > 1e-9:
                axes.append(c / np.linalg.norm(c))
    depth = np.inf
    for axis in axes:
        pa, pb = va @ axis, vb @ axis
        overlap = min(pa.max() - pb.min(), pb.max() - pa.min())
        if overlap <= 0:
            return 0.0
        depth = min(depth, overlap)
    return float(depth)


def deepest_box_penetration(halves, poses_xyzw) -> float:
    return max(
        (box_depth(halves[i], poses_xyzw[i], halves[j], poses_xyzw[j]) for i, j in itertools.combinations(range(len(halves)), 2)),
        default=0.0,
    )
