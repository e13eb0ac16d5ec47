"""``casadi-debris slew``: bang-bang, time-optimal and fuel-optimal slew references.

The job is :func:`casadi_debris.slew`; this module maps its options to the function's
keywords and prints the summary.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar, cast

import click

from casadi_debris.cli.common import (
    BoundedFloat,
    echo_json,
    folder_option,
    in_range,
    main,
    output_options,
    problem_argument,
    say,
)
from casadi_debris.config import limits, load_problem
from casadi_debris.report import format_table
from casadi_debris.store import check_output_folder

if TYPE_CHECKING:
    from casadi_debris.guidance import ManoeuvreSummary
    from casadi_debris.workflows import SlewSummary


def summary_text(summary: SlewSummary) -> str:
    """A short table of the figures a reader looks for first."""
    torque = ", ".join(f"{v:.3g}" for v in summary.max_torque_mNm)
    ratios = summary.worst_axis_ratio
    axis = max(ratios, key=lambda name: ratios[name]) if ratios else "-"
    in_set = summary.worst_torque_set_ratio
    settings = summary.settings
    rows = [
        ["method", summary.method],
        ["duration [s]", f"{summary.duration_s:.2f}"],
        ["eigenaxis bang-bang time at this authority [s]", f"{summary.eigenaxis_duration_s:.2f}"],
        ["max torque x, y, z [mNm]", torque],
        # The gauge is the test (what the allocator can give); the largest share of a
        # pure-axis authority is information: a torque with other components may exceed it.
        ["share of the engines' torque set (the test)", f"{in_set:.4f}"],
        [
            "largest share of a pure-axis authority (info)",
            f"{ratios.get(axis, math.nan):.4f} (about {axis})",
        ],
        ["within the engines' limits", "yes" if summary.limits_ok else "NO"],
        ["fuel [kg]", f"{summary.fuel_kg:.4g}"],
        ["residual vibration [rad]", f"{summary.residual_vibration_rad:.3g}"],
        ["solve time [s]", f"{summary.solve_time_s:.3f}"],
        ["wall time [s]", f"{summary.wall_time_s:.2f}"],
        ["solver status", summary.solver_status],
    ]
    if "flexible_method" in settings:
        rows.insert(9, ["flexible method", settings["flexible_method"]])
    if "starts" in settings:
        optima = ", ".join(f"{value:.6g}" for value in settings["local_optima_s"])
        rows += [
            ["starts agreeing", f"{settings['starts_agreeing']} of {settings['starts']}"],
            ["local optima [s]", optima],
        ]
        # Only the torque-level search refines switch times; the thruster-level one has none.
        if "refinement" in settings:
            rows.append(["switch-time refinement", settings["refinement"]])
        if "torque_box_duration_s" in settings:
            rows.append(
                [
                    "torque-box optimum (a lower bound) [s]",
                    f"{settings['torque_box_duration_s']:.2f}",
                ]
            )
        if "verification_attitude_error_rad" in settings:
            residual = settings["verification_attitude_error_rad"]
            rows.append(["verification residual [rad]", f"{residual:.2g}"])
    if summary.torque_fraction is not None:
        rows.insert(4, ["torque fraction", f"{summary.torque_fraction:.4f}"])
    return format_table(["figure", "value"], rows)


def manoeuvre_text(summary: ManoeuvreSummary) -> str:
    """Each segment of a manoeuvre: window, method, angle, open-loop fuel, authority share."""
    rows = [
        [
            "" if r.segment is None else r.segment,
            r.kind,
            f"{r.start_s:.1f}",
            f"{r.end_s:.1f}",
            r.method or "",
            "" if r.angle_deg is None else f"{r.angle_deg:.2f}",
            "" if r.fuel_kg is None else f"{r.fuel_kg:.4g}",
            "" if r.worst_authority_share is None else f"{r.worst_authority_share:.3f}",
        ]
        for r in summary.segments
    ]
    header = ["segment", "kind", "start [s]", "end [s]", "method", "angle [deg]", "fuel [kg]"]
    header.append("authority share")
    return format_table(header, rows)


AXIS_CHOICES = ("x", "y", "z", "+x", "+y", "+z", "-x", "-y", "-z")


class AxisParam(click.ParamType):
    """A slew axis: a body axis letter (``z``, ``-x``) or three numbers ``a,b,c`` (any
    non-zero vector, normalised by the slew functions)."""

    name = "axis"

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> str | tuple[float, float, float]:
        if isinstance(value, tuple):
            return value
        text = str(value).strip().lower()
        if text in AXIS_CHOICES:
            return text
        parts = text.split(",")
        try:
            numbers = tuple(float(part) for part in parts)
        except ValueError:
            self.fail(
                f"expected x, y, z (optionally signed) or three numbers a,b,c, got {value!r}",
                param,
                ctx,
            )
        if len(numbers) != 3:
            self.fail(f"expected three numbers a,b,c, got {len(numbers)} in {value!r}", param, ctx)
        if not all(math.isfinite(number) for number in numbers):
            self.fail(f"must be three finite numbers, got {value!r}", param, ctx)
        if not any(numbers):
            self.fail(f"must not be the zero vector, got {value!r}", param, ctx)
        return (numbers[0], numbers[1], numbers[2])

    def get_metavar(self, param: click.Parameter, ctx: click.Context | None = None) -> str:
        return "[x|y|z|-x|-y|-z|A,B,C]"


F = TypeVar("F", bound=Callable[..., Any])
MAX_RATE_DEG_S = 1e4
MAX_STARTS = 1000
MAX_WORKERS = 256
MIN_SAMPLE_S = 1e-3


def axis_options(axis_default: str, angle_default: str) -> Callable[[F], F]:
    """``--axis`` (any body vector) and ``--angle-deg``, their defaults said in the help."""

    def decorate(command: F) -> F:
        command = click.option(
            "--angle-deg",
            type=in_range(limits.SLEW_ANGLE_DEG),
            help=f"Slew angle [deg] [{angle_default}].",
        )(command)
        return click.option(
            "--axis",
            type=AxisParam(),
            help="Slew axis: x, y, z (optionally signed) or a body vector a,b,c, e.g. 1,1,1 "
            f"[{axis_default}].",
        )(command)

    return decorate


@main.command()
@problem_argument
@axis_options(
    "the problem's [simulation.slew], else z", "the problem's [simulation.slew], else 180"
)
@click.option(
    "--method",
    type=click.Choice(["bang-bang", "time-optimal", "fuel-optimal"]),
    help="[the problem's [simulation.slew], else bang-bang]",
)
@click.option(
    "--duration-s",
    type=in_range(limits.SLEW_DURATION_S),
    help="Slew time (bang-bang, fuel-optimal); deadline for time-optimal "
    "[the problem's [simulation.slew], if it gives one].",
)
@click.option(
    "--torque-fraction",
    type=BoundedFloat(0.0, 1.0, low_open=True),
    help="Share of the torque authority to use (default: the problem's [simulation.slew], "
    "else 1, or what --duration-s needs).",
)
@click.option(
    "--rate-limit-deg-s",
    type=BoundedFloat(0.0, MAX_RATE_DEG_S, low_open=True),
    help="Bang-bang: largest slew rate (coast).",
)
@click.option(
    "--smoothing-s",
    type=BoundedFloat(0.0, limits.SLEW_DURATION_S.high),
    default=0.0,
    help="Bang-bang: torque ramp per switch.",
)
@click.option("--flexible", is_flag=True, help="Optimal slews: constrain the array vibration left.")
@click.option(
    "--flexible-method",
    type=click.Choice(["ocp", "shaper"]),
    default="ocp",
    show_default=True,
    help="--flexible: modal states in the OCP, or the rigid optimum through a ZV shaper.",
)
@click.option("--thrusters", is_flag=True, help="Optimise the thrust of every engine.")
@click.option(
    "--zero-net-force",
    is_flag=True,
    help="--thrusters: keep the net force zero, as the closed loop's allocator does.",
)
@click.option(
    "--sample-s",
    type=BoundedFloat(MIN_SAMPLE_S, limits.SLEW_DURATION_S.high),
    default=1.0,
    show_default=True,
    help="Output spacing.",
)
@click.option(
    "--starts",
    type=click.IntRange(1, MAX_STARTS),
    help="Time-optimal (torque level): initial guesses of the global search (default 16).",
)
@click.option(
    "--seed",
    type=click.IntRange(0, None),
    default=0,
    show_default=True,
    help="Seed of the random initial guesses.",
)
@click.option(
    "--workers",
    type=click.IntRange(1, MAX_WORKERS),
    help="Time-optimal: processes for the starts; 1 solves them in this process "
    "(default: two with at least four starts on two cores, else one).",
)
@folder_option()
@output_options
def slew(
    problem_file: Path | None,
    axis: str | tuple[float, float, float] | None,
    angle_deg: float | None,
    method: str | None,
    duration_s: float | None,
    torque_fraction: float | None,
    rate_limit_deg_s: float | None,
    smoothing_s: float,
    flexible: bool,
    flexible_method: str,
    thrusters: bool,
    zero_net_force: bool,
    sample_s: float,
    starts: int | None,
    seed: int,
    workers: int | None,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Slew reference profile: the paper's bang-bang or a CasADi time/fuel-optimal slew.

    A problem with a slew (``[simulation.slew]``, as simulate flies it) gives the
    axis, angle, method, duration, torque fraction and thruster level of the options
    not given; otherwise the defaults are 180 deg about z by the paper's bang-bang.
    Writes profile.csv, slew.png and summary.json to --out, prints the summary.
    """
    from casadi_debris.workflows import slew as slew_job

    problem = load_problem(problem_file)
    if out is not None:
        check_output_folder(out, overwrite=overwrite)
    result = slew_job(
        problem,
        axis=axis,
        angle_deg=angle_deg,
        method=method,
        duration_s=duration_s,
        torque_fraction=torque_fraction,
        rate_limit_deg_s=rate_limit_deg_s,
        smoothing_s=smoothing_s,
        flexible=flexible,
        flexible_method=flexible_method,
        thrusters=thrusters,
        zero_net_force=zero_net_force,
        sample_s=sample_s,
        starts=starts,
        seed=seed,
        workers=workers,
        note=say,
    )
    if out is not None:
        result.save(out, overwrite=overwrite)
    if as_json:
        echo_json(result.summary)
    elif result.profile is not None:
        click.echo(summary_text(cast("SlewSummary", result.summary)))
    else:
        click.echo(manoeuvre_text(cast("ManoeuvreSummary", result.summary)))
