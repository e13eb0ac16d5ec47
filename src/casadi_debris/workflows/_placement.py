"""Where should the CubeSats dock: the placement study, its Pareto sweep, its files
(``casadi-debris placement``).

Example
-------
>>> import casadi_debris as cd
>>> result = cd.placement("paper", count=24, candidates=(3, 3))  # doctest: +SKIP
>>> result.summary.figures.worst_ratio, result.summary.solver.gap  # doctest: +SKIP
>>> result.save("runs/placement-paper")  # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Literal

import numpy as np

from casadi_debris.config import Problem, load_problem
from casadi_debris.errors import CasadiDebrisError, InputShapeError
from casadi_debris.geometry import build_geometry, torque_authority
from casadi_debris.report import PLACEMENT_FILE, placement_figures, write_placement
from casadi_debris.studies.placement import (
    DEFAULT_GRID,
    OBJECTIVES,
    CandidateSet,
    ParetoPoint,
    PlacementSettings,
    PlacementStudy,
    PlacementSummary,
    face_candidates,
    optimise_placement,
    pareto_front,
    placement_data,
    placement_summary,
)
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure

LOGGER = logging.getLogger(__name__)
AUTHORITY_RELATIVE_TOLERANCE = 1e-9


def default_pareto_counts(most: int) -> list[int]:
    """Every fourth count from 8 up to ``most`` (and ``most``)."""
    return sorted({*range(8, most + 1, 4), most})


def check_written_layout(path: Path, study: PlacementStudy) -> None:
    """Load the written problem file and check that it has the study's authority.

    Raises
    ------
    CasadiDebrisError
        When the file does not load (e.g. the input problem schedules failures of
        CubeSats the layout does not have) or its authority differs.
    """
    try:
        placed = load_problem(path)
    except CasadiDebrisError as exc:
        raise InputShapeError(f"{PLACEMENT_FILE} would not load: {exc}") from None
    authority = torque_authority(build_geometry(placed), zero_net_force=True)
    expected = study.metrics.authority_Nm.torque_Nm
    got = authority.torque_Nm
    if not np.allclose(got, expected, rtol=AUTHORITY_RELATIVE_TOLERANCE, atol=1e-15):
        raise CasadiDebrisError(f"{PLACEMENT_FILE} loads with authority {got} N m, not {expected}")


@dataclass(frozen=True)
class PlacementResult(JobResult):
    """A placement study: the chosen layout, the input layout beside it, the sweep.

    Attributes
    ----------
    summary : PlacementSummary
        What ``summary.json`` holds: both layouts' figures, the solver's status, the
        sweep.
    study : PlacementStudy
        The candidates, the MILP's solution and the chosen layout's metrics.
    pareto : tuple of ParetoPoint
        The sweep's points (empty without a sweep).
    """

    summary: PlacementSummary
    study: PlacementStudy
    pareto: tuple[ParetoPoint, ...] = ()

    command = "placement"

    def plot(self) -> dict[str, Figure]:
        """``layout`` (the hub in three projections with the chosen CubeSats) and, after a
        sweep, ``pareto``; nothing is written."""
        return placement_figures(self.study, list(self.pareto))

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``placement.toml`` (checked to load with the study's authority),
        ``summary.json``, ``report.md`` and, with ``plots``, ``layout.png`` (and
        ``pareto.png``)."""
        summary = dataclasses.replace(self.summary, out_dir=str(out.absolute()))
        write_placement(staging, self.study, summary, list(self.pareto), plots=plots)
        check_written_layout(staging / PLACEMENT_FILE, self.study)


Objective = Literal["worst-axis", "worst-single-failure", "worst-double-failure"]


