"""The low-thrust transfer as an optimal control problem on the orbit-averaged dynamics.

Why averaged: the transfer lasts over a year, thousands of revolutions; the
state is the five slow MEE and the mass, the control Edelbaum's yaw beta (and a
throttle eta for the propellant objective), held constant over a segment of
many revolutions (:mod:`casadi_debris.orbit.transfer_averaged`). So the optimum
is over yaw *laws per segment*, not over the thrust direction at every instant:
an optimum within that family.

Transcription: multiple shooting, RK4 substeps per segment, solved by IPOPT
(a local NLP solver: the returned optimum is local). It needs a guess that
obeys the dynamics (a flown trajectory, e.g. the Edelbaum guidance's or a
constant-yaw spiral): from states merely interpolated between the two orbits
IPOPT can stall in a locally infeasible point. The staging enters as phases:
burn b fires at its direction's force F_b and flow for its duration; every
burn but the last lasts its full life, the last its free duration ``T_last`` in
[0, its life]. Objectives:

- ``"time"``: throttle 1, minimise the transfer time (the sum of the burns);
- ``"propellant"``: throttle per segment in [0, 1], minimise m0 - mf with the
  transfer time at most ``time_limit_s``.

Terminal constraints: the target's semi-major axis and inclination (the node is
free; the eccentricity is not steered, it stays at its initial value because the
law has no in-plane radial part and J2's averaged rates leave e = 0 unmoved).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Literal

import casadi as ca
import numpy as np

from casadi_debris.orbit.transfer_averaged import N_SLOW, averaged_step
from casadi_debris.orbit.transfer_thrust import Burn
from casadi_debris.units import SECONDS_PER_DAY

Objective = Literal["time", "propellant"]
OBJECTIVES: tuple[Objective, ...] = ("time", "propellant")
DEFAULT_SEGMENTS_PER_BURN = 4
DEFAULT_SUBSTEPS = 4
IPOPT_TOLERANCE = 1e-9
MAX_ITERATIONS = 500


@dataclass(frozen=True, eq=False)
class OptimalTransfer:
    """The solved OCP on its grid.

    Attributes
    ----------
    time_s : ndarray, shape (N + 1,)
    elements : ndarray, shape (N + 1, 5)
        Slow MEE at the nodes.
    mass_kg : ndarray, shape (N + 1,)
    yaw_rad, throttle : ndarray, shape (N,)
        Control of each segment.
    burn : ndarray of int, shape (N,)
        Burn (index into the schedule) of each segment.
    objective : str
    success : bool
        IPOPT's verdict.
    status : str
    iterations : int
    solve_time_s : float
    """

    time_s: np.ndarray
    elements: np.ndarray
    mass_kg: np.ndarray
    yaw_rad: np.ndarray
    throttle: np.ndarray
    burn: np.ndarray
    objective: str
    success: bool
    status: str
    iterations: int
    solve_time_s: float


@dataclass(frozen=True)
class TransferTarget:
    """The OCP's data: start, target, earth and the burns it may use.

    ``guess`` is a trajectory to start from: (time [s], elements (n, 5), mass (n,), yaw (n,)).
    """

    x0: np.ndarray
    mass_kg: float
    radius_m: float
    inclination_rad: float
    earth: tuple[float, float, float]
    burns: list[Burn]
    guess: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def solve_transfer_ocp(
    dynamics: ca.Function,
    data: TransferTarget,
    *,
    objective: Objective = "time",
    time_limit_s: float | None = None,
    segments_per_burn: int = DEFAULT_SEGMENTS_PER_BURN,
    substeps: int = DEFAULT_SUBSTEPS,
) -> OptimalTransfer:
    """Minimum-time or minimum-propellant transfer over the burns of ``data``.

    Parameters
    ----------
    dynamics : casadi.Function
        :func:`~casadi_debris.orbit.transfer_averaged.averaged_dynamics`.
    data : TransferTarget
    objective : {"time", "propellant"}
    time_limit_s : float, optional
        Largest transfer time (required for ``"propellant"``).
    segments_per_burn, substeps : int
        Shooting segments per burn, RK4 steps per segment.
    """
    if objective == "propellant" and time_limit_s is None:
        raise ValueError("the propellant objective needs a time limit")
    opti = ca.Opti()
    n_burns = len(data.burns)
    n = n_burns * segments_per_burn
    scale = np.array([data.x0[0], 1.0, 1.0, 1.0, 1.0])
    xs = opti.variable(N_SLOW, n + 1)
    ms = opti.variable(1, n + 1)
    yaw = opti.variable(1, n)
    throttle = opti.variable(1, n) if objective == "propellant" else ca.DM.ones(1, n)
    last_days = opti.variable()
    last_s = last_days * SECONDS_PER_DAY
    segment_s = [
        (b.duration_s if i < n_burns - 1 else last_s) / segments_per_burn
        for i, b in enumerate(data.burns)
    ]
    opti.subject_to(xs[:, 0] == data.x0 / scale)
    opti.subject_to(ms[0] == 1.0)
    segment = _segment_function(dynamics, substeps)
    for j in range(n):
        burn = data.burns[j // segments_per_burn]
        params = ca.DM([*data.earth, burn.force_N, burn.flow_kg_s])
        x_next, m_next = segment(
            xs[:, j] * scale,
            ms[j] * data.mass_kg,
            ca.vertcat(yaw[j], throttle[j]),
            params,
            segment_s[j // segments_per_burn],
        )
        opti.subject_to(xs[:, j + 1] == x_next / scale)
        opti.subject_to(ms[j + 1] == m_next / data.mass_kg)
    _terminal(opti, xs[:, n] * scale, data)
    opti.subject_to(opti.bounded(-math.pi, yaw, math.pi))
    last_life_days = data.burns[-1].duration_s / SECONDS_PER_DAY
    opti.subject_to(opti.bounded(0.0, last_days, last_life_days))
    fixed_s = sum(b.duration_s for b in data.burns[:-1])
    total_days = fixed_s / SECONDS_PER_DAY + last_days
    if objective == "propellant":
        assert time_limit_s is not None
        opti.subject_to(opti.bounded(0.0, throttle, 1.0))
        opti.subject_to(total_days <= time_limit_s / SECONDS_PER_DAY)
        opti.minimize(1.0 - ms[n])
        opti.set_initial(throttle, 1.0)
    else:
        opti.minimize(total_days / last_life_days)
    guess_days = _initial_guess(opti, data, xs, ms, yaw, fixed_s, segments_per_burn, scale)
    opti.set_initial(last_days, min(max(guess_days, 0.1 * last_life_days), last_life_days))
    return _solve(opti, data, xs, ms, yaw, throttle, last_s, objective, segments_per_burn, scale)


def _segment_function(dynamics: ca.Function, substeps: int) -> ca.Function:
    """One shooting segment as a ``casadi.Function``, called by every segment.

    One function called N times keeps the NLP's expression graph (and its
    derivatives) the size of one segment, not of N.
    """
    x = ca.MX.sym("x", N_SLOW)
    mass = ca.MX.sym("m")
    control = ca.MX.sym("u", 2)
    params = ca.MX.sym("p", 5)
    step = ca.MX.sym("h")
    x_next, m_next = averaged_step(dynamics, x, mass, control, params, step, substeps)
    return ca.Function(
        "segment",
        [x, mass, control, params, step],
        [x_next, m_next],
        ["x", "m", "u", "p", "h"],
        ["x_next", "m_next"],
    )


def _terminal(opti: ca.Opti, x_end: ca.MX, data: TransferTarget) -> None:
    """Semi-major axis and inclination of the target; scaled to order one."""
    p, f, g, h, k = (x_end[i] for i in range(N_SLOW))
    opti.subject_to(p / (1.0 - f * f - g * g) / data.radius_m == 1.0)
    opti.subject_to(h * h + k * k == math.tan(0.5 * data.inclination_rad) ** 2)


def _initial_guess(
    opti: ca.Opti,
    data: TransferTarget,
    xs: ca.MX,
    ms: ca.MX,
    yaw: ca.MX,
    fixed_s: float,
    segments_per_burn: int,
    scale: np.ndarray,
) -> float:
    """Sample the guess trajectory on the OCP grid; returns the guessed last-burn length [days]."""
    times, elements, mass, yaw_guess = data.guess
    last_s = max(times[-1] - fixed_s, 0.0)
    durations = [b.duration_s for b in data.burns[:-1]] + [last_s]
    grid_s = np.minimum(_grid(durations, segments_per_burn), times[-1])
    x_guess = np.array([np.interp(grid_s, times, elements[:, i]) for i in range(N_SLOW)])
    opti.set_initial(xs, x_guess / scale[:, None])
    opti.set_initial(ms, np.interp(grid_s, times, mass) / data.mass_kg)
    opti.set_initial(yaw, np.interp(grid_s[:-1], times, yaw_guess))
    return last_s / SECONDS_PER_DAY


def _grid(durations_s: list[float], segments_per_burn: int) -> np.ndarray:
    """Node times [s] of burns of the given lengths, each cut into equal segments."""
    times = [0.0]
    for length in durations_s:
        base = times[-1]
        times += [base + length * (s + 1) / segments_per_burn for s in range(segments_per_burn)]
    return np.array(times)


def _solve(
    opti: ca.Opti,
    data: TransferTarget,
    xs: ca.MX,
    ms: ca.MX,
    yaw: ca.MX,
    throttle: ca.MX | ca.DM,
    last_s: ca.MX,
    objective: Objective,
    segments_per_burn: int,
    scale: np.ndarray,
) -> OptimalTransfer:
    """Run IPOPT; a failed solve is returned with its last iterate and ``success=False``."""
    opti.solver(
        "ipopt",
        {"print_time": False},
        {"print_level": 0, "tol": IPOPT_TOLERANCE, "max_iter": MAX_ITERATIONS, "sb": "yes"},
    )
    start = time.perf_counter()
    try:
        solution = opti.solve()
        value, success = solution.value, True
    except RuntimeError:
        value, success = opti.debug.value, False
    elapsed = time.perf_counter() - start
    stats = opti.stats()
    durations = [b.duration_s for b in data.burns[:-1]] + [float(value(last_s))]
    times = _grid(durations, segments_per_burn)
    n = len(data.burns) * segments_per_burn
    return OptimalTransfer(
        time_s=np.array(times),
        elements=(np.array(value(xs)).reshape(N_SLOW, n + 1) * scale[:, None]).T,
        mass_kg=np.array(value(ms)).ravel() * data.mass_kg,
        yaw_rad=np.array(value(yaw)).ravel(),
        throttle=np.array(value(throttle) if isinstance(throttle, ca.MX) else throttle).ravel(),
        burn=np.repeat(np.arange(len(data.burns)), segments_per_burn),
        objective=objective,
        success=success,
        status=str(stats.get("return_status", "")),
        iterations=int(stats.get("iter_count", -1)),
        solve_time_s=elapsed,
    )
