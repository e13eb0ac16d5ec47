"""``casadi-debris mission``: from the CubeSats' transfer to the debris' re-entry."""

from __future__ import annotations

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
from casadi_debris.cli.deorbit import limit_years_option, solar_cases, solar_option
from casadi_debris.config import load_problem
from casadi_debris.report.common import format_table


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
    from casadi_debris.orbit.deorbit import DeorbitSettings
    from casadi_debris.workflows.mission import mission_into

    cases = solar_cases(solar)
    from casadi_debris.config.checks import check_transfer_end

    problem = load_problem(problem_file)
    check_transfer_end(problem)
    folder = run_folder(out, "mission", problem.name, overwrite)
    settings = DeorbitSettings(solar=cases, limit_years=limit_years, minimum_swarm=False, samples=0)
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
        needs = "no Δv up to the search bound" if need is None else f"{need:.1f} m/s"
        click.echo(f"{case} solar activity: needs {needs}, re-enters in {when}")
    verdict = "meets" if summary.meets_five_year_rule else "does NOT meet"
    left, capacity = summary.deorbit_dv_available_m_s, summary.deorbit_dv_capacity_m_s
    click.echo(
        f"{verdict} the {summary.limit_years:g}-year rule; deorbit Δv left after transfer and "
        f"detumble {left:.1f} of {capacity:.1f} m/s"
    )
    extra = summary.extra_stages_needed
    if extra is None:
        click.echo("more stages per engine would not meet it: the swarm itself must change")
    elif extra:
        click.echo(f"{extra} more stage(s) on every engine would meet it")
    click.echo(
        f"propellant used {summary.propellant_used_kg:.3f} of {summary.propellant_total_kg:.3f}"
        f" kg; stranded (no torque-free mix can burn it) {summary.propellant_stranded_kg:.3f} kg"
    )
    click.echo(f"written to {folder.absolute()}")
