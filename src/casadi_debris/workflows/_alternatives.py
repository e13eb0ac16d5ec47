"""Swarm designs side by side (``casadi-debris alternatives``): authority, fuel per
torque·time, failure tolerance and mass, without a controller.

Example
-------
>>> import casadi_debris as cd
>>> result = cd.alternatives(["paper", "fewer_stronger"], max_failed=1)  # doctest: +SKIP
>>> [d.weakest_ratio for d in result.summary.designs]  # doctest: +SKIP
[2.88, 4.32]
>>> result.save("runs/alternatives")  # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import logging
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from casadi_debris.report import (
    AlternativesSummary,
    alternatives_figures,
    write_alternatives,
)
from casadi_debris.studies.alternatives import swarm_figures
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure

LOGGER = logging.getLogger(__name__)
DEFAULT_DESIGNS = ("paper", "side_engines_12", "differential_2u", "fewer_stronger", "two_per_face")
"""The paper's swarm and the alternatives it names, as shipped problems."""


@dataclass(frozen=True)
class AlternativesResult(JobResult):
    """Swarm designs side by side.

    Attributes
    ----------
    summary : AlternativesSummary
        Every design's figures, the failure sets tried and the wall time (what
        ``summary.json`` holds).
    """

    summary: AlternativesSummary

    command = "alternatives"

    def plot(self) -> dict[str, Figure]:
        """``alternatives``: authority margin with and without failures, fuel per
        torque·time and added mass per design; nothing is written."""
        return alternatives_figures(self.summary)

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json``, ``alternatives.csv``, ``alternatives.md`` and, with ``plots``,
        ``alternatives.png``."""
        summary = dataclasses.replace(self.summary, out_dir=str(out.absolute()))
        write_alternatives(staging, summary, plots=plots)


def alternatives(
    problem_files: Sequence[ProblemLike] = (),
    *,
    max_failed: int = 2,
    progress: Callable[[str], None] | None = None,
) -> AlternativesResult:
    """Compare swarm designs: authority, fuel per torque·time, failure tolerance, mass.

    For each design: the largest pure torque per signed axis at zero net force, the
    weakest axis over the disturbance, the least propellant per mN·m held an hour, and
    the weakest-axis margin left after the worst single and double CubeSat failure.

    Parameters
    ----------
    problem_files : sequence of Problem, str or Path
        The designs, in the order of the table (problems, files or shipped names);
        default the paper's swarm and the alternatives it names (:data:`DEFAULT_DESIGNS`).
    max_failed : int
        0, 1 or 2: the CubeSat failure sets to try (every one of that size or less, an LP
        per set).
    progress : callable, optional
        ``progress(name)`` as each design starts.

    Returns
    -------
    AlternativesResult

    Raises
    ------
    InputShapeError
        ``max_failed`` outside 0 .. 2.
    ProblemFileError
        A design that does not load (named).
    """
    from casadi_debris.errors import InputShapeError

    if max_failed not in (0, 1, 2):
        raise InputShapeError(f"--max-failed: 0, 1 or 2; got {max_failed!r}")
    loaded = [as_problem(p) for p in (problem_files or DEFAULT_DESIGNS)]
    started = time.perf_counter()
    designs = []
    for problem in loaded:
        LOGGER.info("swarm figures of %s", problem.name)
        if progress is not None:
            progress(problem.name)
        designs.append(swarm_figures(problem, max_failed=max_failed))
    summary = AlternativesSummary(
        designs=designs, max_failed=max_failed, wall_time_s=time.perf_counter() - started
    )
    return AlternativesResult(summary=summary)
