"""Checks of the arrays and ids a :class:`~casadi_debris.allocation.PropulsionState` is given.

Shapes are per engine (rows) and stage (columns); ids read from a user's file
are 1-based. Each check raises with the argument's name.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from casadi_debris.errors import AllocationError, InputShapeError


def checked_id(value: Any, name: str, what: str, count: int) -> int:
    """The 0-based index of a 1-based id read from a user's file."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise AllocationError(f"{name} entries must be integers, got {value!r}")
    if not 1 <= value <= count:
        raise AllocationError(f"{name}: {what} {value} out of range 1..{count}")
    return int(value) - 1


def checked_vector(values: Any, name: str) -> np.ndarray:
    try:
        array = np.array(values, dtype=float)
    except (TypeError, ValueError):
        raise InputShapeError(f"{name} must be numbers") from None
    if array.ndim != 1 or len(array) == 0:
        raise InputShapeError(f"{name} must be a non-empty vector, got shape {array.shape}")
    if not np.all(np.isfinite(array)):
        raise InputShapeError(f"{name} must be finite")
    return array


def per_stage(values: Any, name: str, shape: tuple[int, int]) -> np.ndarray:
    """One value per stage (shared by every engine) or per engine and stage."""
    array = np.asarray(values, dtype=float)
    if array.ndim == 1:
        array = np.broadcast_to(checked_vector(array, name), shape).copy()
    return engine_stage_matrix(array, name, shape[1], shape[0])


def per_engine(values: Any, n_engines: int) -> np.ndarray:
    """One exhaust velocity for every engine, or one each."""
    array = np.asarray(values, dtype=float)
    if array.ndim == 0:
        return np.full(n_engines, float(array))
    if array.shape != (n_engines,):
        raise InputShapeError(
            f"exhaust_velocity_m_s must be a number or one per engine ({n_engines}), "
            f"got shape {array.shape}"
        )
    return array.copy()


def engine_stage_matrix(
    values: Any, name: str, n_stages: int | None, n_engines: int | None = None
) -> np.ndarray:
    try:
        array = np.array(values, dtype=float)
    except (TypeError, ValueError):
        raise InputShapeError(f"{name} must be numbers") from None
    rows = n_engines if n_engines is not None else (len(array) if array.ndim == 2 else -1)
    columns = n_stages if n_stages is not None else (array.shape[1] if array.ndim == 2 else -1)
    if array.shape != (rows, columns) or columns == 0:
        want = f"({n_engines if n_engines is not None else 'n_engines'}, {n_stages or 'n_stages'})"
        raise InputShapeError(f"{name} must have shape {want}, got {array.shape}")
    if not np.all(np.isfinite(array)):
        raise InputShapeError(f"{name} must be finite")
    return array
