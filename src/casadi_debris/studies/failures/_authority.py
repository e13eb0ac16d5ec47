"""What a failure leaves of the swarm without flying it: torque authority and the holding load.

Authority
    The largest pure torque about each signed body axis at zero net force
    with the engines that can still fire (one LP, the six signed axes as its
    blocks: :func:`~casadi_debris.geometry.torque_authority`), and its ratio to the
    disturbance's amplitude about that axis (the paper's "2.8 times the
    worst-case disturbance").

Holding load
    To hold an attitude the engines must cancel the disturbance: the torque
    ``-d(t)`` over one disturbance period, sampled at
    :data:`HOLDING_SAMPLES` instants and allocated (least fuel, zero net
    force, direction kept when out of reach) with the case's engines. Its mean
    thrust per engine ``f_i`` gives the fuel per period, its spread over the
    CubeSats that still fire, and the re-allocation a failure needs (which
    CubeSats' mean thrust rises). The *time to first depletion* is that of the
    first engine to spend every stage it may still use when it keeps firing
    at ``f_i``: ``t_i = L_i F_i / f_i``, where ``L_i`` is its firing time left
    at full thrust ``F_i`` (every stage of an engine has one thrust, so
    ``L_i F_i`` is its impulse left). It leaves out slews and the controller's
    transients, and ends where the first engine drops out and the allocation
    would change.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from casadi_debris.allocation import Allocator, PropulsionState
from casadi_debris.config import Problem
from casadi_debris.dynamics import Model
from casadi_debris.geometry import Authority, Geometry, torque_authority
from casadi_debris.studies.failures._cases import FailureCase
from casadi_debris.studies.failures._records import HoldingSummary
from casadi_debris.studies.failures._sets import axis_ratios, weakest_axis
from casadi_debris.units import MN_PER_N, SECONDS_PER_MINUTE

HOLDING_SAMPLES = 360
"""Instants of the disturbance period the holding load is allocated at (one per degree)."""


@dataclass(frozen=True, eq=False)
class HoldingLoad:
    """The allocation of the torque that cancels the disturbance over one period.

    Attributes
    ----------
    period_s : float
        The disturbance period [s].
    thrust_per_cubesat_N : ndarray, shape (n_cubesats,)
        Mean thrust of each CubeSat's engines over the period [N].
    fuel_per_cubesat_kg : ndarray, shape (n_cubesats,)
        Propellant each CubeSat burns in one period [kg].
    survivors : ndarray of bool, shape (n_cubesats,)
        CubeSats with an engine that can still fire.
    saturated_fraction : float
        Share of the instants at which the disturbance is out of reach (0 .. 1).
    depletion_time_s : float
        Time to the first engine's depletion at its mean thrust [s] (inf when
        nothing fires).
    first_depleted : int or None
        Its CubeSat, 0-based.
    """

    period_s: float
    thrust_per_cubesat_N: np.ndarray
    fuel_per_cubesat_kg: np.ndarray
    survivors: np.ndarray
    saturated_fraction: float
    depletion_time_s: float
    first_depleted: int | None

    @property
    def fuel_spread(self) -> float | None:
        """Largest fuel of a surviving CubeSat over their mean (1: evenly spread)."""
        fuel = self.fuel_per_cubesat_kg[self.survivors]
        return float(fuel.max() / fuel.mean()) if len(fuel) and fuel.mean() > 0 else None

    def record(self) -> HoldingSummary:
        """For JSON: units in the names, CubeSats from 1."""
        return HoldingSummary(
            period_s=self.period_s,
            fuel_per_period_kg=float(self.fuel_per_cubesat_kg.sum()),
            fuel_per_cubesat_kg=tuple(self.fuel_per_cubesat_kg.tolist()),
            fuel_spread=self.fuel_spread,
            thrust_per_cubesat_mN=tuple((self.thrust_per_cubesat_N * MN_PER_N).tolist()),
            saturated_fraction=self.saturated_fraction,
            depletion_time_s=self.depletion_time_s,
            first_depleted_cubesat=None if self.first_depleted is None else self.first_depleted + 1,
        )


@dataclass(frozen=True, eq=False)
class CaseAuthority:
    """Authority and holding load of one case.

    Attributes
    ----------
    case : FailureCase
    torque_Nm : Authority
        Largest pure torque per signed axis at zero net force [N m].
    disturbance_Nm : ndarray, shape (3,)
        The disturbance's amplitude per axis [N m].
    holding : HoldingLoad or None
        None when no engine is left.
    """

    case: FailureCase
    torque_Nm: Authority
    disturbance_Nm: np.ndarray
    holding: HoldingLoad | None

    @property
    def ratio(self) -> dict[str, float]:
        """Authority over the disturbance's amplitude about each signed axis (inf: none)."""
        return axis_ratios(self.torque_Nm, self.disturbance_Nm)

    @property
    def worst_axis(self) -> str:
        """The signed axis of least authority relative to the disturbance."""
        return weakest_axis(self.ratio, self.torque_Nm)

    @property
    def worst_ratio(self) -> float:
        """The least of :attr:`ratio`."""
        return self.ratio[self.worst_axis]


