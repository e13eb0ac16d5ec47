"""``casadi-debris slew``: bang-bang, time-optimal and fuel-optimal slew references."""

from __future__ import annotations

import dataclasses
import json
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click
import numpy as np

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
from casadi_debris.config import Problem, limits, load_problem
from casadi_debris.errors import InputShapeError, SlewInfeasibleError
from casadi_debris.report.common import (
    format_table,
    json_ready,
    write_csv,
    write_json_atomic,
)
from casadi_debris.report.folders import RunFolder, check_output_folder
from casadi_debris.units import MN_PER_N, MNM_PER_NM

if TYPE_CHECKING:
    from casadi_debris.slews import SlewProfile


def summary_for_output(profile: SlewProfile, problem_name: str) -> dict[str, Any]:
    """The summary with display units (mNm, deg) in the keys that need them."""
    summary = profile.summary().to_json()
    summary["angle_deg"] = math.degrees(summary.pop("angle_rad"))
    for name in ("max_torque", "engine_torque_shortfall", "torque_map_residual"):
        if f"{name}_Nm" in summary:
            summary[f"{name}_mNm"] = np.multiply(summary.pop(f"{name}_Nm"), MNM_PER_NM).tolist()
    for name in ("min_thrust", "max_net_force"):
        if f"{name}_N" in summary:
            summary[f"{name}_mN"] = summary.pop(f"{name}_N") * MN_PER_N
    if "limits_authority_Nm" in summary:
        authority = summary.pop("limits_authority_Nm")
        summary["limits_authority_mNm"] = {k: v * MNM_PER_NM for k, v in authority.items()}
    return {"problem": problem_name, **summary}


def write_profile_csv(profile: SlewProfile, path: Path, thrust: bool) -> None:
    """Time series: quaternion, Euler angles (deg), rate (deg/s), acceleration (deg/s^2),
    torque (mNm) and, with ``thrust``, thrust per engine (mN)."""
    columns: dict[str, np.ndarray] = {"time_s": profile.time_s}
    for i in range(4):
        columns[f"q{i}_BN"] = profile.quaternion_BN[:, i]
    for i, name in enumerate(("roll", "pitch", "yaw")):
        columns[f"{name}_deg"] = np.degrees(profile.euler_angles_rad[:, i])
    for i, axis in enumerate("xyz"):
        columns[f"rate_{axis}_deg_s"] = np.degrees(profile.rate_rad_s[:, i])
    for i, axis in enumerate("xyz"):
        columns[f"acceleration_{axis}_deg_s2"] = np.degrees(profile.acceleration_rad_s2[:, i])
    for i, axis in enumerate("xyz"):
        columns[f"torque_{axis}_mNm"] = profile.torque_Nm[:, i] * MNM_PER_NM
    if thrust:
        for i in range(profile.thrust_N.shape[1]):
            columns[f"thrust_{i + 1:02d}_mN"] = profile.thrust_N[:, i] * MN_PER_N
    write_csv(path, columns)


