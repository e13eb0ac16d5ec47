"""Thrusting while pointing: a burn flown by the closed attitude loop.

During a transfer or deorbit burn a body axis ``a`` (the thrust axis) is held
along a direction ``d`` of the orbit's LVLH frame (prograde o1, retrograde -o1,
orbit normal -o2, anti-normal o2; see
:mod:`~casadi_debris.simulation.targets`). The reference is the LVLH track
whose offset q_OB is the least rotation taking ``a`` onto ``d``; the body
starts on it, turning with the frame.

The engines deliver a net force ``phi = T a`` (body axes, ``T`` the thrust)
and the controller's torque together. The loop saturates its torque demand on
the slice of the wrench polytope at that force,

    T_phi = { B f : 0 <= f <= f_max, F f = phi }

(:func:`~casadi_debris.allocation.authority.authority_polytope` with
``force_N``): exactly the torques the engines can add while they deliver
``phi``, neither more (every torque in it is reached with the force kept) nor
less (a fixed torque-free mix with the residual limits ``f_max - f_0`` on top
would give a subset). After each stretch the allocator splits every period's
(torque, phi) among the engines at least propellant
(:meth:`~casadi_debris.allocation.Allocator.allocate_batch` with the force
demand), and the propulsion state burns it with its stages, as in any run.

``T`` is ``thrust_fraction`` times the largest torque-free thrust along ``a``
with the engines' current limits (an LP), or a thrust given in newtons; the
force acts on the plant through the flexible model's translational
coupling (the arrays' modal participation), so that the arrays feel the burn.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import control
import numpy as np
from scipy.optimize import linprog
from scipy.spatial.transform import Rotation

from casadi_debris.allocation import Allocator, AuthorityPolytope, PropulsionState
from casadi_debris.allocation.authority import authority_polytope
from casadi_debris.config import Problem
from casadi_debris.environment.orbit import CircularOrbit
from casadi_debris.model import Model
from casadi_debris.model.attitude import quaternion_to_rotation
from casadi_debris.simulation.closed_loop import SimulationError, discretize_controller
from casadi_debris.simulation.reference import Reference
from casadi_debris.simulation.result import ClosedLoopResult
from casadi_debris.simulation.run import RunInputs, _Rollout, _Series
from casadi_debris.simulation.targets import body_rates, frame_attitude, lvlh_matrices

BurnDirection = Literal["prograde", "retrograde", "normal", "antinormal"]
BURN_DIRECTIONS: tuple[BurnDirection, ...] = ("prograde", "retrograde", "normal", "antinormal")
# In LVLH components (o1 along track, o2 against the orbit normal, o3 to nadir).
_LVLH_DIRECTION = {
    "prograde": (1.0, 0.0, 0.0),
    "retrograde": (-1.0, 0.0, 0.0),
    "normal": (0.0, -1.0, 0.0),
    "antinormal": (0.0, 1.0, 0.0),
}
DEFAULT_PERIOD_S = 0.1


@dataclass(frozen=True, eq=False)
class BurnPlan:
    """What a burn asks for.

    Attributes
    ----------
    direction : {"prograde", "retrograde", "normal", "antinormal"}
        Where the thrust points, in the orbit's LVLH frame.
    body_axis : ndarray, shape (3,)
        Unit thrust axis in body axes.
    duration_s : float
        Engines on [s].
    thrust_fraction : float
        Of the largest torque-free thrust along ``body_axis`` (ignored when
        ``thrust_N`` is given).
    thrust_N : float or None
        The thrust itself [N].
    """

    direction: BurnDirection
    body_axis: np.ndarray
    duration_s: float
    thrust_fraction: float = 1.0
    thrust_N: float | None = None

    def __post_init__(self) -> None:
        if self.direction not in BURN_DIRECTIONS:
            raise SimulationError(
                f"direction: one of {', '.join(BURN_DIRECTIONS)}, got {self.direction!r}"
            )
        axis = np.asarray(self.body_axis, dtype=float)
        if axis.shape != (3,) or not np.all(np.isfinite(axis)) or not np.any(axis):
            raise SimulationError(f"body_axis: three finite numbers, not all zero, got {axis}")
        object.__setattr__(self, "body_axis", axis / np.linalg.norm(axis))
        if not (math.isfinite(self.duration_s) and self.duration_s > 0):
            raise SimulationError(f"duration_s: must be positive, got {self.duration_s}")
        if not 0.0 < self.thrust_fraction <= 1.0:
            raise SimulationError(f"thrust_fraction: in (0, 1], got {self.thrust_fraction}")
        if self.thrust_N is not None and not (math.isfinite(self.thrust_N) and self.thrust_N > 0):
            raise SimulationError(f"thrust_mN: must be positive, got {self.thrust_N}")

    @property
    def direction_lvlh(self) -> np.ndarray:
        """Unit direction in LVLH components, shape (3,)."""
        return np.array(_LVLH_DIRECTION[self.direction])


def strongest_axis(problem: Problem) -> np.ndarray:
    """The body direction of the swarm's largest torque-free thrust, shape (3,).

    The first of :func:`~casadi_debris.orbit.propulsion.swarm_thrust`'s directions
    (ties broken by its order).
    """
    from casadi_debris.orbit.propulsion import swarm_thrust

    return np.asarray(swarm_thrust(problem).segments[0].direction_body, dtype=float)


def torque_free_thrust_N(allocator: Allocator, axis: np.ndarray) -> float:
    """Largest thrust along ``axis`` with zero torque and no force across it [N] (an LP).

    ``max a.F f  s.t.  B f = 0, (1 - a a^T) F f = 0, 0 <= f <= f_max``.
    """
    a = np.asarray(axis, dtype=float)
    across = (np.eye(3) - np.outer(a, a)) @ allocator.force_map
    limits = allocator.max_thrust_N
    result = linprog(
        -(a @ allocator.force_map),
        A_eq=np.vstack([allocator.torque_map, across]),
        b_eq=np.zeros(6),
        bounds=list(zip(np.zeros_like(limits), limits, strict=True)),
        method="highs",
    )
    if result.status != 0 or result.x is None:
        raise SimulationError(f"torque-free thrust LP failed ({result.message})")
    return max(0.0, -float(result.fun or 0.0))


def burn_thrust_N(allocator: Allocator, plan: BurnPlan, *, strict: bool = True) -> float:
    """The thrust a plan gets from the allocator's engines [N]: its own, or its fraction of
    the largest torque-free thrust along its axis (:func:`torque_free_thrust_N`).

    Raises
    ------
    SimulationError
        The plan's thrust exceeds what the engines give (with ``strict``; otherwise
        that is what it gets), or none can thrust along the axis.
    """
    available = torque_free_thrust_N(allocator, plan.body_axis)
    wanted = plan.thrust_fraction * available if plan.thrust_N is None else plan.thrust_N
    if wanted > available * (1.0 + 1e-9):
        if strict:
            raise SimulationError(
                f"thrust_mN: {wanted * 1e3:.4g} mN asked, the engines give at most "
                f"{available * 1e3:.4g} mN along the axis without torque"
            )
        wanted = available
    if wanted <= 0.0:
        raise SimulationError("no engine left can thrust along the burn's axis")
    return wanted


def burn_offset(body_axis: np.ndarray, direction_lvlh: np.ndarray) -> np.ndarray:
    """q_OB (scalar first) of the least rotation taking ``body_axis`` onto ``direction_lvlh``."""
    rotation, _ = Rotation.align_vectors([direction_lvlh], [body_axis])
    xyzw = rotation.as_quat()
    return np.asarray(xyzw[[3, 0, 1, 2]])


def burn_reference(problem: Problem, plan: BurnPlan, period_s: float) -> Reference:
    """The LVLH track holding ``plan.body_axis`` along its direction, one sample per period."""
    orbit = CircularOrbit.from_problem(problem)
    steps = max(1, math.ceil(plan.duration_s / period_s - 1e-9))
    times = np.arange(steps + 1) * period_s
    offset = burn_offset(plan.body_axis, plan.direction_lvlh)
    return Reference(times, frame_attitude(orbit, offset, times), None)


def direction_inertial(problem: Problem, plan: BurnPlan, time_s: np.ndarray) -> np.ndarray:
    """The burn's direction in inertial axes at each time, shape (n, 3)."""
    orbit = CircularOrbit.from_problem(problem)
    return np.asarray(plan.direction_lvlh @ lvlh_matrices(orbit, time_s))


