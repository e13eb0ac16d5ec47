"""The few vector operations of the environment, on numpy arrays and CasADi symbols alike.

Every torque of :mod:`casadi_debris.environment` is written once with these:
given numpy arrays (shape (3,)) it returns numpy arrays, given any CasADi
value (``SX``, ``MX`` or ``DM``, columns (3, 1)) it returns a CasADi
expression. So the numbers a user prints and the compiled closed-loop step come
from one piece of code.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

Vector = Any
"""A numpy array of shape (3,) or a CasADi column (3, 1)."""

_CASADI = (ca.SX, ca.MX, ca.DM)


def symbolic(*values: Any) -> bool:
    """Whether any of ``values`` is a CasADi value (then the result is one too)."""
    return any(isinstance(v, _CASADI) for v in values)


def as_vector(value: Any, like_symbolic: bool) -> Vector:
    """``value`` as a CasADi column (for a symbolic computation) or a float array."""
    if like_symbolic:
        return value if isinstance(value, _CASADI) else ca.DM(np.asarray(value, dtype=float))
    return np.asarray(value, dtype=float)


def cross(a: Vector, b: Vector) -> Vector:
    """a x b."""
    if symbolic(a, b):
        return ca.cross(as_vector(a, True), as_vector(b, True))
    return np.cross(a, b)


def dot(a: Vector, b: Vector) -> Any:
    """a . b (a float or a CasADi scalar)."""
    if symbolic(a, b):
        return ca.dot(as_vector(a, True), as_vector(b, True))
    return float(np.dot(a, b))


def norm(a: Vector) -> Any:
    """|a|."""
    return ca.norm_2(a) if symbolic(a) else float(np.linalg.norm(a))


def matvec(matrix: Any, vector: Vector) -> Vector:
    """M v."""
    if symbolic(matrix, vector):
        return ca.mtimes(as_vector(matrix, True), as_vector(vector, True))
    return np.asarray(matrix, dtype=float) @ np.asarray(vector, dtype=float)


def positive_part(x: Any) -> Any:
    """max(x, 0)."""
    return ca.fmax(x, 0.0) if symbolic(x) else max(float(x), 0.0)


def select(condition: Any, if_true: Any, if_false: Any) -> Any:
    """``if_true`` where ``condition`` holds, else ``if_false``."""
    if symbolic(condition, if_true, if_false):
        return ca.if_else(condition, if_true, if_false)
    return if_true if bool(condition) else if_false


def trig(angle: Any) -> tuple[Any, Any]:
    """(cos, sin) of an angle, float or symbolic."""
    if symbolic(angle):
        return ca.cos(angle), ca.sin(angle)
    return float(np.cos(angle)), float(np.sin(angle))


def stack(components: list[Any]) -> Vector:
    """A vector of its components (floats or CasADi scalars)."""
    if symbolic(*components):
        return ca.vertcat(*components)
    return np.array([float(c) for c in components])


def zeros(like_symbolic: bool) -> Vector:
    """The zero vector."""
    return ca.DM.zeros(3, 1) if like_symbolic else np.zeros(3)
