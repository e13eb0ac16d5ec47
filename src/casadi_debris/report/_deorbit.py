"""A deorbit plan as a run folder: summary.json, one decay CSV per case, the curve, figures."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from casadi_debris.orbit import CaseTrajectory, DeorbitPlan
from casadi_debris.records import FLATTENED, Record
from casadi_debris.store import write_csv, write_json_atomic
from casadi_debris.units import M_PER_KM, SECONDS_PER_DAY

if TYPE_CHECKING:
    from matplotlib.figure import Figure


@dataclass(frozen=True, kw_only=True)
class DeorbitSummary(Record):
    """The plan beside the budget's Δv.

    Attributes
    ----------
    problem_sha256 : str
    budget_dv_m_s : float
        The budget's all-stages, all-directions Δv (the paper's 125 m/s), which leaves
        the torque balance out; the plan's ``capacity_dv_m_s`` keeps it.
    plan : DeorbitPlan
    out_dir : str or None
    """

    problem_sha256: str
    budget_dv_m_s: float
    plan: DeorbitPlan = field(metadata=FLATTENED)
    out_dir: str | None = None


def deorbit_figures(
    report: DeorbitSummary, trajectories: Sequence[CaseTrajectory]
) -> dict[str, Figure]:
    """``decay`` and ``lifetime_vs_dv``, by the file stem they are written under."""
    from casadi_debris.plots import decay_figure, lifetime_curve_figure

    plan = report.plan
    return {
        "decay": decay_figure(trajectories, title=plan.problem, limit_years=plan.limit_years),
        "lifetime_vs_dv": lifetime_curve_figure(
            trajectories,
            title=plan.problem,
            limit_years=plan.limit_years,
            capacity_dv_m_s=plan.capacity_dv_m_s,
        ),
    }


def write_deorbit(
    folder: Path,
    report: DeorbitSummary,
    trajectories: Sequence[CaseTrajectory],
    *,
    plots: bool = True,
) -> None:
    """``summary.json``, ``decay_<case>.csv``, ``lifetime_vs_dv.csv`` and, with ``plots``,
    ``decay.png`` and ``lifetime_vs_dv.png`` (each with its PDF)."""
    write_json_atomic(folder / "summary.json", report)
    for item in trajectories:
        history = item.history
        write_csv(
            folder / f"decay_{item.solar}.csv",
            {
                "time_days": history.time_s / SECONDS_PER_DAY,
                "perigee_km": history.perigee_altitude_m / M_PER_KM,
                "apogee_km": history.apogee_altitude_m / M_PER_KM,
                "eccentricity": history.eccentricity,
                "mass_kg": history.mass_kg,
                "impulse_Ns": history.impulse_Ns,
            },
        )
    columns = {"dv_m_s": trajectories[0].dv_m_s}  # one grid for every case
    for item in trajectories:
        columns[f"reentry_years_{item.solar}"] = np.where(
            np.isfinite(item.reentry_years), item.reentry_years, np.nan
        )
    write_csv(folder / "lifetime_vs_dv.csv", columns)
    if plots:
        from casadi_debris.plots import save_figure

        for stem, figure in deorbit_figures(report, trajectories).items():
            save_figure(figure, folder / f"{stem}.png")
