"""``casadi-debris mission``: from the CubeSats' transfer to the debris' re-entry."""

from __future__ import annotations

from pathlib import Path

import click

from casadi_debris.cli.common import (
    echo_json,
    main,
    problem_argument,
    run_folder,
    run_folder_options,
    say,
)
from casadi_debris.cli.deorbit import limit_years_option, solar_cases, solar_option
from casadi_debris.config import load_problem


@main.command()
@problem_argument
@solar_option
@limit_years_option
@run_folder_options("mission")
def mission(
    problem_file: Path | None,
    solar: str,
    limit_years: float,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    """The mission to re-entry: transfer, detumble, deorbit burns, decay; the five-year verdict.

    Each CubeSat flies the [transfer] alone (Edelbaum, rocket equation), then the swarm
    detumbles the debris in closed loop, then burns what propellant is left, engine by
    engine, to lower the orbit (least Δv per solar case, NRLMSIS, torque-free thrust),
    then the debris decays. Writes summary.json, phases.csv, propellant.csv (per CubeSat
    and stage), mission.png, altitude.png and decay.png (and each figure as PDF).
    """
    from casadi_debris.report import mission_text
    from casadi_debris.workflows import mission as mission_job

    cases = solar_cases(solar)
    problem = load_problem(problem_file)
    folder = run_folder(out, "mission", problem.name, overwrite)
    result = mission_job(problem, solar=cases, limit_years=limit_years, progress=say)
    result.save(folder, overwrite=overwrite)
    if as_json:
        echo_json(result.summary)
        return
    click.echo(mission_text(result.summary, result.horizon_years))
    click.echo(f"written to {folder.absolute()}")
