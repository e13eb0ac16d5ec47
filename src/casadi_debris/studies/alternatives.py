"""A swarm design side by side with others: authority, fuel per torque·time, failure
tolerance and mass, each without a controller.

The paper weighs alternatives to its 24 CubeSats with one main engine each (side-panel
engines, 2U CubeSats firing differentially, fewer CubeSats with more thrust) in words;
:func:`swarm_figures` gives the figures that decide between them for any problem:

- **authority**: the largest pure torque about each signed axis with the engines' forces
  cancelling (the closed loop's allocator keeps the net force zero), an LP over the
  engines (:func:`~casadi_debris.geometry.torque_authority`), and the weakest axis over
  the disturbance amplitude (the paper's "2.8 times the worst-case disturbance");
- **fuel per torque·time**: the least propellant mass flow that gives a pure torque about
  each signed axis at zero net force, per unit torque, an LP (the flow is linear in the
  torque up to the authority, so one solve per axis gives it);
- **failure tolerance**: the weakest-axis ratio left after the worst single and the worst
  double CubeSat failure (every set, an LP each:
  :mod:`~casadi_debris.studies.failures`), and how many of the single and double
  failures keep every signed axis above the disturbance;
- **mass**: the swarm's added mass and the combined body's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.config import SIGNED_AXES, Problem, signed_axis_vector
from casadi_debris.geometry import Authority, Geometry, build_geometry, torque_authority
from casadi_debris.records import Record
from casadi_debris.studies.failures import (
    authority_without,
    axis_ratios,
    first_least,
    set_authority,
    weakest_axis,
)
from casadi_debris.units import G_PER_KG, MN_PER_N, MNM_PER_NM, SECONDS_PER_HOUR


@dataclass(frozen=True)
class FailureTolerance(Record):
    """The weakest-axis authority ratio after failing whole CubeSats.

    Attributes
    ----------
    failed : list of int
        The worst set of that size (1-based CubeSat ids).
    worst_ratio : float
        Its weakest signed axis' authority over the disturbance amplitude.
    sets : int
        Sets of that size tried (all of them).
    sets_above_disturbance : int
        Sets that keep every signed axis above the disturbance amplitude.
    """

    failed: list[int]
    worst_ratio: float
    sets: int
    sets_above_disturbance: int


@dataclass(frozen=True)
class SwarmSummary(Record):
    """What decides between swarm designs, for one problem (see the module's text).

    ``fuel_per_torque_time_g_per_mNm_h``: grams of propellant per mN·m of pure torque held
    for an hour, per signed axis; ``single_failure`` and ``double_failure`` are None when
    the swarm has too few CubeSats for such a set; ``problem_sha256`` hashes the problem
    file (and the files it extends).
    """

    problem: str
    problem_sha256: str
    cubesats: int
    engines: int
    swarm_mass_kg: float
    total_mass_kg: float
    torque_max_zero_force_mNm: dict[str, float]
    weakest_axis: str
    weakest_ratio: float
    fuel_per_torque_time_g_per_mNm_h: dict[str, float]
    single_failure: FailureTolerance | None
    double_failure: FailureTolerance | None


def fuel_per_torque(allocator: Allocator, authority_Nm: Authority) -> dict[str, float]:
    """Least propellant flow per unit pure torque at zero net force, per signed axis.

    The allocator's exact least-fuel answer for half the authority about each signed
    axis (inside the authority, where the least flow is linear in the torque).

    Parameters
    ----------
    allocator : Allocator
        Of the swarm, all engines available.
    authority_Nm : Authority
        At zero net force.

    Returns
    -------
    dict
        ``{"+x": rate [kg/s per N m], ...}``; inf about an axis with no authority.
    """
    rates: dict[str, float] = {}
    for name in SIGNED_AXES:
        if authority_Nm[name] <= 0:
            rates[name] = float("inf")
            continue
        torque_Nm = 0.5 * authority_Nm[name]
        thrust_N = allocator.allocate(torque_Nm * signed_axis_vector(name)).thrust_N
        rates[name] = allocator.fuel_rate_kg_s(thrust_N) / torque_Nm
    return rates


def failure_tolerance(
    geometry: Geometry, disturbance_Nm: np.ndarray, size: int
) -> FailureTolerance | None:
    """The worst set of ``size`` failed CubeSats by weakest-axis ratio, over every set.

    Parameters
    ----------
    geometry : Geometry
    disturbance_Nm : ndarray, shape (3,)
        Disturbance amplitude per axis [N m].
    size : int
        CubeSats failed together.

    Returns
    -------
    FailureTolerance or None
        None when the swarm has ``size`` CubeSats or fewer.
    """
    n_cubesats = len(geometry.cubesats)
    if n_cubesats <= size:
        return None
    found = set_authority(
        range(n_cubesats), size, lambda failed: authority_without(geometry, failed)
    )
    weakest = found.weakest_ratio(disturbance_Nm)
    worst = first_least(weakest)
    return FailureTolerance(
        failed=[k + 1 for k in found.sets[worst]],
        worst_ratio=float(weakest.min()),
        sets=len(found.sets),
        sets_above_disturbance=int(np.sum(weakest > 1.0)),
    )


def swarm_figures(problem: Problem, *, max_failed: int = 2) -> SwarmSummary:
    """Authority, fuel per torque·time, failure tolerance and mass of ``problem``'s swarm.

    Parameters
    ----------
    problem : Problem
    max_failed : int
        0, 1 or 2: the failure sets to try (2: every single and double failure; 276
        double-failure LP sets for the paper's 24 CubeSats).

    Returns
    -------
    SwarmSummary
    """
    geometry = build_geometry(problem)
    allocator = Allocator.from_problem(problem, geometry)
    disturbance_Nm = np.abs(np.asarray(problem.disturbance.amplitude_mNm, dtype=float)) / MN_PER_N
    authority = torque_authority(geometry, zero_net_force=True)
    ratio = axis_ratios(authority, disturbance_Nm)
    weakest = weakest_axis(ratio, authority)
    # kg/s per N m -> g per (mN m h)
    per_mNm_h = G_PER_KG * SECONDS_PER_HOUR / MNM_PER_NM
    fuel = {k: v * per_mNm_h for k, v in fuel_per_torque(allocator, authority).items()}
    tolerance = [
        failure_tolerance(geometry, disturbance_Nm, size) if size <= max_failed else None
        for size in (1, 2)
    ]
    return SwarmSummary(
        problem=problem.name,
        problem_sha256=problem.sha256,
        cubesats=len(geometry.cubesats),
        engines=len(geometry.engines),
        swarm_mass_kg=float(sum(c.mass_kg for c in geometry.cubesats)),
        total_mass_kg=float(geometry.mass_kg),
        torque_max_zero_force_mNm=authority.to_mNm(),
        weakest_axis=weakest,
        weakest_ratio=ratio[weakest],
        fuel_per_torque_time_g_per_mNm_h=fuel,
        single_failure=tolerance[0],
        double_failure=tolerance[1],
    )
