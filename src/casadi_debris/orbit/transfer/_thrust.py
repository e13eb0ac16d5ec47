"""The orbit transfer's burns, staging and propellant, from the swarm's thrust segments.

The thrust itself is :func:`~casadi_debris.orbit._propulsion.swarm_thrust`, the
one model the deorbit burns use too: a few body directions (the engines' own
force directions), each with the largest torque-free impulse the engines give
along it at zero force across it, fired at a constant mix. To thrust along the
direction the steering law asks for, the body is turned so that a segment's
direction points along it (the attitude loop's job, not modelled here; a 180
deg slew takes ~20 min against burns of weeks).

Staging: each engine fires its stages one after the other; a stage holds the
propellant of its rated life at full thrust (``F t_life / (Isp g0)``), so an
engine throttled to F_i < F_max runs ``F_max / F_i`` times longer on it. A
direction fires for its segment's firing time (its most loaded engine has then
spent its share of the stages), then the body is turned to the next direction.
Directions fire strongest first. Burns past the swarm's own stages
(``real=False``) are hypothetical extra stage lives of the same engines: they
size what the swarm lacks.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.geometry import Geometry, max_thrust_N
from casadi_debris.orbit._propulsion import ThrustSegment
from casadi_debris.units import SECONDS_PER_HOUR


@dataclass(frozen=True)
class Burn:
    """One direction firing, at constant force, from ``start_s`` for ``duration_s``.

    ``group`` indexes the thrust segments
    (:attr:`~casadi_debris.orbit._propulsion.SwarmThrust.segments`); ``real`` is
    False for a hypothetical burn past the swarm's stages.
    """

    group: int
    start_s: float
    duration_s: float
    force_N: float
    flow_kg_s: float
    real: bool


def burn_schedule(segments: Sequence[ThrustSegment], extra: int = 0) -> list[Burn]:
    """Every direction's burn in turn, then ``extra`` hypothetical burns cycling through them.

    Parameters
    ----------
    segments : sequence of ThrustSegment
    extra : int
        Burns past the swarm's stages (``real=False``), each as long as the
        real burn of its direction.
    """
    burns: list[Burn] = []
    start = 0.0
    for n in range(len(segments) + extra):
        index = n % len(segments)
        segment = segments[index]
        duration = segment.firing_time_s
        burns.append(
            Burn(index, start, duration, segment.thrust_N, segment.flow_kg_s, n < len(segments))
        )
        start += duration
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
    segments: Sequence[ThrustSegment],
    firing_s: dict[int, float],
) -> list[StageUse]:
    """Stages and propellant per CubeSat after each direction fired for ``firing_s[segment]`` [s].

    Only the swarm's real stages count: firing time past a segment's firing time
    (hypothetical stages) is left out.
    """
    g0 = problem.constants.standard_gravity_m_s2
    limits = max_thrust_N(geometry)
    spent = np.zeros(len(limits))  # stage loads per engine
    propellant = np.zeros(len(limits))
    for index, seconds in firing_s.items():
        segment = segments[index]
        time = min(seconds, segment.firing_time_s)
        thrust = segment.engine_thrust_N
        for engine in segment.engines:
            spec = problem.engines[engine]
            load_s = spec.stage_life_h * SECONDS_PER_HOUR
            spent[engine] += time * thrust[engine] / limits[engine] / load_s
            propellant[engine] += time * thrust[engine] / (spec.isp_s * g0)
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
    segments: Sequence[ThrustSegment],
    burns: list[Burn],
    throttle: tuple[np.ndarray, np.ndarray] | None = None,
) -> list[tuple[float, int, int]]:
    """When each engine's stage ran dry during the real burns.

    Parameters
    ----------
    problem, geometry, segments, burns
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
        thrust = segments[burn.group].engine_thrust_N
        for engine in segments[burn.group].engines:
            spec = problem.engines[engine]
            stage_s = spec.stage_life_h * SECONDS_PER_HOUR * limits[engine] / thrust[engine]
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
