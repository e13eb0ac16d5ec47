"""The mission from launch to re-entry: transfer, detumble, deorbit burns and decay.

The phases, in the order the swarm flies them, each from its own model:

1. **Transfer** of each CubeSat on its own, before docking, from the problem's
   ``[transfer]`` orbit to the debris' (the paper's reading: 150 m/s of the ≈300 m/s one
   stage gives a free-flying CubeSat). Edelbaum's Δv between the circular orbits; the
   propellant by the rocket equation with the CubeSat's mass and its strongest engine;
   the time at that thrust.
2. **Detumble** after docking: the closed-loop rigid-body run of
   :func:`~casadi_debris.simulation.detumble.detumble` (allocator, staging, fuel).
3. **Deorbit**: :func:`~casadi_debris.orbit.plan_deorbit` gives the least Δv each solar
   case needs. The swarm burns what it still carries after the transfer and the detumble:
   the Δv of the propellant left, with the plan's torque-free exhaust speed
   (``capacity / ln(M / (M - m_all))``, ``m_all`` every stage's propellant). A case
   whose need exceeds that flies what is left and its re-entry is computed for it.
4. **Decay** to re-entry; the five-year verdict is the deorbit plan's rule (counted from
   the burn's start) under every solar case.

Propellant is booked per phase and per CubeSat; a shortfall is reported, not hidden.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.errors import ProblemFileError
from casadi_debris.orbit import DeorbitPlan, DeorbitSettings, plan_deorbit
from casadi_debris.orbit.atmosphere import solar_case
from casadi_debris.orbit.curves import CaseTrajectory
from casadi_debris.orbit.deorbit import DeorbitModel
from casadi_debris.orbit.transfer import check_transfer
from casadi_debris.records import Record
from casadi_debris.simulation.detumble import DetumbleResult, detumble
from casadi_debris.units import SECONDS_PER_DAY

DAYS_PER_YEAR = 365.25


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
    case's least Δv, ``deorbit_dv_available_m_s`` what the propellant left after transfer
    and detumble gives. ``propellant_per_cubesat_kg`` maps each phase to one value per
    CubeSat (CubeSat ``k + 1`` at index ``k``).
    """

    problem: str
    detumble_time_h: float | None
    transfer_dv_m_s: float
    transfer_time_days: float
    deorbit_dv_m_s: float
    deorbit_dv_available_m_s: float
    deorbit_dv_capacity_m_s: float
    reentry_years: dict[str, float | None]
    deorbit_dv_needed_m_s: dict[str, float | None]
    meets_five_year_rule: bool
    limit_years: float
    propellant_total_kg: float
    propellant_used_kg: float
    propellant_per_cubesat_kg: dict[str, list[float]]
    phases: list[MissionPhase]


@dataclass(frozen=True, eq=False)
class Mission:
    """The summary and what its figures draw: the detumble run and each case's decay."""

    summary: MissionSummary
    detumble: DetumbleResult
    trajectories: tuple[CaseTrajectory, ...]
    plan: DeorbitPlan


def transfer_per_cubesat(problem: Problem) -> tuple[float, np.ndarray, np.ndarray]:
    """Edelbaum Δv [m/s] of the ``[transfer]``, and each CubeSat's propellant [kg] and
    thrust time [s] flying it alone on its strongest engine."""
    constants = problem.constants
    try:
        dv = check_transfer(problem)
    except ProblemFileError:  # launched into the debris' orbit: nothing to transfer
        dv = 0.0
    propellant, time_s = [], []
    for cubesat in problem.cubesats:
        engine = max(cubesat.engines, key=lambda e: e.thrust_per_stage_mN)
        exhaust = engine.isp_s * constants.standard_gravity_m_s2
        used = cubesat.mass_kg * (1.0 - math.exp(-dv / exhaust))
        propellant.append(used)
        time_s.append(used * exhaust / (engine.thrust_per_stage_mN * 1e-3))
    return dv, np.array(propellant), np.array(time_s)


