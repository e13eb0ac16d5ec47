"""Result types of the allocator: one demand, a batch of demands, a series of demands.

Every field carries its unit in its name (SI); thrusts are per engine, in the
order of the allocator's maps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class Allocation:
    """Thrust of every engine for one demand.

    Attributes
    ----------
    thrust_N : ndarray, shape (n_engines,)
        Within ``0 <= f <= f_max`` always.
    torque_Nm : ndarray, shape (3,)
        Achieved torque ``B f``.
    force_N : ndarray, shape (3,)
        Achieved net force ``F f``.
    demand_torque_Nm : ndarray, shape (3,)
    demand_force_N : ndarray, shape (3,) or None
        None when the force was left free.
    feasible : bool
        The demand was met, to the tolerance :meth:`Allocator.allocate` promises.
    scale : float
        alpha of the direction-preserving saturation (1 when feasible); in
        least-squares mode the projection of the achieved torque on the demand,
        ``tau_a . tau / |tau|^2``.
    mode : str
        ``"exact"``, ``"scaled"``, ``"least_squares"`` or ``"pseudo_inverse"``.
    fuel_rate_kg_s : float
        Propellant mass flow ``sum(f) / (Isp g0)`` [kg/s].
    solver : str
    iterations : int
        Summed over the QP solves of this call.
    solve_time_s : float
        Wall time spent in the back-end (update + solve) [s].
    """

    thrust_N: np.ndarray
    torque_Nm: np.ndarray
    force_N: np.ndarray
    demand_torque_Nm: np.ndarray
    demand_force_N: np.ndarray | None
    feasible: bool
    scale: float
    mode: str
    fuel_rate_kg_s: float
    solver: str
    iterations: int
    solve_time_s: float


@dataclass(frozen=True, eq=False)
class BatchAllocation:
    """Allocations of many demands (rows).

    Attributes
    ----------
    thrust_N : ndarray, shape (k, n_engines)
    torque_Nm, force_N : ndarray, shape (k, 3)
    feasible : ndarray of bool, shape (k,)
    scale : ndarray, shape (k,)
    fuel_rate_kg_s : ndarray, shape (k,)
    iterations : ndarray of int, shape (k,)
    solve_time_s : ndarray, shape (k,)
        Back-end time per demand [s].
    wall_time_s : float
        Whole batch, Python included [s].
    """

    thrust_N: np.ndarray
    torque_Nm: np.ndarray
    force_N: np.ndarray
    feasible: np.ndarray
    scale: np.ndarray
    fuel_rate_kg_s: np.ndarray
    iterations: np.ndarray
    solve_time_s: np.ndarray
    wall_time_s: float


@dataclass(frozen=True, eq=False)
class SeriesAllocation:
    """Allocation of a history of demands (rows), see :meth:`Allocator.allocate_series`.

    Attributes
    ----------
    thrust_N : ndarray, shape (k, n_engines)
    torque_Nm, force_N : ndarray, shape (k, 3)
        Achieved torque ``B f`` and net force ``F f``.
    scale : ndarray, shape (k,)
        alpha of the direction-keeping saturation (1 when the demand is met).
    fuel_rate_kg_s : ndarray, shape (k,)
    point_solves : int
        Demands that needed a QP solve; the others reused an active set.
    wall_time_s : float
    """

    thrust_N: np.ndarray
    torque_Nm: np.ndarray
    force_N: np.ndarray
    scale: np.ndarray
    fuel_rate_kg_s: np.ndarray
    point_solves: int
    wall_time_s: float
