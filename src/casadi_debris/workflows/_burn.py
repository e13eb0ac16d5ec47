"""Thrusting while pointing: a burn flown in closed loop (``casadi-debris burn``).

Example
-------
>>> import casadi_debris as cd
>>> result = cd.burn("paper", direction="normal", hours=0.1)  # doctest: +SKIP
>>> result.summary.burn.pointing_max_arcsec  # doctest: +SKIP
28.3
>>> result.save("runs/burn-paper")  # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from casadi_debris.allocation import Allocator, PropulsionState
from casadi_debris.config import BurnDirection, BurnRequest, Problem
from casadi_debris.dynamics import build_model
from casadi_debris.errors import InputShapeError
from casadi_debris.guidance import (
    BurnPlan,
    burn_limits,
    burn_thrust_N,
    engine_limits_along,
    plan_burn,
)
from casadi_debris.report import BurnSummary, burn_figures, write_burn
from casadi_debris.simulation.burn import (
    BURN_PERIOD_S,
    BurnRun,
    BurnSeries,
    burn_summary,
    first_stage_left,
    simulate_burn,
)
from casadi_debris.units import MN_PER_N, SECONDS_PER_HOUR
from casadi_debris.workflows._controller import controller_for
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure

LOGGER = logging.getLogger(__name__)


@dataclass(frozen=True)
class _Flight:
    """A burn request and how the job flies it.

    Attributes
    ----------
    request : BurnRequest
        What to fly (SI: ``thrust_N``, ``duration_s``).
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

    request: BurnRequest
    first_stage_left_s: float | None = None
    controller: str | Path | None = None
    allow_mismatch: bool = False
    period_s: float = BURN_PERIOD_S
    jit: bool = True

    def plan(self, problem: Problem) -> tuple[BurnPlan, PropulsionState]:
        """The plan of the request and the engines it starts with, checked (quick: two LPs).

        Raises
        ------
        SimulationError
            A field that cannot be flown (named), e.g. a thrust beyond the engines.
        """
        plan = plan_burn(problem, self.request)
        engines = PropulsionState.from_problem(problem)
        if self.first_stage_left_s is not None:
            engines = first_stage_left(engines, self.first_stage_left_s)
        burn_thrust_N(Allocator.from_problem(problem, state=engines), plan)
        return plan, engines


