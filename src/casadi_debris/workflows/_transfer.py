"""The orbit transfer with the swarm's staged engines (``casadi-debris transfer``).

Example
-------
>>> import casadi_debris as cd
>>> result = cd.transfer("paper")  # doctest: +SKIP
>>> round(result.summary.transfer_dv_m_s), result.summary.swarm_suffices  # doctest: +SKIP
(144, False)
>>> result.save("runs/transfer-paper")  # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from casadi_debris.config import Problem
from casadi_debris.orbit import TransferPlan, TransferSummary, plan_transfer
from casadi_debris.orbit.transfer import Objective, check_transfer
from casadi_debris.report import transfer_figures, write_transfer
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure


@dataclass(frozen=True)
class TransferResult(JobResult):
    """A planned orbit transfer: its summary and both trajectories.

    Attributes
    ----------
    summary : TransferSummary
        What ``summary.json`` holds: Δv beside Edelbaum's, time, propellant, stages per
        CubeSat and whether the swarm's own stages suffice.
    plan : TransferPlan
        The guidance law flown and the optimal control problem's solution (SI), the
        thrust directions, the burns and the stage switches.
    problem : Problem
        The problem planned (its target orbit and Earth radius draw the figure).
    """

    summary: TransferSummary
    plan: TransferPlan
    problem: Problem

    command = "transfer"

    def plot(self) -> dict[str, Figure]:
        """``transfer``: altitude, inclination, mass and the firing direction over the
        days, guidance and OCP; nothing is written."""
        return transfer_figures(self.plan, *self._orbits())

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json``, ``guidance.csv``, ``ocp.csv`` and, with ``plots``,
        ``transfer.png`` (and its PDF)."""
        summary = dataclasses.replace(self.summary, out_dir=str(out.absolute()))
        write_transfer(staging, self.plan, summary, *self._orbits(), plots=plots)

    def _orbits(self) -> tuple[float, tuple[float, float]]:
        """The Earth radius [km] and the target's altitude [km] and inclination [deg]."""
        transfer = self.problem.transfer
        target = (transfer.to_altitude_km, transfer.to_inclination_deg)
        return self.problem.constants.earth_radius_km, target


def transfer(
    problem: ProblemLike = None,
    *,
    objective: Objective = "time",
    progress: Callable[[str], None] | None = None,
) -> TransferResult:
    """Plan the problem's ``[transfer]`` with the swarm's thrust directions, staging and J2.

    Edelbaum steering flown in closed loop and an optimal control problem, both on
    orbit-averaged equinoctial elements.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper. Its
        ``[transfer]`` must end on its ``[orbit]``.
    objective : {"time", "propellant"}
        Minimum transfer time, or minimum propellant (throttled, the time at most 10 %
        over the guidance law's).
    progress : callable, optional
        ``progress(line)`` once the transfer is checked, as the long part starts.

    Returns
    -------
    TransferResult

    Raises
    ------
    ProblemFileError
        The ``[transfer]`` does not end on the debris' ``[orbit]``, or has nothing to do.
    """
    problem = as_problem(problem)
    check_transfer(problem)
    if progress is not None:
        progress(f"Planning the transfer of {problem.name} (minimum {objective}) ...")
    plan = plan_transfer(problem, objective=objective)
    return TransferResult(summary=plan.result, plan=plan, problem=problem)
