"""The engine-neutral API: round trips, the quaternion order, the report."""

from __future__ import annotations

import numpy as np
import pytest

import constraint_stabilization as cs
from layouts import boxes_on_floor, overlapping_layout
from oracle import deepest_box_penetration

WXYZ = [0, 1, 2, 6, 3, 4, 5]  # xyzw row -> wxyz row


def test_a_separated_layout_comes_back_bit_for_bit():
    halves, scene = boxes_on_floor(3, seed=1)
    poses = np.array(
        [[0, 0, -0.5, 0, 0, 0, 1], [-2, 0, 1, 0, 0, 0, 1], [0, 0, 1, 0, 0, 0.6, 0.8], [2, 0, 1, 0.5, 0.5, 0.5, 0.5]],
        dtype=float,
    )
    out, report = cs.stabilize(scene, poses, quaternion_order="xyzw")
    assert report.status == "nothing_to_do" and report.converged
    assert np.array_equal(out, poses)
    out_wxyz, _ = cs.stabilize(scene, poses[:, WXYZ], quaternion_order="wxyz")
    assert np.array_equal(out_wxyz, poses[:, WXYZ])


def test_a_sunk_box_is_lifted_by_its_depth():
    scene = cs.Scene()
    scene.add_body(cs.box([5, 5, 0.5]), fixed=True)
    scene.add_body(cs.box([0.5, 0.5, 0.5]), mass=1.0)
    poses = np.array([[0, 0, -0.5, 0, 0, 0, 1], [0.3, -0.2, 0.4, 0, 0, 0, 1]], dtype=float)
    out, report = cs.stabilize(scene, poses, quaternion_order="xyzw")
    assert report.status == "converged"
    assert report.depth_before == pytest.approx(0.1, abs=1e-12)
    # Lifted straight up by the depth and the library's default target
    # margin (1e-5 of the scene's scale), to within the tolerance.
    target = 1e-5 * scene.scale
    assert out[1, 2] == pytest.approx(0.5 + target, abs=2 * report.tolerance + 1e-9)
    assert out[1, 2] >= 0.5 - report.tolerance
    assert np.array_equal(out[0], poses[0])
    assert out[1, :2] == pytest.approx(poses[1, :2], abs=1e-9)


def test_random_overlapping_boxes_are_separated_by_the_oracle():
    halves, scene = boxes_on_floor(12, seed=7)
    poses = overlapping_layout(12, seed=7)
    assert deepest_box_penetration(halves, poses) > 0.05
    out, report = cs.stabilize(scene, poses, quaternion_order="xyzw")
    assert report.converged, report.status
    assert deepest_box_penetration(halves, out) <= report.tolerance
    assert np.array_equal(out[0], poses[0])
    assert report.passes >= 1 and report.islands and report.times["total"] > 0


def test_a_wxyz_input_gives_the_same_world_as_its_xyzw_twin():
    halves, scene = boxes_on_floor(8, seed=3)
    xyzw = overlapping_layout(8, seed=3)
    out_xyzw, rep_a = cs.stabilize(scene, xyzw, quaternion_order="xyzw")
    out_wxyz, rep_b = cs.stabilize(scene, xyzw[:, WXYZ], quaternion_order="wxyz")
    assert np.array_equal(out_wxyz, out_xyzw[:, WXYZ])
    assert rep_a.depth_after == rep_b.depth_after and rep_a.passes == rep_b.passes
    # Read the wrong way, the same numbers are another world.
    out_wrong, _ = cs.stabilize(scene, xyzw[:, WXYZ], quaternion_order="xyzw")
    assert not np.array_equal(out_wrong, out_xyzw[:, WXYZ])


