"""One closed-loop run (``casadi-debris simulate``): the problem's reference flown by the
μ controller, the allocator and the staged engines on the flexible model.

Example
-------
>>> import casadi_debris as cd
>>> run = cd.simulate("paper_slew", duration_s=300.0)  # doctest: +SKIP
>>> run.summary.max_error_deg, run.summary.requirements_met  # doctest: +SKIP
(0.0171, True)
>>> run.save("runs/slew-300s")  # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from casadi_debris.config import FailureEvent, Problem, Target, with_duration
from casadi_debris.errors import InputShapeError
from casadi_debris.store import write_json_atomic
from casadi_debris.workflows._campaign import (
    SimulationSummary,
    one_case,
    parameters_case,
    run_summary,
)
from casadi_debris.workflows._controller import controller_for
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from casadi_debris.campaigns import Case
    from casadi_debris.dynamics import Model
    from casadi_debris.guidance import Reference
    from casadi_debris.simulation import ClosedLoopResult, SegmentRunSummary

LOGGER = logging.getLogger(__name__)

Axis = str | tuple[float, float, float]


@dataclass(frozen=True)
class SimulationResult(JobResult):
    """One closed-loop run: the problem flown, its arrays and its figures.

    Attributes
    ----------
    problem : Problem
        The problem as flown (with the run length, slew and failures asked for).
    result : ClosedLoopResult
        Every time series, SI units.
    summary : SimulationSummary
        The figures in display units, with ``requirements_met``.
    segments : tuple of SegmentRunSummary or None
        Each segment's window, largest error and fuel, for a problem that flies
        ``[[simulation.segments]]``.
    """

    problem: Problem
    result: ClosedLoopResult
    summary: SimulationSummary
    segments: tuple[SegmentRunSummary, ...] | None = None

    def plot(self) -> dict[str, Figure]:
        """The run's figures, by the file stem ``save`` writes them under:
        ``closed_loop`` (reference, error against the requirement, torque against the
        authority) and ``thrust`` (every engine, propellant per CubeSat). Nothing is
        written; close them with ``matplotlib.pyplot.close``."""
        from casadi_debris.report import figure_title, run_figures

        title = f"{figure_title(self.problem)} ({self.summary.case_id})"
        return run_figures(self.result, self.problem, title)

    command = "simulate"

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json``, ``series.csv``, ``closed_loop.png`` and ``thrust.png`` (with
        ``plots``), and ``segments.json`` for a sequence."""
        from casadi_debris.report import figure_title, write_run

        summary = dataclasses.replace(self.summary, out_dir=str(out.absolute()))
        write_run(
            staging,
            self.result,
            summary,
            self.problem,
            with_plots=plots,
            title=f"{figure_title(self.problem)} ({summary.case_id})",
        )
        if self.segments is not None:
            write_json_atomic(staging / "segments.json", {"segments": list(self.segments)})


def simulate(
    problem: ProblemLike = None,
    *,
    controller: str | Path | None = None,
    allow_mismatch: bool = False,
    corner: int | None = None,
    sample: int | None = None,
    seed: int | None = None,
    parameters: str | Path | None = None,
    duration_s: float | None = None,
    axis: Axis | None = None,
    angle_deg: float | None = None,
    failed: Sequence[int] = (),
) -> SimulationResult:
    """Fly the problem's ``[simulation]`` reference in closed loop.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name (``"paper_slew"``); default the paper.
    controller : str or Path, optional
        A controller file (``controller.json`` of ``design``); default the shipped paper
        controller, which flies only the paper's plant.
    allow_mismatch : bool
        Fly a controller designed for another plant anyway.
    corner, sample, seed : int, optional
        Fly corner ``corner`` (0-based) of the uncertainty set, or random sample
        ``sample`` drawn with ``seed`` (default the problem's ``montecarlo.seed``);
        default the nominal plant.
    parameters : str or Path, optional
        A JSON file ``{"parameters": {name: value}}`` (as ``worstcase`` writes it).
    duration_s : float, optional
        End time [s]; default the problem's.
    axis, angle_deg : optional
        Turn the problem's one slew about ``axis`` (``"x"``, ``"-y"`` or a body vector)
        by ``angle_deg`` [deg] instead.
    failed : sequence of int
        CubeSats failed from the start, by 1-based id, on top of the problem's
        ``[[simulation.failures]]``.

    Returns
    -------
    SimulationResult

    Raises
    ------
    InputShapeError
        An option that does not fit the problem (named).
    ControllerMismatchError
        The controller was designed for another plant (and ``allow_mismatch`` is false).
    """
    problem = _as_asked(as_problem(problem), duration_s, axis, angle_deg, failed)
    from casadi_debris.campaigns import fly_case
    from casadi_debris.guidance import scenario_reference

    record, resolved = controller_for(problem, controller, allow_mismatch=allow_mismatch)
    problem, model, case = _chosen_case(problem, parameters, corner, sample, seed)
    reference = scenario_reference(problem)
    result = fly_case(model, record.reduced, reference, case)
    return SimulationResult(
        problem=problem,
        result=result,
        summary=run_summary(problem, case, result, resolved, record),
        segments=_segment_figures(problem, result, reference),
    )


