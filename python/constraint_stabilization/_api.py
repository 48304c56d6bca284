"""The engine-neutral API: shapes, the stabilization call, the batch call.

Poses are ``(n, 7)`` arrays ``[x, y, z, q0, q1, q2, q3]``, one row per body
in the scene's order: the world position of the body's shape frame, then
its rotation as a unit quaternion in the order named by the REQUIRED
keyword ``quaternion_order`` (``"xyzw"``, scalar last, this library's and
SciPy's; ``"wxyz"``, scalar first, MuJoCo's and Isaac's). There is no
default, so a wrong order cannot pass silently.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from . import _native
from ._arrays import (
    check_order,
    poses_from_xyzw,
    poses_to_xyzw,
    real_array,
)
from ._native import Scene, Shape
from .errors import InputError, InputTypeError

__all__ = [
    "Scene",
    "Shape",
    "Report",
    "BatchResult",
    "box",
    "hull",
    "sphere",
    "capsule",
    "cylinder",
    "cone",
    "round_box",
    "round_hull",
    "compound",
    "stabilize",
    "stabilize_batch",
    "setting_names",
]


def _vector3(values: Any, what: str) -> List[float]:
    return [float(v) for v in real_array(values, what, (3,))]


def _length(value: Any, what: str) -> float:
    return float(real_array(value, what, ()))


def box(half_extents: Sequence[float]) -> Shape:
    """A box ``[-h, h]`` centred on its frame's origin."""
    return Shape.cuboid(_vector3(half_extents, "half_extents"))


def hull(vertices: Any) -> Shape:
    """The convex hull of ``(k, 3)`` points given in the shape frame
    (points inside it are allowed)."""
    return Shape.hull(real_array(vertices, "vertices", (None, 3)))


def sphere(radius: float) -> Shape:
    """A ball centred on its frame's origin."""
    return Shape.sphere(_length(radius, "radius"))


def capsule(radius: float, half_height: float) -> Shape:
    """The segment from ``-half_height`` to ``+half_height`` along z grown
    by ``radius`` (MuJoCo's capsule ``size = [radius, half_height]``)."""
    return Shape.capsule(_length(radius, "radius"), _length(half_height, "half_height"))


def cylinder(radius: float, half_height: float) -> Shape:
    """A solid cylinder along z centred on its frame's origin. The library
    works on the true solid by support functions (its default; the
    circumscribed polygonal prism of ``CURVED_DEVIATION_RELATIVE`` remains
    behind the Rust setting ``VClipSettings::curved_support_functions``)."""
    return Shape.cylinder(_length(radius, "radius"), _length(half_height, "half_height"))


def cone(radius: float, half_height: float) -> Shape:
    """A solid cone along z: base of ``radius`` at ``-half_height``, apex
    at ``+half_height`` (the true solid, like a cylinder)."""
    return Shape.cone(_length(radius, "radius"), _length(half_height, "half_height"))


def round_box(half_extents: Sequence[float], radius: float) -> Shape:
    """A box of ``half_extents`` grown by ``radius`` (outer half extents
    ``half_extents + radius``)."""
    return Shape.round_cuboid(_vector3(half_extents, "half_extents"), _length(radius, "radius"))


def round_hull(vertices: Any, radius: float) -> Shape:
    """The convex hull of ``(k, 3)`` points grown by ``radius``."""
    return Shape.round_hull(real_array(vertices, "vertices", (None, 3)), _length(radius, "radius"))


def compound(parts: Sequence[Shape], poses: Any, *, quaternion_order: str) -> Shape:
    """Several convex shapes moving as one body: part ``i`` placed in the
    compound's frame by row ``i`` of ``poses`` (``(k, 7)``)."""
    parts = list(parts)
    for part in parts:
        if not isinstance(part, Shape):
            raise _type_error(f"compound parts must be Shape objects, got {type(part).__name__}")
    return Shape.compound_xyzw(parts, poses_to_xyzw(poses, len(parts), quaternion_order))


def _type_error(message: str) -> Exception:
    return InputTypeError(message)


def setting_names() -> List[str]:
    """The keyword arguments that set the library's ``Settings`` fields."""
    return list(_native.setting_names())


