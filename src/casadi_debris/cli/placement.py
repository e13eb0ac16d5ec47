"""``casadi-debris placement``: where the CubeSats should dock, as a mixed-integer programme."""

from __future__ import annotations

import contextlib
import dataclasses
import os
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import click

from casadi_debris.cli.common import (
    BoundedFloat,
    comma_list,
    echo_json,
    main,
    problem_argument,
    run_folder,
    run_folder_options,
    say,
)
from casadi_debris.config import load_problem
from casadi_debris.errors import InputShapeError
from casadi_debris.report import format_table

if TYPE_CHECKING:
    from casadi_debris.studies.placement import PlacementSummary

OBJECTIVE_NAMES = ("worst-axis", "worst-single-failure", "worst-double-failure")


def parse_count_range(text: str | None) -> tuple[int, int] | None:
    """``--count-range A:B`` as (A, B); the job checks 1 <= A <= B."""
    if text is None:
        return None
    try:
        low, high = (int(p) for p in text.split(":"))
    except ValueError:
        raise InputShapeError(f"--count-range: A:B with whole numbers; got {text!r}") from None
    return low, high


def parse_inertia(text: str | None) -> tuple[float, ...] | None:
    """``--max-added-inertia V`` or ``Vx,Vy,Vz`` [kg m^2] as numbers (the job checks them)."""
    if text is None:
        return None
    parts = comma_list(text, "--max-added-inertia", "40 or 200,40,200")
    try:
        values = tuple(float(p) for p in parts)
    except ValueError:
        raise InputShapeError(f"--max-added-inertia: numbers in kg m^2; got {text!r}") from None
    if len(values) not in (1, 3):
        raise InputShapeError(f"--max-added-inertia: one or three numbers; got {text!r}")
    return values


@main.command()
@problem_argument
@click.option("--count", type=click.IntRange(1, 256), default=None, help="CubeSats [24].")
@click.option("--count-range", default=None, help="Least and most CubeSats, A:B.")
@click.option(
    "--candidates",
    default="4x4",
    show_default=True,
    help="Mounts per face along its two in-face axes (x, y, z order), RxC or N.",
)
@click.option(
    "--side-engines",
    default=None,
    help="Engine templates offered per mount: side-panel engine counts, e.g. 0,2 "
    "[the problem layout's].",
)
@click.option(
    "--objective",
    type=click.Choice(OBJECTIVE_NAMES),
    default="worst-axis",
    show_default=True,
    help="Worst signed axis nominal, or over all single or double CubeSat failures.",
)
@click.option(
    "--max-added-inertia",
    default=None,
    help="Limit on the CubeSats' inertia about the bare debris' CoG, kg m^2: V or Vx,Vy,Vz.",
)
@click.option(
    "--max-slew-s",
    type=BoundedFloat(0.0, 1e9, low_open=True),
    default=None,
    help="Limit on the rigid 180 deg bang-bang slew time about every body axis [s].",
)
@click.option(
    "--min-per-face",
    type=click.IntRange(0, 256),
    default=0,
    show_default=True,
    help="CubeSats on every face at least.",
)
@click.option(
    "--pareto",
    "pareto_counts",
    default=None,
    help="Sweep the Pareto front over these counts (comma-separated, or 'auto': "
    "8, 12, ... up to the count); slow: one MILP per point.",
)
@click.option(
    "--time-limit",
    type=BoundedFloat(0.0, 86400.0, low_open=True),
    default=600.0,
    show_default=True,
    help="Seconds for the MILP (each one of the sweep too).",
)
@run_folder_options("placement")
def placement(
    problem_file: Path | None,
    count: int | None,
    count_range: str | None,
    candidates: str,
    side_engines: str | None,
    objective: str,
    max_added_inertia: str | None,
    max_slew_s: float | None,
    min_per_face: int,
    pareto_counts: str | None,
    time_limit: float,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Choose where N CubeSats dock among candidate mounts on the hub faces, to maximise
    the worst signed axis's zero-net-force torque authority over the disturbance (optionally
    over all single or double CubeSat failures), exactly as a mixed-integer programme
    (HiGHS). Writes placement.toml (a problem file extending PROBLEM.toml with the chosen
    [[cubesats]]), summary.json, report.md and layout.png (pareto.png with --pareto)."""
    from casadi_debris.studies.placement import parse_grid
    from casadi_debris.workflows import placement as placement_job

    sides = None
    if side_engines is not None:
        parts = comma_list(side_engines, "--side-engines", "0,2")
        if not all(p in ("0", "2", "4") for p in parts):
            raise InputShapeError(f"--side-engines: counts among 0, 2, 4; got {side_engines!r}")
        sides = tuple(int(p) for p in parts)
    counts: list[int] | str | None = None
    if pareto_counts is not None:
        counts = (
            "auto"
            if pareto_counts == "auto"
            else [_count(p) for p in comma_list(pareto_counts, "--pareto", "8,16,24")]
        )
    problem = load_problem(problem_file)
    folder = run_folder(out, "placement", problem.name, overwrite)
    with solver_chatter_to_stderr():
        result = placement_job(
            problem,
            count=count,
            count_range=parse_count_range(count_range),
            candidates=parse_grid(candidates),
            side_engines=sides,
            objective=objective,  # type: ignore[arg-type]  # click.Choice checked it
            max_added_inertia=parse_inertia(max_added_inertia),
            max_slew_s=max_slew_s,
            min_per_face=min_per_face,
            pareto_counts=counts,  # type: ignore[arg-type]  # "auto" or counts
            time_limit=time_limit,
            progress=None if as_json else say,
        )
        result.save(folder, overwrite=overwrite)
    summary = dataclasses.replace(result.summary, out_dir=str(folder.absolute()))
    if as_json:
        echo_json(summary)
        return
    _print_summary(summary)


@contextlib.contextmanager
def solver_chatter_to_stderr() -> Iterator[None]:
    """Send what C code prints to standard output (HiGHS does, at times) to stderr instead,
    so that ``--json`` stays clean."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        os.dup2(2, 1)
        yield
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)


def _count(text: str) -> int:
    if not text.isdigit() or not 1 <= int(text) <= 256:
        raise InputShapeError(f"--pareto: counts from 1 to 256 or 'auto'; got {text!r}")
    return int(text)


def _print_summary(summary: PlacementSummary) -> None:
    from casadi_debris.report import failure_label

    chosen, own = summary.figures, summary.input_layout.figures
    worst, own_worst = summary.worst_failure, summary.input_layout.worst_failure
    rows: list[list[object]] = [
        ["CubeSats", chosen.count, own.count],
        ["worst axis", chosen.worst_axis, own.worst_axis],
        ["worst authority / disturbance", chosen.worst_ratio, own.worst_ratio],
        ["slowest rigid slew [s]", chosen.slowest_slew_s, own.slowest_slew_s],
        [
            "weakest one-stage Δv [m/s]",
            chosen.weakest_dv_one_stage_m_s,
            own.weakest_dv_one_stage_m_s,
        ],
    ]
    if worst.failures:  # with none failed it is the row above
        rows.insert(3, [failure_label(worst.failures), worst.worst_ratio, own_worst.worst_ratio])
    click.echo(format_table(["", "chosen", "input layout"], rows))
    solver = summary.solver
    status = "optimal" if solver.optimal else "NOT proven optimal"
    click.echo(f"MILP: {status}, gap {solver.gap:.3g}, {solver.time_s:.1f} s ({solver.method})")
    click.echo(f"written to {summary.out_dir} (placement.toml, report.md)")
