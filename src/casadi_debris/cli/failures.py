"""``casadi-debris failures``: which sets of failed CubeSats (and lost stages) a swarm survives."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from casadi_debris.cli.common import (
    batch_option,
    controller_options,
    echo_json,
    is_quiet,
    main,
    no_jit_option,
    problem_argument,
    run_folder,
    run_folder_options,
    say,
    workers_option,
)
from casadi_debris.config import load_problem
from casadi_debris.errors import InputShapeError
from casadi_debris.report import format_table

if TYPE_CHECKING:
    from casadi_debris.studies.failures import FailuresSummary

_MET = {True: "yes", False: "no", None: "—"}
SHOWN = 10
"""Worst cases the text output lists."""
MAX_CORNERS = 2048
"""Corner plants a set may fly at most (the largest corner set of a problem)."""


def _progress(as_json: bool) -> Any:
    """Each stage on stderr, with a counter of its runs (not with ``--json`` or ``-q``)."""
    from casadi_debris.cli.simulate import cases_progress

    def progress(stage: str) -> Any:
        if as_json or is_quiet():
            return None
        say(stage)
        return cases_progress("  runs") if "plant" in stage or "corners" in stage else None

    return progress


def _text(summary: FailuresSummary) -> str:
    rows = []
    for case in summary.cases[:SHOWN]:
        torque = case.torque_max_zero_force_mNm
        runs = case.closed_loop.nominal
        rows.append(
            [
                " ".join(map(str, case.failed)) or "—",
                " ".join(map(str, case.failed_stage)) or "—",
                f"{min(torque.values()):.3g} ({min(torque, key=torque.__getitem__)})",
                f"{case.worst_ratio:.3g}",
                *(
                    f"{runs[m].error:.4g}" if m in runs and runs[m].error is not None else "—"
                    for m in ("slew", "pointing")
                ),
                _MET[case.closed_loop.met],
            ]
        )
    headers = [
        "failed",
        "stage of",
        "least authority [mNm]",
        "/ disturbance",
        "slew error [deg]",
        "pointing [arcsec]",
        "met",
    ]
    verdict = (
        f"{summary.cases_met} of {summary.case_count} cases meet the requirements; "
        if summary.manoeuvres
        else ""
    )
    return (
        format_table(headers, rows)
        + f"\n{verdict}{summary.case_count} cases written to {summary.out_dir} "
        f"({summary.wall_time_s:.0f} s)"
    )


@main.command()
@problem_argument
@click.option(
    "--max-failed",
    type=int,
    default=2,
    show_default=True,
    help="Largest number of CubeSats failed at once (every set of 1 .. N).",
)
@click.option(
    "--stages/--no-stages",
    default=True,
    show_default=True,
    help="Also a case per CubeSat that loses its first stage (the next takes over).",
)
@click.option(
    "--closed-loop/--no-closed-loop",
    default=True,
    show_default=True,
    help="Fly the problem's slew and pointing run for every case (nominal plant).",
)
@click.option(
    "--corner-sets",
    type=click.IntRange(0),
    default=3,
    show_default=True,
    help="The N worst cases also fly corners of the uncertainty set (0: none).",
)
@click.option(
    "--max-corners",
    type=click.IntRange(1, MAX_CORNERS),
    default=None,
    help="Corners each of those flies, spread evenly over the set [16; 4 with --quick].",
)
@click.option(
    "--quick",
    is_flag=True,
    help="Fewer corners (4). The pointing run is one whole disturbance period either way.",
)
@controller_options
@workers_option
@no_jit_option
@batch_option
@run_folder_options("failures")
def failures(
    problem_file: Path | None,
    max_failed: int,
    stages: bool,
    closed_loop: bool,
    corner_sets: int,
    max_corners: int | None,
    quick: bool,
    controller: Path | None,
    allow_mismatch: bool,
    workers: int,
    no_jit: bool,
    batch_cases: int,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Every set of up to --max-failed failed CubeSats (and a lost stage per CubeSat): torque
    authority left per signed axis, whether the slew and pointing still meet the problem's
    [requirements] in closed loop, fuel and time to first depletion; ranked, the worst first.
    Writes summary.json, cases.csv, report.md, reallocation.csv and authority_loss.png."""
    problem = load_problem(problem_file)
    count = len(problem.cubesats)
    if not 1 <= max_failed <= count:
        raise InputShapeError(
            f"--max-failed: between 1 and {count} (the problem's CubeSats); got {max_failed}"
        )
    folder = run_folder(out, "failures", problem.name, overwrite)
    from casadi_debris.workflows import failures as study_failures

    result = study_failures(
        problem,
        max_failed=max_failed,
        stages=stages,
        closed_loop=closed_loop,
        corner_sets=corner_sets,
        max_corners=max_corners,
        quick=quick,
        controller=controller,
        allow_mismatch=allow_mismatch,
        workers=workers,
        no_jit=no_jit,
        batch_cases=batch_cases,
        progress=_progress(as_json),
    )
    result.save(folder, overwrite=overwrite)
    summary = dataclasses.replace(result.summary, out_dir=str(folder.absolute()))
    if as_json:
        echo_json(summary)
    else:
        click.echo(_text(summary))
