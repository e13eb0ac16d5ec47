"""Detumbling the debris, simulated, beside the budget's estimates (``casadi-debris detumble``).

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.workflows.detumble import detumble_into
>>> report = detumble_into(load_problem(), "runs/detumble-paper")  # doctest: +SKIP
>>> report.run.time_to_threshold_h  # doctest: +SKIP
57.6
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from casadi_debris.allocation import Allocator
from casadi_debris.budgets import budgets_as_dict, compute_budgets
from casadi_debris.config import Problem
from casadi_debris.geometry import build_geometry
from casadi_debris.report.detumble import DetumbleReport, write_detumble
from casadi_debris.report.folders import RunFolder, check_output_folder
from casadi_debris.simulation.closed_loop import SimulationError
from casadi_debris.simulation.detumble import (
    DEFAULT_GAIN_PER_S,
    DEFAULT_PERIOD_S,
    DEFAULT_THRESHOLD_RAD_S,
    detumble,
)
from casadi_debris.simulation.detumble_ocp import problem_time_optimal_detumble
from casadi_debris.units import SECONDS_PER_HOUR


def detumble_into(
    problem: Problem,
    out: str | Path,
    *,
    initial_rate_rad_s: npt.ArrayLike | None = None,
    threshold_rad_s: float = DEFAULT_THRESHOLD_RAD_S,
    gain_per_s: float = DEFAULT_GAIN_PER_S,
    period_s: float = DEFAULT_PERIOD_S,
    ocp: bool = True,
    overwrite: bool = False,
) -> DetumbleReport:
    """Simulate the detumble of ``problem`` and write it into the run folder ``out``.

    Parameters
    ----------
    problem : Problem
    out : str or Path
        Run folder: ``summary.json``, ``series.csv``, ``detumble.png``.
    initial_rate_rad_s, threshold_rad_s, gain_per_s, period_s
        See :func:`~casadi_debris.simulation.detumble.detumble`.
    ocp : bool
        Also solve the time-optimal detumble (averaged OCP, about 20 s).
    overwrite : bool
        Replace a run folder this toolkit wrote.

    Returns
    -------
    DetumbleReport
        The run, the budget's estimates, the momentum bound and the time-optimal detumble.
    """
    out = Path(out)
    check_output_folder(out, overwrite=overwrite)
    result = detumble(
        problem,
        initial_rate_rad_s=initial_rate_rad_s,
        threshold_rad_s=threshold_rad_s,
        gain_per_s=gain_per_s,
        period_s=period_s,
    )
    # The budget's estimates for the tumble flown, which --rate-rad-s may have changed.
    flown = dataclasses.replace(
        problem,
        detumble=dataclasses.replace(problem.detumble, initial_rate_rad_s=result.rate_rad_s[0]),
    )
    budgets = budgets_as_dict(compute_budgets(flown))
    report = DetumbleReport(
        problem=problem.name,
        problem_sha256=problem.sha256,
        budget_time_h=budgets["detumble_time_h"],
        budget_time_full_rigid_h=budgets["detumble_time_full_rigid_h"],
        budget_dv_m_s=budgets["detumble_dv_m_s"],
        momentum_bound_h=momentum_bound_s(problem, result.rate_rad_s[0]) / SECONDS_PER_HOUR,
        run=result.summary,
        out_dir=str(out.absolute()),
        **(_time_optimal(problem, result.rate_rad_s[0], threshold_rad_s) if ocp else {}),
    )
    with RunFolder.claim(out, overwrite=overwrite, command="detumble") as staging:
        write_detumble(staging, result, report)
    return report


def _time_optimal(
    problem: Problem, initial_rate_rad_s: np.ndarray, threshold_rad_s: float
) -> dict[str, Any]:
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
