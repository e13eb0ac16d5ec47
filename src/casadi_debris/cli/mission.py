"""``casadi-debris mission``: from the CubeSats' transfer to the debris' re-entry."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from casadi_debris.cli.common import (
    BoundedFloat,
    comma_list,
    echo_json,
    friendly_errors,
    json_option,
    main,
    out_folder_option,
    overwrite_option,
    problem_argument,
    say,
)
from casadi_debris.config import load_problem
from casadi_debris.errors import InputShapeError
from casadi_debris.report.common import format_table
from casadi_debris.report.folders import default_run_folder


@main.command()
@problem_argument
@click.option(
    "--solar",
    default="low,mean,high",
    show_default=True,
    help="Solar-activity cases of the deorbit and decay, comma-separated.",
)
@click.option(
    "--limit-years",
    type=BoundedFloat(0.0, 100.0, low_open=True),
    default=5.0,
    show_default=True,
    help="Re-entry within this long of the deorbit burn's start (FCC: 5).",
)
@out_folder_option("mission")
@overwrite_option
@json_option
@friendly_errors
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
    detumbles the debris in closed loop, then burns what propellant is left to lower the
    orbit (least Δv per solar case, NRLMSIS), then the debris decays. Writes
    summary.json, phases.csv, propellant.csv, mission.png and decay.png.
    """
    from casadi_debris.orbit.atmosphere import SOLAR_CASES
    from casadi_debris.orbit.deorbit import DeorbitSettings
    from casadi_debris.workflows.mission import mission_into

    cases = comma_list(solar, "--solar", "low,mean,high")
    if [c for c in cases if c not in SOLAR_CASES] or len(set(cases)) != len(cases):
        raise InputShapeError(
            f"--solar: distinct cases among {', '.join(SOLAR_CASES)}, got {solar!r}"
        )
    problem = load_problem(problem_file)
    folder = out or default_run_folder("mission", problem.name)
    settings = DeorbitSettings(
        solar=tuple(cases), limit_years=limit_years, minimum_swarm=False, samples=0
    )
    say(f"Mission of {problem.name}: transfer, detumble, deorbit, decay ...")
    summary = mission_into(problem, folder, settings=settings, overwrite=overwrite)
    if as_json:
        echo_json(summary)
        return
    rows: list[list[Any]] = [
        [p.name, p.start_days, p.duration_days, p.dv_m_s, p.propellant_kg] for p in summary.phases
    ]
    click.echo(
        format_table(["phase", "start [d]", "duration [d]", "dv [m/s]", "propellant [kg]"], rows)
    )
    for case, years in summary.reentry_years.items():
        need = summary.deorbit_dv_needed_m_s[case]
        when = "beyond the horizon" if years is None else f"{years:.2f} years"
        click.echo(f"{case} solar activity: needs {need:.1f} m/s, re-enters in {when}")
    verdict = "meets" if summary.meets_five_year_rule else "does NOT meet"
    left, capacity = summary.deorbit_dv_available_m_s, summary.deorbit_dv_capacity_m_s
    click.echo(
        f"{verdict} the {summary.limit_years:g}-year rule; deorbit Δv left after transfer and "
        f"detumble {left:.1f} of {capacity:.1f} m/s"
    )
    click.echo(f"written to {folder.absolute()}")
