"""Many demands at once: :meth:`Allocator.allocate_batch` (one solve per row) and
:meth:`Allocator.allocate_series` (a history, reusing active sets).

The functions here are those methods' bodies; they read the allocator's scaled
problem (``_qp``, references, bounds, caches), which is private to this package.
Rows are checked as :meth:`Allocator.allocate` checks one demand, and every row
of a series passes the same final check (finite, torque within the promised
tolerance of ``scale`` times the demand) or is recomputed by ``allocate``.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any

import numpy as np

from casadi_debris.allocation._demand import (
    SMALL_DEMAND,
    SMALLEST_SUBNORMAL,
    TORQUE_RTOL,
    as_rows3,
    batch_forces,
    check_rows,
)
from casadi_debris.allocation._results import BatchAllocation, SeriesAllocation
from casadi_debris.allocation._scaled_qp import EXACT_PROXIMAL, THRUST_ROUND_OFF
from casadi_debris.allocation._series import PiecewiseAffineQp

if TYPE_CHECKING:
    from casadi_debris.allocation._allocator import Allocator

# Relative pull-in of a saturated demand in :func:`allocate_series`, so that the
# target lies strictly inside the reachable set (alpha is promised to 1e-9).
SERIES_BACKOFF = 1e-10


def allocate_batch(
    allocator: Allocator, torques_Nm: Any, forces_N: Any, free_force: bool
) -> BatchAllocation:
    """Body of :meth:`Allocator.allocate_batch`."""
    start = time.perf_counter()
    torques = as_rows3(torques_Nm, "torques_Nm")
    check_rows(torques, "torques_Nm", allocator._torque_bound_Nm, "N m")
    forces = batch_forces(torques, forces_N, free_force, allocator._force_bound_N)
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
    check_rows(torques, "torques_Nm", allocator._torque_bound_Nm, "N m")
    qp = allocator._qp
    reference = allocator._torque_ref_Nm
    # Small demands are solved scaled up by a power of two (exactly) and scaled back,
    # as allocate does; those it cannot scale back (saturated at the scaled-up size, or
    # a limit binding there) go to allocate one by one below.
    exponent = _small_exponents(torques, SMALL_DEMAND * reference)
    small = exponent > 0
    any_small = bool(small.any())
    stretched = np.ldexp(torques, exponent[:, None]) if any_small else torques
    scale = allocator.authority_polytope(free_force=free_force).scale(stretched)
    one_by_one = small & (scale < 1.0)
    scale[small] = 1.0
    shrink = np.where(scale < 1.0, scale * (1.0 - SERIES_BACKOFF), 1.0)
    targets = stretched * shrink[:, None] / reference
    targets[one_by_one] = 0.0
    if not free_force:
        targets = np.hstack([targets, np.zeros_like(targets)])
    series_qp = allocator._series_qps.get(free_force)
    if series_qp is None:
        series_qp = PiecewiseAffineQp(qp.rows(free_force), qp.upper, EXACT_PROXIMAL, qp.cost)
        allocator._series_qps[free_force] = series_qp

    def solve_point(target: np.ndarray) -> np.ndarray:
        torque = target[:3] * allocator._torque_ref_Nm
        result = allocator._allocate(torque, None if free_force else np.zeros(3))
        return result.thrust_N / allocator._thrust_ref_N

    u, point_solves = series_qp.solve_series(targets, solve_point)
    u = np.where(u < THRUST_ROUND_OFF, 0.0, np.minimum(u, qp.upper))
    thrust = u * allocator._thrust_ref_N
    if any_small:
        one_by_one |= small & qp.binds(u)
        thrust[small] = np.ldexp(thrust[small], -exponent[small, None])
    achieved = _Achieved(allocator, thrust)
    one_by_one |= ~_rows_met(allocator, achieved, torques, scale, free_force)
    redo = np.flatnonzero(one_by_one)
    for i in redo:
        result = allocator._allocate(torques[i], None if free_force else np.zeros(3))
        thrust[i] = result.thrust_N
        scale[i] = result.scale
    if len(redo):
        achieved = _Achieved(allocator, thrust)
    return SeriesAllocation(
        thrust_N=thrust,
        torque_Nm=achieved.torque_Nm,
        force_N=achieved.force_N,
        scale=scale,
        fuel_rate_kg_s=allocator.fuel_rate_kg_s(thrust),
        point_solves=point_solves + len(redo),
        wall_time_s=time.perf_counter() - start,
    )


class _Achieved:
    """Torque, force and total thrust of every row of ``thrust`` (k, n) [N m, N, N]."""

    def __init__(self, allocator: Allocator, thrust: np.ndarray) -> None:
        self.torque_Nm = thrust @ allocator.torque_map.T
        self.force_N = thrust @ allocator.force_map.T
        self.total_N = thrust @ np.ones(thrust.shape[1])


def _row_max(values: np.ndarray) -> np.ndarray:
    """Largest entry of each row of a (k, 3) array (ten times faster than ``max(axis=1)``
    on three columns)."""
    return np.maximum(np.maximum(values[:, 0], values[:, 1]), values[:, 2])


def _small_exponents(torques: np.ndarray, size_Nm: float) -> np.ndarray:
    """Per row, ``k >= 0`` such that ``2**k`` times the row's largest component is in
    [size_Nm, 2 size_Nm]; 0 for rows of at least that size and for zero rows.

    The largest component is first normalised to [0.5, 1) by its own exponent, so
    that a subnormal row does not overflow ``size_Nm / row``.
    """
    exponent = np.zeros(len(torques), dtype=int)
    largest = _row_max(np.abs(torques))
    small = (largest < size_Nm) & (largest > 0.0)
    if small.any():
        mantissa, power = np.frexp(largest[small])
        _, extra = np.frexp(size_Nm / mantissa)
        exponent[small] = extra - power
    return exponent


def _rows_met(
    allocator: Allocator,
    achieved: _Achieved,
    torques: np.ndarray,
    scale: np.ndarray,
    free_force: bool,
) -> np.ndarray:
    """Per row: finite, and torque (and zero force) within the promised tolerance of
    ``scale`` times the demand (:func:`~casadi_debris.allocation._demand.within_tolerance`).

    A NaN anywhere in a row makes its comparisons False: not met.
    """
    n, lever, force_per_N = allocator.n_engines, allocator._lever_m, allocator._force_per_N
    total = achieved.total_N
    wanted = scale[:, None] * torques
    with np.errstate(invalid="ignore"):  # inf - inf in a broken row: NaN, not met
        size = np.maximum(_row_max(np.abs(wanted)), lever * total)
        tolerance = TORQUE_RTOL * size + n * (lever + 2.0) * SMALLEST_SUBNORMAL
        met = np.isfinite(total) & (_row_max(np.abs(achieved.torque_Nm - wanted)) <= tolerance)
        if not free_force:
            tolerance = (
                TORQUE_RTOL * force_per_N * total + n * (force_per_N + 2.0) * SMALLEST_SUBNORMAL
            )
            met &= _row_max(np.abs(achieved.force_N)) <= tolerance
    return met