def summary_text(summary: dict[str, Any]) -> str:
    """A short table of the figures a reader looks for first."""
    torque = ", ".join(f"{v:.3g}" for v in summary["max_torque_mNm"])
    eigenaxis = summary["eigenaxis_duration_s"]
    eigenaxis = math.nan if eigenaxis is None else eigenaxis
    # JSON has no inf: a need where the authority is zero comes back as None.
    ratios = {k: math.inf if v is None else v for k, v in summary["worst_axis_ratio"].items()}
    axis = max(ratios, key=lambda name: ratios[name]) if ratios else "-"
    worst, worst_at = ratios.get(axis, math.nan), f"about {axis}"
    in_set = summary["worst_torque_set_ratio"]
    if in_set is None or in_set > worst:
        worst = math.inf if in_set is None else in_set
        worst_at = "of the engines' torque set"
    rows = [
        ["method", summary["method"]],
        ["duration [s]", f"{summary['duration_s']:.2f}"],
        ["eigenaxis bang-bang time at this authority [s]", f"{eigenaxis:.2f}"],
        ["max torque x, y, z [mNm]", torque],
        ["worst share of the authority", f"{worst:.4f} ({worst_at})"],
        ["within the engines' limits", "yes" if summary["limits_ok"] else "NO"],
        ["fuel [kg]", f"{summary['fuel_kg']:.4g}"],
        ["residual vibration [rad]", f"{summary['residual_vibration_rad']:.3g}"],
        ["solve time [s]", f"{summary['solve_time_s']:.3f}"],
        ["wall time [s]", f"{summary['wall_time_s']:.2f}"],
        ["solver status", summary["solver_status"]],
    ]
    if "flexible_method" in summary:
        rows.insert(8, ["flexible method", summary["flexible_method"]])
    if "starts" in summary:
        optima = ", ".join(f"{value:.6g}" for value in summary["local_optima_s"])
        rows += [
            ["starts agreeing", f"{summary['starts_agreeing']} of {summary['starts']}"],
            ["local optima [s]", optima],
        ]
        # Only the torque-level search refines switch times; the thruster-level one has none.
        if "refinement" in summary:
            rows.append(["switch-time refinement", summary["refinement"]])
        if "torque_box_duration_s" in summary:
            rows.append(["torque-box optimum [s]", f"{summary['torque_box_duration_s']:.2f}"])
        if "verification_attitude_error_rad" in summary:
            residual = summary["verification_attitude_error_rad"]
            rows.append(["verification residual [rad]", f"{residual:.2g}"])
    if "torque_fraction" in summary:
        rows.insert(4, ["torque fraction", f"{summary['torque_fraction']:.4f}"])
    return format_table(["figure", "value"], rows)


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
# The slew functions name their parameters; the command line names its options.
OPTION_OF_PARAMETER = {
    "axis": "--axis",
    "angle": "--angle-deg",
    "duration_s": "--duration-s",
    "torque_fraction": "--torque-fraction",
    "rate_limit": "--rate-limit-deg-s",
    "smoothing_s": "--smoothing-s",
    "sample_s": "--sample-s",
}


@dataclass(frozen=True)
class SlewRequest:
    """What ``casadi-debris slew`` was asked for, in its options' units."""

    axis: str | tuple[float, float, float]
    angle_deg: float
    method: str
    duration_s: float | None
    torque_fraction: float | None
    rate_limit_deg_s: float | None
    smoothing_s: float
    flexible: bool
    flexible_method: str
    thrusters: bool
    zero_net_force: bool
    sample_s: float
    starts: int | None = None
    seed: int = 0
    workers: int | None = None

    def solve(self, problem: Problem) -> SlewProfile:
        """The profile of the chosen method."""
        from casadi_debris.slews import (
            SlewOptions,
            bang_bang_slew,
            fuel_optimal_slew,
            slew_about_axis,
            time_optimal_slew,
        )

        target = slew_about_axis(self.axis, math.radians(self.angle_deg))
        if self.method == "bang-bang":
            if self.flexible or self.thrusters or self.zero_net_force:
                raise InputShapeError(
                    "--flexible, --thrusters and --zero-net-force apply to the optimal methods"
                )
            rate_limit = self.rate_limit_deg_s
            return bang_bang_slew(
                problem,
                target=target,
                duration_s=self.duration_s,
                torque_fraction=self.torque_fraction,
                rate_limit_rad_s=None if rate_limit is None else math.radians(rate_limit),
                smoothing_s=self.smoothing_s,
                sample_s=self.sample_s,
            )
        if self.rate_limit_deg_s is not None or self.smoothing_s:
            raise InputShapeError("--rate-limit-deg-s and --smoothing-s apply to bang-bang only")
        options = SlewOptions(
            flexible=self.flexible,
            thrusters=self.thrusters,
            zero_net_force=self.zero_net_force,
            torque_fraction=1.0 if self.torque_fraction is None else self.torque_fraction,
            sample_s=self.sample_s,
            flexible_method=self.flexible_method,
            seed=self.seed,
            workers=self.workers,
        )
        if self.starts is not None:  # else the library's default
            options = dataclasses.replace(options, starts=self.starts)
        if self.method == "time-optimal":
            return time_optimal_slew(
                problem, target=target, duration_s=self.duration_s, options=options
            )
        if self.duration_s is None:
            raise InputShapeError("--duration-s: needed for a fuel-optimal slew")
        return fuel_optimal_slew(
            problem, target=target, duration_s=self.duration_s, options=options
        )


