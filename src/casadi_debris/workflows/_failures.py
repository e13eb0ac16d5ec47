"""Which failures a swarm survives, as a job: the campaign of
:mod:`casadi_debris.studies.failures` with the problem's controller and manoeuvres,
written into a folder.

The manoeuvres are those ``design`` verifies a controller on
(:func:`~casadi_debris.workflows._design.verification_problems`): the problem's
own slew (or 180 deg about its slowest axis when it has none) and one
disturbance period of pointing, judged against its ``[requirements]``. The
pointing run lasts one whole period of the disturbance, quick or not: a
failure may take away the authority about one signed axis only, which the
disturbance asks for during half of its period (a sine's other sign); a run
shorter than a period may never ask for it and report the whole swarm's
pointing. Over one period every phase of the disturbance is met, and the
loop's transients (tens of seconds) are short beside it, so that the error over
that period bounds the steady state's. ``quick`` flies fewer corners
(:data:`QUICK_CORNERS`) instead. The controller is the one the problem is bound
to (the shipped paper design for the paper's plant, or ``--controller``), as
``simulate`` flies it.

Example
-------
>>> import casadi_debris as cd
>>> found = cd.failures("paper_slew", max_failed=2, workers=2)  # doctest: +SKIP
>>> found.summary.cases[0].failed, found.summary.cases[0].closed_loop.met  # doctest: +SKIP
>>> found.save("runs/failures-slew")  # doctest: +SKIP
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

from casadi_debris.campaigns import DEFAULT_BATCH_CASES
from casadi_debris.config import Problem
from casadi_debris.dynamics import build_model
from casadi_debris.studies.failures import (
    FailureCase,
    FailureSettings,
    FailuresSummary,
    FailureStudy,
    StageProgress,
    check_max_failed,
    failure_study,
    manoeuvres,
)
from casadi_debris.workflows._campaign import CaseSelection
from casadi_debris.workflows._controller import controller_for
from casadi_debris.workflows._design import verification_problems
from casadi_debris.workflows._reproduce import FULL, QUICK
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure

DEFAULT_CORNERS = 16
"""Corner plants each of the worst sets flies, spread evenly over the set."""
QUICK_CORNERS = QUICK.pointing_cases or DEFAULT_CORNERS
"""Corner plants of each worst set with ``quick`` (as ``design --quick``'s pointing cases)."""


def corners_for(max_corners: int | None, quick: bool) -> int:
    """The corners each worst set flies: ``max_corners`` if given, else by ``quick``."""
    if max_corners is not None:
        return max_corners
    return QUICK_CORNERS if quick else DEFAULT_CORNERS


@dataclass(frozen=True, eq=False)
class FailuresResult(JobResult):
    """A failure campaign: every case studied, ranked, with its summary.

    Attributes
    ----------
    problem : Problem
    study : FailureStudy
        Every case's authority, holding thrusts, depletion and closed-loop runs (SI), the
        whole swarm's baseline and the manoeuvres flown.
    summary : FailuresSummary
        What ``summary.json`` holds (and ``--json`` prints): the cases ranked, the worst
        first, in display units; ``out_dir`` None until saved.
    """

    problem: Problem
    study: FailureStudy
    summary: FailuresSummary

    command = "failures"

    def plot(self) -> dict[str, Figure]:
        """``authority_loss``: the share of the authority each single failure takes, per
        signed axis (none without single failures). Nothing is written."""
        from casadi_debris.report import failure_figures

        return failure_figures(self.summary)

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json``, ``cases.csv``, ``report.md``, ``reallocation.csv`` and
        ``authority_loss.png`` (with ``plots``)."""
        from casadi_debris.report import write_failures

        summary = replace(self.summary, out_dir=str(out.absolute()))
        write_failures(staging, summary, with_plots=plots)


def failures(
    problem: ProblemLike = None,
    *,
    max_failed: int = 2,
    stages: bool = True,
    closed_loop: bool = True,
    corner_sets: int = 3,
    max_corners: int | None = None,
    quick: bool = False,
    controller: str | Path | None = None,
    allow_mismatch: bool = False,
    workers: int | None = None,
    no_jit: bool = False,
    batch_cases: int = DEFAULT_BATCH_CASES,
    progress: StageProgress | None = None,
    cases: Sequence[FailureCase] | None = None,
) -> FailuresResult:
    """Which failures the swarm survives (see :mod:`casadi_debris.studies.failures`).

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper.
    max_failed : int
        Largest number of CubeSats failed at once (every set of 1 .. N).
    stages : bool
        Also a case per CubeSat that loses its first stage (the next takes over).
    closed_loop : bool
        Fly the problem's slew and pointing run for every case (nominal plant).
    corner_sets : int
        The N worst cases also fly corners of the uncertainty set (0: none).
    max_corners : int, optional
        Corner plants each of those flies, spread evenly (default
        :data:`DEFAULT_CORNERS`, or :data:`QUICK_CORNERS` with ``quick``).
    quick : bool
        Fewer corners by default; the pointing run is one whole disturbance period
        either way (see the module).
    controller, allow_mismatch : optional
        A controller file (default the shipped one, for the paper's plant only); fly one
        designed for another plant anyway.
    workers : int, optional
        Local processes for the closed-loop runs; default one per core.
    no_jit, batch_cases : optional
        Run the step on CasADi's virtual machine; cases per compiled call.
    progress : callable, optional
        ``progress(stage)`` as each stage starts; may return a run counter.
    cases : sequence of FailureCase, optional
        Study these cases only (default every case of the settings).

    Returns
    -------
    FailuresResult

    Raises
    ------
    FailureStudyError
        ``max_failed`` outside 1 .. the swarm's CubeSats.
    """
    problem = as_problem(problem)
    settings = FailureSettings(
        max_failed=max_failed,
        stages=stages,
        closed_loop=closed_loop,
        corner_sets=corner_sets,
        workers=(os.cpu_count() or 1) if workers is None else workers,
        jit=not no_jit,
        batch_cases=batch_cases,
    )
    study, flown = _study(
        problem, settings, controller, allow_mismatch, max_corners, quick, progress, cases
    )
    summary = replace(
        study.record(),
        controller_path=None if flown is None else str(flown),
        quick=quick,
        max_corners=corners_for(max_corners, quick),
    )
    return FailuresResult(problem, study, summary)


def _study(
    problem: Problem,
    settings: FailureSettings,
    controller: str | Path | None,
    allow_mismatch: bool,
    max_corners: int | None,
    quick: bool,
    progress: StageProgress | None,
    cases: Sequence[FailureCase] | None,
) -> tuple[FailureStudy, Path | None]:
    """The study, and the controller file flown (None without closed loop)."""
    check_max_failed(settings.max_failed, len(problem.cubesats))
    model = build_model(problem)
    if not settings.closed_loop:
        return failure_study(model, settings, cases=cases, progress=progress), None
    record, resolved = controller_for(problem, controller, allow_mismatch=allow_mismatch)
    # FULL, quick or not: its pointing run is one whole disturbance period (see the module).
    slew, pointing = verification_problems(problem, FULL)
    count = corners_for(max_corners, quick)
    corners = (
        CaseSelection(max_cases=count).cases(model)
        if settings.corner_sets > 0 and count > 0
        else []
    )
    study = failure_study(
        model,
        settings,
        controller=record.reduced,
        manoeuvres=manoeuvres(slew, pointing),
        corner_plants=corners,
        cases=cases,
        progress=progress,
    )
    return study, resolved