@dataclass(frozen=True)
class BurnResult(JobResult):
    """A burn flown in closed loop: its figures and its series.

    Attributes
    ----------
    summary : BurnSummary
        What ``summary.json`` holds: pointing error, Δv three ways, the propellant split,
        stage switches, and the controller flown.
    run : BurnRun
        The closed-loop run and the thrust axis' pointing error (SI).
    series : BurnSeries
        Thrust along the axis [N], Δv along the direction [m/s] and the propellant split
        [kg] over time.
    """

    summary: BurnSummary
    run: BurnRun
    series: BurnSeries

    command = "burn"

    def plot(self) -> dict[str, Figure]:
        """``burn``: the pointing error against the requirement, the thrust and the
        propellant split, stage switches marked; nothing is written."""
        return burn_figures(self.run, self.series, self.summary)

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json``, ``series.csv`` and, with ``plots``, ``burn.png``."""
        summary = dataclasses.replace(self.summary, out_dir=str(out.absolute()))
        write_burn(staging, self.run, self.series, summary, plots=plots)


def burn(
    problem: ProblemLike = None,
    *,
    direction: BurnDirection = "retrograde",
    hours: float = 0.25,
    body_axis: str | Sequence[float] | None = None,
    thrust_fraction: float | None = None,
    thrust_mN: float | None = None,
    first_stage_left_s: float | None = None,
    controller: str | Path | None = None,
    allow_mismatch: bool = False,
    no_jit: bool = False,
    progress: Callable[[str], None] | None = None,
) -> BurnResult:
    """Fly a burn: the thrust axis held along an LVLH direction by the attitude loop on the
    flexible model (every array mode), while the engines deliver the thrust and the
    loop's torque together.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper.
    direction : {"retrograde", "prograde", "normal", "antinormal"}
        Where the thrust points, in the orbit's LVLH frame.
    hours : float
        Engines on [h].
    body_axis : str or sequence of 3 float, optional
        Thrust axis in body axes (``"x"``, ``"-y"``, ... or a vector, not zero); default
        the swarm's strongest torque-free direction.
    thrust_fraction : float, optional
        Of the largest torque-free thrust along the axis, in (0, 1]; default 1.
    thrust_mN : float, optional
        The thrust itself [mN], instead of ``thrust_fraction``.
    first_stage_left_s : float, optional
        Start with every engine's first stage holding this much full-thrust time [s] (to
        see the stages switch in a short burn); default full.
    controller : str or Path, optional
        Controller file; default the shipped paper controller (for the paper's plant).
    allow_mismatch : bool
        Fly a controller designed for another plant.
    no_jit : bool
        Run the control step on CasADi's virtual machine instead of compiled C.
    progress : callable, optional
        ``progress(line)`` once the burn and the controller are checked, as the long part
        starts.

    Returns
    -------
    BurnResult

    Raises
    ------
    InputShapeError
        Both ``thrust_fraction`` and ``thrust_mN``, or a zero ``body_axis``.
    SimulationError
        A burn that cannot be flown (named), e.g. a thrust beyond the engines.
    ControllerMismatchError
        The controller was designed for another plant (and ``allow_mismatch`` is false).
    """
    if thrust_fraction is not None and thrust_mN is not None:
        raise InputShapeError("--thrust-mN: give either --thrust-fraction or --thrust-mN")
    problem = as_problem(problem)
    request = BurnRequest(
        direction=direction,
        body_axis=None if body_axis is None else _body_axis(body_axis),
        thrust_fraction=1.0 if thrust_fraction is None else thrust_fraction,
        thrust_N=None if thrust_mN is None else thrust_mN / MN_PER_N,
        duration_s=hours * SECONDS_PER_HOUR,
    )
    flight = _Flight(
        request,
        first_stage_left_s=first_stage_left_s,
        controller=controller,
        allow_mismatch=allow_mismatch,
        jit=not no_jit,
    )
    return _fly(problem, flight, progress)


def _fly(problem: Problem, flight: _Flight, progress: Callable[[str], None] | None) -> BurnResult:
    """Check the request (two LPs) and the controller, then fly it (the long part)."""
    plan, engines = flight.plan(problem)
    record, controller_path = controller_for(
        problem, flight.controller, allow_mismatch=flight.allow_mismatch
    )
    if progress is not None:
        hours = plan.duration_s / SECONDS_PER_HOUR
        progress(
            f"Flying a {plan.direction} burn of {hours:g} h on {problem.name} (flexible model) ..."
        )
    run = simulate_burn(
        build_model(problem),
        record.reduced,
        plan,
        period_s=flight.period_s,
        propulsion=engines,
        jit=flight.jit,
    )
    allocator = Allocator.from_problem(problem)
    summary, series = burn_summary(problem, run, allocator)
    # Checked against what the engines have left, not their full stages: the state the
    # burn started with (a partly used first stage), fired with the run's own thrust, so
    # an engine spent during the burn gives nothing from then on.
    check = burn_limits(
        problem,
        plan,
        burn_thrust_N(Allocator.from_problem(problem, state=engines), plan, strict=False),
        flight.period_s,
        engine_limits=engine_limits_along(engines, run.result.thrust_N, flight.period_s),
    )
    if not check.limits_ok:
        LOGGER.warning(
            "warning: the burn's attitude needs more torque than the engines add to its thrust: %s",
            check.limits_note,
        )
    report = BurnSummary(
        burn=summary,
        controller_path=str(controller_path),
        first_stage_left_s=flight.first_stage_left_s,
        limits_ok=check.limits_ok,
        limits_note=check.limits_note,
        worst_torque_set_ratio=check.worst_torque_set_ratio,
    )
    return BurnResult(summary=report, run=run, series=series)


def _body_axis(axis: str | Sequence[float]) -> tuple[float, float, float]:
    """An axis name (``"x"``, ``"-y"``) or a vector, as a vector not all zero."""
    from casadi_debris.config import AXIS_TEXTS, axis_unit_vector

    if isinstance(axis, str):
        name = axis.strip().lower()
        if name not in AXIS_TEXTS:
            raise InputShapeError(f"--body-axis: x, -y, ... or three numbers, got {axis!r}")
        x, y, z = (float(v) for v in axis_unit_vector(name))
        return (x, y, z)
    values = np.asarray(axis, dtype=float)
    if values.shape != (3,) or not np.all(np.isfinite(values)) or not np.any(values):
        raise InputShapeError(f"--body-axis: three finite numbers not all zero, got {axis!r}")
    return (float(values[0]), float(values[1]), float(values[2]))
