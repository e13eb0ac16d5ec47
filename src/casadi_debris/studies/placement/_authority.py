"""Zero-net-force torque authority of a chosen layout, with and without failed CubeSats.

One linear programme per set of failed CubeSats
(:func:`~casadi_debris.geometry.axis_authority_Nm`, the six signed axes as
blocks of one LP) over the sets :func:`~casadi_debris.studies.failures.failure_sets`
enumerates.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from casadi_debris.geometry import Authority, axis_authority_Nm
from casadi_debris.studies.failures import authority_ratio, set_authority
from casadi_debris.studies.placement._data import PlacementData


def layout_authority_Nm(
    data: PlacementData, chosen: tuple[int, ...], failed: tuple[int, ...] = ()
) -> Authority:
    """Zero-net-force authority of the chosen candidates with some of them failed."""
    alive = [c for c in chosen if c not in set(failed)]
    engines = data.engines_of(alive)
    torque_Nm = axis_authority_Nm(
        data.torque_map[:, engines], data.force_map[:, engines], data.max_thrust_N[engines]
    )
    return Authority(torque_Nm, zero_net_force=True)


@dataclass(frozen=True)
class WorstFailures:
    """The worst set of ``k`` failed CubeSats per signed axis of one layout.

    Attributes
    ----------
    failures : int
        CubeSats failed per set (k).
    sets : int
        Sets evaluated (C(N, k)).
    authority_Nm : Authority
        Least authority left about each signed axis over the sets (each axis its own
        worst set).
    worst_set : tuple of tuple of int
        Per signed axis, the candidates (0-based) whose failure leaves it.
    """

    failures: int
    sets: int
    authority_Nm: Authority
    worst_set: tuple[tuple[int, ...], ...]

    def ratio(self, disturbance_Nm: np.ndarray) -> np.ndarray:
        """Authority over the disturbance about each signed axis, shape (6,)."""
        return authority_ratio(self.authority_Nm.torque_Nm, disturbance_Nm)


def worst_failures(data: PlacementData, chosen: tuple[int, ...], failures: int) -> WorstFailures:
    """Every set of ``failures`` of the chosen CubeSats failed, by LP; the worst per axis."""
    count = min(failures, len(chosen))
    found = set_authority(chosen, count, lambda failed: layout_authority_Nm(data, chosen, failed))
    authority, worst_set = found.worst_per_axis()
    return WorstFailures(
        failures=count,
        sets=len(found.sets),
        authority_Nm=Authority(authority, zero_net_force=True),
        worst_set=worst_set,
    )
