"""The batch call equals the sequential calls bit for bit, whatever the
number of threads."""

from __future__ import annotations

import numpy as np
import pytest

import constraint_stabilization as cs
from layouts import boxes_on_floor, overlapping_layout
from oracle import deepest_box_penetration

LAYOUTS = 6
BOXES = 10


@pytest.fixture(scope="module")
def bank():
    halves, scene = boxes_on_floor(BOXES, seed=11)
    layouts = np.stack([overlapping_layout(BOXES, seed=100 + b) for b in range(LAYOUTS)])
    return halves, scene, layouts


@pytest.mark.parametrize("threads", [1, 2])
def test_batch_equals_sequential_bit_for_bit(bank, threads):
    halves, scene, layouts = bank
    result = cs.stabilize_batch(scene, layouts, quaternion_order="xyzw", threads=threads)
    assert result.poses.shape == layouts.shape
    for b in range(LAYOUTS):
        poses, report = cs.stabilize(scene, layouts[b], quaternion_order="xyzw")
        assert np.array_equal(result.poses[b], poses), f"layout {b}"
        assert result.status[b] == report.status
        assert result.passes[b] == report.passes
        assert result.depth_before[b] == report.depth_before
        assert result.depth_after[b] == report.depth_after
        assert result.converged[b] == report.converged
    assert result.converged.all()
    for b in range(LAYOUTS):
        assert deepest_box_penetration(halves, result.poses[b]) <= result.tolerance[b]


def test_batch_in_wxyz_is_the_permuted_xyzw_batch(bank):
    halves, scene, layouts = bank
    wxyz = layouts[..., [0, 1, 2, 6, 3, 4, 5]]
    a = cs.stabilize_batch(scene, layouts, quaternion_order="xyzw", threads=2)
    b = cs.stabilize_batch(scene, wxyz, quaternion_order="wxyz", threads=2)
    assert np.array_equal(b.poses, a.poses[..., [0, 1, 2, 6, 3, 4, 5]])


def test_batch_checks_its_input(bank):
    halves, scene, layouts = bank
    with pytest.raises(cs.InputError, match="shape"):
        cs.stabilize_batch(scene, layouts[0], quaternion_order="xyzw")
    bad = layouts.copy()
    bad[3, 2, 3:] = [0, 0, 0, 3.0]
    with pytest.raises(cs.BodyError, match="layout 3"):
        cs.stabilize_batch(scene, bad, quaternion_order="xyzw", threads=2)
    with pytest.raises(cs.InputTypeError):
        cs.stabilize_batch(scene, layouts, quaternion_order="xyzw", threads=1.5)
    empty = cs.stabilize_batch(scene, layouts[:0], quaternion_order="xyzw", threads=1)
    assert empty.poses.shape == (0, BOXES + 1, 7) and empty.status == []
