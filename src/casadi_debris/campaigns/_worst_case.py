"""A worst-case search over the uncertainty box for the closed loop's largest pointing error.

The objective is the nonlinear closed loop itself (:func:`simulate_closed_loop`: flexible
model, star tracker, allocator, engines): the largest attitude error of the
run, over the parameters' normalised positions z in [-1, 1] (the array angle
wraps around when its range is a full turn).

1. Screen: every corner of the campaign's corner set through the *linear*
   closed loop (the plant linearised at the corner, the controller, the
   slew's reference attitude and feedforward torque and the disturbance
   torque), a few milliseconds each. The screen only ranks the corners.
2. Simulate the ``screen_starts`` corners the screen ranks worst, and any
   extra starts (the mu lower bound's worst parameters, say).
3. From the worst of them, a compass (pattern) search: step each parameter
   up and down by ``step`` (in a seeded random order), move on the first
   improvement, halve the step when none improves, stop at ``min_step`` or
   when the budget of simulations is spent.

This is a local search: it returns a case at least as bad as every case it
simulated, not the global worst of the box.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import control
import numpy as np
import scipy.linalg

from casadi_debris.allocation import Allocator
from casadi_debris.dynamics import Model, linearization_function, linearize
from casadi_debris.errors import SimulationError
from casadi_debris.guidance import Reference
from casadi_debris.robust.plant import FULL_CIRCLE_DEG, parameters_from_normalized
from casadi_debris.simulation import ClosedLoopResult, LoopSettings, simulate_closed_loop

_log = logging.getLogger(__name__)
SCREEN_STEP_S = 1.0
# A move must raise the error by this fraction: runs that differ by rounding are ties.
IMPROVEMENT = 1e-6


@dataclass(frozen=True, eq=False)
class Evaluation:
    """One simulation of the search.

    Attributes
    ----------
    index : int
        0-based, in the order run.
    source : str
        ``"screen corner K"``, ``"start"`` or ``"search"``.
    normalized : ndarray, shape (n_parameters,)
    parameters : ndarray, shape (n_parameters,)
    max_error_deg : float
        Largest attitude error of the run (any axis) [deg].
    """

    index: int
    source: str
    normalized: np.ndarray
    parameters: np.ndarray
    max_error_deg: float


@dataclass(frozen=True, eq=False)
class WorstCaseSearch:
    """What the search found and everything it simulated.

    Attributes
    ----------
    best : Evaluation
    evaluations : tuple of Evaluation
    screen_error_deg : ndarray, shape (n_corners,)
        The linear screen's largest error per corner [deg].
    screen_order : ndarray of int, shape (n_corners,)
        Corners ranked worst first by the screen.
    best_run : ClosedLoopResult
        The best case's run.
    seed : int
    final_step : float
        Compass step when the search stopped.
    time_s : float
    """

    best: Evaluation
    evaluations: tuple[Evaluation, ...]
    screen_error_deg: np.ndarray
    screen_order: np.ndarray
    best_run: ClosedLoopResult
    seed: int
    final_step: float
    time_s: float

    @property
    def simulations(self) -> int:
        """Simulations run (the screen's linear runs not counted)."""
        return len(self.evaluations)


def linear_screen(
    model: Model,
    controller: control.StateSpace,
    reference: Reference,
    normalized: np.ndarray,
) -> np.ndarray:
    """Largest attitude error [deg] of the linear closed loop at each row of ``normalized``.

    The plant is linearised about rest at each parameter set (torque [mNm] to
    attitude [deg], star tracker in the loop); the reference attitude enters
    as its rotation vector, the slew's feedforward and the disturbance as
    torques at the plant input (the problem's sine; environment torques, which
    depend on the attitude, are left out). Gyroscopic terms, saturation and the
    engines are left out too: a ranking, not a prediction. The uncertainty box is
    ``model.problem``'s.
    """
    times = reference.time_s
    keep = np.unique(np.round(np.arange(times[0], times[-1], SCREEN_STEP_S) / _period(times)))
    index = np.clip(keep.astype(int), 0, len(times) - 1)
    t = times[index]
    r_deg = np.degrees(_rotation_vectors(reference.quaternion_BN[index]))
    feedforward = np.zeros((len(t), 3))
    if reference.feedforward_Nm is not None:
        feedforward = reference.feedforward_Nm[np.minimum(index, len(reference.feedforward_Nm) - 1)]
    disturbance = np.asarray(model.disturbance.map(len(t))(t)).T
    inputs = np.hstack([r_deg, (feedforward + disturbance) * 1e3]).T
    function = linearization_function(model, sensor=True)
    loops = [
        _error_loop(
            linearize(model, p, sensor=True, units="deg_mNm", function=function), controller
        )
        for p in parameters_from_normalized(model, normalized)
    ]
    return _largest_outputs(loops, t, inputs)


def _largest_outputs(
    loops: Sequence[control.StateSpace], t: np.ndarray, inputs: np.ndarray
) -> np.ndarray:
    """Largest absolute output of each loop driven from rest by ``inputs``, shape (n_loops,).

    What :func:`control.forced_response` gives each loop (the input linear between the
    equally spaced samples ``t``, the exact discretisation by the exponential of the
    augmented matrix), stepped for all loops at once: one Python loop over the samples
    instead of one per corner, which made the screen of 256 corners take seconds
    whatever the search's budget. ``inputs`` has shape (n_inputs, len(t)).
    """
    if not loops:
        return np.empty(0)
    a = np.stack([np.asarray(loop.A, dtype=float) for loop in loops])
    b = np.stack([np.asarray(loop.B, dtype=float) for loop in loops])
    c = np.stack([np.asarray(loop.C, dtype=float) for loop in loops])
    d = np.stack([np.asarray(loop.D, dtype=float) for loop in loops])
    u = np.asarray(inputs, dtype=float)
    n, m, steps = a.shape[1], b.shape[2], len(t)
    feedthrough = np.einsum("kij,js->kis", d, u)
    if n == 0:  # no state: the output is the feedthrough alone
        return np.max(np.abs(feedthrough), axis=(1, 2))
    largest = np.max(np.abs(feedthrough[:, :, 0]), axis=1)  # from rest
    if steps < 2:
        return largest
    dt = (t[-1] - t[0]) / (steps - 1)
    augmented = np.zeros((len(loops), n + 2 * m, n + 2 * m))
    augmented[:, :n, :n] = a * dt
    augmented[:, :n, n : n + m] = b * dt
    augmented[:, n : n + m, n + m :] = np.eye(m)
    exponential = scipy.linalg.expm(augmented)
    a_d = exponential[:, :n, :n]
    b_d1 = exponential[:, :n, n + m :]
    b_d0 = exponential[:, :n, n : n + m] - b_d1
    b_d = np.concatenate([b_d0, b_d1], axis=2)  # on [u(i-1); u(i)]
    x = np.zeros((len(loops), n, 1))
    for i in range(1, steps):
        x = a_d @ x + b_d @ np.concatenate([u[:, i - 1], u[:, i]])[:, None]
        y = (c @ x)[:, :, 0] + feedthrough[:, :, i]
        largest = np.maximum(largest, np.max(np.abs(y), axis=1))
    return largest


def _period(times: np.ndarray) -> float:
    return float(times[1] - times[0]) if len(times) > 1 else 1.0


def _rotation_vectors(quaternions: np.ndarray) -> np.ndarray:
    """Rotation vectors [rad] of scalar-first quaternions, continuous in time."""
    q = np.asarray(quaternions, dtype=float)
    norm = np.linalg.norm(q[:, 1:], axis=1)
    # 2 atan2(|v|, q0), not scipy's canonical form: continuous through 180 deg.
    angle = 2.0 * np.arctan2(norm, q[:, 0])
    return q[:, 1:] * np.where(norm > 0, angle / np.maximum(norm, 1e-300), 2.0)[:, None]


def _error_loop(plant: control.StateSpace, controller: control.StateSpace) -> control.StateSpace:
    """[r (deg); torque (mNm)] -> true attitude error r - theta (deg), u = K (r - y) + torque."""
    a, b, c = (np.asarray(m) for m in (plant.A, plant.B, plant.C))
    ak, bk, ck, dk = (np.asarray(m) for m in control.ssdata(controller))
    n, nk = a.shape[0], ak.shape[0]
    true = np.zeros((3, n))
    true[:, :3] = np.eye(3) * (180.0 / math.pi)
    big_a = np.block([[a - b @ dk @ c, b @ ck], [-bk @ c, ak]])
    big_b = np.block([[b @ dk, b], [bk, np.zeros((nk, 3))]])
    big_c = np.hstack([-true, np.zeros((3, nk))])
    big_d = np.hstack([np.eye(3), np.zeros((3, 3))])
    return control.ss(big_a, big_b, big_c, big_d)


class _Objective:
    """Simulates a normalised parameter set once, remembers every evaluation."""

    def __init__(
        self,
        model: Model,
        controller: control.StateSpace,
        reference: Reference,
        jit: bool,
        progress: Callable[[int, float], None] | None,
    ) -> None:
        self.problem, self.model, self.controller = model.problem, model, controller
        self.reference, self.jit, self.progress = reference, jit, progress
        self.evaluations: list[Evaluation] = []
        self.runs: dict[int, ClosedLoopResult] = {}
        self.best: Evaluation | None = None

    def __call__(self, z: np.ndarray, source: str) -> float:
        for done in self.evaluations:  # a point already run is not run again
            if np.array_equal(done.normalized, z):
                return done.max_error_deg
        p = parameters_from_normalized(self.model, z)
        # A fresh allocator per run, as in a campaign: no warm start carried between cases.
        allocator = Allocator.from_problem(self.problem, self.model.geometry)
        result = simulate_closed_loop(
            self.model,
            self.controller,
            self.reference,
            parameters=p,
            allocator=allocator,
            settings=LoopSettings(jit=self.jit),
        )
        error = float(result.summary().max_error_deg)
        evaluation = Evaluation(len(self.evaluations), source, z.copy(), p, error)
        self.evaluations.append(evaluation)
        if self.best is None or error > self.best.max_error_deg * (1.0 + IMPROVEMENT):
            self.best = evaluation
            self.runs = {evaluation.index: result}
        if self.progress is not None:
            self.progress(len(self.evaluations), error)
        return error


@dataclass(frozen=True)
class WorstCaseSettings:
    """How :func:`worst_case_search` searches.

    Attributes
    ----------
    budget : int
        Simulations at most, starts included.
    screen_starts : int
        Corners ranked worst by the screen that are simulated.
    step, min_step : float
        First and last compass step, in normalised units.
    seed : int
        Seed of the order in which the parameters are stepped.
    jit : bool
        Compile the closed-loop step to C (worth it for many runs).
    """

    budget: int = 50
    screen_starts: int = 3
    step: float = 0.5
    min_step: float = 1.0 / 16.0
    seed: int = 0
    jit: bool = False


def worst_case_search(
    model: Model,
    controller: control.StateSpace,
    reference: Reference,
    corners: np.ndarray,
    *,
    starts: Sequence[np.ndarray] = (),
    settings: WorstCaseSettings = WorstCaseSettings(),
    progress: Callable[[int, float], None] | None = None,
) -> WorstCaseSearch:
    """Search the uncertainty box for the run of largest attitude error (see the module).

    Parameters
    ----------
    model, controller, reference
        As :func:`simulate_closed_loop` takes them (the problem is ``model.problem``;
        controller: error [deg] -> torque [mNm]).
    corners : ndarray, shape (n_corners, n_parameters)
        Normalised corners the linear screen ranks (the campaign's corner set).
    starts : sequence of ndarray
        More normalised starting points, simulated after the screened corners
        (clipped to the box).
    settings : WorstCaseSettings
        Budget, screened corners, compass steps, seed, compiled C.
    progress : callable, optional
        ``progress(simulations_done, max_error_deg)`` after each run.

    Returns
    -------
    WorstCaseSearch
    """
    budget, step, min_step = settings.budget, settings.step, settings.min_step
    if budget < 1 or settings.screen_starts < 1 or not 0 < min_step <= step:
        raise SimulationError("budget and screen_starts >= 1, 0 < min_step <= step")
    began = time.perf_counter()
    screen = linear_screen(model, controller, reference, corners)
    order = np.argsort(screen)[::-1]
    objective = _Objective(model, controller, reference, settings.jit, progress)
    for k in _distinct(screen, order)[: min(settings.screen_starts, budget)]:
        objective(np.asarray(corners[k], dtype=float), f"screen corner {int(k)}")
    for z in starts:
        if len(objective.evaluations) < budget:
            objective(_project(model, np.asarray(z, dtype=float)), "start")
    assert objective.best is not None
    final = _compass(model, objective, budget, step, min_step, settings.seed)
    best = objective.best
    return WorstCaseSearch(
        best=best,
        evaluations=tuple(objective.evaluations),
        screen_error_deg=screen,
        screen_order=order,
        best_run=objective.runs[best.index],
        seed=settings.seed,
        final_step=final,
        time_s=time.perf_counter() - began,
    )


def _distinct(screen: np.ndarray, order: np.ndarray) -> list[int]:
    """``order`` without corners the screen cannot tell from a better-ranked one (the
    arrays turned by half a turn give the same plant)."""
    kept: list[int] = []
    for k in order:
        if all(abs(screen[k] - screen[j]) > 1e-6 * abs(screen[j]) for j in kept):
            kept.append(int(k))
    return kept


def _compass(
    model: Model,
    objective: _Objective,
    budget: int,
    step: float,
    min_step: float,
    seed: int,
) -> float:
    """Opportunistic compass search from the best evaluation so far; returns the last step."""
    rng = np.random.default_rng(seed)
    assert objective.best is not None
    while len(objective.evaluations) < budget and step >= min_step:
        improved = False
        for i in rng.permutation(len(objective.best.normalized)):
            for sign in rng.permutation([-1.0, 1.0]):
                x = objective.best.normalized
                y = x.copy()
                y[i] += sign * step
                y = _project(model, y)
                if np.array_equal(x, y) or len(objective.evaluations) >= budget:
                    continue
                before = objective.best.max_error_deg
                if objective(y, "search") > before * (1.0 + IMPROVEMENT):
                    improved = True
                    break
            if len(objective.evaluations) >= budget:
                break
        if not improved:
            step /= 2.0
    return step


def _project(model: Model, z: np.ndarray) -> np.ndarray:
    """Into the box; a full-turn array angle wraps around instead."""
    layout = model.parameter_layout
    wrapped = np.clip(z, -1.0, 1.0)
    if model.problem.uncertainty.array_angle_deg >= FULL_CIRCLE_DEG:
        for name in set(layout.angle_names):
            i = layout.index(name)
            wrapped[i] = (z[i] + 1.0) % 2.0 - 1.0
    return wrapped
