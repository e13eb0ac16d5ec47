"""The time-optimal detumble as an optimal control problem over the averaged rates.

Only the body rates matter to a detumble: Euler's equations
``J omega' = tau - omega x J omega`` with the torque in the engines' polytope
(body axes); the attitude does not enter. The gyroscopic term keeps ``|H|`` and
the polhode label ``s = m . J^-1 m`` (``m = H / |H|``), so

    d|H|/dt = m . tau,     ds/dt = 2 (J^-1 m - s m) . tau / |H|,

while ``m`` runs round its polhode about once a second at 1 rad/s. Over the hours
of braking ``|H|`` and ``s`` change slowly (``|tau| / (|H| |omega|)`` is about
1e-6), and by averaging their drift is the mean over the polhode
(:mod:`~casadi_debris.simulation.detumble._polhode`).

Pontryagin's principle on the averaged system says which torque to give at each
point of the polhode: the one that minimises ``lambda_H m . tau + lambda_s (2 /
|H|) (J^-1 m - s m) . tau``, a vertex ``argmin_v w . v`` with
``w = cos(theta) m + sin(theta) (J^-1 m - s m) / (a_1 - a_3)``; ``theta = 0`` is the
closed loop's greedy braking, ``theta != 0`` trades braking for moving to a polhode
where the engines brake better. So the optimal control is one angle ``theta`` per
instant, and the OCP is two states: with ``x = ln(|H_0| / |H|)`` as the
independent variable,

    ds/dx = -B(s, theta) / A(s, theta),    dt/dx = -|H| / A(s, theta),

``A`` and ``B`` the polhode means of ``m . tau`` and ``2 (J^-1 m - s m) . tau``,
tabulated and interpolated by B-splines. Multiple shooting (Runge-Kutta 4) and
IPOPT minimise the time to bring ``|H|`` down to the largest momentum whose rates
can all be below the threshold. IPOPT may return a local optimum; the solution is
started from the greedy law and is never worse than it.

The answer is the optimum of the averaged problem: exact as ``|tau| / (|H| |omega|)
-> 0`` and, for the paper's tumble, within 0.2 % of a closed loop with a short
control period (the greedy law). It is not a bound in the strict sense; the
strict one, ``|H_0| / max |tau|``, is lower.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass

import casadi as ca
import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.config import Problem
from casadi_debris.errors import SimulationError
from casadi_debris.geometry import build_geometry
from casadi_debris.parallel import keep_ctrl_c
from casadi_debris.records import Record
from casadi_debris.simulation.detumble._polhode import (
    PolhodeAverages,
    PrincipalBody,
    polhode_averages,
)

LOGGER = logging.getLogger(__name__)

METHOD = "time-optimal OCP over the polhode-averaged rates (multiple shooting, IPOPT; local)"
N_LABELS = 121
N_ANGLES = 49
MAX_ANGLE_RAD = 1.3
N_INTERVALS = 60
SUBSTEPS = 4
# Central symmetry of the polytope, relative to its largest vertex.
SYMMETRY_RTOL = 1e-7


@dataclass(frozen=True, kw_only=True)
class DetumbleOcpSummary(Record):
    """Figures of the time-optimal detumble (averaged OCP).

    Attributes
    ----------
    method : str
    time_s, time_h : float
        Least time to bring ``|H|`` to ``final_momentum_Nms``.
    fuel_kg : float
        Propellant of that detumble.
    greedy_time_h, greedy_fuel_kg : float
        The same averaged model flown with the closed loop's greedy law (``theta = 0``).
    averaged_bound_h : float
        ``(|H_0| - h_end) / max_s |A(s, 0)|``: no control, averaged over the polhode,
        brakes faster than the greedy law on the best polhode (the maximum over the
        tabulated labels).
    initial_momentum_Nms, final_momentum_Nms : float
        ``|J omega_0|`` and the largest ``|H|`` whose rates can all be below the threshold.
    initial_label, final_label : float
        Polhode label ``s`` [1 / (kg m^2)] at the start and the end.
    solver_status : str
        IPOPT's return status.
    wall_time_s : float
    """

    method: str
    time_s: float
    time_h: float
    fuel_kg: float
    greedy_time_h: float
    greedy_fuel_kg: float
    averaged_bound_h: float
    initial_momentum_Nms: float
    final_momentum_Nms: float
    initial_label: float
    final_label: float
    solver_status: str
    wall_time_s: float


@dataclass(eq=False)
class DetumbleOcp:
    """The averaged OCP's solution along ``x = ln(|H_0| / |H|)``.

    Attributes
    ----------
    momentum_Nms : ndarray, shape (n + 1,)
    time_s : ndarray, shape (n + 1,)
    label : ndarray, shape (n + 1,)
        Polhode label ``s`` [1 / (kg m^2)].
    angle_rad : ndarray, shape (n,)
        ``theta`` over each interval.
    greedy_time_s : ndarray, shape (n + 1,)
        When the greedy law (``theta = 0``) brings ``|H|`` to ``momentum_Nms``.
    summary : DetumbleOcpSummary
    """

    momentum_Nms: np.ndarray
    time_s: np.ndarray
    label: np.ndarray
    angle_rad: np.ndarray
    greedy_time_s: np.ndarray
    summary: DetumbleOcpSummary


def time_optimal_detumble(
    inertia_kgm2: np.ndarray,
    vertices_Nm: np.ndarray,
    vertex_fuel_kg_s: np.ndarray,
    initial_rate_rad_s: np.ndarray,
    threshold_rad_s: float,
    *,
    n_intervals: int = N_INTERVALS,
) -> DetumbleOcp:
    """Solve the polhode-averaged time-optimal detumble.

    Parameters
    ----------
    inertia_kgm2 : ndarray, shape (3, 3)
        Rigid body inertia, body axes [kg m^2].
    vertices_Nm : ndarray, shape (k, 3)
        Vertices of the torque polytope, body axes [N m]; centrally symmetric.
    vertex_fuel_kg_s : ndarray, shape (k,)
        Propellant flow of each vertex's least-fuel thrust [kg/s].
    initial_rate_rad_s : ndarray, shape (3,)
    threshold_rad_s : float
    n_intervals : int
        Shooting intervals over ``x``.

    Raises
    ------
    SimulationError
        A spherical body (no precession to average over), a polytope that is not
        centrally symmetric, or no braking at some polhode.
    """
    started = time.perf_counter()
    body = PrincipalBody.from_inertia(inertia_kgm2)
    if body.spherical:
        raise SimulationError("inertia: the averaged OCP needs unequal principal moments")
    vertices = np.asarray(vertices_Nm, dtype=float) @ body.axes
    _check_symmetric(vertices)
    a1, _, a3 = body.inverse_moments
    labels = np.linspace(a3, a1, N_LABELS)
    angles = np.linspace(-MAX_ANGLE_RAD, MAX_ANGLE_RAD, N_ANGLES)
    angles[N_ANGLES // 2] = 0.0  # the greedy law, exactly
    table = polhode_averages(
        body, vertices, np.asarray(vertex_fuel_kg_s, float), labels=labels, angles=angles
    )
    table = _braking_angles(table)
    centre = len(table.angles) // 2  # theta = 0, the greedy law
    momentum0 = np.asarray(inertia_kgm2, float) @ np.asarray(initial_rate_rad_s, float)
    h0 = float(np.linalg.norm(momentum0))
    # Any state with every rate below the threshold has |H| <= sqrt(3) J_max threshold.
    h_end = math.sqrt(3.0) * threshold_rad_s / body.inverse_moments[2]
    if not h0 > h_end:
        raise SimulationError("initial_rate_rad_s: already below the threshold")
    s0 = body.label(body.axes.T @ momentum0 / h0)
    problem = _AveragedProblem(table, h0, math.log(h0 / h_end), n_intervals)
    greedy = problem.rollout(s0, np.zeros(n_intervals))
    angle, status = problem.solve(s0, greedy)
    best = problem.rollout(s0, angle)
    if best[1][-1] > greedy[1][-1]:
        LOGGER.warning("the averaged OCP ended above the greedy law (%s): kept the greedy", status)
        best, angle = greedy, np.zeros(n_intervals)
    label, time_s, fuel = best
    summary = DetumbleOcpSummary(
        method=METHOD,
        time_s=float(time_s[-1]),
        time_h=float(time_s[-1]) / 3600.0,
        fuel_kg=float(fuel[-1]),
        greedy_time_h=float(greedy[1][-1]) / 3600.0,
        greedy_fuel_kg=float(greedy[2][-1]),
        averaged_bound_h=(h0 - h_end) / float(np.max(-table.braking_Nm[:, centre])) / 3600.0,
        initial_momentum_Nms=h0,
        final_momentum_Nms=h_end,
        initial_label=s0,
        final_label=float(label[-1]),
        solver_status=status,
        wall_time_s=time.perf_counter() - started,
    )
    momentum = h0 * np.exp(-problem.grid)
    return DetumbleOcp(momentum, time_s, label, angle, greedy[1], summary)


def _braking_angles(table: PolhodeAverages) -> PolhodeAverages:
    """The table cut to the widest range of angles about 0 that brakes on every polhode
    (beyond, steering can cost all braking and ``dt/dx`` has no meaning)."""
    braking = np.all(table.braking_Nm < 0.0, axis=0)
    centre = len(table.angles) // 2
    if not braking[centre]:
        raise SimulationError("torque polytope: the greedy law cannot brake on some polhode")
    reach = 0
    while reach < centre and braking[centre - reach - 1] and braking[centre + reach + 1]:
        reach += 1
    if reach < 2:
        raise SimulationError("torque polytope: no room to steer the polhode while braking")
    kept = slice(centre - reach, centre + reach + 1)
    return PolhodeAverages(
        table.labels,
        table.angles[kept],
        table.braking_Nm[:, kept],
        table.drift_Nm_per_kgm2[:, kept],
        table.fuel_kg_s[:, kept],
    )


def _check_symmetric(vertices: np.ndarray) -> None:
    """Each vertex's opposite is a vertex: both copies of a polhode brake alike."""
    gaps = np.linalg.norm(vertices[:, None, :] + vertices[None, :, :], axis=2).min(axis=1)
    if np.max(gaps) > SYMMETRY_RTOL * np.max(np.linalg.norm(vertices, axis=1)):
        raise SimulationError(
            "torque polytope: not centrally symmetric (a failed or spent engine?); "
            "the averaged OCP needs -tau reachable with every tau"
        )