def _problem_slew(
    problem: Problem,
    axis: str | tuple[float, float, float] | None,
    angle_deg: float | None,
    method: str | None,
    timing: tuple[float | None, float | None],
    thrusters: bool,
) -> dict[str, Any]:
    """The options left open (None) taken from the problem's slew, as SlewRequest fields.

    The problem's ``[simulation.slew]`` (the slew ``simulate`` flies) gives the axis,
    angle and method, and, when the slew is its own (no other axis, angle or method)
    and neither is given, the duration and torque fraction; its thruster level for
    an optimal method. Without one, 180 deg about z by the paper's bang-bang.
    """
    own = problem.simulation.slew
    if own is None:
        return {
            "axis": axis or "z",
            "angle_deg": 180.0 if angle_deg is None else angle_deg,
            "method": method or "bang-bang",
        }
    if not (axis and angle_deg is not None and method):
        say(f"Slew from {problem.name}'s [simulation.slew] where no option says otherwise.")
    chosen = method or own.method
    same = (axis or own.axis, own.angle_deg if angle_deg is None else angle_deg, chosen)
    if same == (own.axis, own.angle_deg, own.method) and timing == (None, None):
        timing = (own.duration_s, own.torque_fraction)
    own_thrusters = own.thrusters and chosen != "bang-bang" and not thrusters
    resolved: dict[str, Any] = {
        "axis": axis or own.axis,
        "angle_deg": own.angle_deg if angle_deg is None else angle_deg,
        "method": chosen,
        "duration_s": timing[0],
        "torque_fraction": timing[1],
    }
    return resolved | ({"thrusters": True, "zero_net_force": True} if own_thrusters else {})


def _named_after_options(error: Exception, request: SlewRequest) -> InputShapeError:
    """The error with the option it is about in front (the library names its parameters)."""
    text = str(error)
    name, separator, rest = text.partition(": ")
    if separator and name in OPTION_OF_PARAMETER:
        return InputShapeError(f"{OPTION_OF_PARAMETER[name]}: {rest}")
    if text.startswith("--"):
        return InputShapeError(text)
    if isinstance(error, SlewInfeasibleError) and request.duration_s is not None:
        return InputShapeError(f"--duration-s: {text}")
    return InputShapeError(f"--axis/--method: {text}")


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
    started = time.perf_counter()
    problem = load_problem(problem_file)
    if out is not None:
        check_output_folder(out, overwrite=overwrite)
    if problem.simulation.reference == "sequence" and not (axis or angle_deg or method):
        one_slew: tuple[Any, ...] = (duration_s, torque_fraction, rate_limit_deg_s)
        one_slew += (smoothing_s or None, flexible or None, thrusters or None)
        one_slew += (zero_net_force or None, starts, workers)
        _fly_sequence(problem, sample_s, out, overwrite, as_json, one_slew)
        return
    given = {
        "duration_s": duration_s,
        "torque_fraction": torque_fraction,
        "thrusters": thrusters,
        "zero_net_force": zero_net_force,
    }
    chosen = _problem_slew(
        problem, axis, angle_deg, method, (duration_s, torque_fraction), thrusters
    )
    request = SlewRequest(
        **(given | chosen),
        rate_limit_deg_s=rate_limit_deg_s,
        smoothing_s=smoothing_s,
        flexible=flexible,
        flexible_method=flexible_method,
        sample_s=sample_s,
        starts=starts,
        seed=seed,
        workers=workers,
    )
    try:
        profile = request.solve(problem)
    except (InputShapeError, SlewInfeasibleError) as exc:
        raise _named_after_options(exc, request) from None
    summary = summary_for_output(profile, problem.name)
    # What the user waited for: the solve, the flexible check, the shaper, the model build.
    summary["wall_time_s"] = time.perf_counter() - started
    if not summary["limits_ok"]:
        say(_limits_warning(summary))
    if out is not None:
        from casadi_debris.plots.slew import plot_slew

        with RunFolder.claim(out, overwrite=overwrite, command="slew") as folder:
            (folder / "summary.json").write_text(json.dumps(json_ready(summary), indent=2))
            write_profile_csv(profile, folder / "profile.csv", thrusters)
            plot_slew(profile, folder / "slew.png", thrust=thrusters)
    if as_json:
        echo_json(summary)
    else:
        click.echo(summary_text(summary))


