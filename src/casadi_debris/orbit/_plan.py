"""The deorbit plan: every solar case, the smallest swarm, and a Monte Carlo of the plan.

:func:`plan_deorbit` is the public entry point (a later mission timeline composes
it): it builds the :class:`~casadi_debris.orbit._deorbit.DeorbitModel` once, plans
each solar-activity case, finds the governing one (the most Δv), and optionally
searches the smallest swarm and flies the governing plan over solar cycles and
drag coefficients.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.orbit._atmosphere import solar_case
from casadi_debris.orbit._deorbit import DeorbitCase, DeorbitModel, DeorbitSettings, plan_case
from casadi_debris.orbit._lifetime_mc import LifetimeCampaign, lifetime_monte_carlo
from casadi_debris.orbit._swarm_size import MinimumSwarm, minimum_swarm
from casadi_debris.records import Record


@dataclass(frozen=True)
class DeorbitPlan(Record):
    """The five-year answer for one debris and swarm.

    Attributes
    ----------
    problem : str
    altitude_km, inclination_deg : float
        The debris' circular orbit.
    mass_kg : float
        Combined body, CubeSats included.
    drag_area_m2, drag_coefficient, ballistic_coefficient_kg_m2 : float
        Of the decay (tumbling or held).
    burn_drag_areas_m2 : tuple of float
        While each thrust direction fires (held against the velocity), strongest first.
    capacity_dv_m_s : float
        The swarm's torque-free Δv, all stages of all engines.
    limit_years : float
    deorbit_dv_m_s : float
        The largest of the cases' least Δv (the governing case's).
    reentry_years, natural_lifetime_years : dict
        Per solar case.
    meets_five_year_rule : bool
        Under every case.
    governing_case : str
    stages_needed : int or None
        Stages of engine 1's kind whose impulse gives the governing Δv (whether or not
        the swarm has them: compare ``capacity_dv_m_s``); None when no Δv meets the
        limit at the swarm's thrust.
    cases : tuple of DeorbitCase
    minimum_swarm : MinimumSwarm or None
        The fewest CubeSats on one face that meet the limit (when searched and found).
    monte_carlo : LifetimeCampaign or None
        The governing plan flown over solar cycles and C_D (when asked for).
    """

    problem: str
    altitude_km: float
    inclination_deg: float
    mass_kg: float
    drag_area_m2: float
    burn_drag_areas_m2: tuple[float, ...]
    drag_coefficient: float
    ballistic_coefficient_kg_m2: float
    capacity_dv_m_s: float
    limit_years: float
    deorbit_dv_m_s: float
    reentry_years: dict[str, float]
    natural_lifetime_years: dict[str, float]
    meets_five_year_rule: bool
    governing_case: str
    stages_needed: int | None
    cases: tuple[DeorbitCase, ...] = ()
    minimum_swarm: MinimumSwarm | None = None
    monte_carlo: LifetimeCampaign | None = None


def plan_deorbit(
    problem: Problem | DeorbitModel, settings: DeorbitSettings | None = None
) -> DeorbitPlan:
    """The least Δv (and propellant, time, stages) that re-enters the debris within five years.

    Parameters
    ----------
    problem : Problem or DeorbitModel
        The debris' circular orbit (``[orbit]``), its faces and mass, the swarm; or its
        model already built (a swarm with part of its propellant spent, say), used as is.
    settings : DeorbitSettings, optional
        Solar cases, limit, strategies, C_D, minimum swarm search, Monte Carlo.

    Returns
    -------
    DeorbitPlan
        One :class:`DeorbitCase` per solar case; the plan meets the rule when every
        case re-enters within the limit with what the swarm carries.

    Example
    -------
    >>> from casadi_debris import load_problem
    >>> plan = plan_deorbit(load_problem(), DeorbitSettings(solar=("high",)))  # doctest: +SKIP
    >>> plan.meets_five_year_rule  # doctest: +SKIP
    True
    """
    settings = settings or DeorbitSettings()
    model = (
        problem
        if isinstance(problem, DeorbitModel)
        else DeorbitModel.from_problem(problem, settings)
    )
    cases = tuple(plan_case(model, solar_case(name), settings) for name in settings.solar)
    plan = assemble_plan(model, settings, cases)
    governing = next(c for c in cases if c.solar == plan.governing_case)
    if settings.minimum_swarm:
        smallest = minimum_swarm(model, settings, plan.governing_case)
        plan = dataclasses.replace(plan, minimum_swarm=smallest)
    if settings.samples > 0:
        campaign = lifetime_monte_carlo(
            model,
            runs=settings.samples,
            seed=settings.seed,
            dv_m_s=governing.flown_dv_m_s,
            arc_half_width_deg=governing.arc_half_width_deg,
            settings=settings,
            workers=settings.workers,
        )
        plan = dataclasses.replace(plan, monte_carlo=campaign)
    return plan


def assemble_plan(
    model: DeorbitModel, settings: DeorbitSettings, cases: Sequence[DeorbitCase]
) -> DeorbitPlan:
    """The plan's verdict from its cases: the governing case needs the most Δv."""
    problem = model.problem
    needs = [c.deorbit_dv_m_s if math.isfinite(c.deorbit_dv_m_s) else math.inf for c in cases]
    governing = cases[int(np.argmax(needs))]
    return DeorbitPlan(
        problem=problem.name,
        altitude_km=problem.orbit.altitude_km,
        inclination_deg=problem.orbit.inclination_deg,
        mass_kg=model.decay.mass_kg,
        drag_area_m2=model.decay.area_m2,
        burn_drag_areas_m2=model.burn_areas_m2,
        drag_coefficient=model.decay.drag_coefficient,
        ballistic_coefficient_kg_m2=model.decay.coefficient_kg_m2,
        capacity_dv_m_s=model.capacity_dv_m_s,
        limit_years=settings.limit_years,
        deorbit_dv_m_s=governing.deorbit_dv_m_s,
        reentry_years={c.solar: c.reentry_years for c in cases},
        natural_lifetime_years={c.solar: c.natural_lifetime_years for c in cases},
        meets_five_year_rule=all(c.meets_five_year_rule for c in cases),
        governing_case=governing.solar,
        stages_needed=stages_needed(model, governing.deorbit_dv_m_s),
        cases=tuple(cases),
    )


def stages_needed(model: DeorbitModel, dv_m_s: float) -> int | None:
    """Stages (of engine 1's impulse) that give ``dv_m_s`` to the body; None for NaN."""
    if not math.isfinite(dv_m_s):
        return None
    return math.ceil(model.impulse_for(dv_m_s) / model.thrust.stage_impulse_Ns[0] - 1e-9)
