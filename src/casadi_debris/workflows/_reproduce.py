"""The paper end to end: model, budgets, controller, margins, slew and pointing with their
Monte-Carlo envelopes, and ``report.md`` with every figure of the paper next to ours.

Example
-------
>>> import casadi_debris as cd
>>> paper = cd.reproduce("runs/reproduce", quick=True)  # doctest: +SKIP
>>> paper.summary.reproduced, paper.summary.rows  # doctest: +SKIP
(19, 19)
"""

from __future__ import annotations

import logging
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

from casadi_debris.allocation import Allocator
from casadi_debris.budgets import budgets_as_dict, compute_budgets
from casadi_debris.config import Problem, default_problem_path, load_problem, with_duration
from casadi_debris.geometry import build_geometry
from casadi_debris.report import (
    CampaignSummary,
    ControllerSummary,
    MarginsSummary,
    ModelSummary,
    ReproductionRow,
    ReproductionSummary,
    describe_model,
    report_markdown,
    reproduction_rows,
    torque_limits_mNm,
)
from casadi_debris.robust.plant import Controller
from casadi_debris.store import RunFolder, write_json_atomic
from casadi_debris.workflows._campaign import Progress
from casadi_debris.workflows._controller import load_controller
from casadi_debris.workflows._montecarlo import montecarlo
from casadi_debris.workflows._result import ReportFolderResult

if TYPE_CHECKING:
    from casadi_debris.workflows._margins import MarginsResult

LOGGER = logging.getLogger(__name__)


@dataclass(frozen=True)
class Plan:
    """How much of the paper a run reproduces.

    Attributes
    ----------
    margin_samples : int
        Sampled plants of the margin study (the paper: 3000).
    slew_cases, pointing_cases : int or None
        Corners of each campaign, spread evenly (None: all 256).
    pointing_duration_s : float or None
        Length of the pointing run (None: the problem's, one orbit).
    """

    margin_samples: int = 3000
    slew_cases: int | None = None
    pointing_cases: int | None = None
    pointing_duration_s: float | None = None


FULL = Plan()
QUICK = Plan(margin_samples=200, slew_cases=8, pointing_cases=4)
"""A few minutes on two cores (CI); corners spread evenly over the set. The pointing run
keeps its whole orbit: a shorter one meets the disturbance with one sign only, and an
authority that is weaker one way than the other would pass unseen."""
FIGURES = [
    ("Slew (paper Fig. 4): error and torque, corner envelope shaded", "slew/envelope.png"),
    (
        "Pointing (paper Fig. 5): error against 60 arcsec, torque against limits",
        "pointing/envelope.png",
    ),
    ("μ of the robust-performance problem", "margins/mu.png"),
    ("Uncertainty weight W over the sampled relative errors", "margins/uncertainty_weight.png"),
    ("Loop shapes", "margins/loop_shapes.png"),
    ("Margins over sampled plants", "margins/margins.png"),
]


def _paper_problems(plan: Plan) -> tuple[Problem, Problem, Problem]:
    """The paper's problem, its slew and its pointing run (shortened by a quick plan)."""
    problems = default_problem_path().parent
    problem = load_problem(problems / "paper.toml")
    slew_problem = load_problem(problems / "paper_slew.toml")
    pointing_problem = load_problem(problems / "paper_pointing.toml")
    if plan.pointing_duration_s is not None:
        pointing_problem = with_duration(pointing_problem, plan.pointing_duration_s)
    return problem, slew_problem, pointing_problem


def _controller(problem: Problem, design_into: Path | None) -> tuple[Controller, Path]:
    """The shipped controller, or one designed anew
    (:func:`~casadi_debris.workflows._synthesize.synthesize`) and written into
    ``design_into``."""
    if design_into is None:
        return load_controller(None)
    from casadi_debris.workflows._synthesize import synthesize

    record = synthesize(problem).record
    return load_controller(write_json_atomic(design_into / "controller.json", record.to_dict()))


