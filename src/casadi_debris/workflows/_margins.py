"""Margins of a controller on a problem (``casadi-debris margins``): loop-at-a-time gain,
phase and delay margins and the disk margin, nominal and over sampled uncertain plants.

Example
-------
>>> import casadi_debris as cd
>>> study = cd.margins(samples=200)  # doctest: +SKIP
>>> study.summary.nominal.gain_margin_db, study.summary.sampled_min  # doctest: +SKIP
>>> study.save("runs/margins-paper")  # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from casadi_debris.config import Problem
from casadi_debris.report import (
    MarginsSummary,
    margin_figures,
    margins_summary,
    write_margins,
)
from casadi_debris.workflows._controller import controller_for
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from casadi_debris.robust.margins import MarginStudy
    from casadi_debris.robust.plant import Controller


@dataclass(frozen=True)
class MarginsResult(JobResult):
    """A margin study.

    Attributes
    ----------
    problem : Problem
    record : Controller
        The controller studied (its reduced-order state space is the one flown).
    study : MarginStudy
        Per channel and plant: gain [dB], phase [deg] and delay [s] margins, the nominal
        disk margin, the sampled parameters and which plants the loop leaves unstable.
    summary : MarginsSummary
        What ``casadi-debris margins --json`` prints (``out_dir`` None until saved).
    """

    problem: Problem
    record: Controller
    study: MarginStudy
    summary: MarginsSummary

    command = "margins"

    def plot(self) -> dict[str, Figure]:
        """The study's figures by the file stem ``save`` writes them under: ``margins``
        (gain against phase margin of every sampled plant, delay margins) and, for a
        controller that records its uncertainty weight (a μ design), ``mu``,
        ``uncertainty_weight`` and ``loop_shapes``. Nothing is written."""
        return margin_figures(self.problem, self.record, self.study)

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json``, ``sampled_margins.csv`` and (with ``plots``) the figures of
        :meth:`plot` as PNG and PDF."""
        summary = dataclasses.replace(self.summary, out_dir=str(out.absolute()))
        write_margins(staging, summary, self.study, self.plot() if plots else None)


def margins(
    problem: ProblemLike = None,
    *,
    controller: str | Path | None = None,
    allow_mismatch: bool = False,
    samples: int = 3000,
    seed: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> MarginsResult:
    """Loop-at-a-time, delay and disk margins of a controller: nominal and over sampled
    plants of the problem's uncertainty set.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper.
    controller : str or Path, optional
        A controller file (``controller.json`` of ``synthesize`` or ``design``); default
        the shipped paper controller, for the paper's plant only.
    allow_mismatch : bool
        Study a controller designed for another plant anyway.
    samples : int
        Sampled uncertain plants (the corners of the set first).
    seed : int, optional
        Seed of the samples; default the problem's.
    progress : callable, optional
        ``progress(done, total)`` as the sampled plants are analysed.

    Returns
    -------
    MarginsResult

    Raises
    ------
    ControllerMismatchError
        The controller was designed for another plant (and ``allow_mismatch`` is false).
    SynthesisError
        ``samples`` or ``seed`` out of range (named).
    """
    from casadi_debris.robust.margins import margin_study

    problem = as_problem(problem)
    record, path = controller_for(problem, controller, allow_mismatch=allow_mismatch)
    study = margin_study(problem, record.reduced, samples, seed, progress=progress)
    return MarginsResult(
        problem=problem,
        record=record,
        study=study,
        summary=margins_summary(problem, record, path, study),
    )
