"""One slew reference (``casadi-debris slew``): the paper's bang-bang, or a CasADi
time- or fuel-optimal slew at torque or thruster level, rigid or flexible, checked
against the engines over its whole grid; or every segment of a problem's manoeuvre.

Example
-------
>>> import casadi_debris as cd
>>> result = cd.slew("paper", method="bang-bang", duration_s=1228.0)
>>> round(result.summary.torque_fraction, 3), result.summary.limits_ok
(0.561, True)
>>> result.save("runs/slew-bb")  # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from casadi_debris.config import Problem, SlewRequest, Target, slew_about
from casadi_debris.errors import InputShapeError, SlewInfeasibleError
from casadi_debris.records import FLATTENED, OPTIONAL, Record
from casadi_debris.store import write_json_atomic
from casadi_debris.units import MN_PER_N, MNM_PER_NM
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from casadi_debris.config import SlewMethod
    from casadi_debris.guidance import ManoeuvreReference, ManoeuvreSummary
    from casadi_debris.slews import SlewProfile

LOGGER = logging.getLogger(__name__)

Axis = str | tuple[float, float, float]
METHODS = ("bang-bang", "time-optimal", "fuel-optimal")
# The slew functions name their parameters; the command line (and this job) its options.
OPTION_OF_PARAMETER = {
    "axis": "--axis",
    "angle": "--angle-deg",
    "duration_s": "--duration-s",
    "torque_fraction": "--torque-fraction",
    "rate_limit": "--rate-limit-deg-s",
    "smoothing_s": "--smoothing-s",
    "sample_s": "--sample-s",
}


@dataclass(frozen=True, kw_only=True)
class SlewSummary(Record):
    """What ``casadi-debris slew --json`` prints of one slew, in display units.

    Attributes
    ----------
    problem, method : str
    flexible, thrusters : bool
        Array modes in the optimisation; thrust per engine as decision variable.
    axis_B : tuple of 3 float
        Unit slew axis in the body frame.
    angle_deg, duration_s : float
        Slew angle [deg] and slew time [s].
    eigenaxis_duration_s : float
        The eigenaxis bang-bang time at the profile's torque fraction, gyroscopic torque
        included [s]: flyable, so the time-optimal slew at that authority is never longer.
    duration_over_eigenaxis : float
    limits_ok : bool
        Within the engines' limits over the whole grid (``limits_note`` says what failed).
    max_torque_mNm : tuple of 3 float
        Largest |torque| per body axis [mNm].
    fuel_kg, residual_vibration_rad, residual_energy_J : float
        Propellant; detrended attitude oscillation and vibration energy left after the
        end, on the full flexible model.
    solve_time_s, wall_time_s : float
        The method's solve, and all the job took (model build and checks included) [s].
    solver_status : str
    limits_zero_net_force : bool
        The limits were those at zero net force.
    limits_authority_mNm : dict
        Largest pure torque about each signed axis (``"+x"`` ... ``"-z"``) [mNm].
    worst_axis_ratio : dict
        Per signed axis, the largest torque need over the authority about it.
    worst_torque_set_ratio : float
        Largest gauge of the torque in the engines' torque set (1 = at its boundary).
    worst_ratio_time_s : float
        When the larger worst ratio occurs [s from the start].
    limits_note : str
    max_thrust_ratio, min_thrust_mN, torque_map_residual_mNm, max_net_force_mN : float
        Thruster level only (no key otherwise): largest thrust over its bound, smallest
        thrust [mN], largest |tau - B f| [mNm], largest net force [mN].
    engine_torque_shortfall_mNm : float
        Torque level only: the torque the least-fuel thrust misses, worst sample [mNm].
    target_reached : bool
        Optimal slews only (no key otherwise): the profile, integrated from its own
        held controls, ends within ``TARGET_TOLERANCE_RAD`` of the target attitude
        (``final_attitude_error_rad`` gives the figure); false is a profile the solver
        called converged that does not go where it was asked.
    settings : dict
        What the method sets and reports (``torque_fraction``, ``starts``,
        ``local_optima_s``, ``flexible_method``, ...), written beside the other keys.
    """

    problem: str
    method: str
    flexible: bool
    thrusters: bool
    axis_B: tuple[float, ...]
    angle_deg: float
    duration_s: float
    eigenaxis_duration_s: float
    duration_over_eigenaxis: float
    limits_ok: bool
    max_torque_mNm: tuple[float, ...]
    fuel_kg: float
    residual_vibration_rad: float
    residual_energy_J: float
    solve_time_s: float
    wall_time_s: float
    solver_status: str
    limits_zero_net_force: bool
    limits_authority_mNm: dict[str, float]
    worst_axis_ratio: dict[str, float]
    worst_torque_set_ratio: float
    worst_ratio_time_s: float
    limits_note: str
    max_thrust_ratio: float | None = field(default=None, metadata=OPTIONAL)
    min_thrust_mN: float | None = field(default=None, metadata=OPTIONAL)
    torque_map_residual_mNm: float | None = field(default=None, metadata=OPTIONAL)
    max_net_force_mN: float | None = field(default=None, metadata=OPTIONAL)
    engine_torque_shortfall_mNm: float | None = field(default=None, metadata=OPTIONAL)
    target_reached: bool | None = field(default=None, metadata=OPTIONAL)
    settings: dict[str, Any] = field(default_factory=dict, metadata=FLATTENED)

    @property
    def torque_fraction(self) -> float | None:
        """The share of the authority the slew was sized to (None if the method gives none)."""
        value = self.settings.get("torque_fraction")
        return None if value is None else float(value)


# How far from its target an optimal profile may end, integrated open loop from the
# solver's held controls: converged solves end within about 1e-6 rad; a tenth of the
# paper's 0.6 deg slew error is far from both.
TARGET_TOLERANCE_RAD = 1e-3


def slew_summary(profile: SlewProfile, problem_name: str, wall_time_s: float) -> SlewSummary:
    """The summary of ``profile`` in display units (mNm, mN, deg).

    Parameters
    ----------
    profile : SlewProfile
    problem_name : str
    wall_time_s : float
        What the job took [s].
    """
    base = profile.summary()
    check = profile.limits
    settings = dict(profile.settings)
    shortfall = settings.pop("engine_torque_shortfall_Nm", None)
    end_error = settings.get("final_attitude_error_rad")
    # The limit check's keys are fields here; its figures win over a setting of one name,
    # as in the profile's own summary.
    claimed = {f.name for f in dataclasses.fields(SlewSummary)} | set(check.to_json())
    return SlewSummary(
        problem=problem_name,
        method=base.method,
        flexible=base.flexible,
        thrusters=base.thrusters,
        axis_B=tuple(float(v) for v in base.axis_B),
        angle_deg=math.degrees(base.angle_rad),
        duration_s=base.duration_s,
        eigenaxis_duration_s=base.eigenaxis_duration_s,
        duration_over_eigenaxis=base.duration_over_eigenaxis,
        limits_ok=base.limits_ok,
        max_torque_mNm=tuple(float(v) * MNM_PER_NM for v in base.max_torque_Nm),
        fuel_kg=base.fuel_kg,
        residual_vibration_rad=base.residual_vibration_rad,
        residual_energy_J=base.residual_energy_J,
        solve_time_s=base.solve_time_s,
        wall_time_s=wall_time_s,
        solver_status=base.solver_status,
        limits_zero_net_force=check.limits_zero_net_force,
        limits_authority_mNm={k: v * MNM_PER_NM for k, v in check.limits_authority_Nm.items()},
        worst_axis_ratio=dict(check.worst_axis_ratio),
        worst_torque_set_ratio=check.worst_torque_set_ratio,
        worst_ratio_time_s=check.worst_ratio_time_s,
        limits_note=check.limits_note,
        max_thrust_ratio=check.max_thrust_ratio,
        min_thrust_mN=_scaled(check.min_thrust_N, MN_PER_N),
        torque_map_residual_mNm=_scaled(check.torque_map_residual_Nm, MNM_PER_NM),
        max_net_force_mN=_scaled(check.max_net_force_N, MN_PER_N),
        engine_torque_shortfall_mNm=_scaled(shortfall, MNM_PER_NM),
        target_reached=None if end_error is None else bool(end_error <= TARGET_TOLERANCE_RAD),
        settings={k: v for k, v in settings.items() if k not in claimed},
    )


def _scaled(value: float | None, factor: float) -> float | None:
    return None if value is None else float(value) * factor


@dataclass(frozen=True)
class SlewResult(JobResult):
    """A slew reference: its profile and summary; or a manoeuvre's, segment by segment.

    Attributes
    ----------
    problem : Problem
    summary : SlewSummary or ManoeuvreSummary
        A :class:`SlewSummary` for one slew; for a problem that flies
        ``[[simulation.segments]]`` (and no ``axis``, ``angle_deg`` or ``method`` given)
        a :class:`~casadi_debris.guidance.ManoeuvreSummary`.
    profile : SlewProfile or None
        The one slew, SI units (None for a manoeuvre).
    manoeuvre : ManoeuvreReference or None
        The manoeuvre's reference sampled uniformly (None for one slew).
    """

    problem: Problem
    summary: SlewSummary | ManoeuvreSummary
    profile: SlewProfile | None = None
    manoeuvre: ManoeuvreReference | None = None

    command = "slew"

    def plot(self) -> dict[str, Figure]:
        """``slew`` (angles, rates, torque against the authority and, at thruster level,
        every engine's thrust), or ``reference`` for a manoeuvre (angles and rates,
        segments shaded). Nothing is written; close them with ``matplotlib.pyplot.close``."""
        if self.profile is not None:
            from casadi_debris.plots import slew_figure

            return {"slew": slew_figure(self.profile, thrust=self.profile.thrusters)}
        from casadi_debris.plots import manoeuvre_figure
        from casadi_debris.report import figure_title

        reference = self._reference()
        figure = manoeuvre_figure(
            reference.time_s,
            reference.quaternion_BN,
            reference.rate_rad_s,
            reference.summary.segments,
            figure_title(self.problem),
        )
        return {"reference": figure}

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json``, ``profile.csv`` and, with ``plots``, ``slew.png`` (one slew) or
        ``reference.png`` (a manoeuvre), each PNG with its PDF."""
        from casadi_debris.report import write_profile_csv, write_reference_csv

        write_json_atomic(staging / "summary.json", self.summary)
        if self.profile is not None:
            write_profile_csv(self.profile, staging / "profile.csv", self.profile.thrusters)
        else:
            reference = self._reference()
            write_reference_csv(
                reference.time_s,
                reference.quaternion_BN,
                reference.rate_rad_s,
                staging / "profile.csv",
            )
        if plots:
            from casadi_debris.plots import save_figure

            for name, figure in self.plot().items():
                save_figure(figure, staging / f"{name}.png")

    def _reference(self) -> ManoeuvreReference:
        if self.manoeuvre is None:
            raise InputShapeError("a slew result holds a profile or a manoeuvre; this has neither")
        return self.manoeuvre


