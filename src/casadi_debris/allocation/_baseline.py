"""Pseudo-inverse allocation with null-space bias and clipping: a baseline, for comparison only.

The minimum-norm solution ``f = pinv([B; F]) [tau; phi]`` has negative
entries, which one-directional engines cannot give. The classic fix lifts it
along a null-space direction with all entries positive (every engine of a
face pair firing equally: no torque, no force) until the smallest thrust is
zero, then clips at the limits. Clipping changes the torque: the result is
wrong in both size and direction when a limit is hit, which is what the
QP allocator (:class:`~casadi_debris.allocation.Allocator`) avoids.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from casadi_debris.allocation._allocator import Allocator
from casadi_debris.allocation._demand import as_vector3
from casadi_debris.allocation._results import Allocation
from casadi_debris.errors import AllocationError

# A null-space direction counts as positive when its smallest entry exceeds
# this fraction of its largest.
POSITIVE_NULL_TOLERANCE = 1e-9
# Relative torque error under which the baseline's answer counts as exact.
FEASIBLE_RTOL = 1e-9


class PseudoInverseAllocator:
    """Clipped pseudo-inverse on the engines an :class:`Allocator` can fire.

    Parameters
    ----------
    allocator : Allocator
        Gives the maps, the limits and the fuel rate conversion.
    free_force : bool
        Invert the torque rows only (net force free).

    Raises
    ------
    AllocationError
        The available engines have no positive null-space direction (no bias
        can make the pseudo-inverse one-directional).
    """

    def __init__(self, allocator: Allocator, *, free_force: bool = False) -> None:
        self.allocator = allocator
        self.free_force = free_force
        limits = allocator.max_thrust_N
        self._limits = limits
        available = limits > 0
        rows = (
            allocator.torque_map
            if free_force
            else np.vstack([allocator.torque_map, allocator.force_map])
        )
        rows = rows[:, available]
        self._available = available
        self._pinv = np.linalg.pinv(rows)
        # Positive null-space direction: project the all-ones vector on the null space.
        ones = np.ones(int(available.sum()))
        bias = ones - self._pinv @ (rows @ ones)
        if bias.min() <= POSITIVE_NULL_TOLERANCE * bias.max():
            raise AllocationError(
                "the available engines have no positive null-space direction for a "
                "pseudo-inverse bias"
            )
        self._bias = bias / bias.max()

    def allocate(self, torque_Nm: Any, force_N: Any = None) -> Allocation:
        """Thrust by biased, clipped pseudo-inverse (see the module docstring).

        Parameters
        ----------
        torque_Nm : array_like, shape (3,)
        force_N : array_like, shape (3,), optional
            Ignored when the baseline was built with ``free_force``; default zero.
        """
        start = time.perf_counter()
        # The allocator's checks (finite, not absurd): no NaN from an overflowing pinv.
        allocator = self.allocator
        torque = as_vector3(torque_Nm, "torque_Nm", allocator._torque_bound_Nm, "N m")
        force = (
            None
            if self.free_force
            else (
                np.zeros(3)
                if force_N is None
                else as_vector3(force_N, "force_N", allocator._force_bound_N, "N")
            )
        )
        demand = torque if force is None else np.concatenate([torque, force])
        f = self._pinv @ demand
        f = f + max(0.0, -float((f / self._bias).min())) * self._bias
        thrust = np.zeros(len(self._limits))
        thrust[self._available] = f
        thrust = np.clip(thrust, 0.0, self._limits)
        elapsed = time.perf_counter() - start
        achieved = allocator.torque_map @ thrust
        norm2 = float(torque @ torque)
        error = float(np.linalg.norm(achieved - torque))
        return Allocation(
            thrust_N=thrust,
            torque_Nm=achieved,
            force_N=allocator.force_map @ thrust,
            demand_torque_Nm=torque,
            demand_force_N=force,
            feasible=error <= FEASIBLE_RTOL * max(np.sqrt(norm2), 1e-300),
            scale=float(achieved @ torque / norm2) if norm2 > 0 else 1.0,
            mode="pseudo_inverse",
            fuel_rate_kg_s=allocator.fuel_rate_kg_s(thrust),
            solver="pseudo_inverse",
            iterations=0,
            solve_time_s=elapsed,
        )
