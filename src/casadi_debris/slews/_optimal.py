"""Time- and fuel-optimal rest-to-rest slews as CasADi ``Opti`` problems.

The OCP is stated apart from how it is solved, as rockit does:

- :mod:`~casadi_debris.slews._options`: :class:`OptimalSlewSettings`, how a slew is
  modelled, transcribed and checked;
- :mod:`~casadi_debris.slews._ocp_problem`: the statement (states, controls and
  their bounds, end conditions, objectives) on the rigid model;
- :mod:`~casadi_debris.slews._transcription`: direct Radau collocation and IPOPT;
- :mod:`~casadi_debris.slews._initial_guess`: where IPOPT starts (the eigenaxis
  bang-bang, or the shaped rigid optimum);
- :mod:`~casadi_debris.slews._modal_window`: the flexible slew's terminal window,
  the vibration left bounded in closed form;
- :mod:`~casadi_debris.slews._shaper`: the zero-vibration input shaper;
- :mod:`~casadi_debris.slews._ocp_solution`: the solution as a profile.

This module holds the public entry points and the order in which a slew is
solved. A rigid slew is one NLP from the eigenaxis bang-bang. A flexible slew
(``flexible_method="ocp"``) first solves the rigid one, passes its optimum
through the ZV shaper as the guess, then solves bulk and terminal window with
the vibration bound; when IPOPT does not converge on that, or with
``flexible_method="shaper"``, the shaped rigid optimum is the result (said so
in ``settings["flexible_method"]``).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.errors import InputShapeError, SlewInfeasibleError
from casadi_debris.slews._global_slew import (
    global_time_optimal,
    rigid_body_profile,
    search_settings,
)
from casadi_debris.slews._initial_guess import (
    BangBangReferences,
    InitialGuess,
    bang_bang_guess,
    shaped_guess,
)
from casadi_debris.slews._limits import authority_use
from casadi_debris.slews._maneuver import SlewTarget, eigenaxis_duration_s, slew_about_axis
from casadi_debris.slews._modal_window import (
    ENERGY_MARGIN,
    WINDOW_INTERVALS,
    VibrationBound,
    energy_limit,
    window_length_s,
)
from casadi_debris.slews._ocp_problem import SlewOcp
from casadi_debris.slews._ocp_solution import slew_profile
from casadi_debris.slews._options import OptimalSlewSettings
from casadi_debris.slews._profile import SlewProfile, residual_vibration
from casadi_debris.slews._rigid_body import RigidBody
from casadi_debris.slews._shaper import shape, zero_vibration_shaper
from casadi_debris.slews._thruster_search import thruster_time_optimal
from casadi_debris.slews._transcription import (
    RIGID_INTERVALS,
    Horizon,
    NlpSolution,
    SlewNotConvergedError,
    transcribe_and_solve,
)

# Slack on the torque set's gauge within which a torque is in the set: IPOPT meets its
# bounds to about 1e-8 (as the limit check's RATIO_TOLERANCE).
TORQUE_SET_TOLERANCE = 1e-6

__all__ = [
    "OptimalSlewSettings",
    "RigidBody",
    "fuel_optimal_slew",
    "shape",
    "time_optimal_slew",
    "zero_vibration_shaper",
]


class _SlewSolver:
    """Solves one :class:`SlewOcp` for time or for fuel: rigid, modal window or shaped.

    Parameters
    ----------
    ocp : SlewOcp
        The slew stated, with its options; the solver keeps the bang-bang guesses
        and the ZV shaper it computes for it.
    """

    def __init__(self, ocp: SlewOcp) -> None:
        self.ocp = ocp
        self.references = BangBangReferences(ocp)
        self.report: dict[str, Any] = {}
        self._shaper: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    def shaper(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The cascaded ZV shaper of the flexible model's modes
        (:func:`~casadi_debris.slews._shaper.zero_vibration_shaper`), computed once."""
        if self._shaper is None:
            if self.ocp.flexible_model is None:
                raise ValueError("the ZV shaper needs a flexible slew OCP (options.flexible)")
            self._shaper = zero_vibration_shaper(self.ocp.flexible_model, self.ocp.parameters)
        return self._shaper

    def solve(self, *, fuel: bool, duration_s: float | None, check_vibration: bool) -> SlewProfile:
        """The optimal slew: least time (``duration_s`` None) or least propellant in
        ``duration_s`` seconds.

        Raises
        ------
        SlewInfeasibleError
            IPOPT did not converge (on the rigid problem; the modal one falls back).
        """
        options = self.ocp.options
        if not options.flexible or options.flexible_method == "shaper":
            return self._solve_rigid_or_shaped(fuel, duration_s, check_vibration)
        try:
            return self._solve_modal(fuel, duration_s, check_vibration)
        except SlewNotConvergedError as error:
            method = f"shaper (fallback: modal {error})"
        return self._solve_rigid_or_shaped(fuel, duration_s, check_vibration, method=method)

    def _solve_rigid(
        self, fuel: bool, duration_s: float | None
    ) -> tuple[NlpSolution, InitialGuess]:
        """The rigid OCP from the eigenaxis bang-bang; its solution and the guess.

        ``duration_s`` is the length of a fuel-optimal slew (required then); a
        time-optimal one ignores it. A time-optimal torque-level slew is the rigid
        body's, searched globally (:mod:`casadi_debris.slews._global_slew`); a
        thruster-level one is started from several guesses, the torque box's global
        optimum among them (:mod:`casadi_debris.slews._thruster_search`); the search's
        report is kept in ``self.report``.
        """
        ocp = self.ocp
        if fuel:
            if duration_s is None:
                raise ValueError("a fuel-optimal slew needs its duration_s")
            reference = self.references.at(duration_s)
            total_s = duration_s
        else:
            reference = self.references.at(ocp.limit_duration_s)
            total_s = reference.duration_s
        guess = bang_bang_guess(ocp, reference, fuel, total_s)
        if not fuel and not ocp.thrusters and not ocp.options.single_axis:
            return self._time_optimal_torque(guess), guess
        if not fuel and not ocp.options.single_axis:
            solution, self.report = thruster_time_optimal(
                ocp, guess, search_settings(ocp.options, self._bulk_intervals())
            )
            return solution, guess
        solution = transcribe_and_solve(
            ocp,
            fuel=fuel,
            horizon=Horizon(duration_s if fuel else None, self._bulk_intervals()),
            guess=guess,
        )
        return solution, guess

    def _time_optimal_torque(self, guess: InitialGuess) -> NlpSolution:
        """The torque-level time-optimal slew: the torque box's global optimum (the rigid
        body's, :mod:`casadi_debris.slews._global_slew`) when the engines can give its
        torque; else a local optimum within their torque set, started from it.

        The box is the bounding box of the engines' torque set at zero net force (the
        rule of the allocator that flies the slew and of its limit check,
        :func:`~casadi_debris.slews._ocp_problem.torque_set_box`): the set lies in the
        box, so the box's optimum is never longer than the set's, and one inside the set
        is the set's global optimum. The box holds torques the engines cannot give
        together (its corners), so its optimum often leaves the set; it is then the
        start of a collocation solve within the set, whose result IPOPT gives as a local
        optimum (``report["optimum"]`` says which; ``report["box_duration_s"]``, the
        box's optimum, is a lower bound on the set's).
        """
        ocp = self.ocp
        found = global_time_optimal(
            RigidBody(ocp.inertia, ocp.upper, ocp.lower),
            ocp.target,
            search_settings(ocp.options, self._bulk_intervals()),
        )
        self.report = dict(found.report)
        gauge = _torque_set_gauge(ocp, found.torque_Nm)
        if gauge <= 1.0 + TORQUE_SET_TOLERANCE:
            self.report["optimum"] = "global: the torque box's, inside the engines' torque set"
            return NlpSolution(found.knots_s, found.torque_Nm, found.status, 0.0)
        box_s = float(found.knots_s[-1])
        start = shaped_guess(found.knots_s, found.torque_Nm, guess.peak_rate_rad_s)
        try:
            solution = transcribe_and_solve(
                ocp, fuel=False, horizon=Horizon(None, self._bulk_intervals()), guess=start
            )
        except SlewNotConvergedError:
            # From the eigenaxis bang-bang instead (inside the set about a principal axis).
            solution = transcribe_and_solve(
                ocp, fuel=False, horizon=Horizon(None, self._bulk_intervals()), guess=guess
            )
        self.report["optimum"] = (
            "local: within the engines' torque set, started from the global optimum of its "
            f"bounding box ({box_s:.1f} s, a lower bound, which needs {gauge:.2f} x the set)"
        )
        self.report["box_duration_s"] = box_s
        return solution

    def _bulk_intervals(self) -> int:
        return self.ocp.options.intervals or RIGID_INTERVALS

    def _energy_limit(self) -> tuple[float, float]:
        """(limit, bang-bang energy), J.

        See :func:`~casadi_debris.slews._modal_window.energy_limit`.
        """
        ocp = self.ocp
        reference = self.references.at(ocp.limit_duration_s)
        return energy_limit(ocp, reference, ocp.options.residual_energy_fraction)

    def _solve_rigid_or_shaped(
        self,
        fuel: bool,
        duration_s: float | None,
        check_vibration: bool,
        *,
        method: str = "shaper",
    ) -> SlewProfile:
        """The rigid OCP; when flexible, its result through the ZV shaper.

        ``method`` is what ``settings["flexible_method"]`` says of a flexible slew.
        """
        ocp = self.ocp
        started = time.perf_counter()
        shaper = self.shaper() if ocp.flexible_model is not None else None
        if shaper is not None and fuel and duration_s is not None:
            duration_s = duration_s - float(shaper[0][-1])  # the shaper stretches the profile
        solution, _ = self._solve_rigid(fuel, duration_s)
        solve_time = time.perf_counter() - started
        figures: dict[str, Any] = {**self.report, "control_intervals": self._bulk_intervals()}
        if shaper is not None:
            shaper_times, shaper_amplitudes, shaped_frequencies = shaper
            knots, controls = shape(
                solution.knots_s, solution.controls, shaper_times, shaper_amplitudes
            )
            figures = {
                **figures,
                "flexible_method": method,
                "rigid_duration_s": float(solution.knots_s[-1]),
                "shaped_frequencies_rad_s": shaped_frequencies,
                "shaper_length_s": float(shaper_times[-1]),
                "residual_energy_limit_J": self._energy_limit()[0],
            }
            solution = dataclasses.replace(solution, knots_s=knots, controls=controls)
        return slew_profile(
            ocp,
            solution,
            fuel=fuel,
            solve_time_s=solve_time,
            check_vibration=check_vibration,
            figures=figures,
        )

    def _solve_modal(
        self, fuel: bool, duration_s: float | None, check_vibration: bool
    ) -> SlewProfile:
        """Rigid bulk and fine window, the vibration left bounded in closed form
        (:mod:`casadi_debris.slews._modal_window`)."""
        ocp = self.ocp
        shaper_times, shaper_amplitudes, _ = self.shaper()
        shaper_length = float(shaper_times[-1])
        reference_started = time.perf_counter()
        limit, reference_energy = self._energy_limit()
        reference_time = time.perf_counter() - reference_started
        started = time.perf_counter()
        window_s = window_length_s(shaper_length)
        # Guess: the rigid optimum through the ZV shaper. Its length must be nearly right:
        # the modes' phase at the end turns by omega dT, 36 rad per second of change.
        rigid_length = None
        if fuel and duration_s is not None:
            rigid_length = self._rigid_length(duration_s - shaper_length)
        rigid, guess = self._solve_rigid(fuel, rigid_length)
        knots, controls = shape(rigid.knots_s, rigid.controls, shaper_times, shaper_amplitudes)
        if fuel and duration_s is not None:  # squeezed into the duration if it came out longer
            knots = knots * min(1.0, duration_s / float(knots[-1]))
        solution = transcribe_and_solve(
            ocp,
            fuel=fuel,
            horizon=Horizon(
                duration_s - window_s if fuel and duration_s is not None else None,
                self._bulk_intervals(),
                WINDOW_INTERVALS,
                window_s / WINDOW_INTERVALS,
            ),
            guess=shaped_guess(knots, controls, guess.peak_rate_rad_s),
            vibration=VibrationBound.of(ocp, ENERGY_MARGIN * limit),
        )
        figures = {
            **{f"rigid_{key}": value for key, value in self.report.items()},
            "flexible_method": "ocp",
            "window_s": window_s,
            "window_intervals": WINDOW_INTERVALS,
            "rigid_duration_s": float(rigid.knots_s[-1]),
            "predicted_residual_energy_J": solution.predicted_energy_J,
            "residual_energy_limit_J": limit,
            "bang_bang_residual_energy_J": reference_energy,
            "reference_energy_time_s": reference_time,
            "shaper_length_s": shaper_length,
        }
        return slew_profile(
            ocp,
            solution,
            fuel=fuel,
            solve_time_s=time.perf_counter() - started,
            check_vibration=check_vibration,
            figures=figures,
        )

    def _rigid_length(self, wanted_s: float) -> float:
        """Length (s) of the rigid slew whose shaped optimum guesses a fuel-optimal
        flexible one: ``wanted_s``, the duration less the shaper's length, if feasible."""
        if wanted_s >= self.ocp.limit_duration_s:
            return wanted_s
        # Within a shaper's length of the minimum the rigid problem may have no
        # solution: ask it for no less than 1.001 x its own minimum.
        fastest, _ = self._solve_rigid(False, None)
        return max(wanted_s, 1.001 * float(fastest.knots_s[-1]))


