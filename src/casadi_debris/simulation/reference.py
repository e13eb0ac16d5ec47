"""The attitude the closed loop is asked to follow, sampled at the control instants."""

from __future__ import annotations

import dataclasses
import logging
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from scipy.interpolate import CubicHermiteSpline

from casadi_debris.config import Problem, Simulation, SlewReference, SlewSettings
from casadi_debris.dynamics.attitude import quaternion_rate
from casadi_debris.errors import InputShapeError, ProblemFileError, SlewInfeasibleError
from casadi_debris.slews import (
    SlewOptions,
    SlewProfile,
    SlewTarget,
    bang_bang_slew,
    fuel_optimal_slew,
    slew_about_axis,
    time_optimal_slew,
)

if TYPE_CHECKING:
    from casadi_debris.simulation.sequence import Piece

logger = logging.getLogger(__name__)

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
    pieces : tuple of Piece
        The manoeuvre's segments, and the holds between them, in time order
        (empty for a reference built from a slew alone); ``slew`` and
        ``start_s`` are then its first slew's.
    """

    time_s: np.ndarray
    quaternion_BN: np.ndarray
    slew: SlewProfile | None
    start_s: float = 0.0
    feedforward_Nm: np.ndarray | None = None
    pieces: tuple[Piece, ...] = ()


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
    target = slew_about_axis(settings.axis, math.radians(settings.angle_deg))
    return solve_slew(
        problem, target, settings.settings, settings.duration_s, sample_s, "simulation.slew"
    )


def solve_slew(
    problem: Problem,
    target: SlewTarget,
    settings: SlewSettings,
    duration_s: float | None,
    sample_s: float,
    key: str,
) -> SlewProfile:
    """The slew to ``target`` by the method and options of ``settings``.

    Parameters
    ----------
    problem : Problem
    target : SlewTarget
        Start and end attitudes.
    settings : SlewSettings
    duration_s : float or None
        The slew's length [s] (a deadline for time-optimal); None: the method's own.
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
    if settings.method == "fuel-optimal" and duration_s is None:
        # The loader refuses it; a table built in Python may not.
        raise ProblemFileError(
            f"{key}.duration_s", "missing: a fuel-optimal slew needs its duration", problem.source
        )
    try:
        slew = _slew_of(problem, target, settings, duration_s, sample_s)
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
    problem: Problem,
    target: SlewTarget,
    settings: SlewSettings,
    duration_s: float | None,
    sample_s: float,
) -> SlewProfile:
    if settings.method == "bang-bang":
        return bang_bang_slew(
            problem,
            target=target,
            duration_s=duration_s,
            torque_fraction=settings.torque_fraction,
            sample_s=sample_s,
            check_vibration=False,
        )
    options = SlewOptions(
        thrusters=settings.thrusters,
        zero_net_force=settings.thrusters,
        flexible=settings.flexible,
        flexible_method=settings.flexible_method,
        sample_s=sample_s,
        check_vibration=False,
    )
    if settings.torque_fraction is not None:  # else the slew's own default
        options = dataclasses.replace(options, torque_fraction=settings.torque_fraction)
    if settings.method == "time-optimal":
        # A duration is the slew's deadline: the optimum must not be longer.
        return time_optimal_slew(problem, target=target, duration_s=duration_s, options=options)
    return fuel_optimal_slew(
        problem, target=target, duration_s=float(duration_s or 0.0), options=options
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


def _slew_torque(slew: SlewProfile, local_s: np.ndarray) -> np.ndarray:
    """The profile's torque at ``local_s``, zero before its start and after its end, (n, 3)."""
    return np.asarray(slew.input_function.map(len(local_s))(local_s)).T[:, :3]


def sample_reference(
    time_s: np.ndarray,
    slew: SlewProfile | None = None,
    start_s: float = 0.0,
    *,
    feedforward: bool = False,
) -> Reference:
    """Reference quaternions at ``time_s``: the slew shifted by ``start_s``, held outside it
    (interpolated as :func:`slew_quaternions` says)."""
    time_s = np.asarray(time_s, dtype=float)
    if slew is None:
        quaternion = np.tile([1.0, 0.0, 0.0, 0.0], (len(time_s), 1))
        return Reference(time_s, quaternion, None, start_s)
    quaternion = slew_quaternions(slew, time_s - start_s)
    torque = _slew_torque(slew, time_s - start_s) if feedforward else None
    return Reference(time_s, quaternion, slew, start_s, torque)


def control_instants(simulation: Simulation) -> np.ndarray:
    """The run's control instants 0, T, 2T, ... to its duration [s]."""
    period = 1.0 / simulation.control_rate_hz
    steps = max(1, round(simulation.duration_s / period))
    return np.asarray(period * np.arange(steps + 1))


def scenario_reference(problem: Problem) -> Reference:
    """The reference of the problem's ``[simulation]`` table at its control instants:
    a hold, its one slew, or its sequence of segments
    (:mod:`casadi_debris.simulation.sequence`)."""
    from casadi_debris.simulation.sequence import sample_pieces, sequence_pieces

    times = control_instants(problem.simulation)
    pieces = sequence_pieces(problem, PROFILE_SAMPLE_S)
    slews = [piece for piece in pieces if piece.slew is not None]
    torque = None
    if any(piece.feedforward for piece in slews):
        torque = np.zeros((len(times), 3))
        for piece in slews:
            if piece.feedforward and piece.slew is not None:
                torque += _slew_torque(piece.slew, times - piece.start_s)
    first = slews[0] if slews else None
    return Reference(
        times,
        sample_pieces(pieces, times),
        None if first is None else first.slew,
        0.0 if first is None else first.start_s,
        torque,
        tuple(pieces),
    )