def propellant_per_cubesat_kg(problem: Problem) -> np.ndarray:
    """Every stage's propellant of each CubeSat's engines, shape (n_cubesats,) [kg]."""
    g0 = problem.constants.standard_gravity_m_s2
    return np.array(
        [sum(e.stages * e.stage_propellant_kg(g0) for e in c.engines) for c in problem.cubesats]
    )


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
    """
    settings = settings or DeorbitSettings(minimum_swarm=False, samples=0)
    dv_transfer, transfer_kg, transfer_s = transfer_per_cubesat(problem)
    tumble = detumble(problem)
    plan = plan_deorbit(problem, settings)
    model = DeorbitModel.from_problem(problem, settings)
    total = propellant_per_cubesat_kg(problem)
    left_kg = float(total.sum() - transfer_kg.sum() - tumble.summary.fuel_kg)
    mass = plan.mass_kg
    exhaust = plan.capacity_dv_m_s / math.log(mass / (mass - total.sum()))
    available = exhaust * math.log(mass / (mass - max(left_kg, 0.0)))
    trajectories, reentry, needed = [], {}, {}
    for case in plan.cases:
        flown = (
            min(case.deorbit_dv_m_s, available) if math.isfinite(case.deorbit_dv_m_s) else available
        )
        density = model.density(solar_case(case.solar))
        history = model.fly(flown, density, case.arc_half_width_deg, settings.horizon_years)
        years = history.reentry_years
        reentry[case.solar] = years if math.isfinite(years) else None
        needed[case.solar] = case.deorbit_dv_m_s if math.isfinite(case.deorbit_dv_m_s) else None
        trajectories.append(
            CaseTrajectory(case.solar, history, np.array([flown]), np.array([years]))
        )
    meets = all(y is not None and y <= settings.limit_years for y in reentry.values())
    transfer = (dv_transfer, transfer_kg, transfer_s)
    propellant = (available, left_kg, total)
    summary = _summary(
        problem, plan, tumble, transfer, propellant, reentry, needed, meets, trajectories
    )
    return Mission(summary, tumble, tuple(trajectories), plan)


def _summary(
    problem: Problem,
    plan: DeorbitPlan,
    tumble: DetumbleResult,
    transfer: tuple[float, np.ndarray, np.ndarray],
    propellant: tuple[float, float, np.ndarray],
    reentry: dict[str, float | None],
    needed: dict[str, float | None],
    meets: bool,
    trajectories: list[CaseTrajectory],
) -> MissionSummary:
    """The summary and the timeline (the governing case's burn and decay)."""
    dv_transfer, transfer_kg, transfer_s = transfer
    available, left_kg, total = propellant
    run = tumble.summary
    transfer_days = float(transfer_s.max()) / SECONDS_PER_DAY
    detumble_days = run.duration_s / SECONDS_PER_DAY
    governing = next(t for t in trajectories if t.solar == plan.governing_case)
    burn_days = governing.history.burn_end_s / SECONDS_PER_DAY
    deorbit_kg = max(left_kg, 0.0) * min(1.0, plan.deorbit_dv_m_s / available) if available else 0.0
    start_burn = transfer_days + detumble_days
    decay_years = reentry[plan.governing_case]
    phases = [
        MissionPhase("transfer", 0.0, transfer_days, dv_transfer, float(transfer_kg.sum()),
                     "each CubeSat alone, before docking (Edelbaum)"),
        MissionPhase("detumble", transfer_days, detumble_days, run.dv_used_m_s, run.fuel_kg,
                     "docked, closed loop, rigid body"),
        MissionPhase("deorbit burn", start_burn, burn_days, min(plan.deorbit_dv_m_s, available),
                     deorbit_kg, f"governing case: {plan.governing_case} solar activity"),
        MissionPhase("decay", start_burn + burn_days,
                     None if decay_years is None else decay_years * DAYS_PER_YEAR - burn_days,
                     None, 0.0, "natural decay to re-entry"),
    ]  # fmt: skip
    remaining = np.maximum(total - transfer_kg - np.asarray(run.fuel_per_cubesat_kg), 0.0)
    share = remaining / remaining.sum() if remaining.sum() > 0 else remaining
    used = float(transfer_kg.sum() + run.fuel_kg + deorbit_kg)
    return MissionSummary(
        problem=problem.name,
        detumble_time_h=run.time_to_threshold_h,
        transfer_dv_m_s=dv_transfer,
        transfer_time_days=transfer_days,
        deorbit_dv_m_s=plan.deorbit_dv_m_s,
        deorbit_dv_available_m_s=available,
        deorbit_dv_capacity_m_s=plan.capacity_dv_m_s,
        reentry_years=reentry,
        deorbit_dv_needed_m_s=needed,
        meets_five_year_rule=meets,
        limit_years=plan.limit_years,
        propellant_total_kg=float(total.sum()),
        propellant_used_kg=used,
        propellant_per_cubesat_kg={
            "transfer": transfer_kg.tolist(),
            "detumble": list(run.fuel_per_cubesat_kg),
            # Booked in proportion to what each CubeSat has left (the burns' engines are
            # not tracked one by one over the 1000-day burn).
            "deorbit burn": (deorbit_kg * share).tolist(),
        },
        phases=phases,
    )