def time_optimal_slew(
    problem: Problem | RigidBody,
    axis: str | Sequence[float] = "z",
    angle_rad: float = math.pi,
    *,
    target: SlewTarget | None = None,
    duration_s: float | None = None,
    options: OptimalSlewSettings | None = None,
    **settings: Any,
) -> SlewProfile:
    """Minimum-time rest-to-rest slew (free final time, nonlinear attitude dynamics).

    Torque-level rigid slews (and every slew of a :class:`RigidBody`) are searched
    globally: several starts, in parallel, then the best one's switch times refined
    and verified by integration (:mod:`casadi_debris.slews._global_slew`); the
    settings report the starts, the local optima found and the verification
    residual, and a ``logging`` warning says when starts disagree.

    Parameters
    ----------
    problem : Problem or RigidBody
        The debris and its swarm, or a plain rigid body (an inertia and a torque box:
        rigid, torque level; ``fuel_kg`` is then nan, there being no engines).
    axis, angle_rad
        Eigenaxis (``"x"``, ``"-y"``, or any three numbers, normalised) and angle in
        (0, pi] rad (ignored when ``target`` is given).
    target : SlewTarget, optional
        Any rest-to-rest attitude pair.
    duration_s : float, optional
        A deadline (s): the slew must not take longer. Checked after the solve.
    options : OptimalSlewSettings, optional
        How the slew is modelled, solved and checked (default ``OptimalSlewSettings()``).
    **settings
        Any field of :class:`OptimalSlewSettings` by name (``flexible``, ``thrusters``,
        ``starts``, ...), in place of the value in ``options``.

    Returns
    -------
    SlewProfile

    Raises
    ------
    InputShapeError
        A bad option or target, naming it.
    SlewInfeasibleError
        ``"infeasible: minimum is X s"`` when ``duration_s`` is shorter than the
        time-optimal slew; or IPOPT did not converge.

    Examples
    --------
    >>> from casadi_debris import load_problem
    >>> slew = time_optimal_slew(load_problem(), "z", math.pi, check_vibration=False)
    >>> round(slew.duration_s)
    918

    The benchmark of Bilimoria & Wie (1993), J = I and |u_i| <= 1:

    >>> body = RigidBody(inertia_kgm2=np.eye(3), torque_max_Nm=(1, 1, 1))
    >>> slew = time_optimal_slew(body, axis=(0, 0, 1), angle_rad=math.pi, workers=1)
    >>> round(slew.duration_s, 4), round(slew.limit_duration_s, 4)
    (3.2431, 3.5449)
    """
    options = OptimalSlewSettings.merged("time_optimal_slew", options, settings)
    if duration_s is not None:
        _check_finite_duration(duration_s)
    if isinstance(problem, RigidBody):
        return _rigid_body_slew(problem, axis, angle_rad, target, duration_s, options)
    solver = _solver(problem, axis, angle_rad, target, options)
    fastest = solver.solve(
        fuel=False, duration_s=None, check_vibration=options.check_vibration and duration_s is None
    )
    if duration_s is None:
        return fastest
    _check_not_below(duration_s, fastest)
    if not options.check_vibration:
        return fastest
    # The deadline is met: now the (long) check on the flexible model.
    return _vibration_checked(solver.ocp, fastest)