def test_the_quaternion_order_is_required_and_checked():
    halves, scene = boxes_on_floor(1, seed=0)
    poses = overlapping_layout(1, seed=0)
    with pytest.raises(TypeError):
        cs.stabilize(scene, poses)  # type: ignore[call-arg]
    for bad in ["XYZW", "wxzy", "", None, 1]:
        with pytest.raises(cs.InputError):
            cs.stabilize(scene, poses, quaternion_order=bad)
    with pytest.raises(TypeError):
        cs.stabilize_batch(scene, poses[None])  # type: ignore[call-arg]


def test_settings_are_keywords_with_the_library_defaults():
    names = cs.setting_names()
    assert "tolerance_relative" in names and "time_budget" in names and "friction" in names
    halves, scene = boxes_on_floor(4, seed=5)
    poses = overlapping_layout(4, seed=5)
    _, default = cs.stabilize(scene, poses, quaternion_order="xyzw")
    assert default.tolerance == pytest.approx(1e-6 * scene.scale)
    _, loose = cs.stabilize(scene, poses, quaternion_order="xyzw", tolerance_absolute=1e-3, max_passes=50, time_budget=10.0, friction=0.5)
    assert loose.tolerance == 1e-3
    _, one = cs.stabilize(scene, poses, quaternion_order="xyzw", max_passes=1)
    assert one.passes <= 1
    # The same minimizer whichever way the friction rows enter the problem.
    answers = {
        rows: cs.stabilize(scene, poses, quaternion_order="xyzw", friction=0.5, friction_rows=rows)
        for rows in ["all", "implied", "generated"]
    }
    for rows, (corrected, report) in answers.items():
        assert report.converged, rows
        assert report.certified_pairs >= 0 and report.reused_pairs == 0
        assert np.allclose(corrected, answers["all"][0], atol=1e-6 * scene.scale), rows


def test_compounds_and_round_shapes_build_and_separate():
    scene = cs.Scene()
    scene.add_body(cs.box([5, 5, 0.5]), fixed=True)
    dumbbell = cs.compound(
        [cs.sphere(0.2), cs.sphere(0.2), cs.capsule(0.05, 0.3)],
        np.array([[0, 0, -0.3, 1, 0, 0, 0], [0, 0, 0.3, 1, 0, 0, 0], [0, 0, 0, 1, 0, 0, 0]], dtype=float),
        quaternion_order="wxyz",
    )
    assert dumbbell.kind == "compound"
    scene.add_body(dumbbell, mass=2.0)
    scene.add_body(cs.cylinder(0.2, 0.1), density=500.0)
    scene.add_body(cs.round_box([0.1, 0.1, 0.1], 0.05), mass=1.0)
    scene.add_body(cs.hull(np.random.default_rng(0).normal(size=(12, 3)) * 0.2), mass=1.0)
    scene.add_body(cs.cone(0.2, 0.2), mass=1.0)
    poses = np.array(
        [
            [0, 0, -0.5, 0, 0, 0, 1],
            [0, 0, 0.15, 0, 0.7071067811865476, 0, 0.7071067811865476],
            [0.45, 0, 0.05, 0, 0, 0, 1],
            [0.0, 0.45, 0.1, 0, 0, 0, 1],
            [0.4, 0.4, 0.1, 0, 0, 0, 1],
            [-0.5, 0.0, 0.1, 0, 0, 0, 1],
        ]
    )
    out, report = cs.stabilize(scene, poses, quaternion_order="xyzw")
    assert report.converged, report.status
    assert report.depth_before > 0.05
    assert np.array_equal(out[0], poses[0])


def test_the_scene_is_not_changed_by_a_call():
    halves, scene = boxes_on_floor(4, seed=9)
    poses = overlapping_layout(4, seed=9)
    first, _ = cs.stabilize(scene, poses, quaternion_order="xyzw")
    second, _ = cs.stabilize(scene, poses, quaternion_order="xyzw")
    assert np.array_equal(first, second)
    assert len(scene) == 5 and scene.fixed == [True] + [False] * 4
    assert scene.masses[0] is None and all(m > 0 for m in scene.masses[1:])
