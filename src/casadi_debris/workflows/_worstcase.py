"""Worst cases of a controller over the uncertainty box (``casadi-debris worstcase``):
real-parametric mu bounds and a search for the slew of largest pointing error.

Example
-------
>>> import casadi_debris as cd
>>> found = cd.worstcase("paper_slew", budget=20)  # doctest: +SKIP
>>> found.summary.search.max_error_deg  # doctest: +SKIP
0.6503
>>> found.save("runs/worstcase-slew")  # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from casadi_debris.campaigns import (
    Envelope,
    WorstCaseSearch,
    WorstCaseSettings,
    corner_cases,
    worst_case_search,
)
from casadi_debris.config import Problem
from casadi_debris.dynamics import Model, build_model
from casadi_debris.guidance import scenario_reference
from casadi_debris.report import (
    WorstCaseIdentity,
    WorstCaseSummary,
    corner_campaign_envelope,
    worst_case_figure,
    worst_case_summary,
    write_worst_case_files,
)
from casadi_debris.robust.mu import ParametricMu, parametric_mu
from casadi_debris.robust.plant import Controller, recorded_performance_weights
from casadi_debris.workflows._controller import controller_for
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure

StageProgress = Callable[[str], Callable[[int, float], None] | None]
"""``progress(stage)`` before each stage; may return a ``(simulations_done, error_deg)``
callback for the search."""


@dataclass(frozen=True, eq=False)
class WorstCaseResult(JobResult):
    """The mu analysis and the search, with what they were run on.

    Attributes
    ----------
    problem : Problem
    model : Model
    record : Controller
        The controller analysed.
    controller_path : Path
    mu : ParametricMu or None
        The real-parametric mu bounds; None when skipped.
    search : WorstCaseSearch or None
        Every simulation of the search and the worst run; None when skipped.
    envelope : Envelope or None
        The corner campaign's envelope the worst run is drawn over (with ``campaign``).
    summary : WorstCaseSummary
        What ``summary.json`` holds (``identity.out_dir`` None until saved).
    """

    problem: Problem
    model: Model
    record: Controller
    controller_path: Path
    mu: ParametricMu | None
    search: WorstCaseSearch | None
    envelope: Envelope | None
    summary: WorstCaseSummary

    command = "worstcase"

    def plot(self) -> dict[str, Figure]:
        """``worstcase``: the worst run found (over the campaign's envelope when one was
        given); none without a search. Nothing is written."""
        if self.search is None:
            return {}
        return {"worstcase": worst_case_figure(self.problem, self.search, self.envelope)}

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json``, ``worst_parameters.json``, ``mu_*_parameters.json``,
        ``evaluations.csv`` and ``worstcase.png`` (with ``plots``), those that ran."""
        identity = dataclasses.replace(self.summary.identity, out_dir=str(out.absolute()))
        summary = dataclasses.replace(self.summary, identity=identity)
        write_worst_case_files(
            staging, self.model, summary, self.mu, self.search, self.envelope, plots
        )


def worstcase(
    problem: ProblemLike = None,
    *,
    controller: str | Path | None = None,
    allow_mismatch: bool = False,
    budget: int = 50,
    seed: int = 0,
    angles: int | None = None,
    no_mu: bool = False,
    no_search: bool = False,
    campaign: str | Path | None = None,
    jit: bool = False,
    progress: StageProgress | None = None,
) -> WorstCaseResult:
    """Real-parametric mu bounds of the controller, then the worst-slew search.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper. Its
        ``[simulation]`` reference is the run searched (paper_slew: the 180 deg slew
        about z).
    controller : str or Path, optional
        A controller file (``controller.json`` of ``design``); default the shipped one.
    allow_mismatch : bool
        Analyse a controller designed for another plant.
    budget : int
        Simulations of the search at most.
    seed : int
        Seed of the mu lower bound's random starts and of the search's order.
    angles : int, optional
        Array angles of the mu grid (default the corner campaign's).
    no_mu, no_search : bool
        Skip the analysis, the search. The search starts from the mu worst
        performance parameters as well when the analysis ran.
    campaign : str or Path, optional
        A finished corner campaign folder of the same problem (``montecarlo``'s), whose
        envelope the worst run is drawn over and whose worst case it is compared with.
    jit : bool
        Compile the closed-loop step to C for the search.
    progress : callable, optional
        ``progress(stage)`` before each stage; may return a
        ``(simulations_done, error_deg)`` callback for the search.

    Returns
    -------
    WorstCaseResult
    """
    problem = as_problem(problem)
    envelope, compared = (
        (None, None) if campaign is None else corner_campaign_envelope(Path(campaign))
    )
    record, resolved = controller_for(problem, controller, allow_mismatch=allow_mismatch)
    model = build_model(problem)
    mu = None
    if not no_mu:
        if progress is not None:
            progress("real-parametric mu")
        weights = recorded_performance_weights(problem, record.details.get("weights", {}))
        mu = parametric_mu(problem, record.reduced, weights, angles=angles, seed=seed)
    search = None
    if not no_search:
        callback = progress("worst-case search") if progress is not None else None
        search = _search(model, record, mu, budget, seed, jit, callback)
    identity = WorstCaseIdentity(
        problem=problem.name,
        problem_sha256=problem.sha256,
        plant_sha256=problem.plant_sha256,
        controller_path=str(resolved),
        controller_plant_sha256=record.problem_sha256,
        out_dir=None,
    )
    summary = worst_case_summary(identity, model.parameter_layout, mu, search, compared)
    return WorstCaseResult(problem, model, record, resolved, mu, search, envelope, summary)


def _search(
    model: Model,
    record: Controller,
    mu: ParametricMu | None,
    budget: int,
    seed: int,
    jit: bool,
    progress: Callable[[int, float], None] | None,
) -> WorstCaseSearch:
    """The worst-slew search from the corners, and from the mu worst performance
    parameters when the analysis ran."""
    problem = model.problem
    corners = np.array([case.normalized for case in corner_cases(model)])
    worst = None if mu is None else mu.performance.worst
    return worst_case_search(
        model,
        record.reduced,
        scenario_reference(problem),
        corners,
        starts=[] if worst is None else [worst.normalized],
        settings=WorstCaseSettings(budget=budget, seed=seed, jit=jit),
        progress=progress,
    )
