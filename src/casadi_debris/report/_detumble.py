"""A detumble as a run folder: summary.json, series.csv and detumble.png."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from casadi_debris.config import AXIS_NAMES
from casadi_debris.records import FLATTENED, Record
from casadi_debris.simulation.detumble import DetumbleRunResult, DetumbleRunSummary
from casadi_debris.store import write_csv, write_json_atomic
from casadi_debris.units import DEG_PER_RAD, MNM_PER_NM

if TYPE_CHECKING:
    from matplotlib.figure import Figure


@dataclass(frozen=True, kw_only=True)
class DetumbleSummary(Record):
    """The detumble beside the budget's estimates and a bound no detumble can beat.

    Attributes
    ----------
    problem, problem_sha256 : str
    budget_time_h : float
        The budget's (and the paper's) estimate: each axis braked on its own at
        full torque, hub and CubeSats inertia.
    budget_time_full_rigid_h : float
        The same with the arrays' rigid inertia, the body this detumble flies.
    budget_dv_m_s : float
        The budget's share of one face's stage Δv that the firing time uses.
    momentum_bound_h : float
        ``|J omega_0| / max |tau|`` over the torques the engines reach: the angular
        momentum cannot shrink faster than the largest torque.
    run : DetumbleRunSummary
    out_dir : str or None
    ocp_method : str or None
        How ``ocp_time_h`` was found, or why it was not (None when not asked for).
    ocp_time_h, ocp_fuel_kg : float or None
        The time-optimal detumble (averaged OCP) and its propellant: between the
        momentum bound and the closed loop.
    ocp_greedy_time_h : float or None
        The averaged model flown with the closed loop's greedy law: what the closed
        loop tends to as its control period shrinks.
    ocp_averaged_bound_h : float or None
        No control averaged over the precession brakes faster than the greedy law on
        the best polhode: a bound on the averaged OCP (not on the closed loop's
        rates step by step; ``momentum_bound_h`` is that one).
    ocp_solver_status : str or None
    """

    problem: str
    problem_sha256: str
    budget_time_h: float
    budget_time_full_rigid_h: float
    budget_dv_m_s: float
    momentum_bound_h: float
    run: DetumbleRunSummary = field(metadata=FLATTENED)
    out_dir: str | None = None
    ocp_method: str | None = None
    ocp_time_h: float | None = None
    ocp_fuel_kg: float | None = None
    ocp_greedy_time_h: float | None = None
    ocp_averaged_bound_h: float | None = None
    ocp_solver_status: str | None = None


def write_detumble(
    folder: Path, result: DetumbleRunResult, report: DetumbleSummary, *, plots: bool = True
) -> None:
    """``summary.json``, ``series.csv`` (rates in deg/s, torque in mNm) and, with
    ``plots``, ``detumble.png`` (and its PDF)."""
    write_json_atomic(folder / "summary.json", report)
    columns = {"time_s": result.time_s}
    for i, axis in enumerate(AXIS_NAMES):
        columns[f"rate_{axis}_deg_s"] = result.rate_rad_s[:, i] * DEG_PER_RAD
    for i, axis in enumerate(AXIS_NAMES):
        torque = np.append(result.torque_Nm[:, i], result.torque_Nm[-1, i])
        columns[f"torque_{axis}_mNm"] = torque * MNM_PER_NM
    write_csv(folder / "series.csv", columns)
    if plots:
        from casadi_debris.plots import save_figure

        for stem, figure in detumble_figures(result, report).items():
            save_figure(figure, folder / f"{stem}.png")


def detumble_figures(result: DetumbleRunResult, report: DetumbleSummary) -> dict[str, Figure]:
    """``detumble``: the rates against the threshold with the estimates and bounds marked,
    the torque and the propellant per CubeSat."""
    from casadi_debris.plots import detumble_figure

    marks = {
        "per-axis braking estimate": report.budget_time_full_rigid_h,
        "momentum bound": report.momentum_bound_h,
    }
    if report.ocp_time_h is not None:
        marks["time-optimal (averaged OCP)"] = report.ocp_time_h
    return {"detumble": detumble_figure(result, title=report.problem, marks_h=marks)}
