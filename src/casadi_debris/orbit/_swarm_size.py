"""The smallest swarm that brings the debris down within the limit.

A swarm of N CubeSats like the problem's first one (its mass, its first
engine's stages, thrust, Isp and stage life), all pushing along the debris'
strongest thrust direction with zero net torque, is taken as placeable (pairs
symmetric about the centre of gravity: the LP of
:mod:`~casadi_debris.orbit._propulsion` is not re-run for it). The debris
without the problem's CubeSats carries them. For each N the least Δv is that
of :mod:`~casadi_debris.orbit._deorbit` with N's thrust (more thrust, a shorter
burn, a little less Δv) and N's mass; N is the least whose stages carry that
Δv under every solar case. The search is a bisection on N: the carried Δv
grows with N and the needed one does not.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from casadi_debris.orbit._atmosphere import solar_case
from casadi_debris.orbit._deorbit import STRATEGIES, DeorbitModel, DeorbitSettings, best_strategy
from casadi_debris.orbit._propulsion import SwarmThrust, ThrustSegment
from casadi_debris.records import Record
from casadi_debris.units import MN_PER_N, SECONDS_PER_HOUR

MAX_CUBESATS = 1024


@dataclass(frozen=True)
class MinimumSwarm(Record):
    """The fewest CubeSats (all on the strongest direction) that meet the limit.

    Attributes
    ----------
    cubesats : int
    stages : int
        All their stages.
    thrust_mN : float
        Together.
    mass_kg : float
        Debris and swarm.
    deorbit_dv_m_s : float
        Least Δv under the governing case with this thrust.
    capacity_dv_m_s : float
        What the N CubeSats carry.
    strategy : str
    arc_half_width_deg : float
    governing_case : str
    """

    cubesats: int
    stages: int
    thrust_mN: float
    mass_kg: float
    deorbit_dv_m_s: float
    capacity_dv_m_s: float
    strategy: str
    arc_half_width_deg: float
    governing_case: str


def swarm_of(model: DeorbitModel, count: int) -> DeorbitModel:
    """``model`` with ``count`` of its problem's first CubeSat instead of its swarm."""
    problem = model.problem
    cubesat = problem.cubesats[0]
    engine = cubesat.engines[0]
    g0 = problem.constants.standard_gravity_m_s2
    thrust = engine.thrust_per_stage_mN / MN_PER_N * count
    stage_impulse = engine.thrust_per_stage_mN / MN_PER_N * engine.stage_life_h * SECONDS_PER_HOUR
    capacity = np.full(count, stage_impulse * engine.stages)
    direction = model.thrust.segments[0].direction_body
    swarm = SwarmThrust(
        segments=(
            ThrustSegment(
                direction,
                thrust,
                float(capacity.sum()),
                capacity,
                float(capacity.sum()) / (engine.isp_s * g0),
            ),
        ),
        engine_capacity_Ns=capacity,
        stage_impulse_Ns=np.full(count, stage_impulse),
        exhaust_speed_m_s=engine.isp_s * g0,
        engine_cubesat=np.arange(count),
    )
    bare = model.decay.mass_kg - sum(c.mass_kg for c in problem.cubesats)
    return dataclasses.replace(
        model,
        decay=model.decay.with_mass(bare + count * cubesat.mass_kg),
        burn_areas_m2=model.burn_areas_m2[:1],
        thrust=swarm,
    )


def _enough(model: DeorbitModel, settings: DeorbitSettings, case: str) -> tuple[bool, float, str]:
    need, strategy = best_strategy(model, model.density(solar_case(case)), settings)
    return math.isfinite(need) and need <= model.capacity_dv_m_s, need, strategy


def minimum_swarm(
    model: DeorbitModel, settings: DeorbitSettings, governing_case: str
) -> MinimumSwarm | None:
    """The fewest CubeSats that carry the least Δv under ``governing_case`` (then checked
    under the other cases); None if even :data:`MAX_CUBESATS` do not."""
    low, high = 0, 1
    while not _enough(swarm_of(model, high), settings, governing_case)[0]:
        low, high = high, 2 * high
        if high > MAX_CUBESATS:
            return None
    while high - low > 1:
        middle = (low + high) // 2
        if _enough(swarm_of(model, middle), settings, governing_case)[0]:
            high = middle
        else:
            low = middle
    count = high
    for case in settings.solar:
        while not _enough(swarm_of(model, count), settings, case)[0]:
            count += 1
            if count > MAX_CUBESATS:
                return None
    chosen = swarm_of(model, count)
    _, need, strategy = _enough(chosen, settings, governing_case)
    segment = chosen.thrust.segments[0]
    engine = model.problem.cubesats[0].engines[0]
    return MinimumSwarm(
        cubesats=count,
        stages=count * engine.stages,
        thrust_mN=segment.thrust_N * MN_PER_N,
        mass_kg=chosen.decay.mass_kg,
        deorbit_dv_m_s=need,
        capacity_dv_m_s=chosen.capacity_dv_m_s,
        strategy="spiral" if STRATEGIES[strategy] >= 180.0 else "perigee",
        arc_half_width_deg=STRATEGIES[strategy],
        governing_case=governing_case,
    )