def _vibration_checked(ocp: SlewOcp, slew: SlewProfile) -> SlewProfile:
    """``slew`` with the vibration it leaves on the full flexible model."""
    flexible = ocp.problem if ocp.flexible_model is None else ocp.flexible_model
    vibration, energy = residual_vibration(
        flexible, ocp.target, slew.input_function, slew.time_s, slew.duration_s
    )
    return dataclasses.replace(slew, residual_vibration_rad=vibration, residual_energy_J=energy)


def fuel_optimal_slew(
    problem: Problem,
    axis: str | Sequence[float] = "z",
    angle_rad: float = math.pi,
    *,
    duration_s: float,
    target: SlewTarget | None = None,
    options: OptimalSlewSettings | None = None,
    **settings: Any,
) -> SlewProfile:
    """Least-propellant rest-to-rest slew of a given duration.

    Parameters are those of :func:`time_optimal_slew`, with ``duration_s`` (s) the
    slew's length; ``single_axis`` does not apply. Durations below the eigenaxis
    bang-bang that fits the engines' torque set (gyroscopic torque included) are checked
    against the time-optimal slew first.

    Raises
    ------
    InputShapeError
        A bad option or target, naming it.
    SlewInfeasibleError
        ``"infeasible: minimum is X s"`` when ``duration_s`` is shorter than the
        time-optimal slew; or IPOPT did not converge.

    Examples
    --------
    >>> from casadi_debris import load_problem
    >>> slew = fuel_optimal_slew(load_problem(), duration_s=1228.0, check_vibration=False)
    >>> round(slew.fuel_kg * 1e6)
    210
    """
    options = OptimalSlewSettings.merged("fuel_optimal_slew", options, settings)
    if isinstance(problem, RigidBody):
        raise InputShapeError(
            "problem: a fuel-optimal slew needs a Problem (a RigidBody has no engines to "
            "burn propellant)"
        )
    if options.single_axis:
        raise InputShapeError("single_axis applies to time-optimal slews only")
    _check_finite_duration(duration_s)
    solver = _solver(problem, axis, angle_rad, target, options)
    if duration_s < _flyable_eigenaxis_s(solver.ocp):
        # No eigenaxis bang-bang this short fits the engines' torque set, but three free axes
        # can beat it (Bilimoria & Wie 1993): ask the time-optimal OCP.
        _check_not_below(
            duration_s, solver.solve(fuel=False, duration_s=None, check_vibration=False)
        )
    return solver.solve(fuel=True, duration_s=duration_s, check_vibration=options.check_vibration)


