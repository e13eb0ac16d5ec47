"""Checks on the demands handed to the allocator: shapes and finite values."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from casadi_debris.errors import AllocationError, InputShapeError


def as_vector3(value: Any, name: str) -> np.ndarray:
    """``value`` as a float array of shape (3,), finite.

    Raises
    ------
    InputShapeError
        Another shape, or a non-finite entry; the message names ``name``.
    """
    array = np.asarray(value, dtype=float)
    if array.shape != (3,):
        raise InputShapeError(f"{name} must have shape (3,), got {array.shape}")
    x, y, z = array.tolist()  # three scalar checks: a tenth of np.isfinite's cost
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)):
        raise InputShapeError(f"{name} must be finite, got {array.tolist()}")
    return array


def as_rows3(value: Any, name: str) -> np.ndarray:
    """``value`` as a float array of shape (k, 3).

    Raises
    ------
    InputShapeError
        Another shape; the message names ``name``.
    """
    rows = np.asarray(value, dtype=float)
    if rows.ndim != 2 or rows.shape[1] != 3:
        raise InputShapeError(f"{name} must have shape (k, 3), got {rows.shape}")
    return rows


def batch_forces(torques: np.ndarray, forces_N: Any, free_force: bool) -> np.ndarray | None:
    """The force rows of a batch: as given, zero by default, None when free.

    Raises
    ------
    AllocationError
        ``forces_N`` together with ``free_force``.
    InputShapeError
        ``forces_N`` not of the shape of ``torques``, or either not finite.
    """
    if forces_N is not None:
        if free_force:
            raise AllocationError("give either forces_N or free_force, not both")
        forces = np.asarray(forces_N, dtype=float)
        if forces.shape != torques.shape:
            raise InputShapeError(
                f"forces_N must have the shape {torques.shape} of torques_Nm, got {forces.shape}"
            )
    else:
        forces = None if free_force else np.zeros_like(torques)
    if not np.isfinite(torques).all() or (forces is not None and not np.isfinite(forces).all()):
        raise InputShapeError("torques_Nm and forces_N must be finite")
    return forces
