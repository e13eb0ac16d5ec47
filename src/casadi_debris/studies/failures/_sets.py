"""Every set of k failed CubeSats, and the torque authority each leaves.

The failure campaign (:func:`~casadi_debris.studies.failures.failure_cases`), the placement
study's failure-robust objective (:mod:`casadi_debris.studies.placement`)
and the swarm comparison (:mod:`casadi_debris.studies.alternatives`) all ask the
same question of a swarm: fail every set of ``k`` of its CubeSats, solve the
zero-net-force authority LP (:func:`~casadi_debris.geometry.axis_authority_Nm`)
with the engines left, and find the set that leaves least. This module is that
enumeration, in one order (lexicographic), and the ratio of an authority to the
disturbance it must beat.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import SIGNED_AXES
from casadi_debris.geometry import Authority, Geometry, torque_authority

TIE_RTOL = 1e-9
"""Authorities (or ratios) this close, relative to the least, are one worst."""


def failure_sets(members: Iterable[int], size: int) -> list[tuple[int, ...]]:
    """Every set of ``size`` of ``members``, each increasing, in lexicographic order.

    Parameters
    ----------
    members : iterable of int
        CubeSats (or candidates), 0-based; sorted here.
    size : int
        CubeSats failed together (0: the one empty set).

    Returns
    -------
    list of tuple of int
        C(len(members), size) sets.
    """
    return list(itertools.combinations(sorted(members), size))


def authority_ratio(authority_Nm: np.ndarray, disturbance_Nm: np.ndarray) -> np.ndarray:
    """Authority over the disturbance amplitude about each signed axis.

    Parameters
    ----------
    authority_Nm : ndarray, shape (..., 6)
        Per signed axis (+x, -x, +y, -y, +z, -z) [N m].
    disturbance_Nm : ndarray, shape (3,)
        Amplitude per body axis [N m].

    Returns
    -------
    ndarray, shape (..., 6)
        inf about an axis without disturbance.
    """
    amplitude = np.repeat(np.abs(np.asarray(disturbance_Nm, dtype=float)), 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(amplitude > 0, np.asarray(authority_Nm, dtype=float) / amplitude, np.inf)


def axis_ratios(authority_Nm: Authority, disturbance_Nm: np.ndarray) -> dict[str, float]:
    """:func:`authority_ratio` of an authority, as ``{"+x": ratio, ...}``."""
    ratio = authority_ratio(authority_Nm.torque_Nm, disturbance_Nm)
    return dict(zip(SIGNED_AXES, ratio.tolist(), strict=True))


def authority_without(geometry: Geometry, failed: tuple[int, ...]) -> Authority:
    """Zero-net-force authority per signed axis [N m] with every engine of the CubeSats
    ``failed`` (0-based) out."""
    available = ~np.isin(geometry.engine_cubesat, failed)
    return torque_authority(geometry, zero_net_force=True, available=available)


def weakest_axis(ratio: dict[str, float], authority_Nm: Authority) -> str:
    """The signed axis of least authority over the disturbance (of least authority among
    equal ratios, e.g. axes without disturbance)."""
    return min(SIGNED_AXES, key=lambda name: (ratio[name], authority_Nm[name]))


@dataclass(frozen=True, eq=False)
class SetAuthority:
    """The authority left after each set of failed CubeSats.

    Attributes
    ----------
    sets : tuple of tuple of int
        The failure sets (0-based), as :func:`failure_sets` gives them.
    authority_Nm : ndarray, shape (n_sets, 6)
        Authority left per signed axis [N m].
    """

    sets: tuple[tuple[int, ...], ...]
    authority_Nm: np.ndarray

    def worst_per_axis(self) -> tuple[np.ndarray, tuple[tuple[int, ...], ...]]:
        """Least authority per signed axis, shape (6,), and the set that leaves it
        (:func:`first_least` of each column)."""
        worst = [first_least(column) for column in self.authority_Nm.T]
        return self.authority_Nm.min(axis=0), tuple(self.sets[i] for i in worst)

    def weakest_ratio(self, disturbance_Nm: np.ndarray) -> np.ndarray:
        """Each set's least authority over the disturbance over the six axes, shape (n_sets,)."""
        return authority_ratio(self.authority_Nm, disturbance_Nm).min(axis=1) + 0.0  # no -0.0


def first_least(values: np.ndarray) -> int:
    """Index of the first value within :data:`TIE_RTOL` of the least.

    A symmetric swarm has many worst sets, equal but for the LP's round-off; the
    first of them in :func:`failure_sets` order is the one reported, whichever the
    round-off favours.
    """
    values = np.asarray(values, dtype=float)
    least = float(np.min(values))
    return int(np.argmax(values <= least + TIE_RTOL * abs(least)))


def set_authority(
    members: Iterable[int], size: int, authority_Nm: Callable[[tuple[int, ...]], Authority]
) -> SetAuthority:
    """The authority left by every set of ``size`` failed ``members``.

    Parameters
    ----------
    members : iterable of int
    size : int
    authority_Nm : callable
        ``authority_Nm(failed)``: the authority with the CubeSats ``failed`` out (an LP).

    Returns
    -------
    SetAuthority
    """
    sets = failure_sets(members, size)
    values = np.array([authority_Nm(failed).torque_Nm for failed in sets], dtype=float)
    return SetAuthority(tuple(sets), values.reshape(len(sets), len(SIGNED_AXES)))
