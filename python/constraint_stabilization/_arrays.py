"""Input checks of arrays and the quaternion order, done in Python before
anything reaches the library: each failure is an :class:`InputError` (a
``ValueError``) or an :class:`InputTypeError` (a ``TypeError``)."""

from __future__ import annotations

from typing import Any, Optional, Tuple

import numpy as np

from .errors import InputError, InputTypeError

QUATERNION_ORDERS = ("xyzw", "wxyz")

# Columns of a pose row [x, y, z, q0, q1, q2, q3] for each order, as the
# library's [x, y, z, qx, qy, qz, qw]; the permutation is its own kind of
# exact: no arithmetic, so a wxyz layout and its xyzw twin are the same
# numbers for the library.
_TO_XYZW = {"xyzw": [0, 1, 2, 3, 4, 5, 6], "wxyz": [0, 1, 2, 4, 5, 6, 3]}
_FROM_XYZW = {"xyzw": [0, 1, 2, 3, 4, 5, 6], "wxyz": [0, 1, 2, 6, 3, 4, 5]}


def check_order(quaternion_order: Any) -> str:
    """The order if it is ``"xyzw"`` or ``"wxyz"``, else an InputError."""
    if not isinstance(quaternion_order, str) or quaternion_order not in QUATERNION_ORDERS:
        raise InputError(
            f'quaternion_order must be "xyzw" or "wxyz", got {quaternion_order!r}'
        )
    return quaternion_order


def real_array(values: Any, what: str, shape: Tuple[Optional[int], ...]) -> np.ndarray:
    """``values`` as a C-contiguous float64 array of ``shape`` (``None``
    matches any length), finite. Integer and floating dtypes are taken;
    any other (bool, complex, object, strings) is an InputTypeError."""
    array = np.asarray(values)
    if array.dtype.kind not in "fiu":
        raise InputTypeError(
            f"{what} must be an array of real numbers, got dtype {array.dtype}"
        )
    expected = tuple("n" if s is None else s for s in shape)
    if array.ndim != len(shape) or any(
        s is not None and s != got for s, got in zip(shape, array.shape)
    ):
        raise InputError(f"{what} must have shape {expected}, got {array.shape}")
    array = np.array(array, dtype=np.float64, order="C")
    if not np.isfinite(array).all():
        bad = np.argwhere(~np.isfinite(array))[0]
        raise InputError(f"{what}{list(bad)} is {array[tuple(bad)]}: it must be finite")
    return array


def poses_to_xyzw(poses: Any, n: Optional[int], quaternion_order: str, leading: int = 0) -> np.ndarray:
    """Checked ``(..., n, 7)`` poses (``leading`` extra axes) in the
    library's order."""
    order = check_order(quaternion_order)
    shape = (None,) * leading + (n, 7)
    array = real_array(poses, "poses", shape)
    if order == "xyzw":
        return array
    return np.ascontiguousarray(array[..., _TO_XYZW[order]])


def poses_from_xyzw(poses_xyzw: np.ndarray, quaternion_order: str) -> np.ndarray:
    """The library's poses in the caller's order."""
    if quaternion_order == "xyzw":
        return poses_xyzw
    return np.ascontiguousarray(poses_xyzw[..., _FROM_XYZW[quaternion_order]])
