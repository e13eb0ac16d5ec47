"""The combined system of a problem (``casadi-debris model``): mass, CoG, inertia, torque
authority, the arrays, the flexible modes and every engine.

Example
-------
>>> import casadi_debris as cd
>>> described = cd.model()
>>> round(described.summary.mass_kg, 1), round(described.summary.torque_max_mNm["+x"], 2)
(668.0, 4.61)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from casadi_debris.config import Problem
from casadi_debris.report import ModelSummary, describe_model
from casadi_debris.store import write_json_atomic
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from casadi_debris.dynamics import Model


@dataclass(frozen=True)
class ModelResult(JobResult):
    """A problem's combined system, described.

    Attributes
    ----------
    problem : Problem
    model : Model
        The CasADi model of the combined body (named ``casadi.Function``s, its geometry
        and parameters), SI units.
    summary : ModelSummary
        What ``casadi-debris model --json`` prints: mass [kg], CoG [m], inertias
        [kg m^2], torque authority by signed axis [mN m], arrays, modes and thrusters
        (ids from 1).
    """

    problem: Problem
    model: Model
    summary: ModelSummary

    command = "model"

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json`` (the command itself prints it and writes nothing)."""
        write_json_atomic(staging / "summary.json", self.summary)


def model(problem: ProblemLike = None) -> ModelResult:
    """Describe the combined system of a problem.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name (``"side_engines_12"``); default the
        paper.

    Returns
    -------
    ModelResult
        The model built, and its description in display units.
    """
    from casadi_debris.dynamics import build_model

    problem = as_problem(problem)
    built = build_model(problem)
    return ModelResult(problem=problem, model=built, summary=describe_model(built))
