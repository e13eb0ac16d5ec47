"""``casadi-debris export``: the flight step of a problem and a controller as C99."""

from __future__ import annotations

from pathlib import Path

import click

from casadi_debris.cli.common import (
    controller_options,
    echo_json,
    main,
    out_folder_option,
    output_options,
    problem_argument,
    run_folder,
)
from casadi_debris.config import load_problem


@main.command()
@problem_argument
@controller_options
@out_folder_option("export")
@output_options
def export(
    problem_file: Path | None,
    controller: Path | None,
    allow_mismatch: bool,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Write the flight step as portable C99: reference, attitude error, discrete
    controller and least-fuel allocator, one call per control period, with a Makefile,
    CMakeLists.txt, a CSV replay harness (main.c), README.md and manifest.json."""
    from casadi_debris.workflows import export as export_job

    problem = load_problem(problem_file)
    folder = run_folder(out, "export", problem.name, overwrite)
    exported = export_job(
        problem,
        controller=controller,
        allow_mismatch=allow_mismatch,
        out=folder,
        overwrite=overwrite,
    )
    summary = exported.summary
    if as_json:
        echo_json(summary)
        return
    click.echo(f"flight step of {summary.problem} written to {summary.out_dir}")
    click.echo(f"  controller      {summary.controller_file}")
    click.echo(
        f"  period          {summary.period_s} s, {summary.controller_states} controller states"
    )
    click.echo(
        f"  engines         {summary.engines} on {summary.cubesats} CubeSats, "
        f"{summary.stages} stages"
    )
    click.echo(
        f"  reference       {summary.reference_rows} rows, held after {summary.reference_end_s} s"
    )
    click.echo(f"  build           make -C {summary.out_dir}  (see README.md)")