def _rigid_body_slew(
    body: RigidBody,
    axis: str | Sequence[float],
    angle_rad: float,
    target: SlewTarget | None,
    duration_s: float | None,
    options: OptimalSlewSettings,
) -> SlewProfile:
    """The time-optimal slew of a plain rigid body, searched globally."""
    for name in ("flexible", "thrusters", "single_axis"):
        if getattr(options, name):
            raise InputShapeError(
                f"{name}: applies to the slew of a Problem (a RigidBody has no arrays, "
                "no engines, and is searched on all three axes)"
            )
    goal = slew_about_axis(axis, angle_rad) if target is None else target
    started = time.perf_counter()
    scaled = body.scaled(options.torque_fraction)
    intervals = options.intervals or RIGID_INTERVALS
    found = global_time_optimal(scaled, goal, search_settings(options, intervals))
    profile = rigid_body_profile(
        scaled,
        goal,
        found,
        sample_s=options.sample_s,
        solve_time_s=time.perf_counter() - started,
        figures={
            "torque_fraction": options.torque_fraction,
            "control_intervals": intervals,
            "single_axis": False,
        },
    )
    if duration_s is not None:
        _check_not_below(duration_s, profile)
    return profile


def _solver(
    problem: Problem,
    axis: str | Sequence[float],
    angle_rad: float,
    target: SlewTarget | None,
    options: OptimalSlewSettings,
) -> _SlewSolver:
    """The solver of the slew about ``axis`` by ``angle_rad``, or to ``target``."""
    goal = slew_about_axis(axis, angle_rad) if target is None else target
    return _SlewSolver(SlewOcp(problem, goal, options))


