"""The attitude the closed loop is asked to follow, sampled at the control instants."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicHermiteSpline

from casadi_debris.config import Problem, SlewReference
from casadi_debris.errors import ProblemFileError, SlewInfeasibleError
from casadi_debris.model.attitude import quaternion_rate
from casadi_debris.slew import (
    SlewOptions,
    SlewProfile,
    bang_bang_slew,
    fuel_optimal_slew,
    time_optimal_slew,
)

# Spacing of the slew profile the reference interpolates (its switching instants are added).
PROFILE_SAMPLE_S = 1.0


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
    feedforward_Nm : ndarray, shape (n, 3) or None
        Torque added to the controller's demand at each instant (the slew
        profile's), or None for none.
    """

    time_s: np.ndarray
    quaternion_BN: np.ndarray
    slew: SlewProfile | None
    start_s: float = 0.0
    feedforward_Nm: np.ndarray | None = None


def generate_slew(problem: Problem, settings: SlewReference, sample_s: float) -> SlewProfile:
    """The slew a ``[simulation.slew]`` table asks for (rigid; torque level, or thruster
    level with zero net force when ``settings.thrusters``).

    Parameters
    ----------
    problem : Problem
    settings : SlewReference
    sample_s : float
        Output sample spacing [s] (the control period).

    Raises
    ------
    ProblemFileError
        The slew cannot be done as the table asks (e.g. a duration below the
        minimum), naming ``simulation.slew.duration_s`` when one is given.
    """
    try:
        return _slew_of(problem, settings, sample_s)
    except SlewInfeasibleError as exc:
        key = "simulation.slew.duration_s" if settings.duration_s is not None else "simulation.slew"
        raise ProblemFileError(key, str(exc), problem.source) from None


def _slew_of(problem: Problem, settings: SlewReference, sample_s: float) -> SlewProfile:
    angle = math.radians(settings.angle_deg)
    if settings.method == "bang-bang":
        return bang_bang_slew(
            problem,
            settings.axis,
            angle,
            duration_s=settings.duration_s,
            torque_fraction=settings.torque_fraction,
            sample_s=sample_s,
            check_vibration=False,
        )
    options = SlewOptions(
        thrusters=settings.thrusters,
        zero_net_force=settings.thrusters,
        sample_s=sample_s,
        check_vibration=False,
    )
    if settings.torque_fraction is not None:  # else the slew's own default
        options = dataclasses.replace(options, torque_fraction=settings.torque_fraction)
    if settings.method == "time-optimal":
        # A duration is the slew's deadline: the optimum must not be longer.
        return time_optimal_slew(
            problem, settings.axis, angle, duration_s=settings.duration_s, options=options
        )
    if settings.duration_s is None:  # the loader refuses it; a table built in Python may not
        raise ProblemFileError(
            "simulation.slew.duration_s",
            "missing: a fuel-optimal slew needs its duration",
            problem.source,
        )
    return fuel_optimal_slew(
        problem, settings.axis, angle, duration_s=float(settings.duration_s), options=options
    )


def sample_reference(
    time_s: np.ndarray,
    slew: SlewProfile | None = None,
    start_s: float = 0.0,
    *,
    feedforward: bool = False,
) -> Reference:
    """Reference quaternions at ``time_s``: the slew shifted by ``start_s``, held outside it.

    Between the profile's samples (which include every switching instant) the
    quaternion is a cubic Hermite interpolant of its values and derivatives
    ``q_dot = q (x) [0, omega] / 2``, then normalised: fourth-order accurate
    (below 1e-10 rad for the paper's slew sampled every second).
    """
    time_s = np.asarray(time_s, dtype=float)
    if slew is None:
        quaternion = np.tile([1.0, 0.0, 0.0, 0.0], (len(time_s), 1))
        return Reference(time_s, quaternion, None, start_s)
    local = np.clip(time_s - start_s, slew.time_s[0], slew.time_s[-1])
    derivative = quaternion_rate(slew.quaternion_BN, slew.rate_rad_s)
    spline = CubicHermiteSpline(slew.time_s, slew.quaternion_BN, derivative, axis=0)
    quaternion = spline(local)
    quaternion /= np.linalg.norm(quaternion, axis=1, keepdims=True)
    torque = None
    if feedforward:
        # The profile's torque, zero before the start and after the end.
        inputs = np.asarray(slew.input_function.map(len(time_s))(time_s - start_s)).T
        torque = inputs[:, :3]
    return Reference(time_s, quaternion, slew, start_s, torque)


def scenario_reference(problem: Problem) -> Reference:
    """The reference of the problem's ``[simulation]`` table at its control instants."""
    settings = problem.simulation
    period = 1.0 / settings.control_rate_hz
    steps = max(1, round(settings.duration_s / period))
    times = period * np.arange(steps + 1)
    if settings.reference == "hold" or settings.slew is None:
        return sample_reference(times)
    slew = generate_slew(problem, settings.slew, PROFILE_SAMPLE_S)
    return sample_reference(
        times, slew, settings.slew.start_s, feedforward=settings.slew.feedforward
    )