def slew(
    problem: ProblemLike = None,
    *,
    axis: Axis | None = None,
    angle_deg: float | None = None,
    method: str | None = None,
    duration_s: float | None = None,
    torque_fraction: float | None = None,
    rate_limit_deg_s: float | None = None,
    smoothing_s: float = 0.0,
    flexible: bool = False,
    flexible_method: str = "ocp",
    thrusters: bool = False,
    zero_net_force: bool = False,
    sample_s: float = 1.0,
    starts: int | None = None,
    seed: int = 0,
    workers: int | None = None,
    note: Callable[[str], None] | None = None,
) -> SlewResult:
    """Solve a slew reference of the problem, checked against its engines.

    Settings not given come from the problem's ``[simulation.slew]`` (the slew
    ``simulate`` flies; its duration and torque fraction only for that same slew), else
    180 deg about z by the paper's bang-bang. A problem that flies
    ``[[simulation.segments]]`` gives every segment's reference instead, unless
    ``axis``, ``angle_deg`` or ``method`` is given.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper's.
    axis : str or tuple of 3 float, optional
        ``"x"``, ``"-y"``, ... or any non-zero body vector.
    angle_deg : float, optional
        Slew angle in (0, 180] deg.
    method : {"bang-bang", "time-optimal", "fuel-optimal"}, optional
    duration_s : float, optional
        Slew time [s]; a deadline for time-optimal; needed by fuel-optimal.
    torque_fraction : float, optional
        Share of the authority, (0, 1]; default 1, or what a bang-bang's duration needs.
    rate_limit_deg_s, smoothing_s : float
        Bang-bang: the largest rate [deg/s] (a coast); the torque ramp per switch [s].
    flexible, flexible_method : bool, {"ocp", "shaper"}
        Optimal: bound the array vibration left, by the OCP or through a ZV shaper.
    thrusters, zero_net_force : bool
        Optimal: every engine's thrust optimised; their net force kept zero.
    sample_s : float
        Output spacing [s].
    starts, seed, workers : int, optional
        Time-optimal: initial guesses (default 16), their seed, and processes (default
        two with four starts or more on two cores; 1: in this process).
    note : callable, optional
        Told in one line, before the work, when the problem says what to slew.

    Returns
    -------
    SlewResult

    Raises
    ------
    InputShapeError
        A setting that does not fit, named by its option (``--duration-s: ...``).

    Examples
    --------
    >>> import casadi_debris as cd
    >>> cd.slew("paper", axis="x", angle_deg=30.0).summary.limits_ok
    True
    """
    started = time.perf_counter()
    problem = as_problem(problem)
    what = (axis, angle_deg, method, duration_s, torque_fraction, rate_limit_deg_s)
    how = (smoothing_s, flexible, flexible_method, thrusters, zero_net_force, sample_s)
    asked = _Asked(*(what + how), starts, seed, workers)
    if not asked.one_slew(problem):
        return _manoeuvre(problem, asked, note)
    return _one_slew(problem, asked, asked.request(problem, note), started)


