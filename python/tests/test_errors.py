"""Every error class, raised by real misuse where one exists; no panic
ever reaches Python."""

from __future__ import annotations

import numpy as np
import pytest

import constraint_stabilization as cs
from constraint_stabilization import _native
from layouts import boxes_on_floor, overlapping_layout


@pytest.fixture
def two_boxes():
    halves, scene = boxes_on_floor(2, seed=2)
    return scene, overlapping_layout(2, seed=2)


def test_the_classes_form_one_family():
    for cls in [cs.InputError, cs.InputTypeError, cs.GeometryError, cs.SceneError, cs.BodyError, cs.SettingsError, cs.SolverError, cs.DetectionError, cs.InternalError]:
        assert issubclass(cls, cs.StabilizationError)
    assert issubclass(cs.InputError, ValueError) and issubclass(cs.InputTypeError, TypeError)
    assert issubclass(cs.BodyError, cs.SceneError) and issubclass(cs.SettingsError, ValueError)


def test_array_checks_come_before_the_library(two_boxes):
    scene, poses = two_boxes
    with pytest.raises(cs.InputError, match="shape"):
        cs.stabilize(scene, poses[:2], quaternion_order="xyzw")
    with pytest.raises(cs.InputError, match="shape"):
        cs.stabilize(scene, poses[:, :6], quaternion_order="xyzw")
    bad = poses.copy()
    bad[1, 4] = np.nan
    with pytest.raises(cs.InputError, match="finite"):
        cs.stabilize(scene, bad, quaternion_order="xyzw")
    bad[1, 4] = np.inf
    with pytest.raises(cs.InputError, match="finite"):
        cs.stabilize(scene, bad, quaternion_order="xyzw")
    for dtype in [bool, complex, object, str]:
        with pytest.raises(cs.InputTypeError, match="dtype"):
            cs.stabilize(scene, poses.astype(dtype), quaternion_order="xyzw")
    with pytest.raises(cs.InputTypeError):
        cs.stabilize("not a scene", poses, quaternion_order="xyzw")
    with pytest.raises(cs.InputError):
        cs.hull(np.zeros((4, 2)))


def test_settings_errors(two_boxes):
    scene, poses = two_boxes
    with pytest.raises(cs.InputTypeError, match="unknown setting `tolerance`"):
        cs.stabilize(scene, poses, quaternion_order="xyzw", tolerance=1e-3)
    with pytest.raises(cs.InputTypeError, match="tolerance_relative"):
        cs.stabilize(scene, poses, quaternion_order="xyzw", tolerance_relative="small")
    with pytest.raises(cs.SettingsError, match="tolerance_relative"):
        cs.stabilize(scene, poses, quaternion_order="xyzw", tolerance_relative=-1.0)
    with pytest.raises(cs.SettingsError, match="max_passes"):
        cs.stabilize(scene, poses, quaternion_order="xyzw", max_passes=0)
    with pytest.raises(cs.InputError, match="time_budget"):
        cs.stabilize(scene, poses, quaternion_order="xyzw", time_budget=-1.0)
    with pytest.raises(cs.InputError, match="method"):
        cs.stabilize(scene, poses, quaternion_order="xyzw", method="newton")
    with pytest.raises(cs.InputError, match="friction_rows"):
        cs.stabilize(scene, poses, quaternion_order="xyzw", friction_rows="some")
    with pytest.raises(cs.InputTypeError, match="unknown setting"):
        cs.stabilize_batch(scene, poses[None], quaternion_order="xyzw", threads=1, tolerance=1e-3)


def test_library_errors_keep_their_message(two_boxes):
    scene, poses = two_boxes
    with pytest.raises(cs.GeometryError, match="no volume"):
        cs.Scene().add_body(cs.hull(np.zeros((5, 3))), mass=1.0)
    with pytest.raises(cs.GeometryError):
        cs.Scene().add_body(cs.sphere(-1.0), mass=1.0)
    with pytest.raises(cs.BodyError, match="mass is -1"):
        cs.Scene().add_body(cs.box([1, 1, 1]), mass=-1.0)
    with pytest.raises(cs.BodyError, match="friction"):
        cs.Scene().add_body(cs.box([1, 1, 1]), mass=1.0, friction=-0.5)
    bad = poses.copy()
    bad[1, 3:] = [0.0, 0.0, 0.0, 2.0]
    with pytest.raises(cs.BodyError, match="quaternion norm is 2"):
        cs.stabilize(scene, bad, quaternion_order="xyzw")
    with pytest.raises(cs.SceneError, match="no body 9"):
        scene.set_mass_properties(9, 1.0, [0, 0, 0], np.eye(3))
    with pytest.raises(cs.BodyError):
        scene.set_mass_properties(0, 1.0, [0, 0, 0], np.eye(3))  # the fixed floor
    with pytest.raises(cs.InputError):
        cs.Scene().add_body(cs.box([1, 1, 1]), mass=1.0, fixed=True)


@pytest.mark.parametrize(
    "family, cls",
    [
        ("geometry", cs.GeometryError),
        ("body", cs.BodyError),
        ("scene", cs.SceneError),
        ("settings", cs.SettingsError),
        ("solver", cs.SolverError),
        ("detection", cs.DetectionError),
        ("other", cs.StabilizationError),
        ("panic", cs.InternalError),
    ],
)
def test_each_library_family_has_its_class(family, cls):
    with pytest.raises(cls) as caught:
        _native._raise_for_test(family)
    assert type(caught.value).__name__ != "PanicException"
    assert str(caught.value)


def test_hostile_inputs_raise_package_errors_never_panics():
    """Extreme numbers everywhere a user can put one: each either works
    or raises a StabilizationError (pyo3's PanicException derives from
    BaseException, so it would escape this check)."""
    values = [0.0, -0.0, 1e-300, 1e300, -1e300, 5e-324, 1.7e308]
    made = 0
    for v in values:
        for build in [
            lambda: cs.box([v, v, v]),
            lambda: cs.sphere(v),
            lambda: cs.capsule(v, v),
            lambda: cs.cylinder(v, 1.0),
            lambda: cs.cone(1.0, v),
            lambda: cs.round_box([1, 1, 1], v),
            lambda: cs.hull(np.array([[0, 0, 0], [v, 0, 0], [0, v, 0], [0, 0, v]], float)),
            lambda: cs.round_hull(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float), v),
        ]:
            try:
                scene = cs.Scene()
                scene.add_body(build(), mass=1.0)
                scene.add_body(cs.box([1, 1, 1]), mass=1.0)
                poses = np.array([[0, 0, 0, 0, 0, 0, 1], [v, 0, 0, 0, 0, 0, 1]], float)
                cs.stabilize(scene, poses, quaternion_order="xyzw", max_passes=3)
                made += 1
            except cs.StabilizationError:
                pass
    assert made > 0
    halves, scene = boxes_on_floor(2, seed=2)
    poses = overlapping_layout(2, seed=2)
    for key, value in [("tolerance_absolute", 1e300), ("tolerance_relative", 5e-324), ("contact_margin_absolute", 1e300), ("step_max_rotation", 1e-300), ("time_budget", 1e300), ("friction_directions", 10**6), ("friction", 1e300)]:
        try:
            cs.stabilize(scene, poses, quaternion_order="xyzw", max_passes=2, **{key: value})
        except cs.StabilizationError:
            pass
    for threads in [0, -1, 2**70]:
        with pytest.raises(cs.StabilizationError):
            cs.stabilize_batch(scene, poses[None], quaternion_order="xyzw", threads=threads)
