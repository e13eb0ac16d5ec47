"""Detumbling the debris, simulated, beside the budget's estimates (``casadi-debris detumble``).

Example
-------
>>> import casadi_debris as cd
>>> result = cd.detumble("paper", ocp=False)  # doctest: +SKIP
>>> result.summary.run.time_to_threshold_h  # doctest: +SKIP
16.5
>>> result.save("runs/detumble-paper")  # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, TypedDict

import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.budgets import budgets_as_dict, compute_budgets
from casadi_debris.config import Problem
from casadi_debris.geometry import build_geometry
from casadi_debris.report import DetumbleSummary, detumble_figures, write_detumble
from casadi_debris.simulation import SimulationError
from casadi_debris.simulation.detumble import (
    DEFAULT_GAIN_PER_S,
    DEFAULT_THRESHOLD_RAD_S,
    DETUMBLE_PERIOD_S,
    problem_time_optimal_detumble,
)
from casadi_debris.simulation.detumble import DetumbleRunResult as DetumbleRun
from casadi_debris.simulation.detumble import simulate_detumble as fly_detumble
from casadi_debris.units import SECONDS_PER_HOUR
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure


@dataclass(frozen=True)
class DetumbleResult(JobResult):
    """A detumble: the closed-loop run beside the budget's estimates and the bounds.

    Attributes
    ----------
    summary : DetumbleSummary
        What ``summary.json`` holds: the run's figures, the budget's estimates, the
        momentum bound and the time-optimal detumble.
    run : simulation.detumble.DetumbleRunResult
        The run's time series (rates [rad/s], torque [N m], propellant), SI.
    """

    summary: DetumbleSummary
    run: DetumbleRun

    command = "detumble"

    def plot(self) -> dict[str, Figure]:
        """``detumble``: the rates, the torque and the propellant per CubeSat; nothing is
        written."""
        return detumble_figures(self.run, self.summary)

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json``, ``series.csv`` and, with ``plots``, ``detumble.png``."""
        summary = dataclasses.replace(self.summary, out_dir=str(out.absolute()))
        write_detumble(staging, self.run, summary, plots=plots)


def detumble(
    problem: ProblemLike = None,
    *,
    rate_rad_s: Sequence[float] | None = None,
    threshold_rad_s: float = DEFAULT_THRESHOLD_RAD_S,
    gain_per_s: float = DEFAULT_GAIN_PER_S,
    period_s: float = DETUMBLE_PERIOD_S,
    ocp: bool = True,
    progress: Callable[[str], None] | None = None,
) -> DetumbleResult:
    """Detumble the debris in closed loop: rigid body, thruster-level allocation, staging.

    Each period the engines give the torque that shrinks the angular momentum fastest
    (a vertex of the zero-net-force authority), then linear damping once they can. The
    arrays are taken as rigid: the flexible model is not valid at such rates.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper.
    rate_rad_s : sequence of 3 float, optional
        Initial body rate about x, y, z [rad/s]; default the problem's ``[detumble]``.
    threshold_rad_s : float
        Done when every rate component is below this [rad/s].
    gain_per_s : float
        K of the linear tail ``tau = -K J omega`` [1/s].
    period_s : float
        Control period [s]: the torque is held over it.
    ocp : bool
        Also solve the time-optimal detumble (an averaged OCP, about 20 s).
    progress : callable, optional
        ``progress(line)`` as the run starts.

    Returns
    -------
    DetumbleResult

    Raises
    ------
    SimulationError
        A threshold, gain or period that cannot work (named), or no engine left.
    """
    problem = as_problem(problem)
    if progress is not None:
        progress(f"Detumbling {problem.name} (rigid body, {period_s:g} s control period) ...")
    result = fly_detumble(
        problem,
        initial_rate_rad_s=None if rate_rad_s is None else np.asarray(rate_rad_s, dtype=float),
        threshold_rad_s=threshold_rad_s,
        gain_per_s=gain_per_s,
        period_s=period_s,
    )
    # The budget's estimates for the tumble flown, which rate_rad_s may have changed.
    flown = dataclasses.replace(
        problem,
        detumble=dataclasses.replace(problem.detumble, initial_rate_rad_s=result.rate_rad_s[0]),
    )
    budgets = budgets_as_dict(compute_budgets(flown))
    report = DetumbleSummary(
        problem=problem.name,
        problem_sha256=problem.sha256,
        budget_time_h=budgets["detumble_time_h"],
        budget_time_full_rigid_h=budgets["detumble_time_full_rigid_h"],
        budget_dv_m_s=budgets["detumble_dv_m_s"],
        momentum_bound_h=momentum_bound_s(problem, result.rate_rad_s[0]) / SECONDS_PER_HOUR,
        run=result.summary,
        **(_time_optimal(problem, result.rate_rad_s[0], threshold_rad_s) if ocp else {}),
    )
    return DetumbleResult(summary=report, run=result)


class _OcpFields(TypedDict, total=False):
    """The detumble summary's ``ocp_*`` fields."""

    ocp_method: str
    ocp_time_h: float
    ocp_fuel_kg: float
    ocp_greedy_time_h: float
    ocp_averaged_bound_h: float
    ocp_solver_status: str


def _time_optimal(
    problem: Problem, initial_rate_rad_s: np.ndarray, threshold_rad_s: float
) -> _OcpFields:
    """The report's ``ocp_*`` fields; a body or polytope the OCP cannot take says why."""
    try:
        solved = problem_time_optimal_detumble(problem, initial_rate_rad_s, threshold_rad_s)
    except SimulationError as exc:
        return {"ocp_method": f"not solved: {exc}"}
    summary = solved.summary
    return {
        "ocp_method": summary.method,
        "ocp_time_h": summary.time_h,
        "ocp_fuel_kg": summary.fuel_kg,
        "ocp_greedy_time_h": summary.greedy_time_h,
        "ocp_averaged_bound_h": summary.averaged_bound_h,
        "ocp_solver_status": summary.solver_status,
    }


def momentum_bound_s(problem: Problem, initial_rate_rad_s: np.ndarray) -> float:
    """``|J omega_0| / max |tau|``: no torque the engines reach shrinks the angular
    momentum faster than its own magnitude, so no detumble is shorter [s]."""
    geometry = build_geometry(problem)
    vertices = Allocator.from_problem(problem, geometry).authority_polytope().vertices
    momentum = geometry.inertia_total_kgm2 @ np.asarray(initial_rate_rad_s, dtype=float)
    return float(np.linalg.norm(momentum) / np.max(np.linalg.norm(vertices, axis=1)))
