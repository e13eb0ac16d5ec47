"""What the deorbit figures draw: each case's flown plan over time, and lifetime against Δv."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from casadi_debris.orbit._atmosphere import solar_case
from casadi_debris.orbit._deorbit import DeorbitModel, DeorbitSettings
from casadi_debris.orbit._lifetime import DecayHistory
from casadi_debris.orbit._plan import DeorbitPlan

CURVE_POINTS = 13


@dataclass(frozen=True, eq=False)
class CaseTrajectory:
    """One solar case: the plan flown, and re-entry time against the burn's Δv.

    Attributes
    ----------
    solar : str
    history : DecayHistory
        The flown plan, from the burn's start to re-entry (or the horizon).
    dv_m_s : ndarray, shape (k,)
    reentry_years : ndarray, shape (k,)
        With the case's strategy; ``inf`` beyond the horizon.
    """

    solar: str
    history: DecayHistory
    dv_m_s: np.ndarray
    reentry_years: np.ndarray


def case_trajectories(
    model: DeorbitModel, plan: DeorbitPlan, settings: DeorbitSettings
) -> tuple[CaseTrajectory, ...]:
    """Each case's flown plan and its lifetime-Δv curve, on one Δv grid from 0 to past the
    larger of the swarm's capacity and the largest need."""
    needs = [c.deorbit_dv_m_s for c in plan.cases if np.isfinite(c.deorbit_dv_m_s)]
    grid = np.linspace(0.0, 1.2 * max([plan.capacity_dv_m_s, 1.0, *needs]), CURVE_POINTS)
    out = []
    for case in plan.cases:
        density = model.density(solar_case(case.solar))
        fly = lambda dv, c=case, d=density: model.fly(  # noqa: E731
            dv, d, c.arc_half_width_deg, settings.horizon_years
        )
        years = np.array([fly(dv).reentry_years for dv in grid])
        out.append(CaseTrajectory(case.solar, fly(case.flown_dv_m_s), grid, years))
    return tuple(out)