def _campaign(
    problem: Problem,
    controller_path: Path,
    cases: int | None,
    folder: Path,
    workers: int,
    progress: Progress | None,
    moved_to: tuple[Path, Path],
) -> CampaignSummary:
    """One corner campaign (``cases`` spread evenly, None: all), in a report folder being
    built (``moved_to``: its staging folder and where it will be)."""
    return montecarlo(
        problem,
        controller=controller_path,
        corners=True,
        max_cases=cases,
        out=folder,
        workers=workers,
        progress=progress,
        moved_to=moved_to,
    ).summary


def corner_campaigns(
    plan: Plan,
    runs: tuple[Problem, Problem],
    controller_path: Path,
    folders: tuple[Path, Path],
    workers: int,
    stage: Callable[[str], Progress | None],
) -> dict[str, CampaignSummary]:
    """The slew, then the pointing corner campaign of a report, each announced by ``stage``.

    Parameters
    ----------
    plan : Plan
    runs : (Problem, Problem)
        The slew and the pointing problem.
    controller_path : Path
    folders : (Path, Path)
        The report's staging folder and where it will end up.
    workers : int
    stage : callable
        ``stage(name)`` as each campaign starts; may return a case counter.

    Returns
    -------
    dict
        ``{"slew": summary, "pointing": summary}``.
    """
    staging, _ = folders
    return {
        name: _campaign(
            campaign_problem,
            controller_path,
            cases,
            staging / name,
            workers,
            stage(f"{name} Monte Carlo"),
            folders,
        )
        for name, campaign_problem, cases in zip(
            ("slew", "pointing"), runs, (plan.slew_cases, plan.pointing_cases), strict=True
        )
    }


def report_margins(
    problem: Problem,
    controller_path: Path,
    plan: Plan,
    folders: tuple[Path, Path],
    stage: Callable[[str], Progress | None],
) -> MarginsResult:
    """The margin study of a report (:func:`~casadi_debris.workflows._margins.margins`)
    into ``margins/`` (``folders``: the report's staging folder and where it will end
    up); its summary records that folder."""
    from casadi_debris.workflows._margins import margins

    staging, out = folders
    stage(f"margins over {plan.margin_samples} sampled plants")
    study = margins(problem, controller=controller_path, samples=plan.margin_samples)
    # Written into the report's staging folder, which the report claimed as a whole.
    study._write(staging / "margins", out / "margins", plots=True)
    folder = str((out / "margins").absolute())
    return replace(study, summary=replace(study.summary, out_dir=folder))


def stage_announcer(
    progress: Callable[[str], Progress | None] | None,
) -> Callable[[str], Progress | None]:
    """``stage(name)``: a stage logged and handed to ``progress`` (which may return a case
    counter for the stage's campaign)."""

    def stage(name: str) -> Progress | None:
        LOGGER.info(name)
        return None if progress is None else progress(name)

    return stage


def _slew_duration_s(slew_problem: Problem) -> float | None:
    """The reference duration of the paper's slew problem [s]."""
    slew = slew_problem.simulation.slew
    if slew is None:
        raise RuntimeError("the shipped paper_slew.toml has no [simulation.slew] table")
    return slew.duration_s


@dataclass(frozen=True)
class ReproductionResult(ReportFolderResult):
    """The paper reproduced, in the folder it was written to.

    The run writes as it goes (its campaigns keep every case on disk), so the folder is
    written when :func:`reproduce` returns; ``save`` copies it elsewhere.

    Attributes
    ----------
    folder : Path
        The report folder: ``report.md``, ``summary.json``, ``margins/``, ``slew/``,
        ``pointing/`` (and ``controller.json`` when resynthesised).
    margins : MarginsResult
        The margin study of the controller over sampled plants.
    summary : ReproductionSummary
        What ``casadi-debris reproduce --json`` prints: every row of the paper's table
        with its verdict, ``reproduced`` of ``rows``.
    """

    summary: ReproductionSummary

    command = "reproduce"


