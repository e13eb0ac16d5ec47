"""Zero-net-force torque authority of a chosen layout, with and without failed CubeSats.

One linear programme per set of failed CubeSats holds the six signed axes as
independent blocks (the sum of six independent maxima is maximised by each
block's own maximum), which saves five solver calls per set.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from scipy.linalg import block_diag
from scipy.optimize import linprog

from casadi_debris.config import AXIS_NAMES, SIGNED_AXES
from casadi_debris.errors import CasadiDebrisError
from casadi_debris.studies.placement_data import PlacementData


def signed_axis(name: str) -> tuple[int, float]:
    """Axis index and sign of ``"+x"`` ... ``"-z"``."""
    return AXIS_NAMES.index(name[1]), 1.0 if name[0] == "+" else -1.0


def zero_force_authority_Nm(
    torque_map: np.ndarray, force_map: np.ndarray, max_thrust_N: np.ndarray
) -> np.ndarray:
    """Largest pure torque about each signed axis with zero net force [N m], shape (6,).

    Parameters
    ----------
    torque_map, force_map : ndarray, shape (3, n)
        Per newton of each engine (about any point: the force cancels).
    max_thrust_N : ndarray, shape (n,)
        Upper thrust bounds (0 for a failed engine).

    Returns
    -------
    ndarray, shape (6,)
        In the order of ``SIGNED_AXES`` (+x, -x, +y, -y, +z, -z).
    """
    n = len(max_thrust_N)
    if n == 0 or not np.any(max_thrust_N > 0):
        return np.zeros(len(SIGNED_AXES))
    unit = float(np.max(max_thrust_N))  # thrust in units of the largest: order one for HiGHS
    blocks, objective = [], []
    for name in SIGNED_AXES:
        axis, sign = signed_axis(name)
        others = [a for a in range(3) if a != axis]
        blocks.append(np.vstack([torque_map[others], force_map]))
        objective.append(-sign * torque_map[axis])
    a_eq = block_diag(*blocks)
    upper = np.tile(max_thrust_N / unit, len(SIGNED_AXES))
    result = linprog(
        np.concatenate(objective),
        A_eq=a_eq,
        b_eq=np.zeros(a_eq.shape[0]),
        bounds=[(0.0, float(u)) for u in upper],
        method="highs",
    )
    if result.status != 0 or result.x is None:
        raise CasadiDebrisError(f"authority LP failed: {result.message}")
    per_block = -np.array(objective) * result.x.reshape(len(SIGNED_AXES), n)
    return np.maximum(per_block.sum(axis=1), 0.0) * unit


def layout_authority_Nm(
    data: PlacementData, chosen: tuple[int, ...], failed: tuple[int, ...] = ()
) -> np.ndarray:
    """Authority (6 signed axes, N m) of the chosen candidates with some of them failed."""
    alive = [c for c in chosen if c not in set(failed)]
    engines = data.engines_of(alive)
    return zero_force_authority_Nm(
        data.torque_map[:, engines], data.force_map[:, engines], data.max_thrust_N[engines]
    )


@dataclass(frozen=True)
class WorstFailures:
    """The worst set of ``k`` failed CubeSats per signed axis of one layout.

    Attributes
    ----------
    failures : int
        CubeSats failed per set (k).
    sets : int
        Sets evaluated (C(N, k)).
    authority_Nm : ndarray, shape (6,)
        Least authority left about each signed axis over the sets.
    worst_set : tuple of tuple of int
        Per signed axis, the candidates (0-based) whose failure leaves it.
    """

    failures: int
    sets: int
    authority_Nm: np.ndarray
    worst_set: tuple[tuple[int, ...], ...]

    def ratio(self, disturbance_Nm: np.ndarray) -> np.ndarray:
        """Authority over the disturbance about each signed axis, shape (6,)."""
        return self.authority_Nm / np.repeat(disturbance_Nm, 2)


def worst_failures(data: PlacementData, chosen: tuple[int, ...], failures: int) -> WorstFailures:
    """Every set of ``failures`` of the chosen CubeSats failed, by LP; the worst per axis."""
    count = min(failures, len(chosen))
    sets = list(itertools.combinations(sorted(chosen), count))
    values = np.array([layout_authority_Nm(data, chosen, s) for s in sets])
    worst = np.argmin(values, axis=0)
    return WorstFailures(
        failures=count,
        sets=len(sets),
        authority_Nm=values[worst, range(len(SIGNED_AXES))],
        worst_set=tuple(sets[i] for i in worst),
    )
