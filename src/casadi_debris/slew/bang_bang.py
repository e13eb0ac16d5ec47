"""The paper's slew reference: rest-to-rest eigenaxis bang-bang (after Marshall & Pellegrino 2023).

Profile
-------
The eigenaxis angle theta(t) (see :mod:`casadi_debris.slew.maneuver`) follows a
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
of the model (hub, CubeSats and both arrays).

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

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import casadi as ca
import numpy as np

from casadi_debris.config import Problem
from casadi_debris.errors import InputShapeError, SlewInfeasibleError
from casadi_debris.model import Model, build_model
from casadi_debris.model.attitude import axis_angle_quaternion, quaternion_multiply
from casadi_debris.slew.maneuver import (
    SlewTarget,
    check_positive,
    check_torque_fraction,
    eigenaxis_acceleration_limit,
    rigid_limit_duration,
    slew_about_axis,
    torque_limits,
)
from casadi_debris.slew.profile import SlewProfile, finish_profile, input_vector, sample_grid

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


def bang_bang_slew(
    problem: Problem,
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
    model: Model | None = None,
) -> SlewProfile:
    """Rest-to-rest eigenaxis bang-bang slew reference.

    Parameters
    ----------
    problem : Problem
    axis, angle_rad
        Eigenaxis and angle (ignored when ``target`` is given).
    target : SlewTarget, optional
        Any rest-to-rest attitude pair (:func:`~casadi_debris.slew.slew_between`).
    duration_s, torque_fraction, rate_limit_rad_s, smoothing_s
        See :func:`bang_bang_timing`; the paper's slew is ``duration_s=1228``.
    sample_s : float
        Output sample spacing (switching times are added).
    check_vibration : bool
        Integrate the torque on the full flexible model for the residual vibration.
    model : Model, optional
        Rigid model (``build_model(problem, modes=[])``) to take J from.

    Returns
    -------
    SlewProfile
        ``settings`` holds torque_fraction, acceleration_rad_s2, peak_rate_rad_s,
        coast_s, smoothing_s.

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
    rigid = build_model(problem, modes=[]) if model is None else model
    goal = slew_about_axis(axis, angle_rad) if target is None else target
    inertia = np.array(rigid.rigid_inertia(rigid.nominal_parameters))
    alpha_max = eigenaxis_acceleration_limit(inertia, goal.axis_B, *torque_limits(rigid.geometry))
    timing = bang_bang_timing(
        goal.angle_rad,
        alpha_max,
        duration_s=duration_s,
        torque_fraction=torque_fraction,
        rate_limit_rad_s=rate_limit_rad_s,
        smoothing_s=smoothing_s,
    )
    return _profile(
        problem,
        rigid,
        goal,
        timing,
        inertia=inertia,
        alpha_max=alpha_max,
        sample_s=sample_s,
        check_vibration=check_vibration,
        started=started,
    )


def _profile(
    problem: Problem,
    rigid: Model,
    goal: SlewTarget,
    timing: BangBangTiming,
    *,
    inertia: np.ndarray,
    alpha_max: float,
    sample_s: float,
    check_vibration: bool,
    started: float,
) -> SlewProfile:
    """The bang-bang of ``timing`` sampled every ``sample_s`` seconds (and at its
    switches) as a profile; ``inertia`` (kg m^2, shape (3, 3)) and ``alpha_max``
    (rad/s^2) are the rigid body's, ``started`` the ``time.perf_counter`` at the call."""
    input_function, motion_function = _eigenaxis_functions(timing, goal, inertia)
    total = timing.duration_s
    knots = np.cumsum([0.0] + [length for _, length, _, _ in timing.segments()])
    knots[-1] = total
    grid = sample_grid(total, sample_s, knots)
    values = np.array(motion_function.map(len(grid))(grid)).T
    settings = {
        "torque_fraction": timing.acceleration_rad_s2 / alpha_max,
        "acceleration_rad_s2": timing.acceleration_rad_s2,
        "peak_rate_rad_s": timing.peak_rate_rad_s,
        "coast_s": timing.coast_s,
        "smoothing_s": timing.ramp_s,
        "inertia_about_axis_kgm2": float(goal.axis_B @ inertia @ goal.axis_B),
    }
    return finish_profile(
        problem=problem,
        geometry=rigid.geometry,
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
        interval_thrust_N=None,
        duration_s=total,
        limit_duration_s=rigid_limit_duration(goal.angle_rad, alpha_max),
        solve_time_s=time.perf_counter() - started,
        solver_status="analytic",
        settings=settings,
        check_vibration=check_vibration,
    )
