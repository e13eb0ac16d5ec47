"""Checks of the arrays and ids a :class:`~casadi_debris.allocation.PropulsionState` is given.

Shapes are per engine (rows) and stage (columns); ids read from a user's file
are 1-based. Each check raises with the argument's name.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from casadi_debris.errors import AllocationError, InputShapeError


def checked_id(value: Any, name: str, what: str, count: int) -> int:
    """The 0-based index of a 1-based id read from a user's file."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise AllocationError(f"{name} entries must be integer ids (from 1), got {_shown(value)}")
    if not 1 <= value <= count:
        # Ids count from 1: a 0 is most likely a 0-based id.
        hint = " (ids count from 1)" if value == 0 else ""
        raise AllocationError(f"{name}: {what} {value} out of range 1..{count}{hint}")
    return int(value) - 1


def listed(data: dict[str, Any], key: str, entries: str) -> list[Any]:
    """The list under ``key`` of a user's state file (empty when absent); ``entries`` says
    what its entries are, for the message when it is not a list."""
    value = data.get(key, [])
    if not isinstance(value, list):
        raise AllocationError(f"{key} must be a list of {entries}, got {_shown(value)}")
    return value


def checked_pair(
    entry: Any, key: str, first: tuple[str, int], second: tuple[str, int]
) -> tuple[int, int]:
    """The 0-based indices of one ``[first, second]`` pair of 1-based ids under ``key``;
    ``first`` and ``second`` are (what, count), e.g. ("CubeSat", 24)."""
    if not isinstance(entry, list) or len(entry) != 2:
        raise AllocationError(
            f"{key} entries must be [{first[0].lower()}, {second[0].lower()}] pairs, "
            f"got {_shown(entry)}"
        )
    return (
        checked_id(entry[0], key, first[0], first[1]),
        checked_id(entry[1], key, second[0], second[1]),
    )


def _shown(value: Any) -> str:
    """A user's value in a message as JSON writes it (the file is JSON), cut short."""
    try:
        text = json.dumps(value)
    except (TypeError, ValueError):
        text = repr(value)
    return text if len(text) <= 40 else text[:39] + "…"


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
