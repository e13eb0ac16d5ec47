"""``casadi-debris export``: the flight step of a problem and a controller as C99."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

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

if TYPE_CHECKING:
    from casadi_debris.workflows import FmuExportResult


@main.command()
@problem_argument
@controller_options
@click.option(
    "--fmu",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Write the plant (hub, arrays, engines) as this FMI 2.0 co-simulation .fmu "
    "instead of the flight step.",
)
@out_folder_option("export")
@output_options
def export(
    problem_file: Path | None,
    controller: Path | None,
    allow_mismatch: bool,
    fmu: Path | None,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Write the flight step as portable C99: reference, attitude error, discrete
    controller and least-fuel allocator, one call per control period, with a Makefile,
    CMakeLists.txt, a CSV replay harness (main.c), README.md and manifest.json.
    With --fmu, write the debris itself as an FMU for other simulators."""
    from casadi_debris.workflows import export as export_job

    problem = load_problem(problem_file)
    if fmu is not None:
        plant = export_job(problem, controller=controller, fmu=fmu, out=out, overwrite=overwrite)
        _echo_fmu(plant, as_json=as_json)
        return
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


def _echo_fmu(plant: FmuExportResult, *, as_json: bool) -> None:
    """What ``export --fmu`` prints."""
    summary = plant.summary
    if as_json:
        echo_json(summary)
        return
    click.echo(
        f"FMU of {summary.problem} written to {summary.path} "
        f"(FMI {summary.fmi_version} {summary.fmi_type}, {summary.size_bytes} bytes)"
    )
    click.echo(
        f"  plant           {summary.states} states, {summary.engines} engines, "
        f"{summary.modes} modes"
    )
    click.echo(
        f"  variables       {len(summary.inputs)} inputs, {len(summary.outputs)} outputs, "
        f"{len(summary.parameters)} parameters"
    )
    click.echo(f"  integrator      RK4, sub-steps of at most {summary.max_step_s} s")
    click.echo(f"  binary          {summary.platform or 'none (sources only)'}")