def holding_torque_Nm(model: Model) -> np.ndarray:
    """``-d(t)`` at :data:`HOLDING_SAMPLES` instants of one disturbance period, shape (k, 3)."""
    problem = model.problem
    period_s = problem.disturbance.period_min * SECONDS_PER_MINUTE
    times = period_s * np.arange(HOLDING_SAMPLES) / HOLDING_SAMPLES
    return -np.asarray(model.disturbance.map(HOLDING_SAMPLES)(times)).T


def case_authority(
    problem: Problem, geometry: Geometry, case: FailureCase, holding_Nm: np.ndarray
) -> CaseAuthority:
    """Authority and holding load of ``case``.

    Parameters
    ----------
    problem : Problem
    geometry : Geometry
        Of ``problem``.
    case : FailureCase
    holding_Nm : ndarray, shape (k, 3)
        The torque to hold, from :func:`holding_torque_Nm`.
    """
    state = case.propulsion(problem)
    available = state.available
    authority = torque_authority(geometry, zero_net_force=True, available=available)
    disturbance_Nm = np.abs(problem.disturbance.amplitude_mNm) / MN_PER_N
    holding = _holding(problem, geometry, state, holding_Nm) if available.any() else None
    return CaseAuthority(case, authority, disturbance_Nm, holding)


def _holding(
    problem: Problem, geometry: Geometry, state: PropulsionState, holding_Nm: np.ndarray
) -> HoldingLoad:
    """The holding load's allocation with the engines of ``state`` (see the module)."""
    allocator = Allocator.from_problem(problem, geometry, state=state)
    series = allocator.allocate_batch(holding_Nm)
    period_s = problem.disturbance.period_min * SECONDS_PER_MINUTE
    thrust = series.thrust_N.mean(axis=0)
    full = state.max_thrust_N()
    firing = thrust > 0
    depletion = np.full(state.n_engines, np.inf)
    depletion[firing] = state.remaining_life_s()[firing] * full[firing] / thrust[firing]
    first = int(np.argmin(depletion))
    fuel_per_engine = thrust * period_s / state.exhaust_velocity_m_s
    return HoldingLoad(
        period_s=period_s,
        thrust_per_cubesat_N=state.per_cubesat(thrust),
        fuel_per_cubesat_kg=state.per_cubesat(fuel_per_engine),
        survivors=state.per_cubesat(state.available.astype(float)) > 0,
        saturated_fraction=float(np.mean(series.scale < 1.0)),
        depletion_time_s=float(depletion[first]),
        first_depleted=int(state.engine_cubesat[first]) if np.isfinite(depletion[first]) else None,
    )
