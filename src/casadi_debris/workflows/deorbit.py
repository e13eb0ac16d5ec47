"""The five-year deorbit plan of a debris and its swarm (``casadi-debris deorbit``).

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.workflows.deorbit import deorbit_into
>>> report = deorbit_into(load_problem(), "runs/deorbit-paper")  # doctest: +SKIP
>>> report.plan.meets_five_year_rule  # doctest: +SKIP
True
"""

from __future__ import annotations

from pathlib import Path

from casadi_debris.budgets import budgets_as_dict, compute_budgets
from casadi_debris.config import Problem
from casadi_debris.orbit.curves import case_trajectories
from casadi_debris.orbit.deorbit import DeorbitModel, DeorbitSettings
from casadi_debris.orbit.plan import plan_deorbit
from casadi_debris.report.deorbit import DeorbitReport, write_deorbit
from casadi_debris.report.folders import RunFolder, check_output_folder


def deorbit_into(
    problem: Problem,
    out: str | Path,
    settings: DeorbitSettings | None = None,
    *,
    overwrite: bool = False,
) -> DeorbitReport:
    """Plan the deorbit of ``problem`` and write it into the run folder ``out``.

    Parameters
    ----------
    problem : Problem
    out : str or Path
        Run folder: ``summary.json``, ``decay_<case>.csv``, ``lifetime_vs_dv.csv``,
        ``decay.png``, ``lifetime_vs_dv.png``.
    settings : DeorbitSettings, optional
    overwrite : bool
        Replace a run folder this toolkit wrote.

    Returns
    -------
    DeorbitReport
        The plan (see :func:`~casadi_debris.orbit.plan.plan_deorbit`) beside the budget's Δv.
    """
    out = Path(out)
    check_output_folder(out, overwrite=overwrite)
    settings = settings or DeorbitSettings()
    plan = plan_deorbit(problem, settings)
    model = DeorbitModel.from_problem(problem, settings)
    trajectories = case_trajectories(model, plan, settings)
    report = DeorbitReport(
        problem_sha256=problem.sha256,
        budget_dv_m_s=budgets_as_dict(compute_budgets(problem))["dv_all_stages_all_faces_m_s"],
        plan=plan,
        out_dir=str(out.absolute()),
    )
    with RunFolder.claim(out, overwrite=overwrite, command="deorbit") as staging:
        write_deorbit(staging, report, trajectories)
    return report
