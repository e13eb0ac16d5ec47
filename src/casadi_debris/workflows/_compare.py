"""Fuel budgets of problem variants side by side (placements, failures, slew methods).

Example
-------
>>> import casadi_debris as cd
>>> both = cd.compare(["paper_slew"], methods=["bang-bang", "time-optimal"])  # doctest: +SKIP
>>> [row.fuel_slew_kg for row in both.summary.variants]  # doctest: +SKIP
>>> both.save("runs/compare")  # doctest: +SKIP
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.config import SLEW_METHODS, Problem, SlewMethod
from casadi_debris.dynamics import build_model
from casadi_debris.errors import (
    AllocationError,
    InputShapeError,
    ModelError,
)
from casadi_debris.guidance import Reference, scenario_reference
from casadi_debris.report import CompareSummary, VariantRow, write_comparison
from casadi_debris.simulation import (
    ClosedLoopResult,
    SimulationError,
    fuel_between_kg,
    simulate_closed_loop,
)
from casadi_debris.workflows._controller import controller_for
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure

LOGGER = logging.getLogger(__name__)


def variants(
    problems: list[Problem], methods: list[SlewMethod] | None
) -> list[tuple[str, Problem]]:
    """Each problem, and for slew problems each requested slew method."""
    chosen = []
    for problem in problems:
        slew = problem.simulation.slew
        if not methods or slew is None:
            chosen.append((problem.name, problem))
            continue
        for method in methods:
            settings = replace(slew, method=method)
            if method == "time-optimal":
                settings = replace(settings, duration_s=None)
            elif method == "fuel-optimal" and settings.duration_s is None:
                raise InputShapeError(
                    f"{problem.name}: fuel-optimal needs simulation.slew.duration_s"
                )
            variant = replace(problem, simulation=replace(problem.simulation, slew=settings))
            chosen.append((f"{problem.name} / {method}", variant))
    return chosen


def compare_row(
    label: str, problem: Problem, reference: Reference, controller: Any, window_s: float
) -> VariantRow:
    """One variant's nominal closed-loop run, reduced to the budget figures.

    A run that fails (the allocator or the simulation gives up, every engine
    lost) gives a row that says why instead of its figures.
    """
    requirement, required = requirement_of(problem)
    try:
        model = build_model(problem)
        allocator = Allocator.from_problem(problem, model.geometry)
        result = simulate_closed_loop(model, controller, reference, allocator=allocator)
    except (AllocationError, ModelError, SimulationError) as exc:
        LOGGER.warning("variant %s failed: %s", label, exc)
        return VariantRow(
            variant=label, problem=problem.name, error=str(exc), requirement=requirement,
            required=required,
        )  # fmt: skip
    summary = result.summary()
    error = summary.max_error_deg if requirement == "slew_error_deg" else summary.max_error_arcsec
    return VariantRow(
        variant=label,
        problem=problem.name,
        duration_s=summary.duration_s,
        fuel_kg=summary.fuel_kg,
        fuel_window_kg=fuel_between_kg(result, 0.0, window_s),
        fuel_slew_kg=summary.fuel_slew_kg,
        fuel_worst_cubesat_kg=summary.fuel_worst_cubesat_kg,
        dv_left_m_s=_dv_left_m_s(result, summary.fuel_kg),
        stage_switches=summary.stage_switches,
        slew_duration_s=None if reference.slew is None else reference.slew.duration_s,
        max_error_deg=summary.max_error_deg,
        max_error_arcsec=summary.max_error_arcsec,
        requirement=requirement,
        required=required,
        requirement_met=bool(error <= required),
        torque_saturated_s=summary.torque_saturated_s,
        failed_cubesats=int(result.propulsion.failed_cubesats.sum()),
    )


def requirement_of(problem: Problem) -> tuple[str, float]:
    """What a run of ``problem`` is judged against: its slew error bound [deg] for a
    slew or a sequence of segments, its pointing bound [arcsec] for a hold."""
    if problem.simulation.reference != "hold":
        return "slew_error_deg", problem.requirements.slew_error_deg
    return "pointing_arcsec", problem.requirements.pointing_arcsec


def _dv_left_m_s(result: ClosedLoopResult, burnt_kg: float) -> float:
    """Δv the propellant left gives the whole body [m/s]."""
    left_kg = float(result.propulsion.propellant_kg.sum())
    mass_now = result.total_mass_kg - burnt_kg
    exhaust = result.exhaust_velocity_m_s
    engines = result.propulsion.exhaust_velocity_m_s
    if left_kg > 0.0 and not np.all(engines == engines[0]):
        # Engines of different Isp: the propellant left leaves at its own engines' velocity.
        left_per_engine = result.propulsion.propellant_kg.sum(axis=1)
        exhaust = float(np.sum(left_per_engine * engines) / left_kg)
    return exhaust * math.log(mass_now / (mass_now - left_kg))


@dataclass(frozen=True)
class CompareResult(JobResult):
    """Variants side by side: one row of budget figures per variant's nominal run.

    Attributes
    ----------
    summary : CompareSummary
        What ``summary.json`` holds (and ``--json`` prints): the rows, the controller,
        the plants, the common window; ``out_dir`` None until saved.
    """

    summary: CompareSummary

    command = "compare"

    def plot(self) -> dict[str, Figure]:
        """``comparison``: a bar chart per figure, the variants side by side. Nothing is
        written."""
        from casadi_debris.report import comparison_figures

        return comparison_figures(self.summary)

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``comparison.csv``, ``comparison.md``, ``comparison.png`` (with ``plots``) and
        ``summary.json``."""
        summary = replace(self.summary, out_dir=str(out.absolute()))
        write_comparison(staging, summary, with_plots=plots)


