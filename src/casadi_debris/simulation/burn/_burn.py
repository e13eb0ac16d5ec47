"""Thrusting while pointing: a burn flown by the closed attitude loop.

During a transfer or deorbit burn a body axis ``a`` (the thrust axis) is held
along a direction ``d`` of the orbit's LVLH frame (prograde o1, retrograde -o1,
orbit normal -o2, anti-normal o2; see
:mod:`~casadi_debris.guidance`). The reference is the LVLH track
whose offset q_OB is the least rotation taking ``a`` onto ``d``; the body
starts on it, turning with the frame.

The engines deliver a net force ``phi = T a`` (body axes, ``T`` the thrust)
and the controller's torque together. The loop saturates its torque demand on
the slice of the wrench polytope at that force,

    T_phi = { B f : 0 <= f <= f_max, F f = phi }

(:func:`~casadi_debris.allocation.authority_polytope` with
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

import control
import numpy as np

from casadi_debris.allocation import PropulsionState
from casadi_debris.config import Problem
from casadi_debris.dynamics import Model, quaternion_to_rotation
from casadi_debris.environment import CircularOrbit
from casadi_debris.guidance import (
    BurnPlan,
    BurnWindow,
    Reference,
    body_rates,
    burn_offset,
    direction_inertial,
    frame_attitude,
)
from casadi_debris.simulation._closed_loop import SimulationError, discretize_controller
from casadi_debris.simulation._result import ClosedLoopResult
from casadi_debris.simulation._run import LoopSettings, RunInputs, _Rollout, _Series

BURN_PERIOD_S = 0.1


def burn_reference(problem: Problem, plan: BurnPlan, period_s: float) -> Reference:
    """The LVLH track holding ``plan.body_axis`` along its direction, one sample per period."""
    orbit = CircularOrbit.from_problem(problem)
    steps = max(1, math.ceil(plan.duration_s / period_s - 1e-9))
    times = np.arange(steps + 1) * period_s
    offset = burn_offset(plan.body_axis, plan.direction_lvlh)
    return Reference(times, frame_attitude(orbit, offset, times), None)


def pointing_error_rad(
    problem: Problem, plan: BurnPlan, time_s: np.ndarray, quaternion_BN: np.ndarray
) -> np.ndarray:
    """Angle between the thrust axis (``quaternion_BN`` applied to it) and the burn's
    direction at each time [rad], shape (n,)."""
    wanted = direction_inertial(problem, plan, time_s)
    axis = quaternion_to_rotation(quaternion_BN).apply(plan.body_axis)
    cross = np.linalg.norm(np.cross(axis, wanted), axis=1)
    return np.arctan2(cross, np.einsum("ij,ij->i", axis, wanted))


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
    model: Model,
    controller: control.StateSpace,
    plan: BurnPlan,
    *,
    period_s: float = BURN_PERIOD_S,
    propulsion: PropulsionState | None = None,
    jit: bool = False,
) -> BurnRun:
    """Fly a burn in closed loop: the thrust axis held along its direction, force and torque
    allocated together.

    Parameters
    ----------
    model : Model
        The model of the problem flown, ``model.problem`` (flexible: every array mode
        by default).
    controller : control.StateSpace
        Continuous controller, attitude error [deg] -> torque [mNm].
    plan : BurnPlan
    period_s : float
        Control period [s].
    propulsion : PropulsionState, optional
        Engines at the start (default full); not modified.
    jit : bool
        Compile the control step to C (see :func:`~casadi_debris.simulation.simulate_closed_loop`).

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
    problem = model.problem
    reference = burn_reference(problem, plan, period_s)
    discrete = discretize_controller(controller, period_s)
    rollout = _Rollout.of(model, reference, discrete, RunInputs(propulsion=propulsion, failures=()))
    rollout.burns = [BurnWindow(0, rollout.n, plan)]
    # On the frame from the start, turning with it (no start-up transient).
    rate = body_rates(reference.time_s[:2], reference.quaternion_BN[:2])[0]
    n_plant = model.layout.size
    rollout.z[:n_plant] = model.initial_state(reference.quaternion_BN[0], rate)
    rollout.states[0] = rollout.z[:n_plant]
    error = rollout.roll_alone(LoopSettings(jit=jit))
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
