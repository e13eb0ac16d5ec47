"""``casadi-debris deorbit``: the least Δv that brings the debris down within five years."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

import click

from casadi_debris.cli.common import (
    BoundedFloat,
    bounded_option,
    comma_list,
    echo_json,
    main,
    problem_argument,
    run_folder,
    run_folder_options,
    say,
    workers_option,
)
from casadi_debris.config import load_problem
from casadi_debris.config.limits import SEED
from casadi_debris.errors import InputShapeError
from casadi_debris.report import format_table

MAX_SAMPLES = 100_000

solar_option = click.option(
    "--solar",
    default="low,mean,high",
    show_default=True,
    help="Solar-activity cases (constant ECSS long-term levels), comma-separated.",
)
limit_years_option = click.option(
    "--limit-years",
    type=BoundedFloat(0.0, 100.0, low_open=True),
    default=5.0,
    show_default=True,
    help="Re-entry within this long of the burn's start (FCC: 5).",
)


def solar_cases(text: str) -> tuple[str, ...]:
    """``--solar low,mean`` as distinct known cases, or one line naming the option."""
    from casadi_debris.orbit import SOLAR_CASES

    cases = comma_list(text, "--solar", "low,mean,high")
    if [c for c in cases if c not in SOLAR_CASES] or len(set(cases)) != len(cases):
        raise InputShapeError(
            f"--solar: distinct cases among {', '.join(SOLAR_CASES)}, got {text!r}"
        )
    return tuple(cases)


@main.command()
@problem_argument
@solar_option
@limit_years_option
@click.option(
    "--drag-coefficient",
    type=BoundedFloat(0.5, 5.0),
    default=None,
    help="C_D [the problem's [environment] drag_coefficient, 2.2].",
)
@click.option("--held", is_flag=True, help="After the burn the attitude is held, not tumbling.")
@click.option(
    "--minimum-swarm/--no-minimum-swarm",
    default=True,
    show_default=True,
    help="Search the fewest CubeSats that meet the limit.",
)
@click.option(
    "--samples",
    type=click.IntRange(0, MAX_SAMPLES),
    default=0,
    show_default=True,
    help="Lifetime Monte Carlo runs of the governing plan (solar cycles, C_D).",
)
@bounded_option("--seed", SEED, 20250103, "Seed of the Monte Carlo.")
@workers_option
@run_folder_options("deorbit")
def deorbit(
    problem_file: Path | None,
    solar: str,
    limit_years: float,
    drag_coefficient: float | None,
    held: bool,
    minimum_swarm: bool,
    samples: int,
    seed: int,
    workers: int,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Plan the deorbit: least Δv to re-enter within five years, per solar activity.

    NRLMSIS 2.1 density (indices passed, nothing downloaded), the debris' drag area
    from its faces, the swarm's torque-free thrust with staging; lowers the whole
    orbit or the perigee (burns near apogee), whichever needs less Δv, then lets it
    decay. Says whether the swarm suffices, how many stages it takes, and the
    smallest swarm that would.
    """
    from casadi_debris.workflows import deorbit as deorbit_job

    cases = solar_cases(solar)
    problem = load_problem(problem_file)
    folder = run_folder(out, "deorbit", problem.name, overwrite)
    say(f"Planning the deorbit of {problem.name} ({', '.join(cases)} solar activity) ...")
    result = deorbit_job(
        problem,
        solar=cases,
        limit_years=limit_years,
        drag_coefficient=drag_coefficient,
        held=held,
        minimum_swarm=minimum_swarm,
        samples=samples,
        seed=seed,
        workers=workers,
    )
    result.save(folder, overwrite=overwrite)
    report = dataclasses.replace(result.summary, out_dir=str(folder.absolute()))
    if as_json:
        echo_json(report)
        return
    click.echo(_text(report.plan))
    click.echo(f"written to {report.out_dir}")


def _years(value: float) -> str:
    return "> horizon" if not math.isfinite(value) else f"{value:.2f}"


def _text(plan: Any) -> str:
    """The cases as a table, then the verdict, the smallest swarm and the Monte Carlo."""
    from casadi_debris.orbit import SOLAR_CASES

    rows = [
        [
            c.solar,
            _years(c.natural_lifetime_years),
            f"{c.strategy} ({c.arc_half_width_deg:g} deg)",
            c.deorbit_dv_m_s,
            c.propellant_kg,
            c.firing_time_h,
            c.burn_duration_days,
            c.stages_used,
            _years(c.reentry_years),
            "yes" if c.meets_five_year_rule else "no",
        ]
        for c in plan.cases
    ]
    table = format_table(
        [
            "solar",
            "natural [y]",
            "strategy",
            "dv [m/s]",
            "propellant [kg]",
            "firing [h]",
            "burn [d]",
            "stages begun",
            "re-entry [y]",
            "meets",
        ],
        rows,
    )
    verdict = "meets" if plan.meets_five_year_rule else "does NOT meet"
    asked = [c.solar for c in plan.cases]
    # The Monte Carlo below draws whole solar cycles: say when the verdict is narrower.
    scope = (
        ""
        if set(asked) == set(SOLAR_CASES)
        else f" under {' and '.join(asked)} solar activity only"
    )
    need = (
        f"needs {plan.deorbit_dv_m_s:.1f} m/s ({plan.stages_needed} stages' impulse)"
        if math.isfinite(plan.deorbit_dv_m_s)
        else "is out of reach: at this thrust no burn ends in time"
    )
    lines = [
        table,
        f"swarm's torque-free dv {plan.capacity_dv_m_s:.1f} m/s; governing case "
        f"{plan.governing_case} {need}: the swarm {verdict} the "
        f"{plan.limit_years:g}-year rule{scope}",
    ]
    smallest = plan.minimum_swarm
    if smallest is not None:
        lines.append(
            f"smallest swarm: {smallest.cubesats} CubeSats ({smallest.stages} stages, "
            f"{smallest.thrust_mN:.2f} mN) on one face, {smallest.deorbit_dv_m_s:.1f} m/s"
        )
    if plan.monte_carlo is not None:
        mc = plan.monte_carlo
        lines.append(
            f"Monte Carlo ({mc.runs} runs, seed {mc.seed}): re-entry median "
            f"{_years(mc.median_years)} y, 5-95 % {_years(mc.p05_years)}-{_years(mc.p95_years)} y,"
            f" within the limit {100 * mc.within_limit_fraction:.1f} %"
        )
    return "\n".join(lines)
