"""Many demands at once: :meth:`Allocator.allocate_batch` (one solve per row) and
:meth:`Allocator.allocate_series` (a history, reusing active sets).

The functions here are those methods' bodies; they read the allocator's scaled
problem (``_qp``, references, caches), which is private to this package.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any

import numpy as np

from casadi_debris.allocation.demand import as_rows3, batch_forces
from casadi_debris.allocation.results import BatchAllocation, SeriesAllocation
from casadi_debris.allocation.scaled_qp import EXACT_PROXIMAL, THRUST_ROUND_OFF
from casadi_debris.allocation.series import PiecewiseAffineQp
from casadi_debris.errors import InputShapeError

if TYPE_CHECKING:
    from casadi_debris.allocation.allocator import Allocator

# Relative pull-in of a saturated demand in :func:`allocate_series`, so that the
# target lies strictly inside the reachable set (alpha is promised to 1e-9).
SERIES_BACKOFF = 1e-10


def allocate_batch(
    allocator: Allocator, torques_Nm: Any, forces_N: Any, free_force: bool
) -> BatchAllocation:
    """Body of :meth:`Allocator.allocate_batch`."""
    start = time.perf_counter()
    torques = as_rows3(torques_Nm, "torques_Nm")
    forces = batch_forces(torques, forces_N, free_force)
    results = [
        allocator._allocate(torques[i], None if forces is None else forces[i])
        for i in range(len(torques))
    ]
    k, n = len(results), allocator.n_engines
    return BatchAllocation(
        thrust_N=np.array([r.thrust_N for r in results]).reshape(k, n),
        torque_Nm=np.array([r.torque_Nm for r in results]).reshape(k, 3),
        force_N=np.array([r.force_N for r in results]).reshape(k, 3),
        feasible=np.array([r.feasible for r in results], dtype=bool),
        scale=np.array([r.scale for r in results]),
        fuel_rate_kg_s=np.array([r.fuel_rate_kg_s for r in results]),
        iterations=np.array([r.iterations for r in results], dtype=int),
        solve_time_s=np.array([r.solve_time_s for r in results]),
        wall_time_s=time.perf_counter() - start,
    )


def allocate_series(allocator: Allocator, torques_Nm: Any, free_force: bool) -> SeriesAllocation:
    """Body of :meth:`Allocator.allocate_series`."""
    start = time.perf_counter()
    torques = as_rows3(torques_Nm, "torques_Nm")
    if not np.isfinite(torques).all():
        raise InputShapeError("torques_Nm must be finite")
    qp = allocator._qp
    scale = allocator.authority_polytope(free_force=free_force).scale(torques)
    shrink = np.where(scale < 1.0, scale * (1.0 - SERIES_BACKOFF), 1.0)
    targets = torques * shrink[:, None] / allocator._torque_ref_Nm
    rows = qp.rows(free_force)
    if not free_force:
        targets = np.hstack([targets, np.zeros_like(targets)])
    series_qp = allocator._series_qps.get(free_force)
    if series_qp is None:
        series_qp = PiecewiseAffineQp(rows, qp.upper, EXACT_PROXIMAL)
        allocator._series_qps[free_force] = series_qp

    def solve_point(target: np.ndarray) -> np.ndarray:
        torque = target[:3] * allocator._torque_ref_Nm
        result = allocator._allocate(torque, None if free_force else np.zeros(3))
        return result.thrust_N / allocator._thrust_ref_N

    u, point_solves = series_qp.solve_series(targets, solve_point)
    u = np.where(u < THRUST_ROUND_OFF, 0.0, np.minimum(u, qp.upper))
    thrust = u * allocator._thrust_ref_N
    return SeriesAllocation(
        thrust_N=thrust,
        torque_Nm=thrust @ allocator.torque_map.T,
        force_N=thrust @ allocator.force_map.T,
        scale=scale,
        fuel_rate_kg_s=thrust.sum(axis=1) / allocator.exhaust_velocity_m_s,
        point_solves=point_solves,
        wall_time_s=time.perf_counter() - start,
    )
