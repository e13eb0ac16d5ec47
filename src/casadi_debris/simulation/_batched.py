"""Many closed-loop runs at once: one compiled roll-out, mapped over the cases.

The control period of :mod:`~casadi_debris.simulation._closed_loop` with the
model parameters and the authority polytope as inputs (its facets padded to a
capacity, :func:`facet_rows`) is rolled
out over ``chunk_steps`` periods (``mapaccum``) and the roll-out mapped over
``cases`` slots (``map``): one CasADi Function, generated as C, compiled once
per machine into the cache of :mod:`~casadi_debris.simulation._jit_cache` and
called directly on numpy arrays (:class:`~casadi_debris.simulation._native.NativeFunction`).
Every case of a campaign, whatever its plant, failures or depleted stages,
runs on it: nothing is compiled per case or per failure set.

Between stretches each case goes on as a run of its own
(:func:`~casadi_debris.simulation.simulate_closed_loop`): its allocator turns the
stretch's torques into thrust, its engines burn, its failures and depleted
stages end a stretch early and change its authority. Each slot computes
exactly what the one-case roll-out computes from the same inputs, so a case
gives the same numbers in any batch and alone.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import casadi as ca
import numpy as np

from casadi_debris.allocation import AuthorityPolytope
from casadi_debris.dynamics import Model
from casadi_debris.errors import CompileError
from casadi_debris.processes import c_compiler
from casadi_debris.simulation._closed_loop import (
    JIT_FLAGS,
    DiscreteController,
    SimulationError,
    StepInput,
    StepOutput,
    _jit_key,
    _loop_step,
)
from casadi_debris.simulation._jit_cache import compiled_library
from casadi_debris.simulation._native import NativeFunction

FACET_CAPACITY_MIN = 16
"""Facets the compiled step holds at least; more take the next power of two."""

LOGGER = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class BatchedLoop:
    """``chunk_steps`` control periods of ``cases`` closed loops in one compiled call.

    Attributes
    ----------
    native : NativeFunction
        ``(z0, s, p, facets) -> (z, y)``, CasADi's column-major layout.
    cases : int
        Slots of one call.
    chunk_steps : int
        Periods per call.
    facet_capacity : int
        Facets of the authority polytope a slot can hold.
    n_state : int
        Plant and controller states ``z``.
    """

    native: NativeFunction
    cases: int
    chunk_steps: int
    facet_capacity: int
    n_state: int

    def roll(
        self,
        z: np.ndarray,
        inputs: np.ndarray,
        parameters: np.ndarray,
        polytopes: Sequence[AuthorityPolytope],
    ) -> tuple[np.ndarray, np.ndarray]:
        """Roll every slot ``chunk_steps`` periods on.

        Parameters
        ----------
        z : ndarray, shape (cases, n_state)
            Plant and controller state of each slot at the start.
        inputs : ndarray, shape (cases, chunk_steps, StepInput.SIZE)
            Each period's step input.
        parameters : ndarray, shape (cases, n_parameters)
        polytopes : sequence of AuthorityPolytope
            The torque authority of each slot.

        Returns
        -------
        z_all : ndarray, shape (cases, n_state, chunk_steps)
            State after each period.
        y_all : ndarray, shape (cases, StepOutput.SIZE, chunk_steps)
            The step's outputs of each period.
        """
        # One slot's facets (capacity x 4) are 4 x capacity in CasADi's column order.
        facets = np.stack([facet_rows(p, self.facet_capacity).T for p in polytopes])
        z_all, y_all = self.native.call([z, inputs, parameters, facets])
        m, n = self.cases, self.chunk_steps
        return (
            z_all.reshape(m, n, self.n_state).transpose(0, 2, 1),
            y_all.reshape(m, n, StepOutput.SIZE).transpose(0, 2, 1),
        )


def facet_rows(polytope: AuthorityPolytope, capacity: int) -> np.ndarray:
    """The polytope as the ``facets`` input of a step that takes them: shape (capacity, 4).

    Rows ``[n, b]`` (normal, offset), padded with ``[0, 0, 0, 1]``: a zero
    normal never reaches its facet (``n.tau > 0`` fails), so padding changes
    no ratio and the scale is that of the polytope, bit for bit.

    Raises
    ------
    SimulationError
        More facets than ``capacity``.
    """
    count = len(polytope.offsets)
    if count > capacity:
        raise SimulationError(f"{count} facets exceed the step's capacity of {capacity}")
    rows = np.zeros((capacity, 4))
    rows[:, 3] = 1.0
    rows[:count, :3] = polytope.normals
    rows[:count, 3] = polytope.offsets
    return rows


# The batched loops of this process, by model, controller, sampling, slots and capacity.
_BATCHED: dict[str, BatchedLoop | None] = {}


def facet_capacity(polytopes: Sequence[AuthorityPolytope]) -> int:
    """The smallest capacity that holds every polytope: a power of two, at least 16."""
    needed = max((len(p.offsets) for p in polytopes), default=1)
    capacity = FACET_CAPACITY_MIN
    while capacity < needed:
        capacity *= 2
    return capacity


def batched_loop(
    model: Model,
    controller: DiscreteController,
    *,
    cases: int,
    capacity: int,
    integrator_steps: int,
    chunk_steps: int,
) -> BatchedLoop | None:
    """The compiled batched loop (from this process's memory, the machine's cache, or compiled).

    Returns
    -------
    BatchedLoop or None
        None when no C compiler is found or compiling fails (logged): the
        caller then runs each case on CasADi's virtual machine.
    """
    compiler = c_compiler()
    if compiler is None:
        return None
    key = _jit_key(model, controller, None, integrator_steps, chunk_steps)
    key = f"{key}|{cases}|{capacity}"
    if key not in _BATCHED:
        _BATCHED[key] = _compile(
            model, controller, compiler, cases, capacity, integrator_steps, chunk_steps
        )
    return _BATCHED[key]


def release_batched_loops() -> None:
    """Drop this process's batched loops (their libraries stay in the cache)."""
    _BATCHED.clear()


