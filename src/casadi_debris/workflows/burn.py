"""Thrusting while pointing: a burn flown in closed loop (``casadi-debris burn``).

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.workflows.burn import burn_into
>>> report = burn_into(load_problem(), "runs/burn-paper")  # doctest: +SKIP
>>> report.burn.pointing_max_arcsec  # doctest: +SKIP
28.3
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from casadi_debris.allocation import Allocator, PropulsionState
from casadi_debris.config import BurnDirection, Problem
from casadi_debris.dynamics import build_model
from casadi_debris.guidance.burn_plan import BurnPlan, burn_thrust_N, strongest_axis
from casadi_debris.report.burn import BurnReport, write_burn
from casadi_debris.report.folders import RunFolder, check_output_folder
from casadi_debris.simulation.burn import (
    DEFAULT_PERIOD_S,
    BurnRun,
    first_stage_left,
    simulate_burn,
)
from casadi_debris.simulation.burn_figures import BurnSeries, BurnSummary, burn_figures
from casadi_debris.units import MN_PER_N
from casadi_debris.workflows.controller import controller_for


@dataclass(frozen=True)
class BurnRequest:
    """What to fly.

    Attributes
    ----------
    direction : {"prograde", "retrograde", "normal", "antinormal"}
        In the orbit's LVLH frame.
    duration_s : float
        Engines on [s].
    body_axis : tuple of 3 float, optional
        Thrust axis in body axes; default the swarm's strongest torque-free direction.
    thrust_fraction : float
        Of the largest torque-free thrust along the axis.
    thrust_mN : float, optional
        The thrust itself (instead of the fraction) [mN].
    first_stage_left_s : float, optional
        Start with every engine's first stage holding this much full-thrust time
        (to see the stages switch during a short burn); default full.
    controller : str or Path, optional
        Controller file (default the shipped paper controller, for the paper's plant).
    allow_mismatch : bool
        Fly a controller designed for another plant.
    period_s : float
        Control period [s].
    jit : bool
        Compile the control step to C.
    """

    direction: BurnDirection = "retrograde"
    duration_s: float = 600.0
    body_axis: tuple[float, float, float] | None = None
    thrust_fraction: float = 1.0
    thrust_mN: float | None = None
    first_stage_left_s: float | None = None
    controller: str | Path | None = None
    allow_mismatch: bool = False
    period_s: float = DEFAULT_PERIOD_S
    jit: bool = True


@dataclass(frozen=True, eq=False)
class BurnOutcome:
    """A burn's run, series and figures (:func:`fly_burn`)."""

    run: BurnRun
    series: BurnSeries
    summary: BurnSummary
    controller_path: Path


def burn_plan(problem: Problem, request: BurnRequest) -> tuple[BurnPlan, PropulsionState]:
    """The plan a request asks for and the engines it starts with, checked (quick: two LPs).

    Raises
    ------
    SimulationError
        A field that cannot be flown (named), e.g. a thrust beyond the engines.
    """
    r = request
    axis = strongest_axis(problem) if r.body_axis is None else np.asarray(r.body_axis, dtype=float)
    thrust_N = None if r.thrust_mN is None else r.thrust_mN / MN_PER_N
    plan = BurnPlan(r.direction, axis, r.duration_s, r.thrust_fraction, thrust_N)
    engines = PropulsionState.from_problem(problem)
    if r.first_stage_left_s is not None:
        engines = first_stage_left(engines, r.first_stage_left_s)
    burn_thrust_N(Allocator.from_problem(problem, state=engines), plan)
    return plan, engines


def fly_burn(problem: Problem, request: BurnRequest | None = None) -> BurnOutcome:
    """Fly a burn on the problem's flexible model (every array mode) with its controller.

    Parameters
    ----------
    problem : Problem
    request : BurnRequest, optional
        Default a 600 s retrograde burn at full torque-free thrust.

    Returns
    -------
    BurnOutcome
    """
    r = request or BurnRequest()
    record, controller_path = controller_for(problem, r.controller, allow_mismatch=r.allow_mismatch)
    plan, engines = burn_plan(problem, r)
    model = build_model(problem)
    run = simulate_burn(
        problem, model, record.reduced, plan, period_s=r.period_s, propulsion=engines, jit=r.jit
    )
    summary, series = burn_figures(problem, run, Allocator.from_problem(problem))
    return BurnOutcome(run, series, summary, controller_path)


def burn_into(
    problem: Problem,
    out: str | Path,
    request: BurnRequest | None = None,
    *,
    overwrite: bool = False,
) -> BurnReport:
    """Fly a burn (:func:`fly_burn`) and write it into the run folder ``out``.

    Parameters
    ----------
    problem : Problem
    out : str or Path
        Run folder: ``summary.json``, ``series.csv``, ``burn.png`` (and its PDF).
    request : BurnRequest, optional
    overwrite : bool
        Replace a run folder this toolkit wrote.

    Returns
    -------
    BurnReport
    """
    out = Path(out)
    check_output_folder(out, overwrite=overwrite)
    r = request or BurnRequest()
    outcome = fly_burn(problem, r)
    report = BurnReport(
        burn=outcome.summary,
        controller_path=str(outcome.controller_path),
        first_stage_left_s=r.first_stage_left_s,
        out_dir=str(out.absolute()),
    )
    with RunFolder.claim(out, overwrite=overwrite, command="burn") as staging:
        write_burn(staging, outcome.run, outcome.series, report)
    return report