def pointing_error_rad(
    problem: Problem, plan: BurnPlan, time_s: np.ndarray, quaternion_BN: np.ndarray
) -> np.ndarray:
    """Angle between the thrust axis (``quaternion_BN`` applied to it) and the burn's
    direction at each time [rad], shape (n,)."""
    wanted = direction_inertial(problem, plan, time_s)
    axis = quaternion_to_rotation(quaternion_BN).apply(plan.body_axis)
    cross = np.linalg.norm(np.cross(axis, wanted), axis=1)
    return np.arctan2(cross, np.einsum("ij,ij->i", axis, wanted))


@dataclass(eq=False)
class _BurnRollout(_Rollout):
    """A run whose engines also deliver the burn's net force (see the module's text)."""

    plan: BurnPlan | None = None

    def torque_authority(self) -> AuthorityPolytope:
        assert self.plan is not None
        # At the start a thrust beyond the engines is an error; later (engines spent
        # during the burn) the burn goes on with what is left.
        wanted = burn_thrust_N(self.allocator, self.plan, strict=self.k == 0)
        self.force_N = wanted * self.plan.body_axis
        return authority_polytope(
            self.allocator.torque_map,
            self.allocator.force_map,
            self.allocator.max_thrust_N,
            force_N=self.force_N,
        )

    def allocate(self, torques_Nm: np.ndarray) -> tuple[np.ndarray, int]:
        assert self.force_N is not None  # set with the authority
        forces = np.tile(self.force_N, (len(torques_Nm), 1))
        batch = self.allocator.allocate_batch(torques_Nm, forces_N=forces)
        if not batch.feasible.all():
            raise SimulationError("the allocator could not deliver the burn's force and torque")
        return batch.thrust_N, len(torques_Nm)


