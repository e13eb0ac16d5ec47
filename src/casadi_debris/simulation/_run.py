"""One closed-loop scenario: plant, star tracker, controller, allocator, engines, reference.

:func:`simulate_closed_loop` rolls the compiled control period
(:mod:`casadi_debris.simulation._closed_loop`) out in stretches. After each
stretch the allocator turns the applied torques into engine thrust
(least fuel, zero net force) and the propulsion state burns it. A stretch
ends early where the engines change: at a scheduled failure (the problem's
``[[simulation.failures]]``) or where a CubeSat runs out of stages. The loop
is then rebuilt with the new torque authority and goes on from that step.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import casadi as ca
import control
import numpy as np

from casadi_debris.allocation import (
    Allocator,
    AuthorityPolytope,
    PropulsionState,
    authority_polytope,
)
from casadi_debris.config import FailureEvent, Problem
from casadi_debris.dynamics import Model, Parameters
from casadi_debris.guidance import BurnWindow, Reference, burn_thrust_N, burn_windows
from casadi_debris.simulation._batched import roll_together
from casadi_debris.simulation._closed_loop import (
    DiscreteController,
    SimulationError,
    StepInput,
    StepOutput,
    applied_torque,
    build_loop_step,
    discretize_controller,
)
from casadi_debris.simulation._disturbance import disturbance_series, sine_series
from casadi_debris.simulation._events import RunEvent, apply_failure, depleted_event
from casadi_debris.simulation._noise import NoiseStreams, draw_noise
from casadi_debris.simulation._realism import Realism, engine_basis
from casadi_debris.simulation._result import ClosedLoopResult

# The allocator's torque must equal the applied torque to this (relative to
# the largest torque authority): the loop's premise, checked on every run.
ALLOCATION_TOLERANCE = 1e-8
DEFAULT_CHUNK_STEPS = 1000


@dataclass(frozen=True)
class LoopSettings:
    """How the closed loop is rolled out; the same for every run of a call.

    Attributes
    ----------
    integrator : {"rk4", "cvodes"}
    integrator_steps : int, optional
        RK4 steps per period (default the problem's ``simulation.integrator_steps``).
    chunk_steps : int
        Periods per compiled roll-out call.
    jit : bool
        Run the step as compiled C (RK4 only): the batched loop of
        :mod:`~casadi_debris.simulation._batched`, compiled once per machine
        (seconds) and loaded from the cache afterwards.
    """

    integrator: str = "rk4"
    integrator_steps: int | None = None
    chunk_steps: int = DEFAULT_CHUNK_STEPS
    jit: bool = False

    def steps(self, problem: Problem) -> int:
        """RK4 steps per period: this setting's, else ``problem``'s."""
        if self.integrator_steps is None:
            return problem.simulation.integrator_steps
        return self.integrator_steps


@dataclass(frozen=True, eq=False)
class RunInputs:
    """What one run of :func:`simulate_many` varies (each field as in :func:`simulate_closed_loop`).

    Attributes
    ----------
    parameters : ndarray, shape (n_parameters,), optional
    failures : tuple of FailureEvent, optional
    allocator : Allocator, optional
    propulsion : PropulsionState, optional
    noise_seed : int, optional
    """

    parameters: np.ndarray | None = None
    failures: tuple[FailureEvent, ...] | None = None
    allocator: Allocator | None = None
    propulsion: PropulsionState | None = None
    noise_seed: int | None = None


def simulate_closed_loop(
    model: Model,
    controller: control.StateSpace,
    reference: Reference,
    *,
    parameters: np.ndarray | None = None,
    propulsion: PropulsionState | None = None,
    failures: tuple[FailureEvent, ...] | None = None,
    allocator: Allocator | None = None,
    noise_seed: int | None = None,
    settings: LoopSettings = LoopSettings(),
) -> ClosedLoopResult:
    """Run one closed-loop scenario.

    Parameters
    ----------
    model : Model
        The model of the problem flown, ``model.problem`` (all array modes for the
        paper's runs).
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
    allocator : Allocator, optional
        Reused between runs of one problem (its authority polytope and
        active-set regions are kept while the limits do not change); its
        limits are set from the engines.
    noise_seed : int, optional
        Seed of the noise (default ``[sensors] seed``); unused by the ideal loop.
    settings : LoopSettings
        Integrator, its steps, roll-out length, compiled C (default RK4 at the
        problem's steps on CasADi's virtual machine).

    Returns
    -------
    ClosedLoopResult
    """
    outcome = simulate_many(
        model,
        controller,
        reference,
        [RunInputs(parameters, failures, allocator, propulsion, noise_seed)],
        settings=settings,
    )[0]
    if isinstance(outcome, Exception):
        raise outcome
    return outcome


def simulate_many(
    model: Model,
    controller: control.StateSpace,
    reference: Reference,
    runs: Sequence[RunInputs],
    *,
    settings: LoopSettings = LoopSettings(),
    slots: int | None = None,
) -> list[ClosedLoopResult | Exception]:
    """Run several closed-loop scenarios of one problem; with ``jit``, all at once.

    With ``jit`` (RK4, the paper's ideal loop) every stretch of every run is one call of one
    compiled function mapped over the runs
    (:func:`~casadi_debris.simulation._batched.roll_together`); between
    stretches each run allocates, burns and fails as :func:`simulate_closed_loop` does
    alone, and gets the same numbers. Otherwise (or without a C compiler)
    the runs go one after the other on CasADi's virtual machine.

    Parameters
    ----------
    model, controller, reference
        As :func:`simulate_closed_loop`, shared by the runs.
    runs : sequence of RunInputs
        What each run varies.
    settings : LoopSettings
        As :func:`simulate_closed_loop`.
    slots : int, optional
        Cases of the compiled function (default ``len(runs)``): a campaign
        keeps one size for all its batches, so that one library serves them.

    Returns
    -------
    list of (ClosedLoopResult or Exception)
        Per run, its result or what it raised (the other runs go on). Each
        result's ``wall_time_s`` is its share of the whole call.
    """
    started = time.perf_counter()
    problem = model.problem
    period = _control_period(reference)
    discrete = discretize_controller(controller, period)
    realism = Realism.of(problem, period)
    rollouts = [_Rollout.of(model, reference, discrete, run, realism) for run in runs]
    errors = None
    burns = any(r.burns for r in rollouts)  # the batched step has no force input
    if settings.jit and settings.integrator == "rk4" and realism is None and rollouts and not burns:
        errors = roll_together(
            rollouts,
            model,
            discrete,
            slots=slots or len(rollouts),
            integrator_steps=settings.steps(problem),
            chunk_steps=settings.chunk_steps,
        )
    if errors is None:
        errors = [r.roll_alone(settings) for r in rollouts]
    else:
        for rollout in rollouts:
            rollout.compiled = True
    shared = _Series.of(model, reference)
    share = (time.perf_counter() - started) / max(len(rollouts), 1)
    outcomes: list[ClosedLoopResult | Exception] = []
    for rollout, error in zip(rollouts, errors, strict=True):
        if error is not None:
            outcomes.append(error)
            continue
        try:
            outcomes.append(rollout.result(shared, wall_time_s=share))
        except Exception as exc:  # the allocator missed a torque: this run's failure
            outcomes.append(exc)
    return outcomes


@dataclass(frozen=True, eq=False)
class _Series:
    """What every run of one reference shares for its result: the attitude error over
    the whole run (a mapped Function) and the sine disturbance."""

    error: ca.Function
    sine_Nm: np.ndarray

    @classmethod
    def of(cls, model: Model, reference: Reference) -> _Series:
        times = reference.time_s
        return cls(model.attitude_error.map(len(times)), sine_series(model, times[:-1]))


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
    """One run rolled out stretch by stretch, with the engines burning in between.

    :meth:`next_stretch` applies the failures due and gives the periods of the
    next stretch (``polytope`` is then its authority); the caller rolls the
    step over them from ``z`` and hands the states and outputs to :meth:`take`.
    """

    model: Model
    reference: Reference
    parameters: np.ndarray
    controller: DiscreteController
    engines: PropulsionState
    allocator: Allocator
    failures: tuple[FailureEvent, ...]
    problem: Problem
    realism: Realism | None = None
    noise_seed: int | None = None

    @classmethod
    def of(
        cls,
        model: Model,
        reference: Reference,
        controller: DiscreteController,
        run: RunInputs,
        realism: Realism | None = None,
    ) -> _Rollout:
        """A run of ``model.problem`` at its start (engines full unless ``run.propulsion``
        says otherwise)."""
        problem = model.problem
        p = run.parameters
        if run.propulsion is None:
            engines = PropulsionState.from_problem(problem)
        else:
            engines = run.propulsion.copy()
        allocator = run.allocator or Allocator.from_problem(problem, model.geometry, state=engines)
        return cls(
            model=model,
            reference=reference,
            parameters=model.nominal_parameters if p is None else np.asarray(p, dtype=float),
            controller=controller,
            engines=engines,
            allocator=allocator,
            failures=problem.simulation.failures if run.failures is None else run.failures,
            problem=problem,
            realism=realism,
            noise_seed=run.noise_seed,
        )

    def __post_init__(self) -> None:
        self.period = float(self.reference.time_s[1] - self.reference.time_s[0])
        self.n = len(self.reference.time_s) - 1
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
        self.fuel_start_kg = self.engines.propellant_kg.copy()
        self.allocator.update_from_state(self.engines)
        due = [min(self.n, max(0, math.ceil(f.time_s / self.period - 1e-9))) for f in self.failures]
        self.pending = list(zip(due, self.failures, strict=True))
        self.z = np.concatenate(
            [_initial_state(self.model, self.reference), np.zeros(self.controller.n_states)]
        )
        if self.realism is not None:
            aux = self.realism.initial_aux(self.problem, self.reference.quaternion_BN[0])
            self.z = np.concatenate([self.z, aux])
        self.states[0] = self.z[: self.model.layout.size]
        self.k = 0
        self.polytope: AuthorityPolytope | None = None
        self.force_N: np.ndarray | None = None  # a burn's net force on the plant, body axes
        self.burns = burn_windows(self.reference, self.period)
        self.burning: BurnWindow | None = None
        if self.burns and self.realism is not None:
            raise SimulationError("a burn flies the ideal loop: no realistic sensors or engines")

    @property
    def finished(self) -> bool:
        """Every period of the reference is done."""
        return self.k >= self.n

    def next_stretch(self, chunk_steps: int) -> tuple[int, int]:
        """Apply the failures due now, take the engines' authority; the periods (k, stop)."""
        k = self.k
        while self.pending and self.pending[0][0] <= k:
            _, failure = self.pending.pop(0)
            self.events.append(apply_failure(failure, self.engines, k * self.period))
            self.polytope = None
        burning = next((w for w in self.burns if w.start <= k < w.stop), None)
        if burning is not self.burning:  # a burn starts or ends: its force changes the authority
            self.burning, self.polytope = burning, None
        if self.polytope is None:
            self.allocator.update_from_state(self.engines)
            self.polytope = self.torque_authority()
            self.authority.append((k * self.period, self.polytope.axis_reach()))
        stop = min(self.n, k + chunk_steps, self.pending[0][0] if self.pending else self.n)
        return k, min([stop, *(e for w in self.burns for e in (w.start, w.stop) if k < e < stop)])

    def torque_authority(self) -> AuthorityPolytope:
        """The torques the loop saturates to, with the engines' current limits: during a
        burn those it can add while delivering the burn's force (sets ``force_N``)."""
        if self.burning is None:
            self.force_N = None
            return self.allocator.authority_polytope()
        plan = self.burning.plan
        # A thrust beyond the engines is an error at the burn's start; later (engines
        # spent during it) the burn goes on with what is left.
        thrust = burn_thrust_N(self.allocator, plan, strict=self.k == self.burning.start)
        self.force_N = thrust * plan.body_axis
        return authority_polytope(
            self.allocator.torque_map,
            self.allocator.force_map,
            self.allocator.max_thrust_N,
            force_N=self.force_N,
        )

    def allocate(self, torques_Nm: np.ndarray) -> tuple[np.ndarray, int]:
        """Each engine's thrust for the applied torques (k, 3) (and a burn's force), and the
        point solves it took."""
        if self.force_N is None:
            allocation = self.allocator.allocate_series(torques_Nm)
            return allocation.thrust_N, allocation.point_solves
        forces = np.tile(self.force_N, (len(torques_Nm), 1))
        batch = self.allocator.allocate_batch(torques_Nm, forces_N=forces)
        if not batch.feasible.all():
            raise SimulationError("the allocator could not deliver a burn's force and torque")
        return batch.thrust_N, len(torques_Nm)

    def roll_alone(self, settings: LoopSettings) -> Exception | None:
        """Every stretch on this run's own step (rebuilt with each authority); what it raised."""
        chunk_steps = settings.chunk_steps
        try:
            loop, built_for = None, None
            while not self.finished:
                k, stop = self.next_stretch(chunk_steps)
                if self.polytope is None:  # next_stretch always sets it
                    raise SimulationError("a stretch without a torque authority")
                if loop is None or built_for is not self.polytope:
                    loop = build_loop_step(
                        self.model,
                        self.parameters,
                        self.controller,
                        self.polytope,
                        integrator_steps=settings.steps(self.problem),
                        integrator=settings.integrator,
                        chunk_steps=chunk_steps,
                        jit=settings.jit,
                        realism=self.realism,
                        basis=engine_basis(self.allocator) if self._engine_level else None,
                        force_N=self.force_N,
                    )
                    built_for = self.polytope
                    self.compiled = self.compiled or loop.compiled
                inputs = self.inputs(chunk_steps, k, stop, loop.n_inputs)
                z_all, y_all = loop.roll(self.z, inputs, self.parameters)
                self.take(z_all, y_all, k, stop)
        except Exception as exc:  # the caller decides: simulate raises it, a campaign records it
            return exc
        return None

    def take(self, z_all: np.ndarray, y_all: np.ndarray, k: int, stop: int) -> None:
        """Periods k .. stop - 1 rolled (states and outputs, one column each): allocate and
        burn, cut short where the engines change (the next stretch starts there)."""
        z_all = z_all[:, : stop - k]
        y_all = y_all[:, : stop - k].T
        if self.realism is None:
            applied = applied_torque(y_all[:, StepOutput.DEMAND_NM], y_all[:, StepOutput.SCALE])
        else:
            applied = y_all[:, StepOutput.APPLIED_NM]
        engine_level = self._engine_level
        thrust, solves = self.allocate(y_all[:, StepOutput.COMMAND_NM] if engine_level else applied)
        self.point_solves += solves
        if engine_level:  # the engines' effects on the allocated thrust
            change = y_all[:, StepOutput.THRUST_CHANGE_START :]
            thrust = np.clip(thrust + change, 0.0, self.allocator.max_thrust_N)
        done, stage_events = self.engines.advance_series(thrust, self.period)
        for index, event in stage_events:
            time_s = (k + index) * self.period + event.time_s
            self.events.append(depleted_event(event, time_s, self.engines))
        self.outputs[k : k + done] = y_all[:done]
        self.applied[k : k + done] = applied[:done]
        self.thrust[k : k + done] = thrust[:done]
        self.states[k + 1 : k + done + 1] = z_all[: self.model.layout.size, :done].T
        self.z = z_all[:, done - 1].copy()
        self.k = k + done
        if done < stop - k:
            self.polytope = None  # a CubeSat's limit changed: new authority from the step after

    @property
    def _engine_level(self) -> bool:
        return self.realism is not None and self.realism.engine_level

    def inputs(self, chunk_steps: int, k: int, stop: int, rows: int = StepInput.SIZE) -> np.ndarray:
        """The step inputs of periods k .. stop - 1 (``rows`` of them), padded to
        ``chunk_steps`` columns."""
        reference, used = self.reference, stop - k
        inputs = np.zeros((rows, chunk_steps))
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

    def result(self, series: _Series, wall_time_s: float) -> ClosedLoopResult:
        """The run's series and figures; checks the allocator met every applied torque."""
        model, reference, n = self.model, self.reference, self.n
        torque = self.thrust @ self.allocator.torque_map.T
        force = self.thrust @ self.allocator.force_map.T
        if self._engine_level:  # the step's own engines: their misaligned, noisy wrench
            torque = self.outputs[:, StepOutput.APPLIED_NM]
            force = self.outputs[:, StepOutput.FORCE_N]
        # With engine-level effects the step allocates itself: nothing to check here.
        checked = n and not self._engine_level
        residual = float(np.abs(torque - self.applied).max()) if checked else 0.0
        polytope = self.allocator.authority_polytope()
        authority = float(np.abs(polytope.vertices).max()) if n else 1.0
        if residual > ALLOCATION_TOLERANCE * authority:
            raise SimulationError(
                f"the allocator's torque differs from the applied torque by {residual:.3g} N m"
            )
        error = np.asarray(
            series.error(reference.quaternion_BN.T, self.states[:, model.layout.q].T)
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
                model, reference.time_s[:-1], self.states[:-1], self.parameters, series.sine_Nm
            ),
            propulsion=self.engines,
            fuel_start_kg=self.fuel_start_kg,
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
