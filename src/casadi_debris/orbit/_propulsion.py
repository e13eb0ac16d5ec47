"""What the swarm can push the debris with: torque-free impulse along body directions.

The one thrust model of the orbit code: the deorbit burns and the orbit
transfer (:mod:`~casadi_debris.orbit.transfer` makes its burns from these
segments) both use it. To thrust along a body direction d the body is turned so
that d points where the manoeuvre needs it (against the velocity to lower the
orbit, along the steering law's direction in a transfer), and the engines fire
with zero net torque (the attitude must hold) and zero force across d (it would
push the orbit where it is not wanted). With unidirectional engines of one-stage
thrust f_max,i and a total impulse I_max,i (stages x thrust x stage life: a
stage is taken to be impulse-limited, so that a throttled stage lasts longer),
the largest total impulse the swarm gives over all its directions is the linear
program

    max   sum_d  d . F I_d
    s.t.  B I_d = 0,  P_d F I_d = 0           (no torque, no force across d)
          sum_d I_d <= I_max,  I_d >= 0        (each engine's impulse, shared)

over the engines' impulses I_d (one vector per candidate direction: the
engines' own force directions). F and B are the force and torque maps of
:mod:`casadi_debris.geometry`, P_d = 1 - d d^T. Each direction's engines then
fire at the constant mix ``I_d / t_d`` with t_d = max_i I_d,i / f_max,i (the
mix stays torque-free at every instant, and every engine within its thrust),
giving the thrust ``d . F I_d / t_d``. The burn uses the directions in order of
decreasing thrust.

All engines may serve every direction, not only those whose force points along
d: an opposed pair of engines on other faces fires a pure couple (their forces
cancel) that balances the torque of d's own engines, so that these need not be
throttled. For the paper's swarm the ±y engines then all fire at full thrust,
2.56 mN instead of the 2.536 mN of d's engines balanced among themselves, for
0.5 % of two x engines' impulse; the LP weighs that against what those engines
give along their own directions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linprog

from casadi_debris.config import Problem
from casadi_debris.errors import AllocationError
from casadi_debris.geometry import Geometry, build_geometry, max_thrust_N
from casadi_debris.units import SECONDS_PER_HOUR

DIRECTION_DECIMALS = 6
SMALL_IMPULSE_NS = 1e-6
# Engines giving less than this share of a direction's largest engine impulse do not fire.
FIRING_FRACTION = 1e-9


@dataclass(frozen=True, eq=False)
class ThrustSegment:
    """One body direction's share of the burn.

    Attributes
    ----------
    direction_body : ndarray, shape (3,)
        Unit direction of the push in body axes (turned against the velocity).
    thrust_N : float
        Torque-free thrust along it.
    impulse_Ns : float
        Along it, in total.
    engine_impulse_Ns : ndarray, shape (n_engines,)
        What each engine gives in this direction.
    propellant_kg : float, optional
        What the engines burn for it (all engines, couples included).
    """

    direction_body: np.ndarray
    thrust_N: float
    impulse_Ns: float
    engine_impulse_Ns: np.ndarray
    propellant_kg: float | None = None

    @property
    def firing_time_s(self) -> float:
        """How long the direction fires at its constant mix [s]."""
        return self.impulse_Ns / self.thrust_N

    @property
    def engine_thrust_N(self) -> np.ndarray:
        """Each engine's constant thrust while the direction fires [N], shape (n_engines,)."""
        return self.engine_impulse_Ns / self.firing_time_s

    @property
    def engines(self) -> tuple[int, ...]:
        """The engines that fire for this direction, 0-based."""
        limit = FIRING_FRACTION * float(np.max(self.engine_impulse_Ns))
        return tuple(int(i) for i in np.flatnonzero(self.engine_impulse_Ns > limit))

    @property
    def flow_kg_s(self) -> float:
        """Propellant flow while the direction fires [kg/s].

        Raises
        ------
        ValueError
            The segment was made without its propellant.
        """
        if self.propellant_kg is None:
            raise ValueError("this thrust segment carries no propellant figure")
        return self.propellant_kg / self.firing_time_s