@dataclass(frozen=True, eq=False)
class BurnRun:
    """A burn's closed-loop run and what it was asked.

    Attributes
    ----------
    plan : BurnPlan
    result : ClosedLoopResult
        The run (its ``force_N`` the engines' net force per period, body axes).
    pointing_error_rad : ndarray, shape (n + 1,)
        Thrust axis against the burn's direction.
    velocity_N_m_s : ndarray, shape (n + 1, 3)
        The body's velocity change in inertial axes, from its linear momentum.
    """

    plan: BurnPlan
    result: ClosedLoopResult
    pointing_error_rad: np.ndarray
    velocity_N_m_s: np.ndarray


def simulate_burn(
    problem: Problem,
    model: Model,
    controller: control.StateSpace,
    plan: BurnPlan,
    *,
    period_s: float = DEFAULT_PERIOD_S,
    propulsion: PropulsionState | None = None,
    jit: bool = False,
) -> BurnRun:
    """Fly a burn in closed loop: the thrust axis held along its direction, force and torque
    allocated together.

    Parameters
    ----------
    problem : Problem
    model : Model
        Built from ``problem`` (flexible: every array mode by default).
    controller : control.StateSpace
        Continuous controller, attitude error [deg] -> torque [mNm].
    plan : BurnPlan
    period_s : float
        Control period [s].
    propulsion : PropulsionState, optional
        Engines at the start (default full); not modified.
    jit : bool
        Compile the control step to C (see :func:`~casadi_debris.simulation.simulate`).

    Returns
    -------
    BurnRun

    Raises
    ------
    SimulationError
        The thrust asked exceeds what the engines give along the axis, or an
        engine state that cannot thrust along it.
    """
    import time

    started = time.perf_counter()
    reference = burn_reference(problem, plan, period_s)
    discrete = discretize_controller(controller, period_s)
    rollout = _BurnRollout.of(
        problem, model, reference, discrete, RunInputs(propulsion=propulsion, failures=())
    )
    assert isinstance(rollout, _BurnRollout)
    rollout.plan = plan
    # On the frame from the start, turning with it (no start-up transient).
    rate = body_rates(reference.time_s[:2], reference.quaternion_BN[:2])[0]
    n_plant = model.layout.size
    rollout.z[:n_plant] = model.initial_state(reference.quaternion_BN[0], rate)
    rollout.states[0] = rollout.z[:n_plant]
    options = {"integrator_steps": problem.simulation.integrator_steps, "integrator": "rk4"}
    error = rollout.roll_alone(1000, {**options, "jit": jit, "realism": None})
    if error is not None:
        raise error
    result = rollout.result(_Series.of(model, reference), time.perf_counter() - started)
    momenta = model.momenta.map(len(result.time_s))
    linear, _ = momenta(result.state.T, rollout.parameters)
    velocity = np.asarray(linear).T / result.total_mass_kg
    pointing = pointing_error_rad(problem, plan, result.time_s, result.state[:, model.layout.q])
    return BurnRun(plan, result, pointing, velocity - velocity[0])


def first_stage_left(propulsion: PropulsionState, seconds: float) -> PropulsionState:
    """A copy of ``propulsion`` whose engines' first stages hold ``seconds`` of full thrust.

    The rest of each first stage counts as burnt (its firing time as spent at full
    thrust), so that a short burn sees the stages switch.
    """
    if not (math.isfinite(seconds) and seconds >= 0):
        raise SimulationError(f"first_stage_left_s: must be non-negative, got {seconds}")
    state = propulsion.copy()
    full_s = state.stage_capacity_kg[:, 0] * state.exhaust_velocity_m_s / state.stage_thrust_N[:, 0]
    left_kg = state.stage_thrust_N[:, 0] * seconds / state.exhaust_velocity_m_s
    state.propellant_kg[:, 0] = np.minimum(state.propellant_kg[:, 0], left_kg)
    state.firing_time_s[:, 0] = np.maximum(state.firing_time_s[:, 0], full_s - seconds)
    return state
