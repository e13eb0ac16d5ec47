"""``casadi-debris burn``: thrusting while pointing, flown in closed loop."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import click

from casadi_debris.cli.common import (
    BoundedFloat,
    controller_options,
    echo_json,
    main,
    no_jit_option,
    problem_argument,
    run_folder,
    run_folder_options,
    say,
)
from casadi_debris.config import load_problem
from casadi_debris.errors import InputShapeError
from casadi_debris.report import format_table

DIRECTIONS = ("retrograde", "prograde", "normal", "antinormal")


@main.command()
@problem_argument
@click.option(
    "--direction",
    type=click.Choice(DIRECTIONS),
    default="retrograde",
    show_default=True,
    help="Where the thrust points, in the orbit's LVLH frame.",
)
@click.option(
    "--hours",
    type=BoundedFloat(0.0, 24.0, low_open=True),
    default=0.25,
    show_default=True,
    help="Engines on [h].",
)
@click.option(
    "--body-axis",
    help="Thrust axis in body axes: x, -y, ... or a,b,c [the swarm's strongest torque-free "
    "direction].",
)
@click.option(
    "--thrust-fraction",
    type=BoundedFloat(0.0, 1.0, low_open=True),
    default=None,
    help="Of the largest torque-free thrust along the axis [1].",
)
@click.option(
    "--thrust-mN",
    "thrust_mN",
    type=BoundedFloat(0.0, 1e6, low_open=True),
    default=None,
    help="The thrust itself [mN] (instead of --thrust-fraction).",
)
@click.option(
    "--first-stage-left-s",
    type=BoundedFloat(0.0, 1e7),
    default=None,
    help="Start with every engine's first stage holding this much full-thrust time [s] "
    "(to see stages switch in a short burn) [full].",
)
@controller_options
@no_jit_option
@run_folder_options("burn")
def burn(
    problem_file: Path | None,
    direction: str,
    hours: float,
    body_axis: str | None,
    thrust_fraction: float | None,
    thrust_mN: float | None,
    first_stage_left_s: float | None,
    controller: Path | None,
    allow_mismatch: bool,
    no_jit: bool,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Fly a burn: the thrust axis held along an LVLH direction by the attitude loop on the
    flexible model, while the engines deliver the thrust and the loop's torque together.

    Reports the thrust axis' pointing error, Δv (simulated, analytic, rocket equation),
    the propellant split between Δv and attitude, and stage switches.
    """
    from casadi_debris.workflows import burn as burn_job

    problem = load_problem(problem_file)
    axis = None if body_axis is None else _axis(body_axis)
    folder = run_folder(out, "burn", problem.name, overwrite)
    result = burn_job(
        problem,
        direction=direction,  # type: ignore[arg-type]  # click.Choice checked it
        hours=hours,
        body_axis=axis,
        thrust_fraction=thrust_fraction,
        thrust_mN=thrust_mN,
        first_stage_left_s=first_stage_left_s,
        controller=controller,
        allow_mismatch=allow_mismatch,
        no_jit=no_jit,
        progress=say,
    )
    result.save(folder, overwrite=overwrite)
    report = dataclasses.replace(result.summary, out_dir=str(folder.absolute()))
    if as_json:
        echo_json(report)
        return
    b = report.burn
    rows: list[list[Any]] = [
        ["thrust [mN]", b.thrust_mN],
        [
            "pointing error, max / last half [arcsec]",
            f"{b.pointing_max_arcsec:.4g} / {b.pointing_steady_max_arcsec:.4g}",
        ],
        ["requirement [arcsec]", b.pointing_requirement_arcsec],
        ["dv along the direction [m/s]", b.dv_along_m_s],
        ["dv thrust t / M [m/s]", b.dv_m_s],
        ["dv from the plant's momentum [m/s]", b.dv_plant_m_s],
        ["propellant, dv share [kg]", b.fuel_dv_kg],
        ["propellant, attitude share [kg]", b.fuel_attitude_kg],
        ["stage switches", b.run.stage_switches],
        ["array tip deflection from the thrust [m]", b.array_tip_deflection_m],
        ["wall time [s]", f"{b.run.wall_time_s:.1f}"],
    ]
    click.echo(format_table(["figure", "value"], rows))
    click.echo(f"written to {report.out_dir}")


def _axis(text: str) -> str | tuple[float, float, float]:
    """``x``, ``-y``, ... (passed on as the name) or ``a,b,c`` (not all zero) as a vector."""
    from casadi_debris.config import AXIS_TEXTS

    if text.strip().lower() in AXIS_TEXTS:
        return text
    try:
        values = [float(part) for part in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 3 or not all(abs(v) < 1e6 for v in values) or not any(values):
        raise InputShapeError(
            f"--body-axis: x, -y, ... or three numbers a,b,c not all zero, got {text!r}"
        )
    return (values[0], values[1], values[2])