class _AveragedProblem:
    """Multiple shooting over ``x`` of the averaged ``(s, t, fuel)``; control ``theta``."""

    def __init__(self, table: PolhodeAverages, h0: float, x_end: float, n: int) -> None:
        self.n, self.h0 = n, h0
        self.grid = np.linspace(0.0, x_end, n + 1)
        low, high = table.labels[0], table.labels[-1]
        self.low, self.span = low, high - low
        unit = (table.labels - low) / self.span
        # Time in units of the fastest braking of the whole momentum.
        self.unit_s = h0 / float(np.max(-table.braking_Nm))
        values = {
            "braking": table.braking_Nm,
            "drift": table.drift_Nm_per_kgm2,
            "fuel": table.fuel_kg_s,
        }
        grid = [unit.tolist(), table.angles.tolist()]
        self.maps = {
            key: ca.interpolant(key, "bspline", grid, value.ravel(order="F").tolist())
            for key, value in values.items()
        }
        self.max_angle = float(table.angles[-1])
        # Every node of the table brakes (``_braking_angles``), but the cubic spline between
        # nodes near the cut can come close to zero or cross it, and IPOPT's trial steps go
        # there: dt/dx = -|H| / braking then overflows and the next RK stage turns inf - inf
        # into NaN (CasADi's "NaN detected for output g" warnings). The braking is held to
        # at most a thousandth of the least any node has, which the optimum never
        # approaches (it would take a thousand times longer than at that node).
        self.braking_cap = -1e-3 * float(np.min(-table.braking_Nm))
        self.step = self._step_function(x_end / n).expand()

    def _rates(self, x: ca.MX, state: ca.MX, angle: ca.MX) -> ca.MX:
        point = ca.vertcat(ca.fmin(ca.fmax(state[0], 0.0), 1.0), angle)
        braking = ca.fmin(self.maps["braking"](point), self.braking_cap)
        momentum = self.h0 * ca.exp(-x)
        unit_dx = -self.maps["drift"](point) / braking / self.span
        time_dx = -momentum / braking / self.unit_s
        fuel_dx = -momentum * self.maps["fuel"](point) / braking
        return ca.vertcat(unit_dx, time_dx, fuel_dx)

    def _step_function(self, width: float) -> ca.Function:
        x, state, angle = ca.MX.sym("x"), ca.MX.sym("state", 3), ca.MX.sym("angle")
        h = width / SUBSTEPS
        y = state
        for k in range(SUBSTEPS):
            xk = x + k * h
            k1 = self._rates(xk, y, angle)
            k2 = self._rates(xk + h / 2, y + h / 2 * k1, angle)
            k3 = self._rates(xk + h / 2, y + h / 2 * k2, angle)
            k4 = self._rates(xk + h, y + h * k3, angle)
            y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        return ca.Function("averaged_step", [x, state, angle], [y])

    def rollout(
        self, label0: float, angle: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Labels, times [s] and fuel [kg] at the grid nodes for the given angles."""
        states = [np.array([(label0 - self.low) / self.span, 0.0, 0.0])]
        for k in range(self.n):
            step = self.step(self.grid[k], states[-1], angle[k])
            states.append(np.asarray(step, dtype=float).ravel())
        rows = np.array(states)
        return self.low + self.span * rows[:, 0], rows[:, 1] * self.unit_s, rows[:, 2]

    def solve(
        self, label0: float, guess: tuple[np.ndarray, np.ndarray, np.ndarray]
    ) -> tuple[np.ndarray, str]:
        """IPOPT from the greedy rollout; the angles and the solver's status."""
        opti = ca.Opti()
        states = opti.variable(3, self.n + 1)
        angle = opti.variable(self.n)
        opti.subject_to(states[:, 0] == ca.vertcat((label0 - self.low) / self.span, 0.0, 0.0))
        for k in range(self.n):
            opti.subject_to(states[:, k + 1] == self.step(self.grid[k], states[:, k], angle[k]))
        opti.subject_to(opti.bounded(0.0, states[0, :], 1.0))
        opti.subject_to(opti.bounded(-self.max_angle, angle, self.max_angle))
        opti.minimize(states[1, -1])
        labels, times, fuel = guess
        opti.set_initial(states[0, :], ((labels - self.low) / self.span)[None, :])
        opti.set_initial(states[1, :], (times / self.unit_s)[None, :])
        opti.set_initial(states[2, :], fuel[None, :])
        opti.set_initial(angle, 0.0)
        opti.solver(
            "ipopt",
            {"print_time": False},
            {"print_level": 0, "max_iter": 300, "tol": 1e-8, "sb": "yes"},
        )
        try:
            with keep_ctrl_c():
                solution = opti.solve()
            status = str(solution.stats()["return_status"])
            return np.asarray(solution.value(angle), dtype=float).ravel(), status
        except RuntimeError:
            status = str(opti.stats()["return_status"])
            return np.asarray(opti.debug.value(angle), dtype=float).ravel(), status


def problem_time_optimal_detumble(
    problem: Problem, initial_rate_rad_s: np.ndarray, threshold_rad_s: float
) -> DetumbleOcp:
    """:func:`time_optimal_detumble` for the problem's rigid body and engines.

    The polytope is the engines' zero-net-force torques with every stage's limit as
    the problem starts (a detumble spends far less than a stage); the fuel of a vertex
    is that of the allocator's least-fuel thrust for it.
    """
    geometry = build_geometry(problem)
    allocator = Allocator.from_problem(problem, geometry)
    vertices = np.asarray(allocator.authority_polytope().vertices, dtype=float)
    fuel = np.asarray(allocator.fuel_rate_kg_s(allocator.allocate_series(vertices).thrust_N))
    return time_optimal_detumble(
        geometry.inertia_total_kgm2, vertices, fuel, initial_rate_rad_s, threshold_rad_s
    )