def compare(
    problem_files: Sequence[ProblemLike],
    *,
    methods: Sequence[str] | None = None,
    controller: str | Path | None = None,
    allow_mismatch: bool = False,
    progress: Callable[[str], None] | None = None,
) -> CompareResult:
    """Run the nominal closed loop of every variant and tabulate their fuel budgets.

    Parameters
    ----------
    problem_files : sequence of Problem, str or Path
        The variants: problems, problem files or shipped names (at least one).
    methods : sequence of str, optional
        Slew methods to fly on each slew problem (default: each problem's own).
    controller : str or Path, optional
        Controller file (default the shipped paper controller). It must have been
        designed for every variant's plant (see
        :func:`~casadi_debris.workflows._controller.controller_for`) unless
        ``allow_mismatch``.
    allow_mismatch : bool
        Fly the controller on variants whose plant it was not designed for.
    progress : callable, optional
        ``progress(label)`` as each variant starts.

    Returns
    -------
    CompareResult
        One row per variant (fuel over the run, over the window every variant flew and
        during the slew, and of the worst CubeSat [kg], Δv left [m/s], stage switches,
        slew time [s], max error against the problem's requirement, saturated time [s];
        or why its run failed), the controller.
    """
    unknown = sorted(set(methods or ()) - set(SLEW_METHODS))
    if unknown:
        raise InputShapeError(
            f"--methods: unknown {', '.join(unknown)}; choose from {', '.join(SLEW_METHODS)}"
        )
    problems = [as_problem(p) for p in problem_files]
    # Every variant checked before any is flown.
    checked = [controller_for(p, controller, allow_mismatch=allow_mismatch) for p in problems]
    if not checked:
        raise InputShapeError("compare needs at least one problem")
    record, resolved = checked[0]
    rows = []
    chosen = [cast(SlewMethod, m) for m in methods] if methods else None  # checked above
    flown = variants(problems, chosen)
    window_s = min(problem.simulation.duration_s for _, problem in flown)
    # Every reference first: a slew a variant's file asks and the body cannot do is
    # that file's mistake, refused before any variant flies.
    references = [scenario_reference(problem) for _, problem in flown]
    for (label, problem), reference in zip(flown, references, strict=True):
        LOGGER.info("variant %s", label)
        if progress is not None:
            progress(label)
        rows.append(compare_row(label, problem, reference, record.reduced, window_s))
    summary = CompareSummary(
        controller_path=str(resolved),
        controller_plant_sha256=record.problem_sha256,
        plant_sha256={problem.name: problem.plant_sha256 for problem in problems},
        window_s=window_s,
        variants=tuple(rows),
        out_dir=None,
    )
    return CompareResult(summary)
