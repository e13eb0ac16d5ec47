"""The transfer's summary: what it takes, whether the swarm has it, and what it lacks."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.geometry import Geometry, max_thrust_N
from casadi_debris.orbit._elements import keplerian_from_mee
from casadi_debris.orbit._propulsion import ThrustSegment
from casadi_debris.orbit.transfer._guidance import GuidedTransfer, remaining_dv_m_s
from casadi_debris.orbit.transfer._ocp import OptimalTransfer
from casadi_debris.orbit.transfer._thrust import (
    Burn,
    StageUse,
    dv_of_burns,
    stage_switch_times_s,
    stage_use,
)
from casadi_debris.records import Record
from casadi_debris.units import (
    DEG_PER_RAD,
    M_PER_KM,
    MN_PER_N,
    SECONDS_PER_DAY,
    SECONDS_PER_HOUR,
)

# Largest swarm growth tried when sizing the CubeSats it lacks.
MAX_EXTRA_CUBESATS = 1000


@dataclass(frozen=True, kw_only=True)
class TransferSummary(Record):
    """A planned orbit transfer (``casadi-debris transfer``), units in the names.

    Attributes
    ----------
    problem, problem_sha256, objective : str
    edelbaum_dv_m_s : float
        Edelbaum's analytic Δv between the two circular orbits.
    transfer_dv_m_s, transfer_time_days, propellant_kg : float
        The optimal control problem's transfer (rocket equation on its mass).
    dv_vs_edelbaum_percent : float
        ``100 (transfer_dv / edelbaum_dv - 1)``.
    guidance_dv_m_s, guidance_time_days, guidance_propellant_kg : float
        Edelbaum steering flown in closed loop.
    ocp_success : bool
    ocp_status : str
    ocp_iterations : int
    ocp_solve_time_s : float
    final_altitude_km, final_inclination_deg, final_eccentricity : float
        The OCP's final orbit (mean elements).
    thrust_mN : list of float
        Zero-torque force of each thrust direction, in firing order.
    thrust_directions_body : list of list of float
        Those directions, body frame.
    direction_burn_days : list of float
        How long each direction can fire on its own stages.
    available_dv_m_s, available_time_days : float
        What the swarm's own stages give (rocket equation) and for how long.
    swarm_suffices : bool
        The optimal transfer ends before the swarm's own stages are spent.
    reached_altitude_km, reached_inclination_deg, reached_time_days : float
        Where the guidance law is when the swarm's stages are spent (the target if it suffices).
    shortfall_dv_m_s : float
        Edelbaum's Δv from there to the target (0 if it suffices).
    extra_stages_per_cubesat_needed : int
        More stages on every CubeSat that would close the gap.
    extra_cubesats_needed : int
        CubeSats like the swarm's average one (mass, and the propellant it burnt
        here) that would close it, by the rocket equation on the optimal Δv
        (taken as placed to fire at zero torque).
    stages_used : list of StageUse
        Per CubeSat (ids from 1), the swarm's own stages only.
    stage_switches : int
        Stages run dry during the transfer.
    propellant_left_kg : float
        Propellant left in the swarm's stages at the end.
    out_dir : str or None
    """

    problem: str
    problem_sha256: str
    objective: str
    edelbaum_dv_m_s: float
    transfer_dv_m_s: float
    transfer_time_days: float
    propellant_kg: float
    dv_vs_edelbaum_percent: float
    guidance_dv_m_s: float
    guidance_time_days: float
    guidance_propellant_kg: float
    ocp_success: bool
    ocp_status: str
    ocp_iterations: int
    ocp_solve_time_s: float
    final_altitude_km: float
    final_inclination_deg: float
    final_eccentricity: float
    thrust_mN: list[float]
    thrust_directions_body: list[list[float]]
    direction_burn_days: list[float]
    available_dv_m_s: float
    available_time_days: float
    swarm_suffices: bool
    reached_altitude_km: float
    reached_inclination_deg: float
    reached_time_days: float
    shortfall_dv_m_s: float
    extra_stages_per_cubesat_needed: int
    extra_cubesats_needed: int
    stages_used: list[StageUse] = field(default_factory=list)
    stage_switches: int = 0
    propellant_left_kg: float = 0.0
    out_dir: str | None = None


def trajectory_dv_m_s(mass_kg: np.ndarray, burn: np.ndarray, burns: list[Burn]) -> float:
    """Rocket-equation Δv [m/s] of a trajectory: sum of c_b ln(m_j / m_j+1) over its steps."""
    exhaust = np.array([burns[b].force_N / burns[b].flow_kg_s for b in burn[: len(mass_kg) - 1]])
    return float(np.sum(exhaust * np.log(mass_kg[:-1] / mass_kg[1:])))


def summarise(
    problem: Problem,
    geometry: Geometry,
    groups: tuple[ThrustSegment, ...],
    burns: list[Burn],
    guided: GuidedTransfer,
    optimal: OptimalTransfer,
    edelbaum_dv_m_s: float,
) -> tuple[TransferSummary, list[tuple[float, int, int]]]:
    """The :class:`TransferSummary` of a planned transfer, and its stage switches.

    Stage switches: (time [s], CubeSat, stage), 1-based, up to the transfer's end.
    """
    mu = problem.constants.earth_mu_km3_s2 * M_PER_KM**3
    radius_km = problem.constants.earth_radius_km
    target = (
        (radius_km + problem.transfer.to_altitude_km) * M_PER_KM,
        math.radians(problem.transfer.to_inclination_deg),
    )
    real = [b for b in burns if b.real]
    real_end_s = real[-1].start_s + real[-1].duration_s
    end_s = float(optimal.time_s[-1])
    dv = trajectory_dv_m_s(optimal.mass_kg, optimal.burn, burns)
    suffices = end_s <= real_end_s * (1.0 + 1e-9)
    reached = _state_at(guided, min(real_end_s, float(guided.time_s[-1])))
    final = keplerian_from_mee(optimal.elements[-1])
    loaded = sum(
        e.stages * e.stage_propellant_kg(problem.constants.standard_gravity_m_s2)
        for e in problem.engines
    )
    uses = stage_use(problem, geometry, groups, _firing_per_group(optimal, burns))
    profile = (optimal.time_s, optimal.throttle)
    switches = [
        s for s in stage_switch_times_s(problem, geometry, groups, burns, profile) if s[0] <= end_s
    ]
    stage_lives = sum(_stage_life_s(problem, geometry, g) for g in groups)
    result = TransferSummary(
        problem=problem.name,
        problem_sha256=problem.sha256,
        objective=optimal.objective,
        edelbaum_dv_m_s=edelbaum_dv_m_s,
        transfer_dv_m_s=dv,
        transfer_time_days=end_s / SECONDS_PER_DAY,
        propellant_kg=float(optimal.mass_kg[0] - optimal.mass_kg[-1]),
        dv_vs_edelbaum_percent=100.0 * (dv / edelbaum_dv_m_s - 1.0),
        guidance_dv_m_s=trajectory_dv_m_s(guided.mass_kg, guided.burn, burns),
        guidance_time_days=float(guided.time_s[-1]) / SECONDS_PER_DAY,
        guidance_propellant_kg=float(guided.mass_kg[0] - guided.mass_kg[-1]),
        ocp_success=optimal.success,
        ocp_status=optimal.status,
        ocp_iterations=optimal.iterations,
        ocp_solve_time_s=optimal.solve_time_s,
        final_altitude_km=final["semi_major_axis_m"] / M_PER_KM - radius_km,
        final_inclination_deg=final["inclination_rad"] * DEG_PER_RAD,
        final_eccentricity=final["eccentricity"],
        thrust_mN=[g.thrust_N * MN_PER_N for g in groups],
        thrust_directions_body=[[float(v) for v in g.direction_body] for g in groups],
        direction_burn_days=[g.firing_time_s / SECONDS_PER_DAY for g in groups],
        available_dv_m_s=float(dv_of_burns(real, geometry.mass_kg)[-1]),
        available_time_days=real_end_s / SECONDS_PER_DAY,
        swarm_suffices=suffices,
        reached_altitude_km=reached[0] / M_PER_KM - radius_km,
        reached_inclination_deg=reached[1] * DEG_PER_RAD,
        reached_time_days=min(real_end_s, end_s) / SECONDS_PER_DAY,
        shortfall_dv_m_s=0.0 if suffices else remaining_dv_m_s(mu, reached[2], *target),
        extra_stages_per_cubesat_needed=(
            0 if suffices else math.ceil((end_s - real_end_s) / stage_lives)
        ),
        extra_cubesats_needed=0 if suffices else _extra_cubesats(geometry, real, dv),
        stages_used=uses,
        stage_switches=len(switches),
        propellant_left_kg=loaded - sum(u.propellant_kg for u in uses),
    )
    return result, switches


def _stage_life_s(problem: Problem, geometry: Geometry, segment: ThrustSegment) -> float:
    """How much longer a direction fires with one more stage on every engine [s].

    Its most loaded engine (at full thrust) sets its firing time: one stage life
    of that engine more, stretched by its throttle.
    """
    load = segment.engine_thrust_N / max_thrust_N(geometry)
    engine = int(np.argmax(load))
    return problem.engines[engine].stage_life_h * SECONDS_PER_HOUR / load[engine]


def _state_at(guided: GuidedTransfer, time_s: float) -> tuple[float, float, np.ndarray]:
    """Semi-major axis [m], inclination [rad] and slow MEE of the guidance at ``time_s``."""
    elements = np.array([np.interp(time_s, guided.time_s, guided.elements[:, i]) for i in range(5)])
    kepler = keplerian_from_mee(elements)
    return kepler["semi_major_axis_m"], kepler["inclination_rad"], elements


def _firing_per_group(optimal: OptimalTransfer, burns: list[Burn]) -> dict[int, float]:
    """Full-thrust-equivalent firing time [s] of each direction on its own (real) stages."""
    firing: dict[int, float] = {}
    steps = np.diff(optimal.time_s) * optimal.throttle
    for step, burn_index in zip(steps, optimal.burn, strict=True):
        burn = burns[int(burn_index)]
        if burn.real:
            firing[burn.group] = firing.get(burn.group, 0.0) + float(step)
    return firing


def _extra_cubesats(geometry: Geometry, real: list[Burn], dv_needed_m_s: float) -> int:
    """Fewest extra CubeSats, each like the swarm's average one, for ``dv_needed_m_s``.

    Rocket equation on the whole swarm at its mean exhaust speed: the own
    burns' propellant plus, per new CubeSat, its mean mass and the mean
    propellant a CubeSat burnt in the own burns (what this swarm can use of a
    CubeSat's load: side engines that cannot push at zero torque do not count).
    """
    burnt = sum(b.flow_kg_s * b.duration_s for b in real)
    exhaust = sum(b.force_N * b.duration_s for b in real) / burnt
    count = len(geometry.cubesats)
    per_cubesat_kg = burnt / count
    cubesat_mass = sum(c.mass_kg for c in geometry.cubesats) / count
    for extra in range(MAX_EXTRA_CUBESATS + 1):
        mass = geometry.mass_kg + extra * cubesat_mass
        propellant = burnt + extra * per_cubesat_kg
        if exhaust * math.log(mass / (mass - propellant)) >= dv_needed_m_s:
            return extra
    return MAX_EXTRA_CUBESATS
