"""The Pareto front of count, worst authority, rigid slew time and Δv per direction.

For each count the best worst-axis layout is found (no failures), then again
with the rigid slew time held below shrinking fractions of that layout's (the
epsilon-constraint method, :func:`~casadi_debris.studies.placement.slew_rows`) until no layout
meets the limit, and again with at least 1, 2, ... CubeSats on every face (the
one-stage Δv along every direction grows with the weakest face's count).
Every layout found, and the input problem's own, is judged by
:func:`~casadi_debris.studies.placement.layout_metrics`; a layout is on the front when no
other is at least as good in all four figures (fewer or as many CubeSats, as
much worst authority over disturbance, as short a slowest-axis slew, as much
one-stage Δv along the weakest direction) and better in one.
"""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import SIGNED_AXES, Problem
from casadi_debris.errors import InputShapeError
from casadi_debris.studies.placement._data import PlacementData
from casadi_debris.studies.placement._metrics import LayoutMetrics, layout_metrics
from casadi_debris.studies.placement._milp import PlacementSettings, solve_placement

LOGGER = logging.getLogger(__name__)

SLEW_FRACTIONS = (0.98, 0.95, 0.9, 0.8)
"""Slew-time limits, as fractions of each count's best-authority layout's slew time."""
MAX_PER_FACE = 4
"""Least CubeSats per face swept up to this (or the count over six)."""
RELATIVE_TOLERANCE = 1e-9


@dataclass(frozen=True)
class ParetoPoint:
    """One layout of the sweep.

    Attributes
    ----------
    label : str
        ``"N=<count>"``, ``"N=<count>, slew <= <limit> s"`` or ``"input"``.
    chosen : tuple of int or None
        Candidates (0-based); None for the input layout when it is not among them.
    metrics : LayoutMetrics
    max_slew_s : float or None
        The slew limit it was found under.
    optimal : bool
        Its MILP proved optimality (True for the input layout: nothing was solved).
    on_front : bool
    """

    label: str
    chosen: tuple[int, ...] | None
    metrics: LayoutMetrics
    max_slew_s: float | None
    optimal: bool
    on_front: bool = False

    def figures(self) -> np.ndarray:
        """(count, -worst ratio, slowest slew, -weakest Δv): smaller is better in each."""
        m = self.metrics
        return np.array([m.count, -m.worst_ratio, m.slowest_slew_s, -m.weakest_dv_m_s])


def dominates(a: np.ndarray, b: np.ndarray) -> bool:
    """``a`` no worse than ``b`` in every figure and better in one (smaller is better)."""
    scale = np.maximum(np.abs(a), np.abs(b)) * RELATIVE_TOLERANCE + RELATIVE_TOLERANCE
    return bool(np.all(a <= b + scale) and np.any(a < b - scale))


def mark_front(points: Sequence[ParetoPoint]) -> list[ParetoPoint]:
    """The points with ``on_front`` set (see the module)."""
    figures = [p.figures() for p in points]
    return [
        dataclasses.replace(
            p, on_front=not any(dominates(other, own) for other in figures if other is not own)
        )
        for p, own in zip(points, figures, strict=True)
    ]


def _point(
    problem: Problem, data: PlacementData, settings: PlacementSettings, label: str
) -> ParetoPoint | None:
    """The best layout under ``settings``, or None when no layout meets them."""
    try:
        solution = solve_placement(data, settings)
    except InputShapeError:
        return None
    metrics = layout_metrics(
        problem, data.candidates.cubesats(solution.chosen), settings.slew_angle_deg
    )
    return ParetoPoint(label, solution.chosen, metrics, settings.max_slew_s, solution.optimal)


def _count_points(
    problem: Problem,
    data: PlacementData,
    count: int,
    base: PlacementSettings,
    fractions: Sequence[float],
) -> list[ParetoPoint]:
    """The count's best layout, then under slew limits, then with CubeSats on every face."""
    settings = dataclasses.replace(
        base, count=(count, count), failures=0, max_slew_s=None, min_per_face=0
    )
    best = _point(problem, data, settings, f"N={count}")
    if best is None:
        return []
    slew_limited = [
        (
            f"N={count}, slew <= {f * best.metrics.slowest_slew_s:.0f} s",
            dataclasses.replace(settings, max_slew_s=f * best.metrics.slowest_slew_s),
        )
        for f in fractions
        if np.isfinite(best.metrics.slowest_slew_s)
    ]
    spread = [
        (f"N={count}, >= {least} per face", dataclasses.replace(settings, min_per_face=least))
        for least in range(1, min(MAX_PER_FACE, count // len(SIGNED_AXES)) + 1)
    ]
    return [best, *_tightening(problem, data, slew_limited), *_tightening(problem, data, spread)]


def _tightening(
    problem: Problem, data: PlacementData, variants: list[tuple[str, PlacementSettings]]
) -> list[ParetoPoint]:
    """The best layout under each of ever tighter settings, until none meets them."""
    points = []
    for label, settings in variants:
        point = _point(problem, data, settings, label)
        if point is None:
            break
        points.append(point)
    return points


def pareto_front(
    problem: Problem,
    data: PlacementData,
    counts: Sequence[int],
    base: PlacementSettings,
    fractions: Sequence[float] = SLEW_FRACTIONS,
) -> list[ParetoPoint]:
    """Every layout of the sweep and the input layout, front members marked.

    Parameters
    ----------
    problem : Problem
    data : PlacementData
        The candidates.
    counts : sequence of int
        CubeSat counts to sweep.
    base : PlacementSettings
        Gap, time limit, slew angle and added-inertia limit (count, failures and
        slew limit are set per point).
    fractions : sequence of float
        Slew limits per count (see :data:`SLEW_FRACTIONS`).

    Returns
    -------
    list of ParetoPoint
        The input layout last.
    """
    points: list[ParetoPoint] = []
    for count in counts:
        LOGGER.info("Pareto sweep: %d CubeSats", count)
        points.extend(_count_points(problem, data, count, base, fractions))
    own = layout_metrics(problem, problem.cubesats, base.slew_angle_deg)
    points.append(ParetoPoint("input", data.candidates.match(problem.cubesats), own, None, True))
    return mark_front(points)