def _limits_warning(summary: dict[str, Any]) -> str:
    """One line: what the profile needs beyond the engines, and what would fit."""
    remedy = (
        "the optimal slews at thruster level (--thrusters --zero-net-force) stay within them"
        if not summary["thrusters"]
        else "a smaller --torque-fraction or a longer --duration-s may fit"
    )
    return (
        f"warning: this profile is not within the engines' limits "
        f"({summary['limits_note']}; worst at t = {summary['worst_ratio_time_s']:.6g} s), "
        f"so the closed loop cannot fly it as it is; {remedy}"
    )


ONE_SLEW_OPTIONS = (
    "--duration-s",
    "--torque-fraction",
    "--rate-limit-deg-s",
    "--smoothing-s",
    "--flexible",
    "--thrusters",
    "--zero-net-force",
    "--starts",
    "--workers",
)


def _fly_sequence(
    problem: Problem,
    sample_s: float,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
    one_slew: tuple[Any, ...],
) -> None:
    """The reference of the problem's ``[[simulation.segments]]``, as ``simulate`` flies it;
    ``one_slew`` the values of :data:`ONE_SLEW_OPTIONS` (None where not given), refused."""
    from casadi_debris.guidance.sequence import manoeuvre_reference

    for option, value in zip(ONE_SLEW_OPTIONS, one_slew, strict=True):
        if value is not None:
            raise InputShapeError(
                f"{option}: {problem.name}'s [[simulation.segments]] set each slew; "
                "give --axis, --angle-deg or --method to solve one slew instead"
            )

    say(f"Every segment of {problem.name}'s [[simulation.segments]].")
    reference = manoeuvre_reference(problem, sample_s)
    summary = reference.summary
    if out is not None:
        from casadi_debris.plots.slew import plot_manoeuvre
        from casadi_debris.report.simulation import figure_title

        with RunFolder.claim(out, overwrite=overwrite, command="slew") as folder:
            write_json_atomic(folder / "summary.json", summary)
            write_reference_csv(
                reference.time_s, reference.quaternion_BN, reference.rate_rad_s, folder
            )
            plot_manoeuvre(
                reference.time_s,
                reference.quaternion_BN,
                reference.rate_rad_s,
                summary.segments,
                folder / "reference.png",
                figure_title(problem),
            )
    if not summary.slews_within_limits:
        say(
            "warning: a slew is not within the engines' limits (authority share above 1): "
            "the closed loop cannot fly it as it is"
        )
    if as_json:
        echo_json(summary)
        return
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
    click.echo(format_table(header, rows))


def write_reference_csv(
    time_s: np.ndarray, quaternion_BN: np.ndarray, rate_rad_s: np.ndarray, folder: Path
) -> None:
    """profile.csv of a manoeuvre: time, quaternion, 3-2-1 Euler angles (deg), rate (deg/s)."""
    from casadi_debris.dynamics.attitude import euler_angles_321

    columns: dict[str, np.ndarray] = {"time_s": time_s}
    for i in range(4):
        columns[f"q{i}_BN"] = quaternion_BN[:, i]
    angles = euler_angles_321(quaternion_BN)
    for i, name in enumerate(("roll", "pitch", "yaw")):
        columns[f"{name}_deg"] = np.degrees(angles[:, i])
    for i, axis in enumerate("xyz"):
        columns[f"rate_{axis}_deg_s"] = np.degrees(rate_rad_s[:, i])
    write_csv(folder / "profile.csv", columns)
