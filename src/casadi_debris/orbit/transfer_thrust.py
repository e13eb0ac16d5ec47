"""The swarm's thrust for an orbit transfer: thrust directions, their force, and staging.

A CubeSat thrusts only along its face's inward normal, so the swarm pushes the
debris along one of a few body directions (the paper's: six, four engines
each). To thrust along the direction the steering law asks for, the body is
turned so that one direction's engines point along it (the attitude loop's job,
not modelled here; a 180 deg slew takes ~20 min against burns of weeks). The
engines of that direction fire together, throttled so that their torques cancel:
the largest such force is a linear program (:func:`~casadi_debris.geometry.force_authority`
restricted to the direction's engines), its thrusts are the engines' throttles.

Staging: each engine fires its stages one after the other; a stage holds the
propellant of its rated life at full thrust (``F t_life / (Isp g0)``), so an
engine throttled to F_i < F_max runs ``F_max / F_i`` times longer on it. A
direction fires until the first of its engines has spent its last stage (the
others' leftover is reported as unused), then the body is turned to the next
direction. Directions fire strongest first. Burns past the swarm's own stages
(``real=False``) are hypothetical extra stage lives of the same engines: they
size what the swarm lacks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.geometry import Geometry, force_authority, max_thrust_N, thrust_directions
from casadi_debris.units import SECONDS_PER_HOUR

# Engines throttled below this fraction of their limit count as not firing.
FIRING_FRACTION = 1e-9


@dataclass(frozen=True, eq=False)
class ThrustGroup:
    """The engines of one thrust direction, throttled to push along it at zero torque.

    Attributes
    ----------
    direction : ndarray, shape (3,)
        Unit force direction on the body, body frame B.
    engines : tuple of int
        Its engines, 0-based.
    force_N : float
        Net force along ``direction`` [N].
    thrust_N : ndarray, shape (n_engines,)
        Every engine's thrust (zero outside the group) [N].
    flow_kg_s : float
        Propellant flow of the group [kg/s].
    burn_time_s : float
        Firing time until its first engine has spent its last stage [s].
    """

    direction: np.ndarray
    engines: tuple[int, ...]
    force_N: float
    thrust_N: np.ndarray
    flow_kg_s: float
    burn_time_s: float


@dataclass(frozen=True)
class Burn:
    """One direction firing, at constant force, from ``start_s`` for ``duration_s``.

    ``group`` indexes the list of :class:`ThrustGroup`; ``real`` is False for a
    hypothetical burn past the swarm's stages.
    """

    group: int
    start_s: float
    duration_s: float
    force_N: float
    flow_kg_s: float
    real: bool


def thrust_groups(problem: Problem, geometry: Geometry) -> list[ThrustGroup]:
    """The swarm's thrust directions with the force each gives at zero torque, strongest first.

    Directions whose engines cannot balance their torque (force 0) are left out.
    """
    engines = problem.engines
    exhaust = np.array([e.isp_s * problem.constants.standard_gravity_m_s2 for e in engines])
    limits = max_thrust_N(geometry)
    loads_s = np.array([e.stages * e.stage_life_h * SECONDS_PER_HOUR for e in engines])
    groups = []
    for direction, members in thrust_directions(geometry):
        available = np.isin(np.arange(len(limits)), members)
        force, thrust = force_authority(geometry, direction, available)
        firing = thrust > FIRING_FRACTION * limits
        if force <= 0.0 or not firing.any():
            continue
        # Full-thrust life of all stages, stretched by each engine's throttle.
        burn_time = float(np.min(loads_s[firing] * limits[firing] / thrust[firing]))
        groups.append(
            ThrustGroup(
                direction=np.asarray(direction, dtype=float),
                engines=tuple(members),
                force_N=force,
                thrust_N=thrust,
                flow_kg_s=float(np.sum(thrust / exhaust)),
                burn_time_s=burn_time,
            )
        )
    return sorted(groups, key=lambda g: -g.force_N)


def burn_schedule(groups: list[ThrustGroup], extra: int = 0) -> list[Burn]:
    """Every direction's burn in turn, then ``extra`` hypothetical burns cycling through them.

    Parameters
    ----------
    groups : list of ThrustGroup
    extra : int
        Burns past the swarm's stages (``real=False``), each as long as the
        real burn of its direction.
    """
    burns: list[Burn] = []
    start = 0.0
    for n in range(len(groups) + extra):
        index = n % len(groups)
        group = groups[index]
        burns.append(
            Burn(index, start, group.burn_time_s, group.force_N, group.flow_kg_s, n < len(groups))
        )
        start += group.burn_time_s
    return burns


@dataclass(frozen=True)
class StageUse:
    """The stages one CubeSat fired during a transfer (ids from 1).

    Attributes
    ----------
    cubesat : int
        1-based.
    stages : list of int
        Stages it fired (partly or wholly), 1-based.
    spent_stages : float
        Stage loads burnt (e.g. 2.4 = two stages and 40 % of the third).
    propellant_kg : float
    """

    cubesat: int
    stages: list[int]
    spent_stages: float
    propellant_kg: float


def stage_use(
    problem: Problem,
    geometry: Geometry,
    groups: list[ThrustGroup],
    firing_s: dict[int, float],
) -> list[StageUse]:
    """Stages and propellant per CubeSat after each direction fired for ``firing_s[group]`` [s].

    Only the swarm's real stages count: firing time past a group's burn time
    (hypothetical stages) is left out.
    """
    g0 = problem.constants.standard_gravity_m_s2
    limits = max_thrust_N(geometry)
    spent = np.zeros(len(limits))  # stage loads per engine
    propellant = np.zeros(len(limits))
    for index, seconds in firing_s.items():
        group = groups[index]
        time = min(seconds, group.burn_time_s)
        for engine in group.engines:
            spec = problem.engines[engine]
            load_s = spec.stage_life_h * SECONDS_PER_HOUR
            spent[engine] += time * group.thrust_N[engine] / limits[engine] / load_s
            propellant[engine] += time * group.thrust_N[engine] / (spec.isp_s * g0)
    uses = []
    for cubesat in geometry.cubesats:
        loads = max((spent[e] for e in cubesat.engines), default=0.0)
        fired = int(np.ceil(loads - 1e-9)) if loads > 1e-12 else 0
        uses.append(
            StageUse(
                cubesat=cubesat.index + 1,
                stages=list(range(1, fired + 1)),
                spent_stages=float(sum(spent[e] for e in cubesat.engines)),
                propellant_kg=float(sum(propellant[e] for e in cubesat.engines)),
            )
        )
    return uses


def stage_switch_times_s(
    problem: Problem,
    geometry: Geometry,
    groups: list[ThrustGroup],
    burns: list[Burn],
    throttle: tuple[np.ndarray, np.ndarray] | None = None,
) -> list[tuple[float, int, int]]:
    """When each engine's stage ran dry during the real burns.

    Parameters
    ----------
    problem, geometry, groups, burns
    throttle : (ndarray, ndarray), optional
        Node times [s], shape (N + 1,), and the throttle of each segment, shape
        (N,); default full thrust throughout. A throttled stage lasts longer.

    Returns
    -------
    list of (float, int, int)
        (time [s], CubeSat, stage), 1-based, in time order.
    """
    limits = max_thrust_N(geometry)
    if throttle is None:
        throttle = (np.array([0.0, burns[-1].start_s + burns[-1].duration_s]), np.ones(1))
    times = throttle[0]
    firing = np.concatenate([[0.0], np.cumsum(np.diff(times) * throttle[1])])
    events = []
    for burn in (b for b in burns if b.real):
        clock, fired = _burn_firing(burn, times, firing)
        fired_s = fired[-1]
        group = groups[burn.group]
        for engine in group.engines:
            if group.thrust_N[engine] <= FIRING_FRACTION * limits[engine]:
                continue
            spec = problem.engines[engine]
            stage_s = spec.stage_life_h * SECONDS_PER_HOUR * limits[engine] / group.thrust_N[engine]
            for stage in range(1, spec.stages + 1):
                if stage * stage_s <= fired_s * (1.0 + 1e-9):
                    cubesat = geometry.engines[engine].cubesat + 1
                    events.append((float(np.interp(stage * stage_s, fired, clock)), cubesat, stage))
    return sorted(events)


def _burn_firing(
    burn: Burn, times: np.ndarray, firing: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Clock times [s] within a burn and the full-thrust-equivalent firing [s] since it began.

    ``firing`` is the cumulative equivalent firing at ``times``; outside them it
    stays at its end values (no firing past the trajectory).
    """
    end_s = burn.start_s + burn.duration_s
    inside = (times > burn.start_s) & (times < end_s)
    clock = np.concatenate([[burn.start_s], times[inside], [end_s]])
    fired = np.interp(clock, times, firing)
    return clock, fired - fired[0]


def dv_of_burns(burns: list[Burn], mass_kg: float, min_mass_fraction: float = 0.0) -> np.ndarray:
    """Cumulative rocket-equation Δv [m/s] at the end of each burn.

    Stops before a burn that would leave less than ``min_mass_fraction`` of
    ``mass_kg``: the result is then shorter than ``burns``.
    """
    mass, total, out = mass_kg, 0.0, []
    for burn in burns:
        burnt = burn.flow_kg_s * burn.duration_s
        if mass - burnt <= min_mass_fraction * mass_kg:
            break
        total += burn.force_N / burn.flow_kg_s * math.log(mass / (mass - burnt))
        mass -= burnt
        out.append(total)
    return np.array(out)
