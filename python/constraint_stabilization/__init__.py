"""Removes interpenetration between rigid bodies by the smallest
mass-weighted correction of their poses (the Rust library
``constraint-stabilization``): numpy in, numpy out.

>>> import numpy as np, constraint_stabilization as cs
>>> scene = cs.Scene()
>>> scene.add_body(cs.box([5, 5, 0.5]), fixed=True)
0
>>> scene.add_body(cs.box([0.5, 0.5, 0.5]), mass=1.0)
1
>>> poses = np.array([[0, 0, -0.5, 0, 0, 0, 1], [0, 0, 0.4, 0, 0, 0, 1]], float)
>>> fixed, report = cs.stabilize(scene, poses, quaternion_order="xyzw")
>>> report.status
'converged'

See ``python/README.md`` for the whole API; the MuJoCo adapter is
:mod:`constraint_stabilization.mujoco` (imports ``mujoco`` only there).
"""

from ._api import (
    BatchResult,
    Report,
    Scene,
    Shape,
    box,
    capsule,
    compound,
    cone,
    cylinder,
    hull,
    round_box,
    round_hull,
    setting_names,
    sphere,
    stabilize,
    stabilize_batch,
)
from ._arrays import QUATERNION_ORDERS
from .errors import (
    BodyError,
    DetectionError,
    GeometryError,
    InputError,
    InputTypeError,
    InternalError,
    SceneError,
    SettingsError,
    SolverError,
    StabilizationError,
)

__version__ = "0.1.0"

__all__ = [
    "BatchResult",
    "Report",
    "Scene",
    "Shape",
    "QUATERNION_ORDERS",
    "box",
    "capsule",
    "compound",
    "cone",
    "cylinder",
    "hull",
    "round_box",
    "round_hull",
    "setting_names",
    "sphere",
    "stabilize",
    "stabilize_batch",
    "BodyError",
    "DetectionError",
    "GeometryError",
    "InputError",
    "InputTypeError",
    "InternalError",
    "SceneError",
    "SettingsError",
    "SolverError",
    "StabilizationError",
]
