"""The whole mission into a run folder (``casadi-debris mission``).

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.workflows.mission import mission_into
>>> summary = mission_into(load_problem(), "runs/mission-paper")  # doctest: +SKIP
>>> summary.meets_five_year_rule, summary.reentry_years  # doctest: +SKIP
(False, {'low': 7.57, 'mean': 5.0, 'high': 5.0})
"""

from __future__ import annotations

from pathlib import Path

from casadi_debris.config import Problem
from casadi_debris.orbit import DeorbitSettings
from casadi_debris.report.folders import RunFolder, check_output_folder
from casadi_debris.report.mission import write_mission
from casadi_debris.studies.mission import MissionSummary, plan_mission


def mission_into(
    problem: Problem,
    out: str | Path,
    *,
    settings: DeorbitSettings | None = None,
    overwrite: bool = False,
) -> MissionSummary:
    """Plan the mission of ``problem`` (:func:`~casadi_debris.studies.mission.plan_mission`)
    and write it into the run folder ``out`` (:mod:`casadi_debris.report.mission`)."""
    out = Path(out)
    check_output_folder(out, overwrite=overwrite)
    mission = plan_mission(problem, settings)
    with RunFolder.claim(out, overwrite=overwrite, command="mission") as staging:
        write_mission(staging, mission)
    return mission.summary
