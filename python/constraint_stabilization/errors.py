"""The package's exceptions.

Every exception it raises is a :class:`StabilizationError`. The library's
errors keep their message and get the class of their family; the checks of
the Python layer (array shapes, NaN, dtypes, names) raise
:class:`InputError` (also a ``ValueError``) or :class:`InputTypeError`
(also a ``TypeError``) before anything reaches the library. A panic inside
the library (a bug) would be an :class:`InternalError`, never pyo3's
``PanicException``.
"""

from __future__ import annotations

__all__ = [
    "StabilizationError",
    "InputError",
    "InputTypeError",
    "GeometryError",
    "SceneError",
    "BodyError",
    "SettingsError",
    "SolverError",
    "DetectionError",
    "InternalError",
]


class StabilizationError(Exception):
    """Base class of every error of the package."""


class InputError(StabilizationError, ValueError):
    """A bad value given to the package: an array's shape, a NaN or
    infinity, an unknown quaternion order, contradictory keywords."""


class InputTypeError(StabilizationError, TypeError):
    """An argument of the wrong type: an array's dtype, an unknown setting,
    a setting of the wrong type."""


class GeometryError(StabilizationError):
    """A shape could not be built (a degenerate hull, a bad radius...)."""


class SceneError(StabilizationError):
    """A scene is invalid (an index out of range...)."""


class BodyError(SceneError):
    """A body's description or pose is invalid (a mass, a quaternion far
    from unit norm...)."""


class SettingsError(StabilizationError, ValueError):
    """A setting is out of its range."""


class SolverError(StabilizationError):
    """Every solver failed on a problem (the poses are as they were)."""


class DetectionError(StabilizationError):
    """The broad or narrow phase was given invalid input."""


class InternalError(StabilizationError):
    """The library panicked: a bug, reported instead of crashing."""
