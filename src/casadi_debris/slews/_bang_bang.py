"""The paper's slew reference: rest-to-rest eigenaxis bang-bang (after Marshall & Pellegrino 2023).

Profile
-------
The eigenaxis angle theta(t) (see :mod:`casadi_debris.slews._maneuver`) follows a
symmetric accelerate / coast / decelerate law with angular acceleration
magnitude a = torque_fraction * alpha_max. With smoothed switching the
acceleration ramps linearly over ``smoothing_s`` at every switch (a trapezoidal
acceleration, i.e. bounded torque rate), which keeps the array modes from being
hit by torque steps. Per phase of length D (ramp t_r, hold D - 2 t_r, ramp t_r)
the rate grows by omega_c = a (D - t_r) and, the phase being symmetric, the
angle by omega_c D / 2, so with a coast t_c

    Theta = omega_c (D + t_c),     T = 2 D + t_c.

Given a (no rate limit, no duration):  a (D - t_r) D = Theta,
    D = (t_r + sqrt(t_r^2 + 4 Theta / a)) / 2,  t_c = 0.
Rate limit omega_max below a (D - t_r):  D = omega_max / a + t_r,  t_c = Theta / omega_max - D.
Given T only (no coast):  D = T / 2,  a = Theta / ((D - t_r) D)  (the torque fraction follows).
Given T and a (coast fills the time):  D^2 - (T + t_r) D + t_r T + Theta / a = 0, smaller root;
    feasible when (T - t_r)^2 >= 4 Theta / a, i.e. T >= t_r + 2 sqrt(Theta / a).

With t_r = 0 and no coast this is the time-optimal single-axis slew, T = 2 sqrt(Theta / a).

Torque: tau(t) = theta_ddot J e + theta_dot^2 (e x J e), J the full rigid inertia
of the model (hub, CubeSats and both arrays). The acceleration a is sized on that
whole torque (:func:`sized_timing`): about a non-principal axis the gyroscopic
part e x J e is not small (on the paper's debris about (1, 1, 1) it needs 2.6 x the
y authority if a is sized from J e alone), so a is the largest for which the
torque stays within the engines' torque set at zero net force at every instant
(its gauge, :func:`~casadi_debris.slews._limits.authority_use`: the set is what the
allocator can give; a per-axis share above 1 with the gauge at most 1 is flyable).

The paper's 180 deg z slew "completed in 1228 s"
-------------------------------------------------
The paper gives the duration, not the parameters. ``duration_s=1228`` (no
coast, no smoothing) reproduces it with a = 1.482e-5 * 0.5614 rad/s^2, i.e. 56 %
of the 4.32 mNm z authority on the full rigid inertia (291 kg m^2). The same
1228 s follows from half the authority on the paper's I_tot, which leaves the
arrays out (2 sqrt(pi 256.4 / (0.5 * 4.32e-3)) = 1221 s with the toolkit's
hub + CubeSats inertia; 1195 s with the paper's 242 kg m^2 and 4.26 mNm).

Source: M. A. Marshall and S. Pellegrino, "Slew Maneuver Constraints for Agile
Flexible Spacecraft", AIAA SciTech 2023 (cited by the paper for its reference).
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import casadi as ca
import numpy as np

from casadi_debris.config import Problem
from casadi_debris.dynamics import Model, axis_angle_quaternion, build_model, quaternion_multiply
from casadi_debris.errors import InputShapeError, SlewInfeasibleError
from casadi_debris.slews._limits import authority_use
from casadi_debris.slews._maneuver import (
    SlewTarget,
    check_positive,
    check_torque_fraction,
    eigenaxis_acceleration_limit,
    rigid_limit_duration,
    slew_about_axis,
    torque_limits,
)
from casadi_debris.slews._profile import (
    ProfileRequest,
    ProfileSettings,
    SlewProfile,
    finish_profile,
    input_vector,
    sample_grid,
)

DEFAULT_SAMPLE_S = 1.0


@dataclass(frozen=True)
class BangBangTiming:
    """Phase lengths of a bang-(coast-)bang slew.

    Attributes
    ----------
    acceleration_rad_s2 : float
        Magnitude a of the eigenaxis acceleration.
    phase_s, ramp_s, coast_s : float
        Accelerating phase D (= decelerating phase), switch ramp t_r, coast t_c.
    """

    acceleration_rad_s2: float
    phase_s: float
    ramp_s: float
    coast_s: float

    @property
    def duration_s(self) -> float:
        return 2.0 * self.phase_s + self.coast_s

    @property
    def peak_rate_rad_s(self) -> float:
        return self.acceleration_rad_s2 * (self.phase_s - self.ramp_s)

    def segments(self) -> list[tuple[float, float, float, float]]:
        """(start s, length s, acceleration at start, at end) of each piece; no zero lengths."""
        a, ramp = self.acceleration_rad_s2, self.ramp_s
        hold = self.phase_s - 2.0 * ramp
        pieces = [
            (ramp, 0.0, a),
            (hold, a, a),
            (ramp, a, 0.0),
            (self.coast_s, 0.0, 0.0),
            (ramp, 0.0, -a),
            (hold, -a, -a),
            (ramp, -a, 0.0),
        ]
        segments, start = [], 0.0
        for length, a0, a1 in pieces:
            if length > 0.0:
                segments.append((start, length, a0, a1))
                start += length
        return segments


def bang_bang_timing(
    angle_rad: float,
    alpha_max_rad_s2: float,
    *,
    duration_s: float | None = None,
    torque_fraction: float | None = None,
    rate_limit_rad_s: float | None = None,
    smoothing_s: float = 0.0,
) -> BangBangTiming:
    """Solve the bang-bang phase lengths (module notes); raises on impossible requests.

    Parameters
    ----------
    angle_rad : float
        Eigenaxis angle Theta.
    alpha_max_rad_s2 : float
        Largest eigenaxis acceleration of the full torque authority.
    duration_s : float, optional
        Required slew time T.
    torque_fraction : float, optional
        a / alpha_max in (0, 1]; default 1 without a duration.
    rate_limit_rad_s : float, optional
        Largest eigenaxis rate (not together with ``duration_s``).
    smoothing_s : float
        Ramp time t_r of the acceleration at each switch.
    """
    theta = angle_rad
    ramp = float(smoothing_s)
    if not math.isfinite(ramp) or ramp < 0.0:
        raise InputShapeError(f"smoothing_s: must be >= 0, got {smoothing_s}")
    if torque_fraction is not None:
        check_torque_fraction(torque_fraction)
    if rate_limit_rad_s is not None:
        check_positive("rate_limit", rate_limit_rad_s)

    if duration_s is not None:
        if not math.isfinite(duration_s):
            raise InputShapeError(f"duration_s: must be finite, got {duration_s}")
        if rate_limit_rad_s is not None:
            raise InputShapeError("give a duration or a rate limit, not both")
        a = alpha_max_rad_s2 * (1.0 if torque_fraction is None else torque_fraction)
        minimum = ramp + 2.0 * math.sqrt(theta / a)
        if duration_s < minimum * (1.0 - 1e-12):
            raise SlewInfeasibleError(f"infeasible: minimum is {minimum:.6g} s")
        if torque_fraction is None:  # pure bang-bang: the acceleration fills the time
            phase = duration_s / 2.0
            a = theta / ((phase - ramp) * phase)
            coast = 0.0
        else:
            discriminant = max((duration_s - ramp) ** 2 - 4.0 * theta / a, 0.0)
            phase = ((duration_s + ramp) - math.sqrt(discriminant)) / 2.0
            coast = max(duration_s - 2.0 * phase, 0.0)
    else:
        a = alpha_max_rad_s2 * (1.0 if torque_fraction is None else torque_fraction)
        phase = (ramp + math.sqrt(ramp**2 + 4.0 * theta / a)) / 2.0
        coast = 0.0
        if rate_limit_rad_s is not None and a * (phase - ramp) > rate_limit_rad_s:
            phase = rate_limit_rad_s / a + ramp
            coast = theta / rate_limit_rad_s - phase
    if phase < 2.0 * ramp:
        raise InputShapeError(
            f"smoothing_s: {ramp:g} s is longer than half the acceleration phase "
            f"({phase:.6g} s); shorten it"
        )
    return BangBangTiming(a, phase, ramp, coast)


def _piecewise_motion(timing: BangBangTiming, angle_rad: float, t: ca.SX) -> ca.SX:
    """[theta, theta_dot, theta_ddot](t) exactly integrated over the pieces; rest outside."""
    segments = timing.segments()
    start_values = []
    theta, rate = 0.0, 0.0
    for _, length, a0, a1 in segments:
        start_values.append((theta, rate))
        theta += rate * length + a0 * length**2 / 2.0 + (a1 - a0) * length**2 / 6.0
        rate += (a0 + a1) * length / 2.0
    # After the end: at rest on target, a constant (DM) until the first piece wraps it.
    motion: ca.DM | ca.SX = ca.vertcat(angle_rad, 0.0, 0.0)
    for (start, length, a0, a1), (theta0, rate0) in reversed(
        list(zip(segments, start_values, strict=True))
    ):
        s = t - start
        slope = (a1 - a0) / length
        piece = ca.vertcat(
            theta0 + rate0 * s + a0 * s**2 / 2.0 + slope * s**3 / 6.0,
            rate0 + a0 * s + slope * s**2 / 2.0,
            a0 + slope * s,
        )
        motion = ca.if_else(t < start + length, piece, motion)
    return ca.if_else(t < 0.0, ca.vertcat(0.0, 0.0, 0.0), motion)


def _eigenaxis_functions(
    timing: BangBangTiming, goal: SlewTarget, inertia: np.ndarray
) -> tuple[ca.Function, ca.Function]:
    """The bang-bang's model input and motion as functions of time.

    Returns
    -------
    input_function : casadi.Function
        ``u(t)``: the model input, the torque J alpha e + omega^2 e x (J e) that turns
        the rigid body about the fixed eigenaxis e (N m), the rest zero.
    motion_function : casadi.Function
        ``motion(t)``: [angle (rad), rate (rad/s), acceleration (rad/s^2)] about e.
    """
    t = ca.SX.sym("t")
    motion = _piecewise_motion(timing, goal.angle_rad, t)
    e = ca.DM(goal.axis_B)
    moment = ca.DM(inertia) @ e
    torque = motion[2] * moment + motion[1] ** 2 * ca.cross(e, moment)
    input_function = ca.Function("slew_input", [t], [input_vector(torque)], ["t"], ["u"])
    motion_function = ca.Function("slew_motion", [t], [motion], ["t"], ["motion"])
    return input_function, motion_function


def _about_axis(goal: SlewTarget, angle_rad: np.ndarray) -> np.ndarray:
    """Attitudes q_BN (scalar first, shape (n, 4)) turned from the initial one by
    ``angle_rad`` (shape (n,)) about the eigenaxis."""
    return quaternion_multiply(goal.q_initial_BN, axis_angle_quaternion(goal.axis_B, angle_rad))


def sized_timing(
    goal: SlewTarget,
    inertia_kgm2: np.ndarray,
    use: Callable[[np.ndarray], np.ndarray],
    *,
    duration_s: float | None = None,
    torque_fraction: float | None = None,
    rate_limit_rad_s: float | None = None,
    smoothing_s: float = 0.0,
) -> BangBangTiming:
    """The bang-bang whose torque, gyroscopic part included, fits the authority.

    The acceleration a is the largest for which the torque
    tau = theta_ddot J e + theta_dot^2 e x J e needs at most ``torque_fraction``
    (default 1) of the authority at every instant, ``use`` measuring the share a
    torque needs (convex and positively homogeneous). theta_ddot stays in [-a, a] and
    theta_dot^2 in [0, omega_peak^2], so the need is largest at one of the four
    corners (+-a, 0), (+-a, omega_peak^2): exact without a ramp (the corners are
    reached at the switch), a safe bound with one. Without ramp and rate limit
    omega_peak^2 = a Theta and a follows in closed form; otherwise by bisection
    (the need grows with a). A duration then sets the timing as
    :func:`bang_bang_timing` does, with this a as the largest acceleration.

    Parameters
    ----------
    goal : SlewTarget
    inertia_kgm2 : ndarray, shape (3, 3)
    use : callable
        Torques (k, 3) N m -> share of the authority each needs, shape (k,).
    duration_s, torque_fraction, rate_limit_rad_s, smoothing_s
        As in :func:`bang_bang_timing`.

    Raises
    ------
    SlewInfeasibleError
        ``"infeasible: minimum is X s ..."`` for a duration below the fastest bang-bang
        that fits; the authority gives no torque the slew needs.
    """
    if torque_fraction is not None:
        check_torque_fraction(torque_fraction)
    if duration_s is not None and rate_limit_rad_s is not None:
        raise InputShapeError("give a duration or a rate limit, not both")
    target = 1.0 if torque_fraction is None else torque_fraction
    moment = np.asarray(inertia_kgm2, dtype=float) @ goal.axis_B
    gyroscopic = np.cross(goal.axis_B, moment)
    per_acceleration = float(np.max(use(np.array([moment, -moment]))))
    if not math.isfinite(per_acceleration) or per_acceleration <= 0.0:
        raise SlewInfeasibleError("infeasible: the engines give no torque the slew needs")

    def timing_at(a: float) -> BangBangTiming:
        return bang_bang_timing(
            goal.angle_rad,
            a,
            torque_fraction=1.0,
            rate_limit_rad_s=rate_limit_rad_s,
            smoothing_s=smoothing_s,
        )

    if smoothing_s == 0.0 and rate_limit_rad_s is None:
        corners = np.array([m + goal.angle_rad * gyroscopic for m in (moment, -moment)])
        acceleration = target / max(per_acceleration, float(np.max(use(corners))))
    else:
        upper = target / per_acceleration
        acceleration = _bisected(timing_at, moment, gyroscopic, use, upper, target)
    try:
        return bang_bang_timing(
            goal.angle_rad,
            acceleration,
            duration_s=duration_s,
            torque_fraction=None if duration_s is not None and torque_fraction is None else 1.0,
            rate_limit_rad_s=rate_limit_rad_s,
            smoothing_s=smoothing_s,
        )
    except SlewInfeasibleError as error:
        raise SlewInfeasibleError(
            f"{error} (the fastest eigenaxis bang-bang whose torque, gyroscopic part "
            f"included, needs at most {target:.4g} x the authority at every instant)"
        ) from None


def timing_need(
    timing: BangBangTiming,
    moment: np.ndarray,
    gyroscopic: np.ndarray,
    use: Callable[[np.ndarray], np.ndarray],
) -> float:
    """The largest share of the authority the bang-bang's torque needs (corners of
    :func:`sized_timing`); ``moment`` J e and ``gyroscopic`` e x J e, shape (3,)."""
    a, rate2 = timing.acceleration_rad_s2, timing.peak_rate_rad_s**2
    corners = np.array([a * moment, -a * moment, a * moment + rate2 * gyroscopic])
    corners = np.vstack([corners, -a * moment + rate2 * gyroscopic])
    return float(np.max(use(corners)))


BISECTION_STEPS = 48


def _bisected(
    timing_at: Callable[[float], BangBangTiming],
    moment: np.ndarray,
    gyroscopic: np.ndarray,
    use: Callable[[np.ndarray], np.ndarray],
    upper: float,
    target: float,
) -> float:
    """The largest acceleration in (0, ``upper``] whose timing needs at most ``target``
    of the authority; a timing that cannot be built (a ramp longer than half its
    phase) counts as too fast."""
    low, high = 0.0, upper
    for _ in range(BISECTION_STEPS):
        middle = 0.5 * (low + high)
        try:
            fits = timing_need(timing_at(middle), moment, gyroscopic, use) <= target
        except InputShapeError:
            fits = False
        low, high = (middle, high) if fits else (low, middle)
    if low == 0.0:
        timing_at(high)  # raises what keeps every acceleration out (the ramp), or
        raise SlewInfeasibleError("infeasible: no bang-bang of this ramp fits the authority")
    return low


def bang_bang_slew(
    problem: Problem | Model,
    axis: str | Sequence[float] = "z",
    angle_rad: float = math.pi,
    *,
    target: SlewTarget | None = None,
    duration_s: float | None = None,
    torque_fraction: float | None = None,
    rate_limit_rad_s: float | None = None,
    smoothing_s: float = 0.0,
    sample_s: float = DEFAULT_SAMPLE_S,
    check_vibration: bool = True,
) -> SlewProfile:
    """Rest-to-rest eigenaxis bang-bang slew reference.

    Parameters
    ----------
    problem : Problem or Model
        The problem, or its rigid model already built (``build_model(problem, modes=[])``),
        J taken from it.
    axis, angle_rad
        Eigenaxis and angle (ignored when ``target`` is given).
    target : SlewTarget, optional
        Any rest-to-rest attitude pair (:func:`~casadi_debris.slews.slew_between`).
    duration_s, torque_fraction, rate_limit_rad_s, smoothing_s
        See :func:`sized_timing`: ``torque_fraction`` is the largest share of the
        authority (at zero net force, as the closed loop's allocator flies it) the
        torque may need at any instant, gyroscopic torque included; the paper's
        slew is ``duration_s=1228``.
    sample_s : float
        Output sample spacing (switching times are added).
    check_vibration : bool
        Integrate the torque on the full flexible model for the residual vibration.

    Returns
    -------
    SlewProfile
        ``settings`` holds torque_fraction (the share of the authority the torque
        needs at most), acceleration_rad_s2, peak_rate_rad_s, coast_s, smoothing_s.
        A duration below the fastest bang-bang that fits raises SlewInfeasibleError.

    Example
    -------
    >>> from casadi_debris import load_problem
    >>> slew = bang_bang_slew(load_problem(), "z", math.pi, duration_s=1228.0,
    ...                       check_vibration=False)
    >>> round(slew.duration_s)
    1228
    """
    started = time.perf_counter()
    check_positive("sample_s", sample_s)
    rigid = problem if isinstance(problem, Model) else build_model(problem, modes=[])
    goal = slew_about_axis(axis, angle_rad) if target is None else target
    inertia = np.array(rigid.rigid_inertia(rigid.nominal_parameters))
    # The time scale of the OCPs (J e alone); the profile itself is sized on its whole torque.
    alpha_max = eigenaxis_acceleration_limit(inertia, goal.axis_B, *torque_limits(rigid.geometry))
    use = _loop_authority_use(rigid)
    timing = sized_timing(
        goal,
        inertia,
        use,
        duration_s=duration_s,
        torque_fraction=torque_fraction,
        rate_limit_rad_s=rate_limit_rad_s,
        smoothing_s=smoothing_s,
    )
    return _profile(
        rigid,
        goal,
        timing,
        inertia=inertia,
        alpha_max=alpha_max,
        use=use,
        sample_s=sample_s,
        check_vibration=check_vibration,
        started=started,
    )


def _loop_authority_use(rigid: Model) -> Callable[[np.ndarray], np.ndarray]:
    """The share of the authority torques need, as the closed loop's allocator flies them:
    their gauge in the engines' torque set at zero net force."""
    return functools.partial(authority_use, rigid.geometry, zero_net_force=True)


def eigenaxis_guess(model: Model, target: SlewTarget, duration_s: float) -> SlewProfile:
    """The eigenaxis bang-bang of ``duration_s`` with its acceleration from the duration
    alone, no sizing on the authority: where the optimal slews start (a guess need not
    be flyable, and about a non-principal axis this one is not; its ``limits`` say so).

    Parameters
    ----------
    model : Model
        The rigid model (its problem's).
    target : SlewTarget
    duration_s : float
        Its length, s (``SlewOcp.limit_duration_s``, the eigenaxis time on J e alone in
        the OCP's box, for a time-optimal slew's guess).
    """
    started = time.perf_counter()
    inertia = np.array(model.rigid_inertia(model.nominal_parameters))
    alpha_max = eigenaxis_acceleration_limit(inertia, target.axis_B, *torque_limits(model.geometry))
    # A duration below the pure-axis box's eigenaxis time (the OCP's box, the torque set's
    # bounding box, can be wider) is flown as the bang-bang of that duration, no coast.
    alpha_max = max(alpha_max, 4.0 * target.angle_rad / duration_s**2)
    timing = bang_bang_timing(target.angle_rad, alpha_max, duration_s=duration_s)
    return _profile(
        model,
        target,
        timing,
        inertia=inertia,
        alpha_max=alpha_max,
        use=_loop_authority_use(model),
        sample_s=DEFAULT_SAMPLE_S,
        check_vibration=False,
        started=started,
    )


def _profile(
    rigid: Model,
    goal: SlewTarget,
    timing: BangBangTiming,
    *,
    inertia: np.ndarray,
    alpha_max: float,
    use: Callable[[np.ndarray], np.ndarray],
    sample_s: float,
    check_vibration: bool,
    started: float,
) -> SlewProfile:
    """The bang-bang of ``timing`` sampled every ``sample_s`` seconds (and at its
    switches) as a profile; ``inertia`` (kg m^2, shape (3, 3)) and ``alpha_max``
    (rad/s^2) are the rigid body's, ``use`` the share of the authority torques need
    (:func:`sized_timing`), ``started`` the ``time.perf_counter`` at the call."""
    moment = inertia @ goal.axis_B
    need = timing_need(timing, moment, np.cross(goal.axis_B, moment), use)
    input_function, motion_function = _eigenaxis_functions(timing, goal, inertia)
    total = timing.duration_s
    knots = np.cumsum([0.0] + [length for _, length, _, _ in timing.segments()])
    knots[-1] = total
    grid = sample_grid(total, sample_s, knots)
    values = np.array(motion_function.map(len(grid))(grid)).T
    figures = {
        "acceleration_rad_s2": timing.acceleration_rad_s2,
        "peak_rate_rad_s": timing.peak_rate_rad_s,
        "coast_s": timing.coast_s,
        "smoothing_s": timing.ramp_s,
        "inertia_about_axis_kgm2": float(goal.axis_B @ inertia @ goal.axis_B),
    }
    request = ProfileRequest(
        method="bang-bang",
        target=goal,
        flexible=False,
        thrusters=False,
        time_s=grid,
        quaternion_BN=_about_axis(goal, values[:, 0]),
        rate_rad_s=values[:, 1:2] * goal.axis_B,
        acceleration_rad_s2=values[:, 2:3] * goal.axis_B,
        input_function=input_function,
        knots_s=knots,
        duration_s=total,
        limit_duration_s=rigid_limit_duration(goal.angle_rad, alpha_max),
        solve_time_s=time.perf_counter() - started,
        solver_status="analytic",
        figures=figures,
    )
    return finish_profile(
        problem=rigid.problem,
        geometry=rigid.geometry,
        request=request,
        settings=ProfileSettings(torque_fraction=need, check_vibration=check_vibration),
        inertia_kgm2=inertia,
    )
