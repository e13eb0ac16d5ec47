"""Where should the CubeSats dock: the placement study, its Pareto sweep, its files.

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.studies.placement_milp import PlacementSettings
>>> from casadi_debris.workflows.placement import run_placement
>>> summary = run_placement(load_problem(), "runs/placement",
...                         PlacementSettings(count=(24, 24)))  # doctest: +SKIP
>>> summary.figures.torque_max_zero_force_mNm["+y"]  # doctest: +SKIP
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from casadi_debris.config import SIGNED_AXES, Problem, load_problem
from casadi_debris.errors import CasadiDebrisError, InputShapeError
from casadi_debris.geometry import build_geometry, torque_authority
from casadi_debris.report.folders import RunFolder, check_output_folder
from casadi_debris.report.placement import PLACEMENT_FILE, write_placement
from casadi_debris.studies.placement import PlacementStudy, optimise_placement
from casadi_debris.studies.placement_candidates import DEFAULT_GRID, face_candidates
from casadi_debris.studies.placement_data import placement_data
from casadi_debris.studies.placement_milp import OBJECTIVES, PlacementSettings
from casadi_debris.studies.placement_pareto import ParetoPoint, pareto_front
from casadi_debris.studies.placement_records import PlacementSummary, placement_summary

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
    expected = np.array([study.metrics.authority_Nm[n] for n in SIGNED_AXES])
    got = np.array([authority[n] for n in SIGNED_AXES])
    if not np.allclose(got, expected, rtol=AUTHORITY_RELATIVE_TOLERANCE, atol=1e-15):
        raise CasadiDebrisError(f"{PLACEMENT_FILE} loads with authority {got} N m, not {expected}")


def run_placement(
    problem: Problem,
    out: str | Path,
    settings: PlacementSettings,
    *,
    grid: tuple[int, int] = DEFAULT_GRID,
    side_engine_options: tuple[int, ...] | None = None,
    pareto_counts: Sequence[int] | None = None,
    overwrite: bool = False,
    progress: Callable[[str], None] | None = None,
) -> PlacementSummary:
    """Optimise the layout, sweep the Pareto front, write the result folder.

    Parameters
    ----------
    problem : Problem
        Loaded from a file (the written ``placement.toml`` extends it).
    out : str or Path
        Results folder (see :class:`~casadi_debris.report.folders.RunFolder`).
    settings : PlacementSettings
    grid : tuple of int
        Candidate mounts per face.
    side_engine_options : tuple of int, optional
        Engine templates per mount.
    pareto_counts : sequence of int, optional
        Counts of the Pareto sweep (none: no sweep).
    overwrite : bool
    progress : callable, optional
        ``progress(line)`` as the Pareto sweep starts (the one long stage).

    Returns
    -------
    PlacementSummary
        What ``summary.json`` holds (its ``to_json``), ``out_dir`` included.
    """
    if not Path(problem.source).is_file():
        raise InputShapeError(f"placement needs a problem loaded from a file; got {problem.source}")
    out = Path(out)
    check_output_folder(out, overwrite=overwrite)
    say = progress or (lambda line: None)
    data = placement_data(problem, face_candidates(problem, grid, side_engine_options))
    study = optimise_placement(problem, settings, data=data)
    points: list[ParetoPoint] = []
    if pareto_counts:
        say(f"Pareto sweep over {len(pareto_counts)} counts")
        points = pareto_front(problem, data, pareto_counts, settings)
    objective = next(name for name, k in OBJECTIVES.items() if k == settings.failures)
    summary = replace(placement_summary(study, objective, points), out_dir=str(out.absolute()))
    with RunFolder.claim(out, overwrite=overwrite, command="placement") as staging:
        write_placement(staging, study, summary, points)
        check_written_layout(staging / PLACEMENT_FILE, study)
    return summary
