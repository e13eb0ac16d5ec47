"""Worst cases of a controller over the uncertainty box: real-parametric mu bounds and a
search for the slew of largest pointing error.

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.workflows.worstcase import worst_cases
>>> found = worst_cases(load_problem("problems/paper_slew.toml"))  # doctest: +SKIP
>>> found.search.best.max_error_deg  # doctest: +SKIP
0.6503
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import scenario_reference
from casadi_debris.report.folders import RunFolder, check_output_folder
from casadi_debris.report.worstcase import (
    WorstCaseIdentity,
    WorstCaseSummary,
    write_worst_cases,
)
from casadi_debris.robust.controller import ControllerRecord
from casadi_debris.robust.parametric_mu import ParametricMu, parametric_mu
from casadi_debris.robust.weights import recorded_performance_weights
from casadi_debris.simulation import corner_cases
from casadi_debris.simulation.worst_case import WorstCaseSearch, worst_case_search
from casadi_debris.workflows.controller import controller_for


@dataclass(frozen=True, eq=False)
class WorstCases:
    """The mu analysis and the search, with what they were run on.

    Attributes
    ----------
    problem : Problem
    record : ControllerRecord
    controller_path : Path
    mu : ParametricMu or None
        None when skipped.
    search : WorstCaseSearch or None
        None when skipped.
    """

    problem: Problem
    record: ControllerRecord
    controller_path: Path
    mu: ParametricMu | None
    search: WorstCaseSearch | None


def worst_cases(
    problem: Problem,
    controller_path: str | Path | None = None,
    *,
    budget: int = 50,
    seed: int = 0,
    angles: int | None = None,
    with_mu: bool = True,
    with_search: bool = True,
    allow_mismatch: bool = False,
    jit: bool = False,
    progress: Callable[[str], Callable[[int, float], None] | None] | None = None,
) -> WorstCases:
    """Real-parametric mu bounds of the controller, then the worst-slew search.

    Parameters
    ----------
    problem : Problem
        Its ``[simulation]`` reference is the run searched (paper_slew.toml:
        the 180 deg slew about z).
    controller_path : str or Path, optional
        Default the shipped controller.
    budget : int
        Simulations of the search at most.
    seed : int
        Seed of the mu lower bound's random starts and of the search's order.
    angles : int, optional
        Array angles of the mu grid (default the corner campaign's).
    with_mu, with_search : bool
        Run the analysis, the search. The search starts from the mu worst
        performance parameters as well when the analysis ran.
    allow_mismatch : bool
        Analyse a controller designed for another plant.
    jit : bool
        Compile the closed-loop step to C for the search.
    progress : callable, optional
        ``progress(stage)`` before each stage; may return a
        ``(simulations_done, error_deg)`` callback for the search.
    """
    record, resolved = controller_for(problem, controller_path, allow_mismatch=allow_mismatch)
    mu = None
    if with_mu:
        if progress is not None:
            progress("real-parametric mu")
        weights = recorded_performance_weights(problem, record.details.get("weights", {}))
        mu = parametric_mu(problem, record.reduced, weights, angles=angles, seed=seed)
    search = None
    if with_search:
        callback = progress("worst-case search") if progress is not None else None
        model = build_model(problem)
        corners = np.array([case.normalized for case in corner_cases(problem, model)])
        worst = None if mu is None else mu.performance.worst
        search = worst_case_search(
            problem,
            model,
            record.reduced,
            scenario_reference(problem),
            corners,
            starts=[] if worst is None else [worst.normalized],
            budget=budget,
            seed=seed,
            jit=jit,
            progress=callback,
        )
    return WorstCases(problem, record, resolved, mu, search)


def run_worstcase_folder(
    problem: Problem,
    controller_path: str | Path | None,
    out: str | Path,
    *,
    campaign: str | Path | None = None,
    overwrite: bool = False,
    **options: Any,
) -> WorstCaseSummary:
    """:func:`worst_cases` written into the folder ``out`` (see
    :mod:`casadi_debris.report.worstcase`); returns what ``summary.json`` holds.

    ``campaign``: a finished corner campaign folder of the same problem, whose
    envelope the worst run is drawn over and whose worst case it is compared with.
    ``options`` are :func:`worst_cases`'s.
    """
    out = Path(out)
    check_output_folder(out, overwrite=overwrite)
    found = worst_cases(problem, controller_path, **options)
    identity = WorstCaseIdentity(
        problem=problem.name,
        problem_sha256=problem.sha256,
        plant_sha256=problem.plant_sha256,
        controller_path=str(found.controller_path),
        controller_plant_sha256=found.record.problem_sha256,
        out_dir=str(out.absolute()),
    )
    with RunFolder.claim(out, overwrite=overwrite, command="worstcase") as staging:
        return write_worst_cases(
            staging,
            problem,
            build_model(problem),
            identity,
            found.mu,
            found.search,
            None if campaign is None else Path(campaign),
        )
