"""A problem's budgets (``casadi-debris budget``): Δv per stage and face, propellant,
engine lifetime, the transfer and the detumble, each with how it was computed.

Example
-------
>>> import casadi_debris as cd
>>> budgets = cd.budget()
>>> round(budgets.summary.figures["dv_transfer_m_s"])  # the paper's is 150 m/s
144
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from casadi_debris.budgets import BudgetItem
from casadi_debris.config import Problem
from casadi_debris.report import BudgetSummary, budget_summary
from casadi_debris.store import write_json_atomic
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem


@dataclass(frozen=True)
class BudgetResult(JobResult):
    """A problem's budgets.

    Attributes
    ----------
    problem : Problem
    items : tuple of BudgetItem
        Every figure in the order the command prints them: its key (with its unit,
        ``dv_transfer_m_s``), value and how it was computed.
    summary : BudgetSummary
        What ``casadi-debris budget --json`` prints: the figures and ``how``, by key.
    """

    problem: Problem
    items: tuple[BudgetItem, ...]
    summary: BudgetSummary

    command = "budget"

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json`` (the command itself prints it and writes nothing)."""
        write_json_atomic(staging / "summary.json", self.summary)


def budget(problem: ProblemLike = None) -> BudgetResult:
    """The Δv, propellant, lifetime, transfer and detumble budgets of a problem.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper.

    Returns
    -------
    BudgetResult
    """
    from casadi_debris.budgets import compute_budgets

    problem = as_problem(problem)
    items = tuple(compute_budgets(problem))
    return BudgetResult(problem=problem, items=items, summary=budget_summary(problem, items))
