"""The attitude the closed loop is asked to follow, sampled at the control instants."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from casadi_debris.config import Problem, Simulation
from casadi_debris.guidance._sequence import Piece, sample_pieces, sequence_pieces
from casadi_debris.guidance._slew import slew_quaternions, slew_torque
from casadi_debris.slews import SlewProfile

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
    torque = slew_torque(slew, time_s - start_s) if feedforward else None
    return Reference(time_s, quaternion, slew, start_s, torque)


def control_instants(simulation: Simulation) -> np.ndarray:
    """The run's control instants 0, T, 2T, ... to its duration [s]."""
    period = 1.0 / simulation.control_rate_hz
    steps = max(1, round(simulation.duration_s / period))
    return np.asarray(period * np.arange(steps + 1))


def scenario_reference(problem: Problem) -> Reference:
    """The reference of the problem's ``[simulation]`` table at its control instants:
    a hold, its one slew, or its sequence of segments
    (:mod:`casadi_debris.guidance._sequence`)."""
    times = control_instants(problem.simulation)
    pieces = sequence_pieces(problem, PROFILE_SAMPLE_S)
    slews = [piece for piece in pieces if piece.slew is not None]
    torque = None
    if any(piece.feedforward for piece in slews):
        torque = np.zeros((len(times), 3))
        for piece in slews:
            if piece.feedforward and piece.slew is not None:
                torque += slew_torque(piece.slew, times - piece.start_s)
    first = slews[0] if slews else None
    return Reference(
        times,
        sample_pieces(pieces, times),
        None if first is None else first.slew,
        0.0 if first is None else first.start_s,
        torque,
        tuple(pieces),
    )