@dataclass(frozen=True)
class Report:
    """What a call did, as plain Python objects.

    ``status`` is one of ``nothing_to_do`` (no penetration deeper than the
    tolerance: no pose touched), ``converged``, ``pass_limit``,
    ``time_limit``, ``stalled``, ``unsolved``; ``converged`` is true for
    the first two. Depths are exact penetration depths (the smallest
    translation that separates the deepest pair), in the scene's length
    unit; ``tolerance`` is the absolute tolerance the call used
    (``tolerance_relative`` times ``scale`` unless ``tolerance_absolute``).
    ``penetrations_before``/``_after`` list ``(body_a, body_b, depth)``
    deeper than the tolerance; ``islands`` every island solved in every
    pass (``pass_index``, ``bodies``, ``outcome``, ``solver``,
    ``constraints``, depths); ``islands_left`` the islands the last pass
    could not finish, with the ``reason``; ``pair_queries`` the narrow
    phase's exact queries, ``certified_pairs`` the candidate pairs a bound
    on their motion certified separated and ``reused_pairs`` those whose
    earlier answer at the same poses was reused (neither queried);
    ``times`` seconds per stage,
    measured inside the library (``total`` is the library's whole call).
    """

    status: str
    converged: bool
    passes: int
    scale: float
    tolerance: float
    depth_before: float
    depth_after: float
    penetrations_before: List[Tuple[int, int, float]]
    penetrations_after: List[Tuple[int, int, float]]
    displacement: float
    bodies_moved: int
    restored_input: bool
    pair_queries: int
    certified_pairs: int
    reused_pairs: int
    islands_left: List[Dict[str, Any]]
    islands: List[Dict[str, Any]]
    times: Dict[str, float]


@dataclass(frozen=True)
class BatchResult:
    """The result of :func:`stabilize_batch`: ``poses`` ``(B, n, 7)`` in the
    caller's quaternion order, and one entry per layout in each array."""

    poses: np.ndarray
    status: List[str]
    converged: np.ndarray
    passes: np.ndarray
    depth_before: np.ndarray
    depth_after: np.ndarray
    tolerance: np.ndarray
    bodies_moved: np.ndarray
    seconds: np.ndarray = field(repr=False)


# More threads than this is a mistake (rayon would try to start them).
MAX_THREADS = 4096


def _check_scene(scene: Any) -> Scene:
    if not isinstance(scene, Scene):
        raise _type_error(f"scene must be a constraint_stabilization.Scene, got {type(scene).__name__}")
    return scene


def stabilize(scene: Scene, poses: Any, *, quaternion_order: str, **settings: Any) -> Tuple[np.ndarray, Report]:
    """Removes the interpenetration of one layout of ``scene`` by the
    smallest mass-weighted correction of its dynamic bodies' poses.

    ``poses`` is ``(n, 7)`` (see the module docs); the result is the
    corrected ``(n, 7)`` poses in the same quaternion order, and a
    :class:`Report`. Bodies the call did not move come back bit for bit.
    ``settings`` are the library's ``Settings`` fields by name
    (:func:`setting_names`), defaults the library's. The scene itself is
    not changed. The GIL is released while the library works.
    """
    scene = _check_scene(scene)
    check_order(quaternion_order)
    xyzw = poses_to_xyzw(poses, len(scene), quaternion_order)
    corrected, report = _native.stabilize_xyzw(scene, xyzw, **settings)
    return poses_from_xyzw(corrected, quaternion_order), Report(**report)


def stabilize_batch(
    scene: Scene,
    poses: Any,
    *,
    quaternion_order: str,
    threads: Optional[int] = None,
    **settings: Any,
) -> BatchResult:
    """:func:`stabilize` on each of ``B`` layouts ``(B, n, 7)`` of one
    scene, in parallel on ``threads`` threads (``None``: one per core) with
    the GIL released. Each layout is solved exactly as :func:`stabilize`
    solves it alone (its own copy of the scene, its own stabilizer), so the
    result is bit-identical to the sequential calls whatever ``threads``.
    A ``time_budget`` makes results depend on timing, as in any call.
    """
    scene = _check_scene(scene)
    check_order(quaternion_order)
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, (int, np.integer))):
        raise _type_error(f"threads must be an int or None, got {type(threads).__name__}")
    if threads is not None and not 1 <= threads <= MAX_THREADS:
        raise InputError(f"threads is {threads}: it must be between 1 and {MAX_THREADS}")
    xyzw = poses_to_xyzw(poses, len(scene), quaternion_order, leading=1)
    corrected, info = _native.stabilize_batch_xyzw(scene, xyzw, threads, **settings)
    return BatchResult(
        poses=poses_from_xyzw(corrected, quaternion_order),
        status=list(info["status"]),
        converged=np.asarray(info["converged"], dtype=bool),
        passes=np.asarray(info["passes"], dtype=np.int64),
        depth_before=np.asarray(info["depth_before"], dtype=np.float64),
        depth_after=np.asarray(info["depth_after"], dtype=np.float64),
        tolerance=np.asarray(info["tolerance"], dtype=np.float64),
        bodies_moved=np.asarray(info["bodies_moved"], dtype=np.int64),
        seconds=np.asarray(info["seconds"], dtype=np.float64),
    )