def placement(
    problem: ProblemLike = None,
    *,
    count: int | None = None,
    count_range: tuple[int, int] | None = None,
    candidates: int | tuple[int, int] = DEFAULT_GRID,
    side_engines: Sequence[int] | None = None,
    objective: Objective = "worst-axis",
    max_added_inertia: float | Sequence[float] | None = None,
    max_slew_s: float | None = None,
    min_per_face: int = 0,
    pareto_counts: Sequence[int] | Literal["auto"] | None = None,
    time_limit: float = 600.0,
    progress: Callable[[str], None] | None = None,
) -> PlacementResult:
    """Choose where the CubeSats dock among candidate mounts on the hub faces.

    Maximises the worst signed axis's zero-net-force torque authority over the
    disturbance (optionally over all single or double CubeSat failures), exactly, as a
    mixed-integer programme (HiGHS).

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem loaded from a file or a shipped name (the written ``placement.toml``
        extends it); default the paper.
    count : int, optional
        CubeSats to place; default 24.
    count_range : tuple of 2 int, optional
        Least and most CubeSats instead of ``count``.
    candidates : int or tuple of 2 int
        Mounts per face along its two in-face axes (x, y, z order); an int is square.
    side_engines : sequence of int, optional
        Engine templates offered per mount, as side-panel engine counts among 0, 2, 4;
        default the problem layout's.
    objective : {"worst-axis", "worst-single-failure", "worst-double-failure"}
        The worst signed axis nominal, or over all single or double CubeSat failures.
    max_added_inertia : float or sequence of float, optional
        Limit on the CubeSats' inertia about the bare debris' CoG [kg m^2]: one for every
        axis, or three (x, y, z).
    max_slew_s : float, optional
        Limit on the rigid 180 deg bang-bang slew time about every body axis [s].
    min_per_face : int
        CubeSats on every face at least.
    pareto_counts : sequence of int or "auto", optional
        Sweep the Pareto front over these counts (``"auto"``: 8, 12, ... up to the most
        CubeSats); one MILP per point.
    time_limit : float
        Seconds for the MILP (each one of the sweep too).
    progress : callable, optional
        ``progress(line)`` as the Pareto sweep starts (the one long stage).

    Returns
    -------
    PlacementResult

    Raises
    ------
    InputShapeError
        A setting out of range (named), or a problem not loaded from a file.
    """
    problem = as_problem(problem)
    if not Path(problem.source).is_file():
        raise InputShapeError(f"placement needs a problem loaded from a file; got {problem.source}")
    limits = _count_limits(count, count_range)
    settings = _settings(limits, objective, max_added_inertia, max_slew_s, min_per_face, time_limit)
    counts = _pareto_counts(pareto_counts, limits[1])
    data = placement_data(problem, _candidates(problem, candidates, side_engines))
    study = optimise_placement(problem, settings, data=data)
    points: list[ParetoPoint] = []
    if counts:
        (progress or LOGGER.info)(f"Pareto sweep over {len(counts)} counts")
        points = pareto_front(problem, data, counts, settings)
    summary = placement_summary(study, objective, points)
    return PlacementResult(summary=summary, study=study, pareto=tuple(points))


MAX_COUNT = 256


def _candidates(
    problem: Problem, grid: int | tuple[int, int], side_engines: Sequence[int] | None
) -> CandidateSet:
    """The candidate mounts: ``grid`` per face (an int is square), each offered with the
    engine templates ``side_engines`` asks for (default the problem layout's)."""
    rows, columns = (grid, grid) if isinstance(grid, int) else grid
    sides = None if side_engines is None else _side_engines(side_engines)
    return face_candidates(problem, (rows, columns), sides)


def _settings(
    count: tuple[int, int],
    objective: str,
    max_added_inertia: float | Sequence[float] | None,
    max_slew_s: float | None,
    min_per_face: int,
    time_limit: float,
) -> PlacementSettings:
    """The MILP's settings from the job's keywords, the objective checked by name."""
    if objective not in OBJECTIVES:
        raise InputShapeError(f"objective: one of {', '.join(OBJECTIVES)}; got {objective!r}")
    return PlacementSettings(
        count=count,
        failures=OBJECTIVES[objective],
        max_added_inertia_kgm2=_inertia(max_added_inertia),
        max_slew_s=max_slew_s,
        min_per_face=min_per_face,
        time_limit_s=time_limit,
    )


MAX_INERTIA_KGM2 = 1e6


def _count_limits(count: int | None, count_range: tuple[int, int] | None) -> tuple[int, int]:
    """``count`` or ``count_range`` (default 24) as (least, most)."""
    if count is not None and count_range is not None:
        raise InputShapeError("--count and --count-range: give one of them")
    if count_range is None:
        return (count, count) if count is not None else (24, 24)
    low, high = count_range
    if not 1 <= low <= high <= MAX_COUNT:
        raise InputShapeError(f"--count-range: 1 <= A <= B <= {MAX_COUNT}; got {low}:{high}")
    return low, high


def _inertia(value: float | Sequence[float] | None) -> tuple[float, float, float] | None:
    """``max_added_inertia`` as one limit per axis [kg m^2]."""
    if value is None:
        return None
    values = [float(value)] if isinstance(value, int | float) else [float(v) for v in value]
    values = values * 3 if len(values) == 1 else values
    if len(values) != 3 or not all(0.0 < v <= MAX_INERTIA_KGM2 for v in values):
        raise InputShapeError(
            f"--max-added-inertia: one or three numbers in (0, {MAX_INERTIA_KGM2:g}] kg m^2; "
            f"got {value!r}"
        )
    return values[0], values[1], values[2]


def _side_engines(counts: Sequence[int]) -> tuple[int, ...]:
    """The engine templates per mount, each a side-panel engine count among 0, 2, 4."""
    if not counts or not all(c in (0, 2, 4) for c in counts):
        raise InputShapeError(f"--side-engines: counts among 0, 2, 4; got {list(counts)}")
    return tuple(int(c) for c in counts)


def _pareto_counts(counts: Sequence[int] | str | None, most: int) -> list[int] | None:
    """The sweep's counts: given, or every fourth from 8 up to ``most`` for ``"auto"``."""
    if counts is None:
        return None
    if isinstance(counts, str):
        if counts != "auto":
            raise InputShapeError(f"--pareto: counts or 'auto'; got {counts!r}")
        return default_pareto_counts(most)
    if not counts or not all(1 <= c <= MAX_COUNT for c in counts):
        raise InputShapeError(f"--pareto: counts from 1 to {MAX_COUNT}; got {list(counts)}")
    return [int(c) for c in counts]
