"""The placement study: the MILP's layout judged beside the input layout (see the
package's text)."""

from __future__ import annotations

from dataclasses import dataclass

from casadi_debris.config import Problem
from casadi_debris.studies.placement._authority import WorstFailures, worst_failures
from casadi_debris.studies.placement._candidates import (
    DEFAULT_GRID,
    Candidate,
    CandidateSet,
    cubesat_template,
    face_candidates,
)
from casadi_debris.studies.placement._data import PlacementData, placement_data
from casadi_debris.studies.placement._metrics import LayoutMetrics, layout_metrics
from casadi_debris.studies.placement._milp import (
    PlacementSettings,
    PlacementSolution,
    solve_placement,
)


@dataclass(frozen=True)
class InputLayout:
    """The input problem's own CubeSats, judged like the chosen layout.

    Attributes
    ----------
    metrics : LayoutMetrics
    among_candidates : tuple of int or None
        The candidates (0-based) that are exactly its CubeSats, or None when some
        CubeSat is not a candidate (then the optimum need not beat it).
    worst : WorstFailures
        Its worst failure set per axis for the study's number of failures.
    """

    metrics: LayoutMetrics
    among_candidates: tuple[int, ...] | None
    worst: WorstFailures


@dataclass(frozen=True)
class PlacementStudy:
    """The chosen layout and the input layout beside it.

    Attributes
    ----------
    problem : Problem
    settings : PlacementSettings
    candidates : CandidateSet
    solution : PlacementSolution
    metrics : LayoutMetrics
        Of the chosen layout, from the toolkit's geometry and budgets.
    input_layout : InputLayout
    """

    problem: Problem
    settings: PlacementSettings
    candidates: CandidateSet
    solution: PlacementSolution
    metrics: LayoutMetrics
    input_layout: InputLayout

    @property
    def chosen(self) -> tuple[Candidate, ...]:
        return tuple(self.candidates.candidates[i] for i in self.solution.chosen)


def own_candidates(problem: Problem) -> CandidateSet:
    """The problem's own CubeSats as candidates, each its own mount."""
    return CandidateSet(
        grid=(0, 0),
        side_engine_options=(),
        template=cubesat_template(problem),
        candidates=tuple(
            Candidate(i, i, cubesat.face or "", 0, cubesat)
            for i, cubesat in enumerate(problem.cubesats)
        ),
    )


def judge_input_layout(
    problem: Problem, candidates: CandidateSet, failures: int, slew_angle_deg: float
) -> InputLayout:
    """The input layout's metrics and worst failures (see :class:`InputLayout`)."""
    own = placement_data(problem, own_candidates(problem))
    chosen = tuple(range(len(problem.cubesats)))
    return InputLayout(
        metrics=layout_metrics(problem, problem.cubesats, slew_angle_deg),
        among_candidates=candidates.match(problem.cubesats),
        worst=worst_failures(own, chosen, failures),
    )


def optimise_placement(
    problem: Problem,
    settings: PlacementSettings,
    grid: tuple[int, int] = DEFAULT_GRID,
    side_engine_options: tuple[int, ...] | None = None,
    data: PlacementData | None = None,
) -> PlacementStudy:
    """Choose where the CubeSats dock (see :func:`solve_placement`) and judge the result.

    Parameters
    ----------
    problem : Problem
        The debris, its CubeSat, its engine and its disturbance.
    settings : PlacementSettings
    grid : tuple of int
        Candidate mounts per face (see :func:`~casadi_debris.studies.placement.face_candidates`).
    side_engine_options : tuple of int, optional
        Engine templates per mount (side-panel engine counts).
    data : PlacementData, optional
        Reused when already built for these candidates.

    Returns
    -------
    PlacementStudy
    """
    if data is None:
        data = placement_data(problem, face_candidates(problem, grid, side_engine_options))
    candidates = data.candidates
    own = candidates.match(problem.cubesats)
    # The input layout, when it is a candidate, is a known answer the search must not lose.
    solution = solve_placement(data, settings, incumbents=[own] if own is not None else [])
    metrics = layout_metrics(problem, candidates.cubesats(solution.chosen), settings.slew_angle_deg)
    return PlacementStudy(
        problem=problem,
        settings=settings,
        candidates=candidates,
        solution=solution,
        metrics=metrics,
        input_layout=judge_input_layout(
            problem, candidates, settings.failures, settings.slew_angle_deg
        ),
    )
