"""Swarm designs side by side (``casadi-debris alternatives``): authority, fuel per
torque·time, failure tolerance and mass, without a controller.

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.workflows.alternatives import compare_alternatives
>>> problems = [load_problem(name) for name in ("paper", "fewer_stronger")]
>>> report = compare_alternatives(problems, "runs/alternatives")  # doctest: +SKIP
>>> [d.weakest_ratio for d in report.designs]  # doctest: +SKIP
[2.88, 4.32]
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from pathlib import Path

from casadi_debris.config import Problem
from casadi_debris.report.alternatives import AlternativesReport, write_alternatives
from casadi_debris.report.folders import RunFolder, check_output_folder
from casadi_debris.studies.alternatives import swarm_figures

LOGGER = logging.getLogger(__name__)
DEFAULT_DESIGNS = ("paper", "side_engines_12", "differential_2u", "fewer_stronger", "two_per_face")
"""The paper's swarm and the alternatives it names, as shipped problems."""


def compare_alternatives(
    problems: list[Problem],
    out: str | Path,
    *,
    max_failed: int = 2,
    overwrite: bool = False,
    progress: Callable[[str], None] | None = None,
) -> AlternativesReport:
    """Compute every design's figures and write them into the run folder ``out``.

    Parameters
    ----------
    problems : list of Problem
        The designs, in the order of the table.
    out : str or Path
        Run folder (see :mod:`casadi_debris.report.alternatives`).
    max_failed : int
        0, 1 or 2: the CubeSat failure sets to try (every one of that size or less).
    overwrite : bool
        Replace a run folder this toolkit wrote.
    progress : callable, optional
        ``progress(name)`` as each design starts.

    Returns
    -------
    AlternativesReport
    """
    out = Path(out)
    check_output_folder(out, overwrite=overwrite)
    started = time.perf_counter()
    designs = []
    for problem in problems:
        LOGGER.info("swarm figures of %s", problem.name)
        if progress is not None:
            progress(problem.name)
        designs.append(swarm_figures(problem, max_failed=max_failed))
    report = AlternativesReport(
        designs=designs,
        max_failed=max_failed,
        wall_time_s=time.perf_counter() - started,
        out_dir=str(out.absolute()),
    )
    with RunFolder.claim(out, overwrite=overwrite, command="alternatives") as staging:
        write_alternatives(staging, report)
    return report
