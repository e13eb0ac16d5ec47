"""Initial guesses of the slew OCP: controls on a time grid, a length, a peak rate.

A rigid slew starts from the eigenaxis bang-bang
(:func:`~casadi_debris.slews._bang_bang.eigenaxis_guess`) at the requested
duration or at the rigid limit, its torque put in the OCP's controls (the
least-fuel thrust at thruster level). A flexible slew starts from the rigid
optimum through the zero-vibration shaper (:mod:`casadi_debris.slews._shaper`).
The transcription marches the guess's controls through its own collocation
equations, so the guess's states need not be given.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from casadi_debris.slews._bang_bang import eigenaxis_guess
from casadi_debris.slews._ocp_problem import SlewOcp
from casadi_debris.slews._profile import SlewProfile
from casadi_debris.slews._propellant import least_fuel_thrust
from casadi_debris.slews._shaper import held


@dataclass(frozen=True)
class InitialGuess:
    """Where IPOPT starts.

    Attributes
    ----------
    controls : callable
        ``controls(times_s)``: the OCP's controls (SI, shape (n, n_u)) at the times
        (s, shape (n,)).
    total_s : float
        The guess's length, s; also the unit of the integrals in the objective.
    peak_rate_rad_s : float
        Its peak body rate, rad/s: the scale of the rates and of the end momentum.
    """

    controls: Callable[[np.ndarray], np.ndarray]
    total_s: float
    peak_rate_rad_s: float


class BangBangReferences:
    """The eigenaxis bang-bang slews of one OCP, each duration computed once.

    Parameters
    ----------
    ocp : SlewOcp
    """

    def __init__(self, ocp: SlewOcp) -> None:
        self.ocp = ocp
        self._profiles: dict[float, SlewProfile] = {}

    def at(self, duration_s: float) -> SlewProfile:
        """Eigenaxis bang-bang of ``duration_s`` (s; at least the rigid limit)."""
        duration_s = max(duration_s, self.ocp.limit_duration_s)
        if duration_s not in self._profiles:
            self._profiles[duration_s] = eigenaxis_guess(
                self.ocp.rigid_model, self.ocp.target, duration_s
            )
        return self._profiles[duration_s]


def bang_bang_guess(
    ocp: SlewOcp, reference: SlewProfile, fuel: bool, total_s: float
) -> InitialGuess:
    """The torque-level ``reference`` as a guess of ``total_s`` seconds."""
    peak_rate = float(np.max(np.linalg.norm(reference.rate_rad_s, axis=1)))
    return InitialGuess(
        controls=lambda times: control_guess(ocp, reference, times, fuel),
        total_s=total_s,
        peak_rate_rad_s=peak_rate,
    )


def shaped_guess(knots_s: np.ndarray, controls: np.ndarray, peak_rate_rad_s: float) -> InitialGuess:
    """Controls held on knot intervals as a guess.

    Parameters
    ----------
    knots_s : ndarray, shape (N + 1,)
        Interval bounds, s, from 0.
    controls : ndarray, shape (N, n_u)
        The control held on each interval, SI.
    peak_rate_rad_s : float
        The peak rate they give, rad/s.
    """
    return InitialGuess(
        controls=lambda times: held(knots_s, controls, times),
        total_s=float(knots_s[-1]),
        peak_rate_rad_s=peak_rate_rad_s,
    )


def control_guess(
    ocp: SlewOcp, reference: SlewProfile, times_s: np.ndarray, fuel: bool
) -> np.ndarray:
    """Controls of the torque-level ``reference`` at ``times_s`` in the OCP's form.

    Returns
    -------
    ndarray, shape (len(times_s), n_u)
        Torque in the box (N m), its positive and negative parts (fuel-optimal
        torque level), or the least-fuel thrust of each engine (N, thruster level).
    """
    inputs = np.array(reference.input_function.map(len(times_s))(times_s)).T
    torque = np.clip(inputs[:, :3], ocp.lower, ocp.upper)
    if ocp.thrusters:
        return least_fuel_thrust(ocp.geometry, torque, zero_net_force=ocp.options.zero_net_force)[0]
    if fuel:
        return np.hstack([np.maximum(torque, 0.0), np.maximum(-torque, 0.0)])
    return torque
