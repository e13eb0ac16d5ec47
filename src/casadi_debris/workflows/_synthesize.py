"""μ-synthesis of the attitude controller (``casadi-debris synthesize``): the paper's
Section III on any problem, the controller reduced and its μ checked.

Example
-------
>>> import casadi_debris as cd
>>> design = cd.synthesize(max_iterations=2)  # doctest: +SKIP
>>> design.summary.mu_peak_reduced, design.record.reduced.nstates  # doctest: +SKIP
>>> design.save("runs/synthesize-paper")  # controller.json, summary.json  # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from casadi_debris.config import Problem
from casadi_debris.store import write_json_atomic
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from casadi_debris.robust.plant import Controller
    from casadi_debris.robust.synthesis import ControllerDesign, Iteration, SynthesisSummary

Progress = Callable[[str, "Iteration | None"], None]
"""``progress(stage, iteration)``: at each stage's end (``iteration`` None) and after the
H∞ step and every D-K iteration."""


@dataclass(frozen=True)
class SynthesisResult(JobResult):
    """A μ-synthesis: the controller and everything that made it.

    Attributes
    ----------
    problem : Problem
    design : ControllerDesign
        The sampled plants, the fitted uncertainty weight, the generalised plant, the
        D-K iterations and the μ bound of the reduced controller.
    summary : SynthesisSummary
        What ``casadi-debris synthesize --json`` prints (``controller_path`` None until
        saved).
    """

    problem: Problem
    design: ControllerDesign
    summary: SynthesisSummary

    command = "synthesize"

    @property
    def record(self) -> Controller:
        """The controller (full and reduced order, with the plant it was designed for), as
        ``controller.json`` holds it."""
        return self.design.record

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``controller.json`` (fly it with ``controller=``) and ``summary.json``."""
        summary = dataclasses.replace(
            self.summary, controller_path=str((out / "controller.json").absolute())
        )
        write_json_atomic(staging / "controller.json", self.record.to_dict())
        write_json_atomic(staging / "summary.json", summary)


def synthesize(
    problem: ProblemLike = None,
    *,
    mu_points: int = 150,
    max_iterations: int = 8,
    d_orders: Sequence[int] = (1, 2, 4),
    samples: int | None = None,
    seed: int | None = None,
    progress: Progress | None = None,
) -> SynthesisResult:
    """D-K μ-synthesis of the attitude controller, reduced and checked.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper.
    mu_points : int
        Frequencies of the μ grid (log-spaced, 1e-4 .. 1e2 rad/s).
    max_iterations : int
        D-K iterations at most.
    d_orders : sequence of int
        D-scale orders tried at each step.
    samples : int, optional
        Sampled models for the uncertainty-weight fit; default the problem's.
    seed : int, optional
        Their seed; default the problem's.
    progress : callable, optional
        ``progress(stage, iteration)`` (see :data:`Progress`).

    Returns
    -------
    SynthesisResult

    Raises
    ------
    SynthesisError
        A setting out of its range (named), or a problem no controller can be designed for.
    """
    from casadi_debris.robust.synthesis import SynthesisSettings, design_controller

    problem = as_problem(problem)
    settings = SynthesisSettings(
        samples=samples,
        seed=seed,
        mu_points=mu_points,
        d_orders=tuple(d_orders),
        max_iterations=max_iterations,
    )
    design = design_controller(problem, settings, progress)
    return SynthesisResult(problem=problem, design=design, summary=design.summary())
