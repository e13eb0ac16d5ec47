"""``casadi-debris detumble``: the tumble braked in closed loop through the staged engines."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import click

from casadi_debris.cli.common import (
    BoundedFloat,
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

MAX_RATE_RAD_S = 100.0


@main.command()
@problem_argument
@click.option(
    "--rate-rad-s",
    help="Initial body rate about x, y, z [rad/s] [the problem's [detumble], 1,1,1 for the paper].",
)
@click.option(
    "--threshold-rad-s",
    type=BoundedFloat(0.0, 1.0, low_open=True),
    default=1e-4,
    show_default=True,
    help="Done when every rate component is below this.",
)
@click.option(
    "--gain-per-s",
    type=BoundedFloat(0.0, 10.0, low_open=True),
    default=0.02,
    show_default=True,
    help="K of the linear tail tau = -K J omega [1/s].",
)
@click.option(
    "--period-s",
    type=BoundedFloat(0.01, 10.0),
    default=1.0,
    show_default=True,
    help="Control period: the torque is held over it.",
)
@click.option(
    "--ocp/--no-ocp",
    default=True,
    show_default=True,
    help="Also solve the time-optimal detumble (averaged OCP, about 20 s).",
)
@run_folder_options("detumble")
def detumble(
    problem_file: Path | None,
    rate_rad_s: str | None,
    threshold_rad_s: float,
    gain_per_s: float,
    period_s: float,
    ocp: bool,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Detumble the debris in closed loop: rigid body, thruster-level allocation, staging, fuel.

    Each period the engines give the torque that shrinks the angular momentum fastest
    (a vertex of the zero-net-force authority), then linear damping once they can.
    The arrays are taken as rigid: the flexible model is not valid at such rates.
    Reports the time to the threshold, fuel per CubeSat, stage switches and Δv
    beside the budget's per-axis estimate, a momentum bound and the time-optimal
    detumble (an OCP over the rates averaged over their precession).
    """
    from casadi_debris.workflows import detumble as detumble_job

    problem = load_problem(problem_file)
    rate = None if rate_rad_s is None else _rates(rate_rad_s)
    folder = run_folder(out, "detumble", problem.name, overwrite)
    result = detumble_job(
        problem,
        rate_rad_s=rate,
        threshold_rad_s=threshold_rad_s,
        gain_per_s=gain_per_s,
        period_s=period_s,
        ocp=ocp,
        progress=say,
    )
    result.save(folder, overwrite=overwrite)
    report = dataclasses.replace(result.summary, out_dir=str(folder.absolute()))
    if as_json:
        echo_json(report)
        return
    run = report.run
    done = "not reached" if run.time_to_threshold_h is None else f"{run.time_to_threshold_h:.2f}"
    rows: list[list[Any]] = [
        ["time to the threshold [h]", done],
        ["budget: per-axis braking, full rigid inertia [h]", report.budget_time_full_rigid_h],
        ["budget: per-axis braking, hub + CubeSats (paper) [h]", report.budget_time_h],
        ["momentum bound [h]", report.momentum_bound_h],
        *_ocp_rows(report),
        ["fuel [kg]", run.fuel_kg],
        ["worst CubeSat fuel [kg]", run.fuel_worst_cubesat_kg],
        ["dv used [m/s]", run.dv_used_m_s],
        ["budget dv [m/s]", report.budget_dv_m_s],
        ["stage switches", run.stage_switches],
        ["wall time [s]", f"{run.wall_time_s:.1f}"],
    ]
    click.echo(format_table(["figure", "value"], rows))
    click.echo(f"written to {report.out_dir}")


def _ocp_rows(report: Any) -> list[list[Any]]:
    """The time-optimal detumble's rows, or why it is missing."""
    if report.ocp_method is None:
        return []
    if report.ocp_time_h is None:
        return [["time-optimal detumble", report.ocp_method]]
    return [
        ["time-optimal detumble, averaged OCP [h]", report.ocp_time_h],
        ["  its fuel [kg]", report.ocp_fuel_kg],
        ["  greedy law, same averaged model [h]", report.ocp_greedy_time_h],
        ["  no averaged control is faster than [h]", report.ocp_averaged_bound_h],
    ]


def _rates(text: str) -> tuple[float, float, float]:
    """``--rate-rad-s a,b,c`` as three finite rates within +-MAX_RATE_RAD_S."""
    try:
        values = [float(part) for part in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 3 or not all(abs(v) <= MAX_RATE_RAD_S for v in values):
        raise InputShapeError(
            f"--rate-rad-s: three rates a,b,c in rad/s, each within ±{MAX_RATE_RAD_S:g}, "
            f"got {text!r}"
        )
    return values[0], values[1], values[2]
