"""Detumbling the debris in closed loop: rate damping through the staged engines.

From the problem's initial tumble (``[detumble] initial_rate_rad_s``, the paper's
1 rad/s about every axis) the controller asks every control period for the torque
that shrinks the angular momentum ``H = J omega`` fastest among those the engines
can give at zero net force (a vertex of the authority polytope), and for the
linear damping ``tau = -K J omega`` once the engines can give that; the torque is
held over the period. The body is the rigid one: at such rates the
flexible model's constant mass matrix is not valid (the arrays' centrifugal
stiffening and large deflections are not in it), so the arrays are taken as rigid,
their inertia included.

The rates are integrated by a compiled CasADi function over stretches of periods
(Runge-Kutta 4, with Euler's gyroscopic term); after each stretch the allocator
turns the applied torques into the least-fuel thrust of every engine and the
propulsion state burns it. A stretch ends early where an engine's limit changes
(a stage spent): the polytope is rebuilt from there. The run stops once every
rate component has stayed below the threshold for a whole period, or at the
time limit.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np
import numpy.typing as npt

from casadi_debris.allocation import Allocator, AuthorityPolytope, PropulsionState
from casadi_debris.config import Problem
from casadi_debris.errors import CompileError, SimulationError
from casadi_debris.geometry import build_geometry
from casadi_debris.processes import c_compiler
from casadi_debris.records import Record
from casadi_debris.simulation._closed_loop import saturation_scale
from casadi_debris.simulation._jit_cache import compiled_function

LOGGER = logging.getLogger(__name__)

DEFAULT_THRESHOLD_RAD_S = 1e-4
# Rate-damping gain: the linear tail decays with a time constant of 1 / K [s].
DEFAULT_GAIN_PER_S = 0.02
STRETCH_STEPS = 2000
DETUMBLE_PERIOD_S = 1.0
# Runge-Kutta steps per control period: 0.1 s steps at 1 rad/s keep the rate equations'
# error per step near 1e-7 of the rate.
SUBSTEPS = 10


@dataclass(frozen=True, kw_only=True)
class DetumbleRunSummary(Record):
    """Figures of a closed-loop detumble.

    Attributes
    ----------
    initial_rate_rad_s : tuple of 3 float
    threshold_rad_s : float
        Every rate component below it ends the detumble.
    gain_per_s : float
        K of ``tau = -K J omega``.
    time_to_threshold_s, time_to_threshold_h : float or None
        None when the time limit came first.
    duration_s : float
        Simulated time.
    final_rate_rad_s : tuple of 3 float
    fuel_kg, fuel_worst_cubesat_kg : float
    fuel_per_cubesat_kg : tuple of float
    dv_used_m_s : float
        Rocket equation over the propellant burnt.
    stage_switches : int
    saturated_s : float
        Time the demand was scaled down to the authority.
    inertia_kgm2 : tuple of 3 tuples of 3 float
        The rigid body's inertia about its CoG (arrays included).
    control_period_s : float
    wall_time_s : float
    """

    initial_rate_rad_s: tuple[float, ...]
    threshold_rad_s: float
    gain_per_s: float
    time_to_threshold_s: float | None
    time_to_threshold_h: float | None
    duration_s: float
    final_rate_rad_s: tuple[float, ...]
    fuel_kg: float
    fuel_worst_cubesat_kg: float
    fuel_per_cubesat_kg: tuple[float, ...]
    dv_used_m_s: float
    stage_switches: int
    saturated_s: float
    inertia_kgm2: tuple[tuple[float, ...], ...]
    control_period_s: float
    wall_time_s: float


@dataclass(eq=False)
class DetumbleRunResult:
    """Series of a detumble (SI units), one row per control instant.

    Attributes
    ----------
    time_s : ndarray, shape (n + 1,)
    rate_rad_s : ndarray, shape (n + 1, 3)
    torque_Nm : ndarray, shape (n, 3)
        Applied over each period.
    scale : ndarray, shape (n,)
        Saturation factor of the demand.
    fuel_per_cubesat_kg : ndarray, shape (n + 1, n_cubesats)
        Propellant burnt so far.
    summary : DetumbleRunSummary
    """

    time_s: np.ndarray
    rate_rad_s: np.ndarray
    torque_Nm: np.ndarray
    scale: np.ndarray
    fuel_per_cubesat_kg: np.ndarray
    summary: DetumbleRunSummary


def rate_damping_stretch(
    inertia_kgm2: np.ndarray, period_s: float, polytope: AuthorityPolytope, gain_per_s: float
) -> ca.Function:
    """``omega_0 -> omega, torque, scale`` over a stretch of periods, compiled when it can be.

    One period: the linear demand ``d = -K J omega`` while the engines can give it
    (``alpha = min(1, min_{n.d > 0} b / (n.d)) = 1``); beyond, the vertex ``v`` of
    the authority polytope that minimises ``v . J omega``: the torque that shrinks
    the angular momentum fastest (``d|H|^2/dt = 2 H . tau``, the gyroscopic term
    does no work on it). The torque is held while ``J omega' = tau - omega x J omega``
    is integrated (Runge-Kutta 4, ``SUBSTEPS`` steps).
    """
    inertia = ca.DM(inertia_kgm2)
    omega = ca.SX.sym("omega", 3)
    momentum = inertia @ omega
    demand = -gain_per_s * momentum
    scale = saturation_scale(demand, polytope)
    vertices = np.asarray(polytope.vertices, dtype=float)
    fastest = ca.SX(ca.DM(vertices[0]))
    best = ca.dot(fastest, momentum)
    for vertex in vertices[1:]:
        score = ca.dot(ca.DM(vertex), momentum)
        fastest = ca.if_else(score < best, ca.DM(vertex), fastest)
        best = ca.fmin(score, best)
    torque = ca.if_else(scale >= 1.0, demand, fastest)
    w = held_torque_rates(inertia_kgm2, omega, torque, period_s, SUBSTEPS)
    step = ca.Function("detumble_step", [omega], [w, torque, ca.fmin(scale, 1.0)])
    compiler = c_compiler()
    if compiler is not None:
        try:
            step = compiled_function(step, compiler)
        except CompileError as exc:
            LOGGER.warning("the detumble runs on CasADi's virtual machine: %s", exc)
    return step.mapaccum("detumble_stretch", STRETCH_STEPS, [0], [0])


def held_torque_rates(
    inertia_kgm2: np.ndarray, omega: Any, torque: Any, duration_s: Any, substeps: int
) -> Any:
    """The rates after ``duration_s`` of ``J omega' = tau - omega x J omega`` with ``tau``
    held (Runge-Kutta 4 in ``substeps`` steps), as a CasADi expression (SX or MX).

    Parameters
    ----------
    inertia_kgm2 : ndarray, shape (3, 3)
    omega, torque : CasADi expressions, shape (3,)
        Rates at the start [rad/s] and the held torque [N m].
    duration_s : float or CasADi expression
    substeps : int
    """
    inertia = ca.DM(inertia_kgm2)
    inverse = ca.DM(np.linalg.inv(inertia_kgm2))

    def rate(w: Any) -> Any:
        return inverse @ (torque - ca.cross(w, inertia @ w))

    h = duration_s / substeps
    w = omega
    for _ in range(substeps):
        k1 = rate(w)
        k2 = rate(w + h / 2 * k1)
        k3 = rate(w + h / 2 * k2)
        k4 = rate(w + h * k3)
        w = w + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return w


def simulate_detumble(
    problem: Problem,
    *,
    initial_rate_rad_s: npt.ArrayLike | None = None,
    threshold_rad_s: float = DEFAULT_THRESHOLD_RAD_S,
    gain_per_s: float = DEFAULT_GAIN_PER_S,
    period_s: float = DETUMBLE_PERIOD_S,
    max_duration_s: float | None = None,
) -> DetumbleRunResult:
    """Detumble the rigid body in closed loop through the problem's engines.

    Parameters
    ----------
    problem : Problem
    initial_rate_rad_s : array_like, shape (3,), optional
        Default the problem's ``[detumble] initial_rate_rad_s``.
    threshold_rad_s : float
        Done when every rate component is below it [rad/s].
    gain_per_s : float
        K of the rate damping ``tau = -K J omega`` [1/s]; the control period
        times K must be below 1.
    period_s : float
        Control period [s]: the torque is held over it. The attitude loop's 10 Hz
        is not needed to brake a tumble; 1 s keeps a 16-hour run short.
    max_duration_s : float, optional
        Time limit [s]; default 4 times the per-axis braking estimate, and at
        least a day.

    Raises
    ------
    SimulationError
        A threshold, gain or limit that cannot work (named), or no engine left.
    """
    started = time.perf_counter()
    rate0 = np.asarray(
        problem.detumble.initial_rate_rad_s if initial_rate_rad_s is None else initial_rate_rad_s,
        dtype=float,
    )
    _check(rate0, threshold_rad_s, gain_per_s, period_s)
    geometry = build_geometry(problem)
    inertia = geometry.inertia_total_kgm2
    allocator = Allocator.from_problem(problem, geometry)
    engines = PropulsionState.from_problem(problem)
    if max_duration_s is None:
        authority = allocator.authority_polytope().axis_reach()
        estimate = np.max(np.abs(inertia @ rate0) / np.min(authority.reshape(3, 2), axis=1))
        max_duration_s = max(4.0 * float(estimate), 86400.0)
    n_max = math.ceil(max_duration_s / period_s)
    rollout = _Rollout(inertia, period_s, gain_per_s, allocator, engines)
    rollout.run(rate0, threshold_rad_s, n_max)
    return rollout.result(problem, rate0, threshold_rad_s, time.perf_counter() - started)


def _check(rate0: np.ndarray, threshold: float, gain: float, period_s: float) -> None:
    if rate0.shape != (3,) or not np.all(np.isfinite(rate0)):
        raise SimulationError(f"initial_rate_rad_s: three finite rates, got {rate0.tolist()}")
    if not threshold > 0.0:
        raise SimulationError(f"threshold_rad_s: must be positive, got {threshold}")
    if not 0.0 < gain * period_s < 1.0:
        raise SimulationError(
            f"gain_per_s: K times the control period ({period_s:g} s) must be in (0, 1), "
            f"got K = {gain}"
        )


@dataclass(eq=False)
class _Rollout:
    """The rates rolled out stretch by stretch, the engines burning in between."""

    inertia: np.ndarray
    period_s: float
    gain: float
    allocator: Allocator
    engines: PropulsionState

    def __post_init__(self) -> None:
        self.rates: list[np.ndarray] = []
        self.torques: list[np.ndarray] = []
        self.scales: list[np.ndarray] = []
        self.fuel: list[np.ndarray] = []
        self.impulse_Ns = 0.0
        self.switches = 0
        n_engines = len(self.engines.engine_cubesat)
        self.membership = np.zeros((n_engines, self.engines.n_cubesats))
        self.membership[np.arange(n_engines), self.engines.engine_cubesat] = 1.0
        self.functions: dict[int, ca.Function] = {}

    def run(self, rate0: np.ndarray, threshold: float, n_max: int) -> None:
        omega, done = rate0, 0
        self.rates.append(rate0[None, :])
        self.fuel.append(np.zeros((1, self.engines.n_cubesats)))
        polytope = self._polytope()
        while done < n_max:
            if not np.any(self.engines.available):
                raise SimulationError("every CubeSat has failed or is spent: no engine can fire")
            stretch = self._function(polytope)
            w, tau, alpha = stretch(omega)
            w, tau, alpha = np.asarray(w).T, np.asarray(tau).T, np.asarray(alpha).ravel()
            below = np.flatnonzero(np.abs(w).max(axis=1) < threshold)
            used = min(STRETCH_STEPS, n_max - done, below[0] + 1 if below.size else STRETCH_STEPS)
            thrust = self.allocator.allocate_series(tau[:used]).thrust_N
            steps, events = self.engines.advance_series(thrust, self.period_s)
            self.switches += len(events)
            self._keep(w[:steps], tau[:steps], alpha[:steps], thrust[:steps])
            omega, done = w[steps - 1], done + steps
            if steps < used:
                polytope = self._polytope()
            elif below.size and below[0] < steps:
                return

    def _polytope(self) -> AuthorityPolytope:
        self.allocator.update_from_state(self.engines)
        return self.allocator.authority_polytope()

    def _function(self, polytope: AuthorityPolytope) -> ca.Function:
        key = hash((polytope.offsets.tobytes(), polytope.normals.tobytes()))
        if key not in self.functions:
            self.functions[key] = rate_damping_stretch(
                self.inertia, self.period_s, polytope, self.gain
            )
        return self.functions[key]

    def _keep(
        self, rates: np.ndarray, torques: np.ndarray, scales: np.ndarray, thrust: np.ndarray
    ) -> None:
        self.rates.append(rates)
        self.torques.append(torques)
        self.scales.append(scales)
        burnt_kg = thrust * self.period_s / self.engines.exhaust_velocity_m_s
        per_cubesat = np.cumsum(burnt_kg @ self.membership, axis=0) + self.fuel[-1][-1]
        self.fuel.append(per_cubesat)
        self.impulse_Ns += float(thrust.sum()) * self.period_s

    def result(
        self, problem: Problem, rate0: np.ndarray, threshold: float, wall_time_s: float
    ) -> DetumbleRunResult:
        rates = np.vstack(self.rates)
        torques, scales = np.vstack(self.torques), np.concatenate(self.scales)
        time_s = np.arange(len(rates)) * self.period_s
        below = np.abs(rates[-1]).max() < threshold
        fuel = self.fuel[-1][-1]
        mass_kg = build_geometry(problem).mass_kg
        # The propellant's mean exhaust velocity: total impulse over propellant.
        exhaust = self.impulse_Ns / fuel.sum() if fuel.sum() > 0 else 0.0
        summary = DetumbleRunSummary(
            initial_rate_rad_s=tuple(rate0),
            threshold_rad_s=threshold,
            gain_per_s=self.gain,
            time_to_threshold_s=float(time_s[-1]) if below else None,
            time_to_threshold_h=float(time_s[-1]) / 3600.0 if below else None,
            duration_s=float(time_s[-1]),
            final_rate_rad_s=tuple(rates[-1]),
            fuel_kg=float(fuel.sum()),
            fuel_worst_cubesat_kg=float(fuel.max()),
            fuel_per_cubesat_kg=tuple(fuel),
            dv_used_m_s=exhaust * math.log(mass_kg / (mass_kg - float(fuel.sum()))),
            stage_switches=self.switches,
            saturated_s=float(np.sum(scales < 1.0) * self.period_s),
            inertia_kgm2=tuple(tuple(row) for row in self.inertia),
            control_period_s=self.period_s,
            wall_time_s=wall_time_s,
        )
        return DetumbleRunResult(time_s, rates, torques, scales, np.vstack(self.fuel), summary)
