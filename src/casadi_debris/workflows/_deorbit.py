"""The five-year deorbit plan of a debris and its swarm (``casadi-debris deorbit``).

Example
-------
>>> import casadi_debris as cd
>>> result = cd.deorbit("paper", solar=("mean",), minimum_swarm=False)  # doctest: +SKIP
>>> result.summary.plan.meets_five_year_rule  # doctest: +SKIP
True
>>> result.save("runs/deorbit-paper")  # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from casadi_debris.budgets import budgets_as_dict, compute_budgets
from casadi_debris.orbit import (
    CaseTrajectory,
    DeorbitModel,
    DeorbitSettings,
    case_trajectories,
    plan_deorbit,
)
from casadi_debris.report import DeorbitSummary, deorbit_figures, write_deorbit
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure


@dataclass(frozen=True)
class DeorbitResult(JobResult):
    """A deorbit plan: its summary and each solar case's flown plan and lifetime curve.

    Attributes
    ----------
    summary : DeorbitSummary
        The plan beside the budget's Δv (what ``summary.json`` holds).
    trajectories : tuple of CaseTrajectory
        Per solar case: the decay from the burn's start and re-entry time against Δv (SI).
    """

    summary: DeorbitSummary
    trajectories: tuple[CaseTrajectory, ...]

    command = "deorbit"

    def plot(self) -> dict[str, Figure]:
        """``decay`` (altitude band over the years, per solar case) and ``lifetime_vs_dv``
        (re-entry time against the burn's Δv); nothing is written."""
        return deorbit_figures(self.summary, self.trajectories)

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json``, ``decay_<case>.csv``, ``lifetime_vs_dv.csv`` and, with
        ``plots``, ``decay.png`` and ``lifetime_vs_dv.png`` (and their PDFs)."""
        summary = dataclasses.replace(self.summary, out_dir=str(out.absolute()))
        write_deorbit(staging, summary, self.trajectories, plots=plots)


def deorbit(
    problem: ProblemLike = None,
    *,
    solar: Sequence[str] = ("low", "mean", "high"),
    limit_years: float = 5.0,
    drag_coefficient: float | None = None,
    held: bool = False,
    minimum_swarm: bool = True,
    samples: int = 0,
    seed: int = 20250103,
    workers: int | None = None,
) -> DeorbitResult:
    """Plan the deorbit: the least Δv that re-enters within ``limit_years``, per solar case.

    NRLMSIS 2.1 density, the debris' drag area from its faces, the swarm's torque-free
    thrust with staging; lowers the whole orbit or the perigee (burns near apogee),
    whichever needs less Δv, then lets the debris decay.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper.
    solar : sequence of str
        Solar-activity cases among ``"low"``, ``"mean"``, ``"high"`` (constant ECSS
        long-term levels), each once.
    limit_years : float
        Re-entry within this long of the burn's start [years] (the FCC's 5).
    drag_coefficient : float, optional
        C_D [-]; default the problem's ``[environment] drag_coefficient``.
    held : bool
        After the burn the attitude is held (strongest thrust direction against the
        velocity) instead of tumbling.
    minimum_swarm : bool
        Also search the fewest CubeSats that meet the limit.
    samples : int
        Lifetime Monte Carlo runs of the governing plan (solar cycles, C_D); 0: none.
    seed : int
        Seed of that Monte Carlo.
    workers : int, optional
        Local worker processes of the Monte Carlo; default one per core.

    Returns
    -------
    DeorbitResult

    Raises
    ------
    InputShapeError
        A setting out of range or an unknown solar case (named).
    """
    problem = as_problem(problem)
    settings = DeorbitSettings(
        solar=tuple(solar),
        limit_years=limit_years,
        drag_coefficient=drag_coefficient,
        tumbling=not held,
        minimum_swarm=minimum_swarm,
        samples=samples,
        seed=seed,
        workers=(os.cpu_count() or 1) if workers is None else workers,
    )
    plan = plan_deorbit(problem, settings)
    model = DeorbitModel.from_problem(problem, settings)
    summary = DeorbitSummary(
        problem_sha256=problem.sha256,
        budget_dv_m_s=budgets_as_dict(compute_budgets(problem))["dv_all_stages_all_faces_m_s"],
        plan=plan,
    )
    return DeorbitResult(summary=summary, trajectories=case_trajectories(model, plan, settings))