def _flyable_eigenaxis_s(ocp: SlewOcp) -> float:
    """The eigenaxis bang-bang time within the OCP's torque set (its net-force rule, times
    its torque fraction), gyroscopic torque included, s: every longer duration has a
    feasible profile (a slower bang-bang)."""
    fraction = ocp.options.torque_fraction

    def use(torque_Nm: np.ndarray) -> np.ndarray:
        return authority_use(ocp.geometry, torque_Nm, ocp.zero_net_force) / fraction

    return eigenaxis_duration_s(ocp.target.angle_rad, ocp.inertia, ocp.target.axis_B, use)


def _check_finite_duration(duration_s: float) -> None:
    if not math.isfinite(duration_s):
        raise InputShapeError(f"duration_s: must be finite, got {duration_s}")


def _check_not_below(duration_s: float, fastest: SlewProfile) -> None:
    """Raise unless ``duration_s`` is at least the time-optimal slew's length."""
    if duration_s < fastest.duration_s:
        raise SlewInfeasibleError(f"infeasible: minimum is {fastest.duration_s:.6g} s")


def _torque_set_gauge(ocp: SlewOcp, torque_Nm: np.ndarray) -> float:
    """The largest share of the OCP's torque set that torques (shape (k, 3), N m) need:
    max over samples and facets of n_i . tau / b_i (at most 1 inside the set; infinite
    for a torque beyond a facet through the origin)."""
    facets = ocp.torque_set()
    if facets is None:
        return 0.0
    normals, offsets = facets
    reach = np.asarray(torque_Nm) @ normals.T
    positive = offsets > 0.0
    inside_flat = bool(np.all(reach[:, ~positive] <= 0.0))
    gauge = float(np.max(reach[:, positive] / offsets[positive], initial=0.0))
    return gauge if inside_flat else math.inf
