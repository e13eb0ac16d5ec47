"""The slews a reference follows: one ``[simulation.slew]`` solved as it asks (bang-bang,
time- or fuel-optimal), and a slew profile's attitude at any instant."""

from __future__ import annotations

import logging
import math

import numpy as np
from scipy.interpolate import CubicHermiteSpline

from casadi_debris.config import Problem, SlewRequest
from casadi_debris.dynamics import quaternion_rate
from casadi_debris.errors import InputShapeError, ProblemFileError, SlewInfeasibleError
from casadi_debris.slews import (
    OptimalSlewSettings,
    SlewProfile,
    SlewTarget,
    bang_bang_slew,
    fuel_optimal_slew,
    slew_about_axis,
    time_optimal_slew,
)

logger = logging.getLogger(__name__)


def generate_slew(problem: Problem, request: SlewRequest, sample_s: float) -> SlewProfile:
    """The slew a ``[simulation.slew]`` table asks for: a turn about a body axis from the
    reference attitude (rigid; torque level, or thruster level with zero net force when
    ``request.thrusters``).

    Parameters
    ----------
    problem : Problem
    request : SlewRequest
        A turn (``request.axis``, ``request.angle_deg``).
    sample_s : float
        Output sample spacing [s] (the control period).

    Raises
    ------
    ProblemFileError
        The slew cannot be done as the table asks (e.g. a duration below the
        minimum), naming ``simulation.slew.duration_s`` when one is given.
    """
    target = slew_about_axis(request.axis, math.radians(request.angle_deg))
    return solve_slew(problem, target, request, sample_s, "simulation.slew")


def solve_slew(
    problem: Problem,
    target: SlewTarget,
    request: SlewRequest,
    sample_s: float,
    key: str,
) -> SlewProfile:
    """The slew to ``target`` (``request.target`` resolved for its start attitude) by the
    method, timing and options of ``request``.

    Parameters
    ----------
    problem : Problem
    target : SlewTarget
        Start and end attitudes.
    request : SlewRequest
        Its ``duration_s`` is the slew's length [s] (a deadline for time-optimal); None:
        the method's own.
    sample_s : float
        Output sample spacing [s].
    key : str
        Dotted key of the table the slew comes from, for errors.

    Raises
    ------
    ProblemFileError
        The slew cannot be done as asked, naming ``<key>.duration_s`` when a
        duration is given, else ``key``.
    """
    duration_s = request.duration_s
    if request.method == "fuel-optimal" and duration_s is None:
        # The loader refuses it; a request built in Python may not.
        raise ProblemFileError(
            f"{key}.duration_s", "missing: a fuel-optimal slew needs its duration", problem.source
        )
    try:
        slew = _slew_of(problem, target, request, sample_s)
    except SlewInfeasibleError as exc:
        named = f"{key}.duration_s" if duration_s is not None else key
        raise ProblemFileError(named, str(exc), problem.source) from None
    except InputShapeError as exc:
        raise ProblemFileError(key, str(exc), problem.source) from None
    if not slew.limits.limits_ok:
        # Flown anyway (the loop saturates with the direction kept), but never silently.
        logger.warning(
            "%s: the %s slew is not within the engines' limits (%s; worst at t = %.6g s): "
            "the closed loop will saturate following it",
            key,
            slew.method,
            slew.limits.limits_note,
            slew.limits.worst_ratio_time_s,
        )
    return slew


def _slew_of(
    problem: Problem, target: SlewTarget, request: SlewRequest, sample_s: float
) -> SlewProfile:
    if request.method == "bang-bang":
        return bang_bang_slew(
            problem,
            target=target,
            duration_s=request.duration_s,
            torque_fraction=request.torque_fraction,
            rate_limit_rad_s=request.rate_limit_rad_s,
            sample_s=sample_s,
            check_vibration=False,
        )
    options = OptimalSlewSettings.for_request(request, sample_s=sample_s, check_vibration=False)
    if request.method == "time-optimal":
        # A duration is the slew's deadline: the optimum must not be longer.
        return time_optimal_slew(
            problem, target=target, duration_s=request.duration_s, options=options
        )
    return fuel_optimal_slew(
        problem, target=target, duration_s=float(request.duration_s or 0.0), options=options
    )


def slew_quaternions(slew: SlewProfile, local_s: np.ndarray) -> np.ndarray:
    """The slew's attitude at times ``local_s`` from its start, held outside it, (n, 4).

    Between the profile's samples (which include every switching instant) the
    quaternion is a cubic Hermite interpolant of its values and derivatives
    ``q_dot = q (x) [0, omega] / 2``, then normalised: fourth-order accurate
    (below 1e-10 rad for the paper's slew sampled every second).
    """
    local = np.clip(local_s, slew.time_s[0], slew.time_s[-1])
    derivative = quaternion_rate(slew.quaternion_BN, slew.rate_rad_s)
    spline = CubicHermiteSpline(slew.time_s, slew.quaternion_BN, derivative, axis=0)
    quaternion = spline(local)
    quaternion /= np.linalg.norm(quaternion, axis=1, keepdims=True)
    return np.asarray(quaternion)


def slew_torque(slew: SlewProfile, local_s: np.ndarray) -> np.ndarray:
    """The profile's torque at ``local_s``, zero before its start and after its end, (n, 3)."""
    return np.asarray(slew.input_function.map(len(local_s))(local_s)).T[:, :3]