def _compile(
    model: Model,
    controller: DiscreteController,
    compiler: str,
    cases: int,
    capacity: int,
    integrator_steps: int,
    chunk_steps: int,
) -> BatchedLoop | None:
    step = _loop_step(model, None, controller, capacity, integrator_steps, "rk4")
    n_state = model.layout.size + controller.n_states
    n_p = len(model.parameter_names)
    rollout = step.mapaccum("loop_rollout", chunk_steps)
    z0 = ca.MX.sym("z0", n_state)
    s = ca.MX.sym("s", StepInput.SIZE, chunk_steps)
    p = ca.MX.sym("p", n_p)
    facets = ca.MX.sym("facets", capacity, 4)
    # A case's parameters and facets hold over the stretch: repeated for each period.
    z_all, y_all = rollout(z0, s, ca.repmat(p, 1, chunk_steps), ca.repmat(facets, 1, chunk_steps))
    one_case = ca.Function("loop_case", [z0, s, p, facets], [z_all, y_all])
    mapped = one_case.map(cases)
    inputs = mapped.mx_in()
    function = ca.Function("loop_batch", inputs, mapped.call(inputs))
    try:
        library = compiled_library(function, compiler, JIT_FLAGS)
        native = NativeFunction(function, library)
    except CompileError as exc:
        LOGGER.warning("the batched control step runs on CasADi's virtual machine: %s", exc)
        return None
    return BatchedLoop(native, cases, chunk_steps, capacity, n_state)


class Stretching(Protocol):
    """What :func:`roll_together` drives: one run, stretch by stretch (see ``run._Rollout``)."""

    parameters: np.ndarray
    z: np.ndarray
    polytope: AuthorityPolytope | None

    @property
    def finished(self) -> bool: ...

    def next_stretch(self, chunk_steps: int) -> tuple[int, int]: ...

    def inputs(self, chunk_steps: int, k: int, stop: int) -> np.ndarray: ...

    def take(self, z_all: np.ndarray, y_all: np.ndarray, k: int, stop: int) -> None: ...


def roll_together(
    runs: Sequence[Stretching],
    model: Model,
    controller: DiscreteController,
    *,
    slots: int,
    integrator_steps: int,
    chunk_steps: int,
) -> list[Exception | None] | None:
    """Roll every run to its end, one batched call per stretch for all of them.

    Parameters
    ----------
    runs : sequence of Stretching
        The runs, each at its start; at most ``slots``.
    model : Model
    controller : DiscreteController
    slots : int
        Cases of the compiled loop (the runs fill the first slots; the rest
        repeat the first run and are not used).
    integrator_steps, chunk_steps : int

    Returns
    -------
    list of (Exception or None) or None
        Per run, what it raised (it stopped there; the others went on), or
        None when it ran to its end. None instead of the list when no batched
        loop can be compiled: then no run has started.
    """
    if not 0 < len(runs) <= slots:
        raise ValueError(f"{len(runs)} runs for {slots} slots")
    options = {"cases": slots, "integrator_steps": integrator_steps, "chunk_steps": chunk_steps}
    if batched_loop(model, controller, capacity=FACET_CAPACITY_MIN, **options) is None:
        return None
    errors: list[Exception | None] = [None] * len(runs)
    live = [i for i, run in enumerate(runs) if not run.finished]
    while live:
        stretches: dict[int, tuple[int, int]] = {}
        for i in live:
            try:
                stretches[i] = runs[i].next_stretch(chunk_steps)
            except Exception as exc:  # this run stops; the batch goes on
                errors[i] = exc
        live = [i for i in live if errors[i] is None]
        if not live:
            break
        polytopes = [_authority(runs[i]) for i in live]
        loop = batched_loop(model, controller, capacity=facet_capacity(polytopes), **options)
        if loop is None:
            for i in live:
                errors[i] = SimulationError("the batched step could not be compiled")
            break
        z_all, y_all = _roll_slots(loop, [runs[i] for i in live], [stretches[i] for i in live])
        for slot, i in enumerate(live):
            k, stop = stretches[i]
            try:
                runs[i].take(z_all[slot], y_all[slot], k, stop)
            except Exception as exc:
                errors[i] = exc
        live = [i for i in live if errors[i] is None and not runs[i].finished]
    return errors


def _authority(run: Stretching) -> AuthorityPolytope:
    if run.polytope is None:  # next_stretch always sets it
        raise SimulationError("a run's stretch has no torque authority")
    return run.polytope


def _roll_slots(
    loop: BatchedLoop, runs: Sequence[Stretching], stretches: Sequence[tuple[int, int]]
) -> tuple[np.ndarray, np.ndarray]:
    """One batched call: the runs' stretches in the first slots, the first run's in the rest."""
    n = loop.chunk_steps
    chosen = [*range(len(runs)), *([0] * (loop.cases - len(runs)))]
    z = np.stack([runs[i].z for i in chosen])
    inputs = np.stack([runs[i].inputs(n, *stretches[i]).T for i in chosen])
    parameters = np.stack([runs[i].parameters for i in chosen])
    polytopes = [_authority(runs[i]) for i in chosen]
    return loop.roll(z, inputs, parameters, polytopes)