def _one_slew(problem: Problem, asked: _Asked, request: SlewRequest, started: float) -> SlewResult:
    """The slew ``request`` solved as ``asked``, its summary timed from ``started``
    (``time.perf_counter``), a warning logged when the engines cannot fly it."""
    profile = asked.solve(problem, request)
    # What the user waited for: the solve, the flexible check, the shaper, the model build.
    summary = slew_summary(profile, problem.name, time.perf_counter() - started)
    if not summary.limits_ok:
        LOGGER.warning(_limits_warning(summary))
    if summary.target_reached is False:
        LOGGER.warning(
            "warning: this profile ends %.4g deg from its target (its held controls "
            "integrated open loop), although the solver reported %s: do not fly it as it is",
            math.degrees(float(summary.settings["final_attitude_error_rad"])),
            summary.solver_status,
        )
    return SlewResult(problem=problem, summary=summary, profile=profile)


@dataclass(frozen=True)
class _Asked:
    """The job's keywords, in the options' units; None: the problem's own.

    What to slew becomes a :class:`~casadi_debris.config.SlewRequest` (:meth:`request`,
    resolved against the problem); the rest (``smoothing_s``, ``sample_s``, ``starts``,
    ``seed``, ``workers``) is how it is solved and sampled.
    """

    axis: Axis | None
    angle_deg: float | None
    method: str | None
    duration_s: float | None
    torque_fraction: float | None
    rate_limit_deg_s: float | None
    smoothing_s: float
    flexible: bool
    flexible_method: str
    thrusters: bool
    zero_net_force: bool
    sample_s: float
    starts: int | None
    seed: int
    workers: int | None

    def __post_init__(self) -> None:
        if self.method is not None and self.method not in METHODS:
            methods = ", ".join(METHODS)
            raise InputShapeError(f"--method: must be one of {methods}, got {self.method!r}")

    def one_slew(self, problem: Problem) -> bool:
        """Whether to solve one slew (else the problem's segments, none of them chosen)."""
        chosen = self.axis or self.angle_deg or self.method
        return problem.simulation.reference != "sequence" or bool(chosen)

    def request(self, problem: Problem, note: Callable[[str], None] | None) -> SlewRequest:
        """The slew asked for, what is left open taken from the problem's
        (:func:`_problem_slew`)."""
        all_given = self.axis and self.angle_deg is not None and self.method
        if note is not None and problem.simulation.slew is not None and not all_given:
            note(f"Slew from {problem.name}'s [simulation.slew] where no option says otherwise.")
        rate_limit = self.rate_limit_deg_s
        asked = slew_about(
            self.axis or "z",
            180.0 if self.angle_deg is None else self.angle_deg,
            method=cast("SlewMethod", self.method or "bang-bang"),
            duration_s=self.duration_s,
            torque_fraction=self.torque_fraction,
            rate_limit_rad_s=None if rate_limit is None else math.radians(rate_limit),
            thrusters=self.thrusters,
            zero_net_force=self.zero_net_force,
            flexible=self.flexible,
            flexible_method=self.flexible_method,
        )
        own = problem.simulation.slew
        return asked if own is None else _problem_slew(own, self, asked)

    def solve(self, problem: Problem, request: SlewRequest) -> SlewProfile:
        """The profile of the request's method, errors named after the options."""
        try:
            return self._solve(problem, request)
        except (InputShapeError, SlewInfeasibleError) as exc:
            raise _named_after_options(exc, request) from None

    def _solve(self, problem: Problem, request: SlewRequest) -> SlewProfile:
        from casadi_debris.slews import (
            OptimalSlewSettings,
            bang_bang_slew,
            fuel_optimal_slew,
            slew_about_axis,
            time_optimal_slew,
        )

        target = slew_about_axis(request.axis, math.radians(request.angle_deg))
        if request.method == "bang-bang":
            if request.flexible or request.thrusters or request.zero_net_force:
                raise InputShapeError(
                    "--flexible, --thrusters and --zero-net-force apply to the optimal methods"
                )
            return bang_bang_slew(
                problem,
                target=target,
                duration_s=request.duration_s,
                torque_fraction=request.torque_fraction,
                rate_limit_rad_s=request.rate_limit_rad_s,
                smoothing_s=self.smoothing_s,
                sample_s=self.sample_s,
            )
        if request.rate_limit_rad_s is not None or self.smoothing_s:
            raise InputShapeError("--rate-limit-deg-s and --smoothing-s apply to bang-bang only")
        options = OptimalSlewSettings.for_request(
            request,
            sample_s=self.sample_s,
            starts=self.starts,
            seed=self.seed,
            workers=self.workers,
        )
        if request.method == "time-optimal":
            return time_optimal_slew(
                problem, target=target, duration_s=request.duration_s, options=options
            )
        if request.duration_s is None:
            raise InputShapeError("--duration-s: needed for a fuel-optimal slew")
        return fuel_optimal_slew(
            problem, target=target, duration_s=request.duration_s, options=options
        )


