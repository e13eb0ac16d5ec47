"""What a slew has to do: the rest-to-rest attitude pair, its eigenaxis, and the rigid limits.

Eigenaxis rotation (Wie, *Space Vehicle Dynamics and Control*, 2nd ed., Sec. 7.3)
---------------------------------------------------------------------------------
Any rest-to-rest re-orientation q_i -> q_f is one rotation by the angle Theta
about a body-fixed unit axis e (the eigenaxis):

    q_f = q_i (x) [cos(Theta / 2), sin(Theta / 2) e],   Theta in (0, pi] (short way).

Rotating about e with angle theta(t), the body rate is omega = theta_dot e and
Euler's equation J omega_dot + omega x J omega = tau gives the torque

    tau(t) = theta_ddot J e + theta_dot**2 (e x J e).

With per-axis limits tau_min,i <= tau_i <= tau_max,i the largest eigenaxis
acceleration (gyroscopic term neglected: it vanishes about a principal axis and
is second order in the rate) is

    alpha_max = min_i  limit_i / |(J e)_i|,   limit_i = tau_max,i if (J e)_i > 0 else -tau_min,i

and the rest-to-rest bang-bang (accelerate half way, decelerate half way) takes

    T_limit = 2 sqrt(Theta / alpha_max)  (= 2 sqrt(Theta J / tau) about a principal axis),

the rigid eigenaxis limit every slew of this package is measured against.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import AXIS_NAMES
from casadi_debris.dynamics import (
    axis_angle_quaternion,
    error_quaternion,
    quaternion_axis_angle,
    quaternion_multiply,
)
from casadi_debris.errors import InputShapeError, SlewInfeasibleError
from casadi_debris.geometry import Geometry, torque_authority

QUATERNION_TOLERANCE = 1e-9


# Axis components below this share of the largest are round-off (cleared).
AXIS_ROUND_OFF = 1e-12


@dataclass(frozen=True)
class SlewTarget:
    """A rest-to-rest re-orientation.

    Attributes
    ----------
    q_initial_BN, q_final_BN : ndarray, shape (4,)
        Unit quaternions (scalar first) of B relative to N at start and end;
        ``q_final_BN = q_initial_BN (x) [cos(angle/2), sin(angle/2) axis_B]``.
    axis_B : ndarray, shape (3,)
        Unit eigenaxis in body (and, being fixed during the rotation, inertial) axes.
    angle_rad : float
        Eigenaxis angle, in (0, pi].
    """

    q_initial_BN: np.ndarray
    q_final_BN: np.ndarray
    axis_B: np.ndarray
    angle_rad: float


def axis_vector(axis: str | Sequence[float] | np.ndarray) -> np.ndarray:
    """Unit vector of ``"x"``, ``"-z"``, ... or of three numbers, shape (3,).

    Components under ``AXIS_ROUND_OFF`` of the largest are round-off and are cleared:
    left in, a subnormal one (5e-306) reaches the integrators as products that
    underflow, and turns the axis by less than any solver tolerance anyway.
    """
    if isinstance(axis, str):
        name = axis.strip().lower()
        sign = -1.0 if name.startswith("-") else 1.0
        name = name.lstrip("+-")
        if name not in AXIS_NAMES:
            raise InputShapeError(f"axis: expected x, y, z (optionally signed), got {axis!r}")
        vector = np.zeros(3)
        vector[AXIS_NAMES.index(name)] = sign
        return vector
    vector = np.asarray(axis, dtype=float)
    if vector.shape != (3,) or not np.all(np.isfinite(vector)):
        raise InputShapeError(f"axis: expected three finite numbers, got {axis!r}")
    largest = float(np.max(np.abs(vector)))
    if largest == 0.0:
        raise InputShapeError("axis: must not be zero")
    vector = vector / largest  # scaled first: the squares of 1e-170 underflow to zero
    vector = np.where(np.abs(vector) < AXIS_ROUND_OFF, 0.0, vector)
    return vector / float(np.linalg.norm(vector))


def _unit_quaternion(q: Sequence[float] | np.ndarray, name: str) -> np.ndarray:
    array = np.asarray(q, dtype=float)
    if array.shape != (4,) or not np.all(np.isfinite(array)):
        raise InputShapeError(f"{name}: expected four finite numbers (scalar first), got {q!r}")
    norm = float(np.linalg.norm(array))
    if norm == 0.0:
        raise InputShapeError(f"{name}: must not be zero")
    return array / norm


def slew_about_axis(
    axis: str | Sequence[float] | np.ndarray,
    angle_rad: float,
    q_initial_BN: Sequence[float] | np.ndarray = (1.0, 0.0, 0.0, 0.0),
) -> SlewTarget:
    """Rest-to-rest rotation by ``angle_rad`` about a body axis.

    Parameters
    ----------
    axis : str, or sequence or array of 3 floats
        ``"x"``, ``"y"``, ``"z"`` (optionally with a sign) or a vector in B.
    angle_rad : float
        Rotation angle in (0, pi] rad; larger turns are the short way about -axis.
    q_initial_BN : sequence or array of 4 floats
        Starting attitude (scalar first).
    """
    e = axis_vector(axis)
    if not math.isfinite(angle_rad) or not 0.0 < angle_rad <= math.pi + 1e-12:
        raise InputShapeError(
            f"angle: must be in (0, 180] deg, got {math.degrees(angle_rad):g} deg "
            "(turn about the opposite axis for the other way round)"
        )
    angle = min(angle_rad, math.pi)
    q0 = _unit_quaternion(q_initial_BN, "q_initial_BN")
    return SlewTarget(q0, quaternion_multiply(q0, axis_angle_quaternion(e, angle)), e, angle)


def slew_between(
    q_initial_BN: Sequence[float] | np.ndarray, q_final_BN: Sequence[float] | np.ndarray
) -> SlewTarget:
    """Rest-to-rest slew between two attitudes, the short way round.

    The eigenaxis and angle are those of q_rel = q_i^-1 (x) q_f taken the short
    way round (angle <= pi).
    """
    q0 = _unit_quaternion(q_initial_BN, "q_initial_BN")
    qf = _unit_quaternion(q_final_BN, "q_final_BN")
    axis, angle = quaternion_axis_angle(error_quaternion(q0, qf))
    if math.sin(float(angle) / 2.0) < QUATERNION_TOLERANCE:
        raise InputShapeError("q_final_BN: equals q_initial_BN, nothing to slew")
    return slew_about_axis(axis, float(angle), q0)


def check_torque_fraction(torque_fraction: float) -> None:
    """Raise unless 0 < torque_fraction <= 1 (the share of the engines' authority used)."""
    if not math.isfinite(torque_fraction) or not 0.0 < torque_fraction <= 1.0:
        raise InputShapeError(f"torque_fraction: must be in (0, 1], got {torque_fraction}")


def check_positive(name: str, value: float) -> None:
    """Raise unless ``value`` is finite and > 0, naming it."""
    if not math.isfinite(value) or value <= 0.0:
        raise InputShapeError(f"{name}: must be > 0, got {value}")


def torque_limits(
    geometry: Geometry, torque_fraction: float = 1.0
) -> tuple[np.ndarray, np.ndarray]:
    """Per-axis torque box from the engines: (lower, upper), N m, shape (3,) each.

    The box is ``torque_fraction`` times the largest pure torque about each signed
    body axis (:func:`casadi_debris.geometry.torque_authority`, a linear programme
    over the engines).
    """
    check_torque_fraction(torque_fraction)
    authority = torque_authority(geometry)
    upper = np.array([authority[f"+{a}"] for a in AXIS_NAMES]) * torque_fraction
    lower = -np.array([authority[f"-{a}"] for a in AXIS_NAMES]) * torque_fraction
    return lower, upper


def eigenaxis_acceleration_limit(
    inertia_kgm2: np.ndarray, axis_B: np.ndarray, lower_Nm: np.ndarray, upper_Nm: np.ndarray
) -> float:
    """Largest eigenaxis angular acceleration alpha_max (rad/s^2) within the torque box.

    Both signs of the acceleration are needed in a rest-to-rest slew, so the
    smaller of the two is returned.
    """
    moment = np.asarray(inertia_kgm2, dtype=float) @ axis_B
    ratios = []
    for sign in (1.0, -1.0):
        demand = sign * moment
        for i in range(3):
            if abs(demand[i]) > 1e-12 * float(np.max(np.abs(moment))):
                limit = upper_Nm[i] if demand[i] > 0 else -lower_Nm[i]
                ratios.append(limit / abs(demand[i]))
    alpha = min(ratios)
    if alpha <= 0.0:
        raise SlewInfeasibleError("infeasible: the engines give no torque about the slew axis")
    return float(alpha)


def rigid_limit_duration(angle_rad: float, alpha_max_rad_s2: float) -> float:
    """Rest-to-rest eigenaxis bang-bang time 2 sqrt(Theta / alpha_max), s."""
    return 2.0 * math.sqrt(angle_rad / alpha_max_rad_s2)


def eigenaxis_duration_s(
    angle_rad: float,
    inertia_kgm2: np.ndarray,
    axis_B: np.ndarray,
    use: Callable[[np.ndarray], np.ndarray],
) -> float:
    """Rest-to-rest eigenaxis bang-bang time at the full authority, gyroscopic torque included, s.

    With the acceleration +-a, the rate^2 grows from 0 to a Theta (no coast), so
    tau / a runs over the segments between the vertices +-J e and +-J e + Theta e x J e;
    ``use`` (convex, positively homogeneous: the share of the authority a torque needs,
    1 the most) is largest at one of them, and the largest a is 1 / max use(vertex).
    The profile is flyable (every instant within the authority), so the time-optimal
    slew of the same authority is never longer.

    Parameters
    ----------
    angle_rad : float
    inertia_kgm2 : ndarray, shape (3, 3)
    axis_B : ndarray, shape (3,)
        Unit eigenaxis.
    use : callable
        Torques (k, 3) N m -> share of the authority each needs, shape (k,).

    Raises
    ------
    SlewInfeasibleError
        The authority gives no torque the slew needs.
    """
    moment = np.asarray(inertia_kgm2, dtype=float) @ axis_B
    gyroscopic = angle_rad * np.cross(axis_B, moment)
    vertices = np.array([moment, -moment, moment + gyroscopic, -moment + gyroscopic])
    need = float(np.max(use(vertices)))
    if not math.isfinite(need) or need <= 0.0:
        raise SlewInfeasibleError("infeasible: the engines give no torque the slew needs")
    return rigid_limit_duration(angle_rad, 1.0 / need)