def _chosen_case(
    problem: Problem,
    parameters: str | Path | None,
    corner: int | None,
    sample: int | None,
    seed: int | None,
) -> tuple[Problem, Model, Case]:
    """The problem, model and case a run flies (``parameters``, ``corner``, ``sample`` or
    the nominal); a case of ``[[montecarlo.vary]]`` that changes keys of the problem file
    flies its own problem and model."""
    from casadi_debris.config import problem_with_values
    from casadi_debris.dynamics import build_model

    model = build_model(problem)
    if parameters is not None:
        if corner is not None or sample is not None:
            raise InputShapeError("give one of --corner, --sample and --parameters")
        case = parameters_case(model, *read_parameters_file(Path(parameters)))
    else:
        case = one_case(model, corner, sample, seed)
    if case.file_values:
        problem = problem_with_values(problem, case.file_values)
        model = build_model(problem)
    return problem, model, case


def read_parameters_file(path: Path) -> tuple[Any, str]:
    """The ``parameters`` mapping of a JSON file and the case id it gives (default its stem)."""
    import json

    from casadi_debris.config import read_regular_file
    from casadi_debris.errors import UnreadableFileError

    try:
        data = json.loads(read_regular_file(path).decode("utf-8"))
    except UnreadableFileError as exc:
        raise InputShapeError(f"--parameters {path}: {exc}") from None
    except (UnicodeDecodeError, ValueError) as exc:
        raise InputShapeError(f"--parameters {path}: not JSON ({exc})") from None
    if not isinstance(data, dict) or "parameters" not in data:
        raise InputShapeError(f"--parameters {path}: expected an object with 'parameters'")
    case_id = data.get("case_id", path.stem)
    return data["parameters"], case_id if isinstance(case_id, str) else path.stem


def _as_asked(
    problem: Problem,
    duration_s: float | None,
    axis: Axis | None,
    angle_deg: float | None,
    failed: Sequence[int],
) -> Problem:
    """``problem`` with the run length, the slew's axis and angle, and the CubeSats failed
    from the start that were asked for."""
    if duration_s is not None:
        problem = with_duration(problem, duration_s, field="--duration-s")
    if axis is not None or angle_deg is not None:
        problem = _with_slew(problem, axis, angle_deg)
    if failed:
        problem = _with_failed(problem, failed)
    return problem


def _segment_figures(
    problem: Problem, result: ClosedLoopResult, reference: Reference
) -> tuple[SegmentRunSummary, ...] | None:
    """Each segment's figures when the problem flies ``[[simulation.segments]]``, else None."""
    if problem.simulation.reference != "sequence":
        return None
    from casadi_debris.simulation import segment_figures

    return tuple(segment_figures(result, reference.pieces))


def _with_slew(problem: Problem, axis: Axis | None, angle_deg: float | None) -> Problem:
    """``problem`` with its one slew turned about ``axis`` by ``angle_deg`` (None: its own).

    The slew keeps its method and timing; a bang-bang timed by its duration keeps the
    torque fraction that duration gives instead (another turn takes another time).
    """
    slew = problem.simulation.slew
    option = "--axis" if axis is not None else "--angle-deg"
    if slew is None:
        flies = (
            "[[simulation.segments]] (edit their targets)"
            if problem.simulation.reference == "sequence"
            else "no slew (give a problem with a [simulation.slew], e.g. paper_slew)"
        )
        raise InputShapeError(f"{option}: {problem.name} flies {flies}")
    turn = Target(
        "rotation",
        axis=slew.axis if axis is None else axis,
        angle_deg=slew.angle_deg if angle_deg is None else angle_deg,
    )
    changed = dataclasses.replace(slew, target=turn)
    if slew.method == "bang-bang" and slew.duration_s is not None and slew.torque_fraction is None:
        # The file's duration sets the share of the authority its slew uses; another turn
        # flies at that share (paper_slew: 0.561), not in that time.
        from casadi_debris.guidance import generate_slew

        fraction = generate_slew(problem, slew, 1.0).settings["torque_fraction"]
        changed = dataclasses.replace(changed, duration_s=None, torque_fraction=fraction)
        # A warning, so that the command shows it: the turn keeps the share, not the time.
        LOGGER.warning(
            "the slew about the new axis flies at %s's torque fraction %.3f", problem.name, fraction
        )
    simulation = dataclasses.replace(problem.simulation, slew=changed)
    # The figures are titled from the description, which told of the file's own slew.
    turned = (
        changed.axis if isinstance(changed.axis, str) else ",".join(f"{v:g}" for v in changed.axis)
    )
    description = f"{changed.angle_deg:g} deg {changed.method} slew about {turned} ({problem.name})"
    return dataclasses.replace(problem, simulation=simulation, description=description)


def _with_failed(problem: Problem, cubesat_ids: Sequence[int]) -> Problem:
    """``problem`` with the CubeSats (1-based ids) failed at time 0, before its own
    failures."""
    count = len(problem.cubesats)
    bad = sorted({i for i in cubesat_ids if not 1 <= i <= count})
    if bad:
        raise InputShapeError(f"--failed: CubeSat ids run from 1 to {count}; got {bad}")
    indices = sorted({i - 1 for i in cubesat_ids})
    events = tuple(FailureEvent(0.0, i, None) for i in indices) + problem.simulation.failures
    ordered = tuple(sorted(events, key=lambda event: event.time_s))
    return dataclasses.replace(
        problem, simulation=dataclasses.replace(problem.simulation, failures=ordered)
    )