def _problem_slew(own: SlewRequest, asked: _Asked, request: SlewRequest) -> SlewRequest:
    """``request`` with what ``asked`` leaves open (None) taken from the problem's slew.

    The problem's ``[simulation.slew]`` (the slew ``simulate`` flies) gives the axis,
    angle and method, and, when the slew is its own (no other axis, angle or method)
    and neither is given, the duration and torque fraction; its thruster level for
    an optimal method.
    """
    method = cast("SlewMethod", asked.method or own.method)
    angle_deg = own.angle_deg if asked.angle_deg is None else asked.angle_deg
    turn = Target("rotation", axis=asked.axis or own.axis, angle_deg=angle_deg)
    timing = (asked.duration_s, asked.torque_fraction)
    its_own = (turn.axis, angle_deg, method) == (own.axis, own.angle_deg, own.method)
    if its_own and timing == (None, None):
        timing = (own.duration_s, own.torque_fraction)
    own_thrusters = own.thrusters and method != "bang-bang" and not asked.thrusters
    resolved = dataclasses.replace(
        request,
        target=turn,
        method=method,
        duration_s=timing[0],
        torque_fraction=timing[1],
    )
    if own_thrusters:
        resolved = dataclasses.replace(resolved, thrusters=True, zero_net_force=True)
    return resolved


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


