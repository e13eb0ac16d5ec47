"""The attitude the closed loop is asked to follow, sampled at the control instants."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import Problem, SlewReference
from casadi_debris.slew import (
    SlewProfile,
    bang_bang_slew,
    fuel_optimal_slew,
    time_optimal_slew,
)


@dataclass(frozen=True, eq=False)
class Reference:
    """Reference attitude at the control instants.

    Attributes
    ----------
    time_s : ndarray, shape (n,)
    quaternion_BN : ndarray, shape (n, 4)
        Scalar first, unit norm.
    slew : SlewProfile or None
        The slew it follows (None for a hold).
    start_s : float
        When the slew starts [s].
    """

    time_s: np.ndarray
    quaternion_BN: np.ndarray
    slew: SlewProfile | None
    start_s: float = 0.0


def generate_slew(problem: Problem, settings: SlewReference, sample_s: float) -> SlewProfile:
    """The slew a ``[simulation.slew]`` table asks for (rigid, torque level).

    Parameters
    ----------
    problem : Problem
    settings : SlewReference
    sample_s : float
        Output sample spacing [s] (the control period).
    """
    angle = math.radians(settings.angle_deg)
    common = {"sample_s": sample_s, "check_vibration": False}
    if settings.method == "bang-bang":
        return bang_bang_slew(
            problem,
            settings.axis,
            angle,
            duration_s=settings.duration_s,
            torque_fraction=settings.torque_fraction,
            **common,
        )
    fraction = (
        {} if settings.torque_fraction is None else {"torque_fraction": settings.torque_fraction}
    )
    if settings.method == "time-optimal":
        return time_optimal_slew(problem, settings.axis, angle, **fraction, **common)
    return fuel_optimal_slew(
        problem, settings.axis, angle, duration_s=float(settings.duration_s), **fraction, **common
    )


def sample_reference(
    time_s: np.ndarray,
    slew: SlewProfile | None = None,
    start_s: float = 0.0,
) -> Reference:
    """Reference quaternions at ``time_s``: the slew shifted by ``start_s``, held outside it.

    Between the profile's samples the quaternion is interpolated linearly and
    normalised (the profile is sampled at the control period, so this only
    fills switching instants).
    """
    time_s = np.asarray(time_s, dtype=float)
    if slew is None:
        quaternion = np.tile([1.0, 0.0, 0.0, 0.0], (len(time_s), 1))
        return Reference(time_s, quaternion, None, start_s)
    local = np.clip(time_s - start_s, slew.time_s[0], slew.time_s[-1])
    quaternion = np.column_stack(
        [np.interp(local, slew.time_s, slew.quaternion_BN[:, j]) for j in range(4)]
    )
    quaternion /= np.linalg.norm(quaternion, axis=1, keepdims=True)
    return Reference(time_s, quaternion, slew, start_s)


def scenario_reference(problem: Problem) -> Reference:
    """The reference of the problem's ``[simulation]`` table at its control instants."""
    settings = problem.simulation
    period = 1.0 / settings.control_rate_hz
    steps = max(1, round(settings.duration_s / period))
    times = period * np.arange(steps + 1)
    if settings.reference == "hold" or settings.slew is None:
        return sample_reference(times)
    slew = generate_slew(problem, settings.slew, period)
    return sample_reference(times, slew, settings.slew.start_s)
