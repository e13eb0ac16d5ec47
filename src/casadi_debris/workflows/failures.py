"""Which failures a swarm survives, as a job: the campaign of
:mod:`casadi_debris.studies.failures` with the problem's controller and manoeuvres,
written into a folder.

The manoeuvres are those ``design`` verifies a controller on
(:func:`~casadi_debris.workflows.design.verification_problems`): the problem's
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
>>> from casadi_debris import load_problem
>>> from casadi_debris.studies.failures import FailureSettings
>>> from casadi_debris.workflows.failures import failures_folder
>>> summary = failures_folder(load_problem("problems/paper_slew.toml"), "runs/failures",
...                           FailureSettings(max_failed=2, workers=2))  # doctest: +SKIP
>>> summary.cases[0].failed, summary.cases[0].closed_loop.met  # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

from casadi_debris.config import Problem
from casadi_debris.dynamics import build_model
from casadi_debris.report.failures import write_failures
from casadi_debris.report.folders import RunFolder
from casadi_debris.studies.failure_cases import FailureCase, check_max_failed
from casadi_debris.studies.failure_records import FailureStudyRecord
from casadi_debris.studies.failure_runs import StageProgress, manoeuvres
from casadi_debris.studies.failures import FailureSettings, FailureStudy, failure_study
from casadi_debris.workflows.campaign import CaseSelection
from casadi_debris.workflows.controller import controller_for
from casadi_debris.workflows.design import verification_problems
from casadi_debris.workflows.reproduce import FULL, QUICK

DEFAULT_CORNERS = 16
"""Corner plants each of the worst sets flies, spread evenly over the set."""
QUICK_CORNERS = QUICK.pointing_cases or DEFAULT_CORNERS
"""Corner plants of each worst set with ``quick`` (as ``design --quick``'s pointing cases)."""


def corners_for(max_corners: int | None, quick: bool) -> int:
    """The corners each worst set flies: ``max_corners`` if given, else by ``quick``."""
    if max_corners is not None:
        return max_corners
    return QUICK_CORNERS if quick else DEFAULT_CORNERS


def run_failure_study(
    problem: Problem,
    settings: FailureSettings,
    *,
    controller_path: str | Path | None = None,
    allow_mismatch: bool = False,
    max_corners: int | None = None,
    quick: bool = False,
    progress: StageProgress | None = None,
    cases: Sequence[FailureCase] | None = None,
) -> tuple[FailureStudy, Path | None]:
    """The failure campaign of ``problem`` (see :mod:`casadi_debris.studies.failures`).

    Parameters
    ----------
    problem : Problem
    settings : FailureSettings
    controller_path : str or Path, optional
        Controller file (default the shipped one, for the paper's plant only).
    allow_mismatch : bool
        Fly a controller designed for another plant.
    max_corners : int, optional
        Corner plants of each of the ``settings.corner_sets`` worst cases, spread evenly
        (default :data:`DEFAULT_CORNERS`, or :data:`QUICK_CORNERS` with ``quick``).
    quick : bool
        Fewer corners by default; the pointing run is one whole disturbance period
        either way (see the module).
    progress : callable, optional
        ``progress(stage)`` as each stage starts; may return a run counter.
    cases : sequence of FailureCase, optional
        Study these cases only (default every case of ``settings``).

    Returns
    -------
    FailureStudy
    Path or None
        The controller file flown (None without closed loop).
    """
    check_max_failed(settings.max_failed, len(problem.cubesats))
    model = build_model(problem)
    if not settings.closed_loop:
        return failure_study(problem, model, settings, cases=cases, progress=progress), None
    record, resolved = controller_for(problem, controller_path, allow_mismatch=allow_mismatch)
    # FULL, quick or not: its pointing run is one whole disturbance period (see the module).
    slew, pointing = verification_problems(problem, FULL)
    count = corners_for(max_corners, quick)
    corners = (
        CaseSelection(max_cases=count).cases(problem, model)
        if settings.corner_sets > 0 and count > 0
        else []
    )
    study = failure_study(
        problem,
        model,
        settings,
        controller=record.reduced,
        manoeuvres=manoeuvres(slew, pointing),
        corner_plants=corners,
        cases=cases,
        progress=progress,
    )
    return study, resolved


def failures_folder(
    problem: Problem,
    out: str | Path,
    settings: FailureSettings,
    *,
    controller_path: str | Path | None = None,
    allow_mismatch: bool = False,
    max_corners: int | None = None,
    quick: bool = False,
    overwrite: bool = False,
    progress: StageProgress | None = None,
) -> FailureStudyRecord:
    """Run the failure campaign of ``problem`` into the folder ``out``.

    Parameters are those of :func:`run_failure_study`, and

    out : str or Path
        Result folder (``summary.json``, ``cases.csv``, ``report.md``,
        ``reallocation.csv``, ``authority_loss.png``), written atomically.
    overwrite : bool
        Replace a folder this toolkit wrote.

    Returns
    -------
    FailureStudyRecord
        What ``summary.json`` holds (its ``to_json``).
    """
    out = Path(out)
    with RunFolder.claim(out, overwrite=overwrite, command="failures") as staging:
        study, controller = run_failure_study(
            problem,
            settings,
            controller_path=controller_path,
            allow_mismatch=allow_mismatch,
            max_corners=max_corners,
            quick=quick,
            progress=progress,
        )
        record = replace(
            study.record(),
            controller_path=None if controller is None else str(controller),
            quick=quick,
            max_corners=corners_for(max_corners, quick),
            out_dir=str(out.absolute()),
        )
        write_failures(staging, record)
    return record