def _limits_warning(summary: SlewSummary) -> str:
    """One line: what the profile needs beyond the engines, and what would fit."""
    remedy = (
        "the optimal slews at thruster level (--thrusters --zero-net-force) stay within them"
        if not summary.thrusters
        else "a smaller --torque-fraction or a longer --duration-s may fit"
    )
    return (
        f"warning: this profile is not within the engines' limits "
        f"({summary.limits_note}; worst at t = {summary.worst_ratio_time_s:.6g} s), "
        f"so the closed loop cannot fly it as it is; {remedy}"
    )


def _manoeuvre(problem: Problem, asked: _Asked, note: Callable[[str], None] | None) -> SlewResult:
    """The reference of the problem's ``[[simulation.segments]]``, as ``simulate`` flies
    it; the settings of one slew are refused (the segments set each slew)."""
    from casadi_debris.guidance import manoeuvre_reference

    one_slew = {
        "--duration-s": asked.duration_s,
        "--torque-fraction": asked.torque_fraction,
        "--rate-limit-deg-s": asked.rate_limit_deg_s,
        "--smoothing-s": asked.smoothing_s or None,
        "--flexible": asked.flexible or None,
        "--thrusters": asked.thrusters or None,
        "--zero-net-force": asked.zero_net_force or None,
        "--starts": asked.starts,
        "--workers": asked.workers,
    }
    for option, value in one_slew.items():
        if value is not None:
            raise InputShapeError(
                f"{option}: {problem.name}'s [[simulation.segments]] set each slew; "
                "give --axis, --angle-deg or --method to solve one slew instead"
            )
    if note is not None:
        note(f"Every segment of {problem.name}'s [[simulation.segments]].")
    reference = manoeuvre_reference(problem, asked.sample_s)
    if not reference.summary.slews_within_limits:
        LOGGER.warning(
            "warning: a slew is not within the engines' limits (authority share above 1): "
            "the closed loop cannot fly it as it is"
        )
    if not reference.summary.tracks_within_limits:
        notes = "; ".join(
            f"segment {r.segment} ({r.kind}): {r.limits_note}"
            for r in reference.summary.segments
            if r.kind != "slew" and r.limits_ok is False
        )
        LOGGER.warning(
            "warning: a track or burn needs more torque than the engines give: %s", notes
        )
    return SlewResult(problem=problem, summary=reference.summary, manoeuvre=reference)
