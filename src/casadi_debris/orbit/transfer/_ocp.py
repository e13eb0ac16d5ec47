"""The low-thrust transfer as an optimal control problem on the orbit-averaged dynamics.

Why averaged: the transfer lasts over a year, thousands of revolutions; the
state is the five slow MEE and the mass, the control Edelbaum's yaw beta (and a
throttle eta for the propellant objective), held constant over a segment of
many revolutions (:func:`~casadi_debris.orbit.transfer.averaged_dynamics`). So the optimum
is over yaw *laws per segment*, not over the thrust direction at every instant:
an optimum within that family.

Transcription: multiple shooting, RK4 substeps per segment, solved by IPOPT
(a local NLP solver: the returned optimum is local). It needs a guess that
obeys the dynamics (a flown trajectory, e.g. the Edelbaum guidance's or a
constant-yaw spiral): from states merely interpolated between the two orbits
IPOPT can stall in a locally infeasible point. The staging enters as a known
thrust schedule: burn b fires at its direction's force F_b and flow for its
duration; every burn but the last lasts its full life, the last its free
duration ``T_last`` in [0, its life]. The burns are cut into arcs (a few per
burn when they are few); the arcs are grouped into at most ``intervals``
shooting intervals of consecutive arcs, each with one yaw (and throttle) and
its arcs integrated one after the other inside it. So a weak swarm's hundred
burns give the NLP no more variables than the paper's seven, and the staging
stays exact (every burn boundary is an arc boundary). Objectives:

- ``"time"``: throttle 1, minimise the transfer time (the sum of the burns);
- ``"propellant"``: throttle per shooting interval in [0, 1], minimise m0 - mf with the
  transfer time at most ``time_limit_s``.

Terminal constraints: the target's semi-major axis and inclination (the node is
free; the eccentricity is not steered, it stays at its initial value because the
law has no in-plane radial part and J2's averaged rates leave e = 0 unmoved).
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass
from typing import Any, Literal

import casadi as ca
import numpy as np

from casadi_debris.orbit.transfer._averaged import N_SLOW, averaged_step
from casadi_debris.orbit.transfer._thrust import Burn
from casadi_debris.parallel import keep_ctrl_c
from casadi_debris.units import SECONDS_PER_DAY

Objective = Literal["time", "propellant"]
OBJECTIVES: tuple[Objective, ...] = ("time", "propellant")
DEFAULT_SEGMENTS_PER_BURN = 4
DEFAULT_SUBSTEPS = 4
# Parameters of one arc in a shooting interval: force [N], flow [kg/s], length [s].
ARC_PARAMS = 3
# Longest RK4 step: J2 turns the node about 1 deg a day, and RK4 on a rotation of
# theta per step shrinks the inclination vector by theta^6 / 144; at 4 days that
# is below 1e-9 per step, at a 20-day burn in one step 1e-5 (a tenth of the plane change
# over a long spiral).
MAX_STEP_S = 4.0 * SECONDS_PER_DAY
IPOPT_TOLERANCE = 1e-9
MAX_ITERATIONS = 500


@dataclass(frozen=True, eq=False)
class OptimalTransfer:
    """The solved OCP on its grid of arcs (N arcs; several may share a shooting interval).

    Attributes
    ----------
    time_s : ndarray, shape (N + 1,)
    elements : ndarray, shape (N + 1, 5)
        Slow MEE at the arc boundaries.
    mass_kg : ndarray, shape (N + 1,)
    yaw_rad, throttle : ndarray, shape (N,)
        Control of each arc (its shooting interval's).
    burn : ndarray of int, shape (N,)
        Burn (index into the schedule) of each arc.
    objective : str
    success : bool
        IPOPT's verdict.
    status : str
    iterations : int
    solve_time_s : float
    intervals : int
        Shooting intervals of the NLP.
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
    intervals: int = 0


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
    intervals: int | None = None,
) -> OptimalTransfer:
    """Minimum-time or minimum-propellant transfer over the burns of ``data``.

    Parameters
    ----------
    dynamics : casadi.Function
        :func:`~casadi_debris.orbit.transfer.averaged_dynamics`.
    data : TransferTarget
    objective : {"time", "propellant"}
    time_limit_s : float, optional
        Largest transfer time (required for ``"propellant"``).
    segments_per_burn : int
        Arcs per burn (equal parts of it).
    substeps : int
        RK4 steps per arc when an interval holds one arc; an interval of k arcs
        gives each ``ceil(substeps / k)``; in any case at least one step per
        :data:`MAX_STEP_S` of arc.
    intervals : int, optional
        Most shooting intervals (default: one per arc).
    """
    if objective == "propellant" and time_limit_s is None:
        raise ValueError("the propellant objective needs a time limit")
    grid = _ArcGrid.of(len(data.burns), segments_per_burn, intervals)
    opti = ca.Opti()
    n = len(grid.groups)
    scale = np.array([data.x0[0], 1.0, 1.0, 1.0, 1.0])
    xs = opti.variable(N_SLOW, n + 1)
    ms = opti.variable(1, n + 1)
    yaw = opti.variable(1, n)
    throttle = opti.variable(1, n) if objective == "propellant" else ca.DM.ones(1, n)
    last_days = opti.variable()
    last_s = last_days * SECONDS_PER_DAY
    opti.subject_to(xs[:, 0] == data.x0 / scale)
    opti.subject_to(ms[0] == 1.0)
    arc_x, arc_m = [], []
    functions: dict[tuple[int, ...], ca.Function] = {}
    for j, group in enumerate(grid.groups):
        steps = grid.steps(data.burns, group, substeps)
        if steps not in functions:
            functions[steps] = _segment_function(dynamics, steps)
        segment = functions[steps]
        arcs = [grid.arc_params(data.burns, a, last_s) for a in group]
        x_next, m_next = segment(
            xs[:, j] * scale,
            ms[j] * data.mass_kg,
            ca.vertcat(yaw[j], throttle[j]),
            ca.vertcat(*data.earth),
            ca.vertcat(*[v for arc in arcs for v in arc]),
        )
        arc_x.append(x_next)
        arc_m.append(m_next)
        opti.subject_to(xs[:, j + 1] == x_next[:, -1] / scale)
        opti.subject_to(ms[j + 1] == m_next[-1] / data.mass_kg)
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
    guess_days = _initial_guess(opti, data, grid, (xs, ms, yaw), fixed_s, scale)
    opti.set_initial(last_days, min(max(guess_days, 0.1 * last_life_days), last_life_days))
    trajectory = (ca.horzcat(*arc_x), ca.horzcat(*arc_m), yaw, throttle)
    return _solve(opti, data, grid, trajectory, last_s, objective)