def reproduce(
    out: str | Path = Path("runs") / "reproduce",
    *,
    quick: bool = False,
    resynthesize: bool = False,
    workers: int | None = None,
    overwrite: bool = False,
    progress: Callable[[str], Progress | None] | None = None,
) -> ReproductionResult:
    """Reproduce the paper into the folder ``out``: model, budgets, controller, margins,
    slew and pointing with their corner campaigns, and ``report.md`` with every figure of
    the paper next to ours.

    Parameters
    ----------
    out : str or Path
        Report folder, written whole or not at all.
    quick : bool
        Fewer samples and corners and a shorter pointing run (CI: minutes).
    resynthesize : bool
        Design the controller anew (about a minute) instead of the shipped one.
    workers : int, optional
        Local processes for the campaigns; default one per core.
    overwrite : bool
        Replace a report folder this toolkit wrote.
    progress : callable, optional
        ``progress(stage)`` is called as each stage starts and may return a
        case counter for the stage's campaign (see
        :data:`~casadi_debris.workflows._campaign.Progress`).

    Returns
    -------
    ReproductionResult
        ``summary.table`` (each row of the paper's table with its verdict) and
        ``summary.reproduced`` of ``summary.rows``.

    Example
    -------
    >>> import casadi_debris as cd
    >>> paper = cd.reproduce("runs/reproduce", quick=True)  # doctest: +SKIP
    >>> paper.summary.reproduced, paper.summary.rows  # doctest: +SKIP
    (19, 19)
    """
    started = time.perf_counter()
    plan = QUICK if quick else FULL
    problem, slew_problem, pointing_problem = _paper_problems(plan)
    out = Path(out)
    workers = workers or os.cpu_count() or 1

    stage = stage_announcer(progress)
    with RunFolder.claim(out, overwrite=overwrite, command="reproduce") as staging:
        stage("model and budgets")
        model_summary = describe_model(problem)
        budgets = budgets_as_dict(compute_budgets(problem))
        if resynthesize:
            stage("synthesising the controller (D-K iteration)")
        record, controller_path = _controller(problem, staging if resynthesize else None)
        margins = report_margins(problem, controller_path, plan, (staging, out), stage)
        runs = (slew_problem, pointing_problem)
        campaigns = corner_campaigns(plan, runs, controller_path, (staging, out), workers, stage)
        rows = _rows(
            problem, model_summary, budgets, record, margins.summary, campaigns,
            _slew_duration_s(slew_problem),
        )  # fmt: skip
        summary = ReproductionSummary(
            problem=problem.name,
            problem_sha256=problem.sha256,
            controller_path=str(controller_path),
            quick=quick,
            workers=workers,
            time_s=time.perf_counter() - started,
            reproduced=sum(row.reproduced is True for row in rows),
            rows=len(rows),
            table=tuple(row.entry() for row in rows),
            out_dir=str(out.absolute()),
        )
        _write_report(staging, rows, summary)
    return ReproductionResult(folder=out, margins=margins, summary=summary)


def _rows(
    problem: Problem,
    model_summary: ModelSummary,
    budgets: dict[str, float],
    record: Controller,
    margins: MarginsSummary,
    campaigns: dict[str, CampaignSummary],
    slew_duration_s: float | None,
) -> list[ReproductionRow]:
    """The paper's table: each stage's results next to the paper's figures."""
    limits = torque_limits_mNm(Allocator.from_problem(problem, build_geometry(problem)))
    return reproduction_rows(
        model_summary,
        budgets,
        ControllerSummary.of(record),
        margins,
        campaigns["slew"],
        slew_duration_s,
        campaigns["pointing"],
        limits,
    )


def _write_report(folder: Path, rows: list[ReproductionRow], summary: ReproductionSummary) -> None:
    """``report.md`` with the figures the run made, and ``summary.json``."""
    figures = [(title, path) for title, path in FIGURES if (folder / path).exists()]
    (folder / "report.md").write_text(report_markdown(rows, summary, figures))
    write_json_atomic(folder / "summary.json", summary)
