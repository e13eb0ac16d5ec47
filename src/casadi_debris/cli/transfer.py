"""``casadi-debris transfer``: the low-thrust orbit transfer with the swarm's staged engines."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import click

from casadi_debris.cli.common import (
    echo_json,
    main,
    problem_argument,
    run_folder,
    run_folder_options,
    say,
)
from casadi_debris.config import load_problem
from casadi_debris.report import format_table


@main.command()
@problem_argument
@click.option(
    "--objective",
    type=click.Choice(["time", "propellant"]),
    default="time",
    show_default=True,
    help="Minimum transfer time, or minimum propellant (throttled, time at most 10 % over the "
    "guidance law's).",
)
@run_folder_options("transfer")
def transfer(
    problem_file: Path | None, objective: str, out: Path | None, overwrite: bool, as_json: bool
) -> None:
    """Plan the problem's [transfer] with the swarm's thrust directions, staging and J2.

    Edelbaum steering flown in closed loop and an optimal control problem, both on
    orbit-averaged equinoctial elements; reports Δv beside Edelbaum's, time,
    propellant, stages per CubeSat, and whether the swarm's own stages suffice
    (if not: how far they get and what more it takes).
    """
    from casadi_debris.workflows import transfer as transfer_job

    problem = load_problem(problem_file)
    folder = run_folder(out, "transfer", problem.name, overwrite)
    planned = transfer_job(problem, objective=objective, progress=say)  # type: ignore[arg-type]
    planned.save(folder, overwrite=overwrite)
    result = dataclasses.replace(planned.summary, out_dir=str(folder.absolute()))
    if as_json:
        echo_json(result)
        return
    rows: list[list[Any]] = [
        ["Edelbaum dv [m/s]", result.edelbaum_dv_m_s],
        ["OCP dv [m/s]", result.transfer_dv_m_s],
        ["OCP time [days]", result.transfer_time_days],
        ["OCP propellant [kg]", result.propellant_kg],
        ["guidance dv [m/s]", result.guidance_dv_m_s],
        ["guidance time [days]", result.guidance_time_days],
        ["own stages: dv [m/s]", result.available_dv_m_s],
        ["own stages: firing time [days]", result.available_time_days],
        ["swarm suffices", "yes" if result.swarm_suffices else "no"],
    ]
    if not result.swarm_suffices:
        rows += [
            ["reached altitude [km]", result.reached_altitude_km],
            ["reached inclination [deg]", result.reached_inclination_deg],
            ["shortfall dv [m/s]", result.shortfall_dv_m_s],
            ["extra stages per CubeSat needed", result.extra_stages_per_cubesat_needed],
            ["extra CubeSats needed", result.extra_cubesats_needed],
        ]
    click.echo(format_table(["figure", "value"], rows))
    click.echo(f"written to {result.out_dir}")
