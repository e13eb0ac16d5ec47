"""One closed-loop scenario: plant, star tracker, controller, allocator, engines, reference.

:func:`simulate` rolls the compiled control period
(:mod:`casadi_debris.simulation.closed_loop`) out in stretches. After each
stretch the allocator turns the applied torques into engine thrust
(least fuel, zero net force) and the propulsion state burns it. A stretch
ends early where the engines change: at a scheduled failure (the problem's
``[[simulation.failures]]``) or where a CubeSat runs out of stages. The loop
is then rebuilt with the new torque authority and goes on from that step.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import control
import numpy as np

from casadi_debris.allocation import Allocator, PropulsionState, StageEvent
from casadi_debris.config import FailureEvent, Problem
from casadi_debris.model import Model, Parameters
from casadi_debris.simulation.closed_loop import (
    DiscreteController,
    LoopStep,
    SimulationError,
    StepInput,
    StepOutput,
    applied_torque,
    build_loop_step,
    discretize_controller,
)
from casadi_debris.simulation.disturbance import disturbance_series
from casadi_debris.simulation.noise import NoiseStreams, draw_noise
from casadi_debris.simulation.realism import Realism, engine_basis
from casadi_debris.simulation.reference import Reference
from casadi_debris.simulation.summary import (
    SETTLE_BAND_ARCSEC,
    EventRecord,
    RunSummary,
    settle_time_s,
    summarize,
)
from casadi_debris.units import ARCSEC_PER_RAD

# The allocator's torque must equal the applied torque to this (relative to
# the largest torque authority): the loop's premise, checked on every run.
ALLOCATION_TOLERANCE = 1e-8
DEFAULT_CHUNK_STEPS = 1000


EVENT_KINDS = ("stage_depleted", "stage_failed", "cubesat_failed", "engine_failed")


@dataclass(frozen=True)
class RunEvent:
    """Something that changed the engines during a run.

    Attributes
    ----------
    time_s : float
        When [s].
    kind : {"stage_depleted", "stage_failed", "cubesat_failed", "engine_failed"}
    cubesat : int
        0-based (``text`` and the summary number CubeSats from 1).
    stage : int or None
        The stage depleted or failed (0-based); None for a whole CubeSat or engine.
    next_stage : int or None
        The stage firing afterwards; None when the CubeSat has none left.
    switched : bool
        Whether the stage that fires changed (a depleted stage always; a failed
        stage only when it was the one firing).
    engine : int or None
        The engine that failed or whose stage ran dry, counted among its
        CubeSat's own engines (0-based), for a CubeSat with several; None otherwise.
    """

    time_s: float
    kind: str
    cubesat: int
    stage: int | None = None
    next_stage: int | None = None
    switched: bool = False
    engine: int | None = None

    @property
    def text(self) -> str:
        """The event in words, CubeSats, engines and stages numbered from 1."""
        who = f"CubeSat {self.cubesat + 1}"
        if self.engine is not None:
            who += f" engine {self.engine + 1}"
        if self.kind in ("cubesat_failed", "engine_failed"):
            return f"{who} failed"
        if self.kind == "stage_failed":
            return f"{who}: stage {_number(self.stage)} failed"
        then = "none left" if self.next_stage is None else f"stage {self.next_stage + 1} takes over"
        return f"{who}: stage {_number(self.stage)} empty, {then}"

    def record(self) -> EventRecord:
        """The event as a user reads it: 1-based ids, in words."""
        return EventRecord(
            time_s=self.time_s,
            kind=self.kind,
            cubesat=self.cubesat + 1,
            engine=None if self.engine is None else self.engine + 1,
            stage=None if self.stage is None else self.stage + 1,
            next_stage=None if self.next_stage is None else self.next_stage + 1,
            stage_switch=self.switched,
            event=self.text,
        )


def _number(stage: int | None) -> str:
    return "?" if stage is None else str(stage + 1)


@dataclass(eq=False)
class ClosedLoopResult:
    """Time series and figures of one closed-loop run (SI units).

    Attributes
    ----------
    time_s : ndarray, shape (n + 1,)
        Control instants, 0 .. duration.
    state : ndarray, shape (n + 1, n_x)
        Plant state (model layout) at each instant.
    rate_rad_s : ndarray, shape (n + 1, 3)
        Body rate omega_BN in B.
    reference_BN : ndarray, shape (n + 1, 4)
    error_rad : ndarray, shape (n + 1, 3)
        True attitude minus reference (doubled error-quaternion vector).
    measured_error_rad : ndarray, shape (n, 3)
        What the star tracker told the controller at each step.
    demand_Nm, torque_Nm : ndarray, shape (n, 3)
        Controller demand, and the allocator's torque ``B f`` held over each step.
    force_N : ndarray, shape (n, 3)
        Net force of the thrust (zero to round-off).
    scale : ndarray, shape (n,)
        Saturation factor alpha (1: demand met).
    thrust_N : ndarray, shape (n, n_engines)
    disturbance_Nm : ndarray, shape (n, 3)
        At the start of each step.
    propulsion : PropulsionState
        At the end.
    events : list of RunEvent
        Failures and depleted stages, in time order.
    parameters : dict
        Model parameters by name.
    control_period_s : float
    allocation_residual_Nm : float
        Largest |B f - applied torque| over the run.
    point_solves : int
        QP solves the allocator needed (the rest reused active sets).
    wall_time_s : float
    slew_window_s : (float, float) or None
        Start and end of the reference slew [s].
    compiled_step : bool or None
        Whether the control period ran as compiled C code.
    authority_time_s : ndarray, shape (m,)
        When the torque authority took each of its values: the start, and each
        failure or depleted stage after which the loop was rebuilt [s].
    authority_Nm : ndarray, shape (m, 6)
        Largest pure torque at zero net force about +x, -x, +y, -y, +z, -z
        (magnitudes) from each of those instants on [N m].
    noise_seed : int or None
        Seed of the sensors' and engines' noise (None: the ideal loop, no noise).
    """

    time_s: np.ndarray
    state: np.ndarray
    rate_rad_s: np.ndarray
    reference_BN: np.ndarray
    error_rad: np.ndarray
    measured_error_rad: np.ndarray
    demand_Nm: np.ndarray
    torque_Nm: np.ndarray
    force_N: np.ndarray
    scale: np.ndarray
    thrust_N: np.ndarray
    disturbance_Nm: np.ndarray
    propulsion: PropulsionState
    fuel_start_kg: np.ndarray
    events: list[RunEvent]
    parameters: dict[str, float]
    control_period_s: float
    total_mass_kg: float
    allocation_residual_Nm: float
    point_solves: int
    wall_time_s: float
    slew_window_s: tuple[float, float] | None = None
    compiled_step: bool | None = None
    authority_time_s: np.ndarray = field(default_factory=lambda: np.zeros(0))
    authority_Nm: np.ndarray = field(default_factory=lambda: np.zeros((0, 6)))
    noise_seed: int | None = None

    @property
    def fuel_per_cubesat_kg(self) -> np.ndarray:
        """Propellant burnt by each CubeSat during the run, shape (n_cubesats,) [kg]."""
        return self.propulsion.per_cubesat(self.fuel_per_engine_kg)

    @property
    def fuel_per_engine_kg(self) -> np.ndarray:
        """Propellant burnt by each engine during the run, shape (n_engines,) [kg]."""
        return (self.fuel_start_kg - self.propulsion.propellant_kg).sum(axis=1)

    @property
    def exhaust_velocity_m_s(self) -> float:
        """Effective exhaust velocity of the propellant burnt [m/s].

        The engines' one exhaust velocity when they share an Isp; otherwise the
        mean over the engines weighted by the propellant each burnt (total
        impulse over total propellant, the velocity the rocket equation takes
        for the run's Delta v), or their plain mean if nothing was burnt.
        """
        exhaust = self.propulsion.exhaust_velocity_m_s
        if np.all(exhaust == exhaust[0]):
            return float(exhaust[0])
        fuel = self.fuel_per_engine_kg
        if fuel.sum() <= 0.0:
            return float(np.mean(exhaust))
        return float(np.sum(fuel * exhaust) / fuel.sum())

    @property
    def estimation_error_rad(self) -> np.ndarray:
        """What the controller was told minus the truth, shape (n, 3) [rad]:
        ``measured_error_rad - error_rad`` at the start of each step."""
        return self.measured_error_rad - self.error_rad[:-1]

    def settle_time_s(self, band_rad: float = SETTLE_BAND_ARCSEC / ARCSEC_PER_RAD) -> float | None:
        """First instant after which every error component stays inside ``band_rad``.

        None when the run ends outside the band.
        """
        return settle_time_s(self.time_s, self.error_rad, band_rad)

    def summary(self) -> RunSummary:
        """Figures of the run, units in the names."""
        return summarize(self)


def _depleted(event: StageEvent, time_s: float, propulsion: PropulsionState) -> RunEvent:
    siblings = np.flatnonzero(propulsion.engine_cubesat == event.cubesat)
    several = len(siblings) > 1
    return RunEvent(
        time_s,
        "stage_depleted",
        event.cubesat,
        event.stage,
        event.next_stage,
        switched=True,
        engine=int(np.searchsorted(siblings, event.engine)) if several else None,
    )


def _apply_failure(failure: FailureEvent, propulsion: PropulsionState, time_s: float) -> RunEvent:
    cubesat = failure.cubesat
    if failure.engine is not None:
        propulsion.fail_engine(cubesat, failure.engine)
        return RunEvent(time_s, "engine_failed", cubesat, engine=failure.engine)
    if failure.stage is None:
        propulsion.fail_cubesat(cubesat)
        return RunEvent(time_s, "cubesat_failed", cubesat)
    engines = np.flatnonzero(propulsion.engine_cubesat == cubesat)
    before = propulsion.active_stage[engines]
    propulsion.fail_stage(cubesat, failure.stage)
    after = propulsion.active_stage[engines]
    firing = after[after < propulsion.n_stages]
    return RunEvent(
        time_s,
        "stage_failed",
        cubesat,
        failure.stage,
        int(firing.min()) if len(firing) else None,
        switched=bool(np.any((after != before) & (before == failure.stage))),
    )


def simulate(
    problem: Problem,
    model: Model,
    controller: control.StateSpace,
    reference: Reference,
    *,
    parameters: np.ndarray | None = None,
    propulsion: PropulsionState | None = None,
    failures: tuple[FailureEvent, ...] | None = None,
    integrator: str = "rk4",
    integrator_steps: int | None = None,
    chunk_steps: int = DEFAULT_CHUNK_STEPS,
    allocator: Allocator | None = None,
    jit: bool = False,
    noise_seed: int | None = None,
) -> ClosedLoopResult:
    """Run one closed-loop scenario.

    Parameters
    ----------
    problem : Problem
    model : Model
        Built from ``problem`` (all array modes for the paper's runs).
    controller : control.StateSpace
        Continuous controller, attitude error [deg] -> torque [mNm].
    reference : Reference
        Reference at the control instants; its times set the run
        (uniform, spacing = control period).
    parameters : ndarray, shape (n_parameters,), optional
        Model parameter vector, laid out as ``model.parameter_layout`` (default nominal).
    propulsion : PropulsionState, optional
        Engines at the start (default all full); not modified.
    failures : tuple of FailureEvent, optional
        Default the problem's ``simulation.failures``.
    integrator : {"rk4", "cvodes"}
    integrator_steps : int, optional
        RK4 steps per period (default the problem's).
    chunk_steps : int
        Periods per compiled roll-out call.
    allocator : Allocator, optional
        Reused between runs of one problem (its authority polytope and
        active-set regions are kept while the limits do not change); its
        limits are set from the engines.
    jit : bool
        Run the step as compiled C (see
        :func:`~casadi_debris.simulation.build_loop_step`): worth its few
        seconds of compiling when many runs share it (Monte Carlo).
    noise_seed : int, optional
        Seed of the noise (default ``[sensors] seed``); unused by the ideal loop.

    Returns
    -------
    ClosedLoopResult
    """
    started = time.perf_counter()
    period = _control_period(reference)
    p = model.nominal_parameters if parameters is None else np.asarray(parameters, dtype=float)
    engines = PropulsionState.from_problem(problem) if propulsion is None else propulsion.copy()
    fuel_start = engines.propellant_kg.copy()
    steps = problem.simulation.integrator_steps if integrator_steps is None else integrator_steps
    realism = Realism.of(problem, period)
    rollout = _Rollout(
        model=model,
        reference=reference,
        parameters=p,
        controller=discretize_controller(controller, period),
        engines=engines,
        allocator=allocator or Allocator.from_problem(problem, model.geometry, state=engines),
        loop_options={
            "integrator_steps": steps,
            "integrator": integrator,
            "chunk_steps": chunk_steps,
            "jit": jit,
            "realism": realism,
        },
        problem=problem,
        noise_seed=noise_seed,
    )
    rollout.run(problem.simulation.failures if failures is None else failures)
    return rollout.result(fuel_start, wall_time_s=time.perf_counter() - started)


def _control_period(reference: Reference) -> float:
    """The reference's uniform spacing [s], which the run takes as its control period."""
    times = reference.time_s
    if len(times) < 2:
        raise SimulationError("the reference needs at least two instants")
    period = float(times[1] - times[0])
    if not np.allclose(np.diff(times), period, rtol=1e-9, atol=1e-12):
        raise SimulationError("the reference must be sampled uniformly (one per control period)")
    return period


@dataclass(eq=False)
class _Rollout:
    """The compiled loop rolled out stretch by stretch, with the engines burning in between."""

    model: Model
    reference: Reference
    parameters: np.ndarray
    controller: DiscreteController
    engines: PropulsionState
    allocator: Allocator
    loop_options: dict[str, Any]
    problem: Problem
    noise_seed: int | None = None

    def __post_init__(self) -> None:
        self.period = float(self.reference.time_s[1] - self.reference.time_s[0])
        self.n = len(self.reference.time_s) - 1
        self.realism: Realism | None = self.loop_options["realism"]
        self.noise: NoiseStreams | None = None
        if self.realism is not None:
            times = self.reference.time_s[:-1]
            self.noise = draw_noise(self.problem, self.model.geometry, times, self.noise_seed)
        self.states = np.zeros((self.n + 1, self.model.layout.size))
        width = StepOutput.SIZE if self.realism is None else self.realism.output_size
        self.outputs = np.zeros((self.n, width))
        self.applied = np.zeros((self.n, 3))
        self.thrust = np.zeros((self.n, self.engines.n_engines))
        self.events: list[RunEvent] = []
        self.point_solves = 0
        self.compiled = False
        self.authority: list[tuple[float, np.ndarray]] = []
        self.allocator.update_from_state(self.engines)

    def run(self, failures: tuple[FailureEvent, ...]) -> None:
        """Every period of the reference; failures applied at their periods."""
        period, n = self.period, self.n
        failure_steps = [min(n, max(0, math.ceil(f.time_s / period - 1e-9))) for f in failures]
        pending = list(zip(failure_steps, failures, strict=True))
        x0 = _initial_state(self.model, self.reference)
        z = np.concatenate([x0, np.zeros(self.controller.n_states)])
        if self.realism is not None:
            aux = self.realism.initial_aux(self.problem, self.reference.quaternion_BN[0])
            z = np.concatenate([z, aux])
        self.states[0] = z[: self.model.layout.size]
        loop: LoopStep | None = None
        k = 0
        while k < n:
            while pending and pending[0][0] <= k:
                _, failure = pending.pop(0)
                self.events.append(_apply_failure(failure, self.engines, k * period))
                loop = None
            if loop is None:
                loop = self._build_loop(k * period)
            stop = min(n, k + loop.chunk_steps, pending[0][0] if pending else n)
            z, done = self._stretch(loop, z, k, stop)
            if done < stop - k:
                loop = None  # a CubeSat's limit changed: rebuild from the step after
            k += done

    def _build_loop(self, time_s: float) -> LoopStep:
        self.allocator.update_from_state(self.engines)
        polytope = self.allocator.authority_polytope()
        self.authority.append((time_s, polytope.axis_reach()))
        basis = None
        if self.realism is not None and self.realism.engine_level:
            basis = engine_basis(self.allocator)
        loop = build_loop_step(
            self.model, self.parameters, self.controller, polytope, basis=basis, **self.loop_options
        )
        self.compiled = self.compiled or loop.compiled
        return loop

    def _stretch(self, loop: LoopStep, z: np.ndarray, k: int, stop: int) -> tuple[np.ndarray, int]:
        """Periods k .. stop - 1, cut short where the engines change; (state, periods done)."""
        z_all, y_all = loop.roll(z, self._inputs(loop, k, stop), self.parameters)
        z_all = z_all[:, : stop - k]
        y_all = y_all[:, : stop - k].T
        if self.realism is None:
            applied = applied_torque(y_all[:, StepOutput.DEMAND_NM], y_all[:, StepOutput.SCALE])
        else:
            applied = y_all[:, StepOutput.APPLIED_NM]
        engine_level = self.realism is not None and self.realism.engine_level
        allocation = self.allocator.allocate_series(
            y_all[:, StepOutput.COMMAND_NM] if engine_level else applied
        )
        self.point_solves += allocation.point_solves
        thrust = allocation.thrust_N
        if engine_level:  # the engines' effects on the allocated thrust
            change = y_all[:, StepOutput.THRUST_CHANGE_START :]
            thrust = np.clip(thrust + change, 0.0, self.allocator.max_thrust_N)
        done, stage_events = self.engines.advance_series(thrust, self.period)
        for index, event in stage_events:
            time_s = (k + index) * self.period + event.time_s
            self.events.append(_depleted(event, time_s, self.engines))
        self.outputs[k : k + done] = y_all[:done]
        self.applied[k : k + done] = applied[:done]
        self.thrust[k : k + done] = thrust[:done]
        self.states[k + 1 : k + done + 1] = z_all[: self.model.layout.size, :done].T
        return z_all[:, done - 1], done

    def _inputs(self, loop: LoopStep, k: int, stop: int) -> np.ndarray:
        """The step inputs of periods k .. stop - 1, padded to ``chunk_steps`` columns."""
        reference, used = self.reference, stop - k
        inputs = np.zeros((loop.n_inputs, loop.chunk_steps))
        if self.realism is not None and self.noise is not None:
            inputs[StepInput.SIZE :, :used] = self.realism.inputs.rows(
                self.problem, self.noise, self.period, k, stop
            )
        inputs[StepInput.TIME_S, :used] = reference.time_s[k:stop]
        inputs[StepInput.REFERENCE_BN, :used] = reference.quaternion_BN[k:stop].T
        if reference.feedforward_Nm is not None:
            inputs[StepInput.FEEDFORWARD_NM, :used] = reference.feedforward_Nm[k:stop].T
        # Padding periods: identity reference, results unused.
        inputs[StepInput.REFERENCE_BN.start, used:] = 1.0
        return inputs

    def result(self, fuel_start_kg: np.ndarray, wall_time_s: float) -> ClosedLoopResult:
        """The run's series and figures; checks the allocator met every applied torque."""
        model, reference, n = self.model, self.reference, self.n
        torque = self.thrust @ self.allocator.torque_map.T
        force = self.thrust @ self.allocator.force_map.T
        engine_level = self.realism is not None and self.realism.engine_level
        if engine_level:  # the step's own engines: their misaligned, noisy wrench
            torque = self.outputs[:, StepOutput.APPLIED_NM]
            force = self.outputs[:, StepOutput.FORCE_N]
        # With engine-level effects the step allocates itself: nothing to check here.
        residual = float(np.abs(torque - self.applied).max()) if n and not engine_level else 0.0
        polytope = self.allocator.authority_polytope()
        authority = float(np.abs(polytope.vertices).max()) if n else 1.0
        if residual > ALLOCATION_TOLERANCE * authority:
            raise SimulationError(
                f"the allocator's torque differs from the applied torque by {residual:.3g} N m"
            )
        error = np.asarray(
            model.attitude_error.map(n + 1)(
                reference.quaternion_BN.T, self.states[:, model.layout.q].T
            )
        ).T
        p = Parameters.from_vector(model.parameter_layout, self.parameters)
        return ClosedLoopResult(
            time_s=reference.time_s,
            state=self.states,
            rate_rad_s=self.states[:, model.layout.omega],
            reference_BN=reference.quaternion_BN,
            error_rad=error,
            measured_error_rad=self.outputs[:, StepOutput.MEASURED_ERROR_RAD],
            demand_Nm=self.outputs[:, StepOutput.DEMAND_NM],
            torque_Nm=torque,
            force_N=force,
            scale=self.outputs[:, StepOutput.SCALE],
            thrust_N=self.thrust,
            disturbance_Nm=disturbance_series(
                model, reference.time_s[:-1], self.states[:-1], self.parameters
            ),
            propulsion=self.engines,
            fuel_start_kg=fuel_start_kg,
            events=self.events,
            parameters=p.to_dict(),
            control_period_s=self.period,
            total_mass_kg=p.mass_kg,
            allocation_residual_Nm=residual,
            point_solves=self.point_solves,
            wall_time_s=wall_time_s,
            compiled_step=self.compiled,
            authority_time_s=np.array([t for t, _ in self.authority]),
            authority_Nm=np.array([reach for _, reach in self.authority]).reshape(-1, 6),
            noise_seed=None if self.noise is None else self.noise.seed,
            slew_window_s=(
                None
                if reference.slew is None
                else (reference.start_s, reference.start_s + reference.slew.duration_s)
            ),
        )


def _initial_state(model: Model, reference: Reference) -> np.ndarray:
    """At rest, arrays undeformed, on the reference's first attitude."""
    return model.initial_state(quaternion=reference.quaternion_BN[0])