@dataclass(frozen=True, eq=False)
class SwarmThrust:
    """The swarm's torque-free impulse, direction by direction.

    Attributes
    ----------
    segments : tuple of ThrustSegment
        In order of decreasing thrust.
    engine_capacity_Ns : ndarray, shape (n_engines,)
        Each engine's impulse, all stages.
    stage_impulse_Ns : ndarray, shape (n_engines,)
        One stage's.
    exhaust_speed_m_s : float
        Isp g0 (impulse-weighted over the engines when they differ).
    engine_cubesat : ndarray of int, shape (n_engines,)
        0-based CubeSat of each engine.
    """

    segments: tuple[ThrustSegment, ...]
    engine_capacity_Ns: np.ndarray
    stage_impulse_Ns: np.ndarray
    exhaust_speed_m_s: float
    engine_cubesat: np.ndarray

    @property
    def impulse_Ns(self) -> float:
        """All the torque-free impulse [N s]."""
        return float(sum(s.impulse_Ns for s in self.segments))

    def engine_impulse(self, impulse_Ns: float) -> np.ndarray:
        """Each engine's impulse after the burn has given ``impulse_Ns``, shape (n_engines,)."""
        used = np.zeros_like(self.engine_capacity_Ns)
        left = impulse_Ns
        for segment in self.segments:
            share = min(1.0, left / segment.impulse_Ns) if segment.impulse_Ns > 0 else 0.0
            used += share * segment.engine_impulse_Ns
            left -= share * segment.impulse_Ns
            if left <= SMALL_IMPULSE_NS:
                break
        return used

    def firing_time_s(self, impulse_Ns: float) -> float:
        """Engine-on time to give ``impulse_Ns`` through the segments in order [s]."""
        time, left = 0.0, impulse_Ns
        for segment in self.segments:
            part = min(left, segment.impulse_Ns)
            time += part / segment.thrust_N
            left -= part
        if left > SMALL_IMPULSE_NS and self.segments:
            time += left / self.segments[-1].thrust_N
        return time


def _candidate_directions(geometry: Geometry) -> np.ndarray:
    """The engines' distinct force directions, shape (k, 3)."""
    directions = np.round(geometry.force_map.T, DIRECTION_DECIMALS)
    _, first = np.unique(directions, axis=0, return_index=True)
    return geometry.force_map.T[np.sort(first)]


def swarm_thrust(problem: Problem, geometry: Geometry | None = None) -> SwarmThrust:
    """The largest torque-free impulse of the swarm along its directions (one LP).

    Parameters
    ----------
    problem : Problem
    geometry : Geometry, optional

    Returns
    -------
    SwarmThrust

    Raises
    ------
    AllocationError
        The LP failed, or no direction gives any torque-free thrust.
    """
    geometry = geometry or build_geometry(problem)
    g0 = problem.constants.standard_gravity_m_s2
    engines = problem.engines
    f_max = max_thrust_N(geometry)
    stage_impulse = np.array(
        [f * e.stage_life_h * SECONDS_PER_HOUR for f, e in zip(f_max, engines, strict=True)]
    )
    capacity = stage_impulse * np.array([e.stages for e in engines])
    isp = np.array([e.isp_s for e in engines])
    directions = _candidate_directions(geometry)
    n, k = len(f_max), len(directions)
    objective = -np.concatenate([d @ geometry.force_map for d in directions])
    blocks = []
    for index, d in enumerate(directions):
        rows = np.vstack([geometry.torque_map, (np.eye(3) - np.outer(d, d)) @ geometry.force_map])
        block = np.zeros((6, n * k))
        block[:, index * n : (index + 1) * n] = rows
        blocks.append(block)
    result = linprog(
        objective,
        A_ub=np.tile(np.eye(n), k),
        b_ub=capacity,
        A_eq=np.vstack(blocks),
        b_eq=np.zeros(6 * k),
        bounds=(0.0, None),
        method="highs",
    )
    if result.status != 0 or result.x is None:
        raise AllocationError(f"swarm thrust: impulse LP failed ({result.message})")
    segments = []
    for index, d in enumerate(directions):
        impulses = np.clip(result.x[index * n : (index + 1) * n], 0.0, None)
        along = float(d @ geometry.force_map @ impulses)
        if along <= SMALL_IMPULSE_NS:
            continue
        time = float(np.max(impulses / f_max))
        propellant = float(np.sum(impulses / (isp * g0)))
        segments.append(ThrustSegment(d, along / time, along, impulses, propellant))
    if not segments:
        raise AllocationError("swarm thrust: no body direction gets any torque-free thrust")
    segments.sort(key=lambda s: -s.thrust_N)
    return SwarmThrust(
        segments=tuple(segments),
        engine_capacity_Ns=capacity,
        stage_impulse_Ns=stage_impulse,
        exhaust_speed_m_s=float(g0 * np.sum(capacity) / np.sum(capacity / isp)),
        engine_cubesat=geometry.engine_cubesat,
    )