@dataclass(frozen=True)
class _ArcGrid:
    """Arcs (burn, share of the burn) and their grouping into shooting intervals."""

    arcs: tuple[tuple[int, float], ...]
    groups: tuple[tuple[int, ...], ...]

    @classmethod
    def of(cls, n_burns: int, per_burn: int, intervals: int | None) -> _ArcGrid:
        """``per_burn`` equal arcs per burn, in at most ``intervals`` balanced groups."""
        arcs = tuple((b, 1.0 / per_burn) for b in range(n_burns) for _ in range(per_burn))
        count = len(arcs) if intervals is None else max(1, min(intervals, len(arcs)))
        cuts = np.linspace(0, len(arcs), count + 1).round().astype(int)
        groups = tuple(tuple(range(a, b)) for a, b in itertools.pairwise(cuts))
        return cls(arcs, groups)

    def arc_params(self, burns: list[Burn], arc: int, last_s: Any) -> tuple[Any, Any, Any]:
        """(force [N], flow [kg/s], length [s]) of an arc; the last burn's length is free."""
        burn, share = self.arcs[arc]
        length = last_s if burn == len(burns) - 1 else burns[burn].duration_s
        return burns[burn].force_N, burns[burn].flow_kg_s, share * length

    def steps(self, burns: list[Burn], group: tuple[int, ...], substeps: int) -> tuple[int, ...]:
        """RK4 steps of each arc of an interval: ``ceil(substeps / k)`` for k arcs, and at
        least one per :data:`MAX_STEP_S` of the arc (the last burn at its full life)."""
        share = -(-substeps // len(group))
        return tuple(
            max(share, math.ceil(self.arcs[a][1] * burns[self.arcs[a][0]].duration_s / MAX_STEP_S))
            for a in group
        )

    def times_s(self, burns: list[Burn], last_s: float) -> np.ndarray:
        """Arc boundary times [s], shape (N + 1,)."""
        lengths = [float(self.arc_params(burns, a, last_s)[2]) for a in range(len(self.arcs))]
        return np.concatenate([[0.0], np.cumsum(lengths)])

    def node_arcs(self) -> np.ndarray:
        """Index of the arc boundary at each shooting node, shape (intervals + 1,)."""
        return np.array([0] + [group[-1] + 1 for group in self.groups])

    def arc_interval(self) -> np.ndarray:
        """Shooting interval of each arc, shape (N,)."""
        return np.concatenate([np.full(len(g), j) for j, g in enumerate(self.groups)])


def _segment_function(dynamics: ca.Function, steps: tuple[int, ...]) -> ca.Function:
    """One shooting interval of arcs of ``steps`` RK4 steps each as a ``casadi.Function``.

    Inputs: state, mass, control ``[yaw, throttle]``, earth ``[mu, Re, J2]`` and
    the arcs' ``[force, flow, length]`` one after the other; outputs: the state
    (5, arcs) and mass (1, arcs) at the end of every arc. One function per layout
    of steps, called by every interval with that layout, keeps the NLP's
    expression graph (and its derivatives) the size of one interval. Not expanded
    to SX: for the paper that saves a tenth of IPOPT's time and costs almost the
    whole solve's CPU time again in building the expanded derivatives.
    """
    x = ca.MX.sym("x", N_SLOW)
    mass = ca.MX.sym("m")
    control = ca.MX.sym("u", 2)
    earth = ca.MX.sym("earth", 3)
    arc = ca.MX.sym("arcs", ARC_PARAMS * len(steps))
    states, masses = [], []
    state, m = x, mass
    for a, substeps in enumerate(steps):
        force, flow, length = (arc[ARC_PARAMS * a + i] for i in range(ARC_PARAMS))
        params = ca.vertcat(earth, force, flow)
        state, m = averaged_step(dynamics, state, m, control, params, length, substeps)
        states.append(state)
        masses.append(m)
    return ca.Function(
        "segment",
        [x, mass, control, earth, arc],
        [ca.horzcat(*states), ca.horzcat(*masses)],
        ["x", "m", "u", "earth", "arcs"],
        ["x_arcs", "m_arcs"],
    )


def _terminal(opti: ca.Opti, x_end: ca.MX, data: TransferTarget) -> None:
    """Semi-major axis and inclination of the target; scaled to order one."""
    p, f, g, h, k = (x_end[i] for i in range(N_SLOW))
    opti.subject_to(p / (1.0 - f * f - g * g) / data.radius_m == 1.0)
    opti.subject_to(h * h + k * k == math.tan(0.5 * data.inclination_rad) ** 2)


def _initial_guess(
    opti: ca.Opti,
    data: TransferTarget,
    grid: _ArcGrid,
    variables: tuple[ca.MX, ca.MX, ca.MX],
    fixed_s: float,
    scale: np.ndarray,
) -> float:
    """Sample the guess at the shooting nodes; returns the guessed last-burn length [days]."""
    xs, ms, yaw = variables
    times, elements, mass, yaw_guess = data.guess
    last_s = max(times[-1] - fixed_s, 0.0)
    grid_s = np.minimum(grid.times_s(data.burns, last_s)[grid.node_arcs()], times[-1])
    x_guess = np.array([np.interp(grid_s, times, elements[:, i]) for i in range(N_SLOW)])
    opti.set_initial(xs, x_guess / scale[:, None])
    opti.set_initial(ms, np.interp(grid_s, times, mass) / data.mass_kg)
    opti.set_initial(yaw, np.interp(grid_s[:-1], times, yaw_guess))
    return last_s / SECONDS_PER_DAY


def _solve(
    opti: ca.Opti,
    data: TransferTarget,
    grid: _ArcGrid,
    trajectory: tuple[ca.MX, ca.MX, ca.MX, ca.MX | ca.DM],
    last_s: ca.MX,
    objective: Objective,
) -> OptimalTransfer:
    """Run IPOPT; a failed solve is returned with its last iterate and ``success=False``."""
    opti.solver(
        "ipopt",
        {"print_time": False},
        {"print_level": 0, "tol": IPOPT_TOLERANCE, "max_iter": MAX_ITERATIONS, "sb": "yes"},
    )
    start = time.perf_counter()
    try:
        with keep_ctrl_c():
            solution = opti.solve()
        value, success = solution.value, True
    except RuntimeError:
        value, success = opti.debug.value, False
    elapsed = time.perf_counter() - start
    stats = opti.stats()
    arc_x, arc_m, yaw, throttle = trajectory
    n = len(grid.arcs)
    elements = np.array(value(arc_x)).reshape(N_SLOW, n)
    control = [np.array(value(c) if isinstance(c, ca.MX) else c).ravel() for c in (yaw, throttle)]
    interval = grid.arc_interval()
    return OptimalTransfer(
        time_s=grid.times_s(data.burns, float(value(last_s))),
        elements=np.vstack([data.x0, elements.T]),
        mass_kg=np.concatenate([[data.mass_kg], np.array(value(arc_m)).ravel()]),
        yaw_rad=control[0][interval],
        throttle=control[1][interval],
        burn=np.array([burn for burn, _ in grid.arcs]),
        objective=objective,
        success=success,
        status=str(stats.get("return_status", "")),
        iterations=int(stats.get("iter_count", -1)),
        solve_time_s=elapsed,
        intervals=len(grid.groups),
    )
