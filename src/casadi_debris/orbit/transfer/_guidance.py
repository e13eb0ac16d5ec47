"""Closed-loop Edelbaum steering: the transfer flown by feedback on the averaged dynamics.

Every guidance period the law measures the mean semi-major axis a and
inclination i, solves Edelbaum's transfer from there to the target (circular
orbits, :func:`~casadi_debris.orbit.transfer.edelbaum_yaw`) and flies
its initial yaw beta0 for the period. By the principle of optimality the
re-planned yaw is the open-loop optimum's when nothing disturbs the spiral; J2,
eccentricity and the staged, changing thrust are what the feedback absorbs.
The transfer ends when Edelbaum's remaining Δv is below a tolerance; the last
periods are shortened to that remaining Δv at the current acceleration, so the
law does not overshoot. Between burns the body is turned to the next thrust
direction (taken as instantaneous: minutes against weeks).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from casadi_debris.orbit.transfer._averaged import (
    averaged_step,
    edelbaum_yaw,
    radius_inclination,
)
from casadi_debris.orbit.transfer._thrust import Burn
from casadi_debris.units import SECONDS_PER_DAY

DEFAULT_PERIOD_S = 0.5 * SECONDS_PER_DAY
DEFAULT_TOLERANCE_M_S = 1e-3
# Shortened last periods converge geometrically; this caps a non-converging tail.
MAX_TAIL_STEPS = 60


@dataclass(frozen=True, eq=False)
class GuidedTransfer:
    """A transfer flown by the guidance law, one row per guidance period.

    Attributes
    ----------
    time_s : ndarray, shape (n,)
    elements : ndarray, shape (n, 5)
        Slow MEE ``[p (m), f, g, h, k]``.
    mass_kg : ndarray, shape (n,)
    yaw_rad : ndarray, shape (n,)
        Yaw flown from each row to the next (last repeats).
    burn : ndarray of int, shape (n,)
        Burn (index into the schedule) firing from each row to the next.
    reached : bool
        The remaining Edelbaum Δv fell below the tolerance.
    remaining_dv_m_s : float
        Edelbaum's Δv from the final state to the target.
    """

    time_s: np.ndarray
    elements: np.ndarray
    mass_kg: np.ndarray
    yaw_rad: np.ndarray
    burn: np.ndarray
    reached: bool
    remaining_dv_m_s: float


def remaining_dv_m_s(
    mu_m3_s2: float, x: np.ndarray, target_radius_m: float, target_inclination_rad: float
) -> float:
    """Edelbaum Δv [m/s] from slow elements ``x`` to the target circular orbit."""
    radius, inclination = radius_inclination(x)
    v0, v1 = math.sqrt(mu_m3_s2 / radius), math.sqrt(mu_m3_s2 / target_radius_m)
    angle = 0.5 * math.pi * (target_inclination_rad - inclination)
    return math.sqrt(max(v0 * v0 - 2.0 * v0 * v1 * math.cos(angle) + v1 * v1, 0.0))


def edelbaum_guidance(
    dynamics: ca.Function,
    x0: np.ndarray,
    mass_kg: float,
    target: tuple[float, float],
    burns: list[Burn],
    earth: tuple[float, float, float],
    *,
    period_s: float = DEFAULT_PERIOD_S,
    tolerance_m_s: float = DEFAULT_TOLERANCE_M_S,
) -> GuidedTransfer:
    """Fly Edelbaum steering through the burn schedule until the target or the last burn.

    Parameters
    ----------
    dynamics : casadi.Function
        :func:`~casadi_debris.orbit.transfer.averaged_dynamics`.
    x0 : ndarray, shape (5,)
        Initial slow MEE.
    mass_kg : float
    target : (float, float)
        Target radius [m] and inclination [rad] (circular orbit).
    burns : list of Burn
    earth : (float, float, float)
        mu [m^3/s^2], Re [m], J2.
    period_s : float
        Guidance period (the yaw is held over it).
    tolerance_m_s : float
        Done below this remaining Edelbaum Δv.
    """
    mu = earth[0]
    x, mass, time = np.asarray(x0, dtype=float), float(mass_kg), 0.0
    rows: list[tuple[float, np.ndarray, float, float, int]] = []
    remaining = remaining_dv_m_s(mu, x, *target)
    for index, burn in enumerate(burns):
        end = burn.start_s + burn.duration_s
        params = [*earth, burn.force_N, burn.flow_kg_s]
        tail = 0
        while time < end * (1.0 - 1e-12) and remaining > tolerance_m_s and tail < MAX_TAIL_STEPS:
            radius, inclination = radius_inclination(x)
            yaw = edelbaum_yaw(mu, radius, target[0], target[1] - inclination)
            to_go_s = remaining / (burn.force_N / mass)
            step = min(period_s, end - time, to_go_s)
            tail += step == to_go_s
            rows.append((time, x, mass, yaw, index))
            x_next, m_next = averaged_step(dynamics, x, mass, [yaw, 1.0], params, step)
            x, mass, time = np.array(x_next).ravel(), float(m_next), time + step
            remaining = remaining_dv_m_s(mu, x, *target)
        if remaining <= tolerance_m_s:
            break
    last_yaw = rows[-1][3] if rows else 0.0
    last_burn = rows[-1][4] if rows else 0
    rows.append((time, x, mass, last_yaw, last_burn))
    return GuidedTransfer(
        time_s=np.array([r[0] for r in rows]),
        elements=np.array([r[1] for r in rows]),
        mass_kg=np.array([r[2] for r in rows]),
        yaw_rad=np.array([r[3] for r in rows]),
        burn=np.array([r[4] for r in rows], dtype=int),
        reached=remaining <= tolerance_m_s,
        remaining_dv_m_s=remaining,
    )
