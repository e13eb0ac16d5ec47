"""The mission from launch to re-entry: transfer, detumble, deorbit burns and decay.

The phases, in the order the swarm flies them, each from its own model:

1. **Transfer** of each CubeSat on its own, before docking, from the problem's
   ``[transfer]`` orbit to the debris' (the paper's reading: 150 m/s of the ≈300 m/s one
   stage gives a free-flying CubeSat). Edelbaum's Δv between the circular orbits; the
   propellant by the rocket equation with the CubeSat's mass and its strongest engine;
   the time at that thrust.
2. **Detumble** after docking: the closed-loop rigid-body run of
   :func:`~casadi_debris.simulation.detumble.simulate_detumble` (allocator, staging, fuel). The
   run starts from full tanks: the transfer burns less than a stage, so the stages the
   detumble fires keep their thrust.
3. **Deorbit**: the swarm as the transfer and the detumble leave it, engine by engine
   (the torque-free impulse LP of :func:`~casadi_debris.orbit.swarm_thrust`
   on what each engine still carries; what no torque-free mix can use is *stranded*),
   and the docked body's mass without the propellant burnt so far;
   :func:`~casadi_debris.orbit.plan_deorbit` on that model gives each solar case's least
   Δv and flies it, or everything usable when that is less.
4. **Decay** to re-entry; the five-year verdict is the deorbit plan's rule (counted from
   the burn's start) under every solar case.

Propellant is booked engine by engine and stage by stage
(:mod:`~casadi_debris.studies.propellant_books`): the transfer on each CubeSat's
strongest engine, the detumble as the run's allocator fired the engines, the deorbit
burn (the governing case's) as the torque-free mixes of its directions, in the plan's
order (strongest with full tanks first).
A shortfall is reported, not hidden.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import Problem, check_transfer_end
from casadi_debris.geometry import Geometry, build_geometry
from casadi_debris.orbit import (
    DIRECTION_DECIMALS,
    CaseTrajectory,
    DeorbitCase,
    DeorbitModel,
    DeorbitPlan,
    DeorbitSettings,
    SwarmThrust,
    plan_deorbit,
    solar_case,
    swarm_thrust,
)
from casadi_debris.orbit.transfer import transfer_dv_m_s
from casadi_debris.records import Record
from casadi_debris.simulation.detumble import DetumbleRunResult, simulate_detumble
from casadi_debris.studies.propellant_books import PhaseBook, PropellantBooks, detumble_engine_kg
from casadi_debris.units import DAYS_PER_YEAR, SECONDS_PER_DAY

MAX_EXTRA_STAGES = 10
"""More stages per engine than this is another swarm, not the same one topped up."""


@dataclass(frozen=True)
class MissionPhase(Record):
    """One phase of the timeline: when, how long, what it costs.

    ``start_days`` counts from the start of the transfer; ``propellant_kg`` is the whole
    swarm's.
    """

    name: str
    start_days: float
    duration_days: float | None
    dv_m_s: float | None
    propellant_kg: float
    note: str


@dataclass(frozen=True)
class MissionSummary(Record):
    """The mission's ``summary.json``: the answer to the five-year question and its parts.

    ``reentry_years`` (per solar case, from the deorbit burn's start; None beyond the
    plan's horizon) is for the Δv the swarm still has, ``deorbit_dv_m_s`` the governing
    case's least Δv, ``deorbit_dv_available_m_s`` the torque-free Δv of the propellant
    left after transfer and detumble (``deorbit_dv_capacity_m_s``: with full tanks).
    ``propellant_per_cubesat_kg`` maps each phase to one value per CubeSat (CubeSat
    ``k + 1`` at index ``k``); ``books`` has the same per stage, and the stages each
    CubeSat has begun by each phase's end. ``propellant_stranded_kg`` is what no
    torque-free mix of the deorbit burn can use (per CubeSat in
    ``stranded_per_cubesat_kg``); ``propellant_left_kg`` all that is left after the
    burn, stranded included; ``capacity_per_stage_kg`` what each CubeSat's stages carry
    when full (summed over its engines). ``problem_sha256`` hashes the problem file (and
    the files it extends). ``extra_stages_needed``: how many more stages on every engine
    would make the mission meet the rule (0 when it does; None when
    :data:`MAX_EXTRA_STAGES` would not).
    """

    problem: str
    problem_sha256: str
    detumble_time_h: float | None
    transfer_dv_m_s: float
    transfer_time_days: float
    deorbit_dv_m_s: float
    deorbit_dv_available_m_s: float
    deorbit_dv_capacity_m_s: float
    reentry_years: dict[str, float | None]
    deorbit_dv_needed_m_s: dict[str, float | None]
    meets_five_year_rule: bool
    extra_stages_needed: int | None
    limit_years: float
    governing_case: str
    propellant_total_kg: float
    propellant_used_kg: float
    propellant_left_kg: float
    propellant_stranded_kg: float
    stranded_per_cubesat_kg: list[float]
    capacity_per_stage_kg: list[list[float]]
    propellant_per_cubesat_kg: dict[str, list[float]]
    books: list[PhaseBook]
    phases: list[MissionPhase]


@dataclass(frozen=True, eq=False)
class Mission:
    """The summary and what its figures draw: the detumble run and each case's decay.

    ``plan`` is the deorbit plan of the swarm as the transfer and detumble leave it,
    ``model`` that swarm and body (its thrust: the directions' torque-free mixes).
    """

    summary: MissionSummary
    detumble: DetumbleRunResult
    trajectories: tuple[CaseTrajectory, ...]
    plan: DeorbitPlan
    model: DeorbitModel


def transfer_per_cubesat(problem: Problem) -> tuple[float, np.ndarray, np.ndarray]:
    """Edelbaum Δv [m/s] of the ``[transfer]``, and each CubeSat's propellant [kg] and
    thrust time [s] flying it alone on its strongest engine."""
    dv, engine_kg, time_s = transfer_per_engine(problem)
    cubesat = np.asarray(problem.engine_cubesats)
    n = len(problem.cubesats)
    return dv, np.bincount(cubesat, weights=engine_kg, minlength=n), time_s


def transfer_per_engine(problem: Problem) -> tuple[float, np.ndarray, np.ndarray]:
    """Edelbaum Δv [m/s]; each engine's transfer propellant [kg], shape (n_engines,)
    (each CubeSat's strongest engine burns, the others not); each CubeSat's thrust time
    [s], shape (n_cubesats,)."""
    g0 = problem.constants.standard_gravity_m_s2
    check_transfer_end(problem)
    dv = transfer_dv_m_s(problem)  # 0 for CubeSats launched into the debris' orbit
    engine_kg = np.zeros(len(problem.engines))
    time_s = []
    first = 0
    for cubesat in problem.cubesats:
        k = max(range(len(cubesat.engines)), key=lambda j: cubesat.engines[j].thrust_per_stage_mN)
        engine = cubesat.engines[k]
        exhaust = engine.isp_s * g0
        used = cubesat.mass_kg * (1.0 - math.exp(-dv / exhaust))
        engine_kg[first + k] = used
        time_s.append(used * exhaust / (engine.thrust_per_stage_mN * 1e-3))
        first += len(cubesat.engines)
    return dv, engine_kg, np.array(time_s)


def propellant_per_cubesat_kg(problem: Problem) -> np.ndarray:
    """Every stage's propellant of each CubeSat's engines, shape (n_cubesats,) [kg]."""
    g0 = problem.constants.standard_gravity_m_s2
    return np.array(
        [sum(e.stages * e.stage_propellant_kg(g0) for e in c.engines) for c in problem.cubesats]
    )


def thrust_left(
    problem: Problem, geometry: Geometry, left_Ns: np.ndarray, full: SwarmThrust
) -> SwarmThrust:
    """The torque-free thrust of the swarm whose engine ``i`` carries ``left_Ns[i]`` [N s].

    The LP of :func:`swarm_thrust` on the problem with each engine's stage life cut in
    proportion to what it has left (thrust and directions unchanged); the stages keep
    their full impulse (``full.stage_impulse_Ns``) for counting. The directions keep the
    order of ``full`` (strongest with full tanks first: the plan's order): the uneven
    leftovers of the detumble change the thrusts by a percent or so, and re-sorting on
    them could swap directions of very different drag area, changing the plan for no
    reason of its own.
    """
    capacity = full.engine_capacity_Ns
    fractions = iter(np.divide(left_Ns, capacity, out=np.zeros_like(capacity), where=capacity > 0))
    cubesats = tuple(
        dataclasses.replace(
            c,
            engines=tuple(
                dataclasses.replace(e, stage_life_h=e.stage_life_h * float(next(fractions)))
                for e in c.engines
            ),
        )
        for c in problem.cubesats
    )
    thrust = swarm_thrust(dataclasses.replace(problem, cubesats=cubesats), geometry)
    rank = {_key(s.direction_body): i for i, s in enumerate(full.segments)}
    segments = sorted(thrust.segments, key=lambda s: rank.get(_key(s.direction_body), len(rank)))
    return dataclasses.replace(
        thrust, segments=tuple(segments), stage_impulse_Ns=full.stage_impulse_Ns
    )


def _key(direction: np.ndarray) -> tuple[float, ...]:
    return tuple(np.round(direction, DIRECTION_DECIMALS).tolist())


def plan_mission(problem: Problem, settings: DeorbitSettings | None = None) -> Mission:
    """Fly the mission's phases for ``problem`` (see the module's text).

    Parameters
    ----------
    problem : Problem
        Debris, swarm, ``[orbit]`` (the debris'), ``[transfer]`` and ``[detumble]``.
    settings : DeorbitSettings, optional
        Of the deorbit plan (solar cases, limit, ...); the minimum-swarm search and the
        lifetime Monte Carlo are left to ``casadi-debris deorbit``.

    Returns
    -------
    Mission

    Raises
    ------
    AllocationError
        A CubeSat's strongest engine does not carry the transfer's propellant.
    """
    settings = settings or DeorbitSettings(minimum_swarm=False, samples=0)
    geometry = build_geometry(problem)
    books = PropellantBooks.from_problem(problem)
    dv_transfer, transfer_kg, transfer_s = transfer_per_engine(problem)
    pages = [books.burn("transfer", transfer_kg)]
    tumble = simulate_detumble(problem)
    pages.append(books.burn("detumble", detumble_engine_kg(problem, tumble)))
    full = swarm_thrust(problem, geometry)
    left_Ns = books.left_impulse_Ns()  # before the deorbit burn
    thrust = thrust_left(problem, geometry, left_Ns, full)
    mass = geometry.mass_kg - float(books.used_kg.sum())
    model = DeorbitModel.from_problem(problem, settings, thrust=thrust, mass_kg=mass)
    plan = plan_deorbit(model, settings)
    governing = next(c for c in plan.cases if c.solar == plan.governing_case)
    usable_kg = thrust.engine_impulse(thrust.impulse_Ns) / books.exhaust_m_s
    stranded = books.per_cubesat(np.clip(books.left_kg() - usable_kg, 0.0, None))
    deorbit_kg = thrust.engine_impulse(governing.impulse_Ns) / books.exhaust_m_s
    pages.append(books.burn("deorbit burn", deorbit_kg))
    trajectories = [_trajectory(model, case, settings) for case in plan.cases]
    # With full tanks: the same rocket equation on the same model (no second build).
    capacity = dataclasses.replace(
        model, thrust=full, decay=model.decay.with_mass(geometry.mass_kg)
    ).capacity_dv_m_s
    extra: int | None = 0
    if not plan.meets_five_year_rule:
        stage_kg = float((full.stage_impulse_Ns / books.exhaust_m_s).sum())
        extra = extra_stages_needed(problem, settings, (geometry, full), (left_Ns, mass, stage_kg))
    summary = _summary(
        problem, plan, tumble, (dv_transfer, transfer_s), books, pages, stranded, (capacity, extra)
    )
    return Mission(summary, tumble, tuple(trajectories), plan, model)


def extra_stages_needed(
    problem: Problem,
    settings: DeorbitSettings,
    swarm: tuple[Geometry, SwarmThrust],
    before_burn: tuple[np.ndarray, float, float],
) -> int | None:
    """The fewest more stages on every engine with which the deorbit meets the rule.

    ``before_burn`` is what the swarm has when the deorbit burn starts: each engine's
    impulse left [N s], shape (n_engines,), the mass [kg], and one more stage's
    propellant on every engine [kg]. Each extra stage adds a full stage's impulse to
    every engine and its propellant to the mass; the deorbit is then planned again (its
    least Δv grows with the mass). None when :data:`MAX_EXTRA_STAGES` would not do.
    """
    geometry, full = swarm
    left_Ns, mass_kg, stage_kg = before_burn
    for extra in range(1, MAX_EXTRA_STAGES + 1):
        topped_Ns = left_Ns + extra * full.stage_impulse_Ns
        thrust = thrust_left(problem, geometry, topped_Ns, full)
        heavier = mass_kg + extra * stage_kg
        model = DeorbitModel.from_problem(problem, settings, thrust=thrust, mass_kg=heavier)
        if plan_deorbit(model, settings).meets_five_year_rule:
            return extra
    return None


def _trajectory(
    model: DeorbitModel, case: DeorbitCase, settings: DeorbitSettings
) -> CaseTrajectory:
    """The case's flown plan, burn and decay, for the figures."""
    density = model.density(solar_case(case.solar))
    history = model.fly(case.flown_dv_m_s, density, case.arc_half_width_deg, settings.horizon_years)
    return CaseTrajectory(
        case.solar, history, np.array([case.flown_dv_m_s]), np.array([history.reentry_years])
    )


def _finite(value: float) -> float | None:
    return value if math.isfinite(value) else None


def _summary(
    problem: Problem,
    plan: DeorbitPlan,
    tumble: DetumbleRunResult,
    transfer: tuple[float, np.ndarray],
    books: PropellantBooks,
    pages: list[PhaseBook],
    stranded: np.ndarray,
    capacity_and_extra: tuple[float, int | None],
) -> MissionSummary:
    """The summary and the timeline (the governing case's burn and decay);
    ``capacity_and_extra``: the deorbit Δv with full tanks [m/s] and the extra stages
    on every engine that would meet the rule."""
    dv_transfer, transfer_s = transfer
    capacity_dv_m_s, extra_stages = capacity_and_extra
    run = tumble.summary
    governing = next(c for c in plan.cases if c.solar == plan.governing_case)
    transfer_days = float(transfer_s.max()) / SECONDS_PER_DAY
    detumble_days = run.duration_s / SECONDS_PER_DAY
    burn_days = governing.burn_duration_days
    start_burn = transfer_days + detumble_days
    decay_years = _finite(governing.reentry_years)
    kg = {page.phase: page.propellant_kg for page in pages}
    phases = [
        MissionPhase("transfer", 0.0, transfer_days, dv_transfer, kg["transfer"],
                     "each CubeSat alone, before docking (Edelbaum)"),
        MissionPhase("detumble", transfer_days, detumble_days, run.dv_used_m_s, kg["detumble"],
                     "docked, closed loop, rigid body"),
        MissionPhase("deorbit burn", start_burn, burn_days, governing.flown_dv_m_s,
                     kg["deorbit burn"], f"governing case: {plan.governing_case} solar activity"),
        MissionPhase("decay", start_burn + burn_days,
                     None if decay_years is None else decay_years * DAYS_PER_YEAR - burn_days,
                     None, 0.0, "natural decay to re-entry"),
    ]  # fmt: skip
    reentry = {c.solar: _finite(c.reentry_years) for c in plan.cases}
    return MissionSummary(
        problem=problem.name,
        problem_sha256=problem.sha256,
        detumble_time_h=run.time_to_threshold_h,
        transfer_dv_m_s=dv_transfer,
        transfer_time_days=transfer_days,
        deorbit_dv_m_s=plan.deorbit_dv_m_s,
        deorbit_dv_available_m_s=plan.capacity_dv_m_s,
        deorbit_dv_capacity_m_s=capacity_dv_m_s,
        reentry_years=reentry,
        deorbit_dv_needed_m_s={c.solar: _finite(c.deorbit_dv_m_s) for c in plan.cases},
        meets_five_year_rule=all(y is not None and y <= plan.limit_years for y in reentry.values()),
        extra_stages_needed=extra_stages,
        limit_years=plan.limit_years,
        governing_case=plan.governing_case,
        propellant_total_kg=float(books.capacity_kg.sum()),
        propellant_used_kg=float(books.used_kg.sum()),
        propellant_left_kg=float(books.left_kg().sum()),
        propellant_stranded_kg=float(stranded.sum()),
        stranded_per_cubesat_kg=stranded.tolist(),
        capacity_per_stage_kg=books.per_cubesat(books.capacity_kg).tolist(),
        propellant_per_cubesat_kg={page.phase: page.per_cubesat_kg for page in pages},
        books=pages,
        phases=phases,
    )
