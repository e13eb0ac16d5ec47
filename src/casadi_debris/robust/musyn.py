"""D-K iteration (mu-synthesis) for the four-block design with input uncertainty.

K step: H-infinity synthesis on the D-scaled plant (:mod:`.hinf`). D step: mu
upper bound of the closed loop on a frequency grid (:mod:`.mu`) and a fitted
D(s) (:mod:`.dscale`). The best controller (lowest peak mu on the *unscaled*
closed loop) is kept; the iteration stops when mu no longer improves by the
relative ``tolerance`` or after ``max_iterations``.

Why not dkpy: it calls ``control.hinfsyn`` (SLICOT's gamma search from
1e100, 15 s per step on this 25-state plant, and unreliable on D-scaled
plants), computes mu by an LMI through cvxpy (an extra heavy dependency, slower
than SLICOT AB13MD, which is exact for two full blocks) and fits the pointwise
D by least squares (SB10YD), which stalls on this problem; see the notes of
issue 3.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import control
import numpy as np

from casadi_debris.errors import SynthesisError
from casadi_debris.robust.dscale import fit_d_scale, inverse
from casadi_debris.robust.hinf import HinfResult, hinf_synthesis
from casadi_debris.robust.interconnect import GeneralizedPlant, static_gain
from casadi_debris.robust.mu import MuBound, mu_upper_bound
from casadi_debris.robust.uncertainty import frequency_response


@dataclass(frozen=True)
class Iteration:
    """One D-K step.

    Attributes
    ----------
    index : int
        0 for the plain H-infinity design.
    d_order : int
        Order of the D-scale used (0 for none).
    gamma : float
        H-infinity norm of the scaled closed loop.
    mu_peak : float
        Peak mu of the unscaled closed loop.
    controller_order : int
    time_s : float
    """

    index: int
    d_order: int
    gamma: float
    mu_peak: float
    controller_order: int
    time_s: float


@dataclass(frozen=True, eq=False)
class MusynResult:
    """Outcome of the D-K iteration.

    Attributes
    ----------
    controller : control.StateSpace
        Best controller found (error [deg] -> torque [mNm] when the plant is
        in design units).
    mu : MuBound
        Its mu upper bound on ``omega``.
    omega : ndarray
    iterations : list of Iteration
    hinf_gamma_first : float
    """

    controller: control.StateSpace
    mu: MuBound
    omega: np.ndarray
    iterations: list[Iteration] = field(default_factory=list)
    hinf_gamma_first: float = float("nan")

    @property
    def mu_peak(self) -> float:
        return self.mu.peak


def closed_loop_mu(
    plant: GeneralizedPlant, controller: control.StateSpace, omega: np.ndarray
) -> tuple[np.ndarray, MuBound]:
    """Closed-loop response and its mu bound; raises if the loop is unstable."""
    closed = plant.system.lft(controller, plant.n_controls, plant.n_measurements)
    if closed.nstates and np.max(np.linalg.eigvals(closed.A).real) >= 0:
        raise SynthesisError("closed loop is unstable")
    responses = frequency_response(closed, omega)
    return responses, mu_upper_bound(responses, plant.blocks)


def _scaled(plant: GeneralizedPlant, d_scale: control.StateSpace) -> control.StateSpace:
    n_delta = plant.blocks[0]
    rest_out = plant.system.noutputs - n_delta
    rest_in = plant.system.ninputs - n_delta
    left = control.append(*([d_scale] * n_delta), static_gain(np.eye(rest_out)))
    right = control.append(*([inverse(d_scale)] * n_delta), static_gain(np.eye(rest_in)))
    system = plant.system
    bare = control.ss(system.A, system.B, system.C, system.D)
    return left * bare * right


@dataclass(frozen=True, eq=False)
class _Trial:
    """A controller designed against one D-scale order, with its unscaled closed loop."""

    d_order: int
    synthesis: HinfResult
    responses: np.ndarray
    mu: MuBound


def _d_step(
    plant: GeneralizedPlant,
    omega: np.ndarray,
    d_orders: Sequence[int],
    responses: np.ndarray,
    mu: MuBound,
) -> _Trial | None:
    """One D-K step: D-scales of each order fitted to the current closed loop, a
    controller for each, and the one of lowest peak mu (None if every order failed)."""
    trials = []
    for order in d_orders:
        d_scale = fit_d_scale(omega, responses, mu.mu, mu.scales[:, 0], plant.blocks[0], order)
        try:
            result = hinf_synthesis(
                _scaled(plant, d_scale),
                plant.n_measurements,
                plant.n_controls,
                gamma_start=mu.peak,
            )
            trial_responses, trial_mu = closed_loop_mu(plant, result.controller, omega)
        except SynthesisError:
            continue
        trials.append(_Trial(order, result, trial_responses, trial_mu))
    return min(trials, key=lambda trial: trial.mu.peak, default=None)


def dk_iteration(
    plant: GeneralizedPlant,
    omega: np.ndarray,
    *,
    d_orders: Sequence[int] = (2,),
    max_iterations: int = 8,
    tolerance: float = 0.005,
    progress: Callable[[Iteration], None] | None = None,
) -> MusynResult:
    """mu-synthesis by D-K iteration.

    Parameters
    ----------
    plant : GeneralizedPlant
        Two full complex blocks: uncertainty, then performance.
    omega : ndarray
        Frequency grid [rad/s] for mu and the D fit.
    d_orders : sequence of int
        D-scale orders tried at every step (the best resulting mu is kept).
    max_iterations : int
        D-K steps after the first H-infinity design.
    tolerance : float
        Stop when the peak mu improves by less than this fraction.
    progress : callable, optional
        Called with each :class:`Iteration` as it completes.

    Returns
    -------
    MusynResult
    """
    if len(plant.blocks) != 2:
        raise SynthesisError("dk_iteration handles exactly two full blocks")
    start = time.perf_counter()
    first = hinf_synthesis(plant.system, plant.n_measurements, plant.n_controls)
    responses, mu = closed_loop_mu(plant, first.controller, omega)
    record = Iteration(
        0, 0, first.gamma, mu.peak, first.controller.nstates, time.perf_counter() - start
    )
    iterations = [record]
    if progress:
        progress(record)
    best_controller, best_mu = first.controller, mu
    for index in range(1, max_iterations + 1):
        step_start = time.perf_counter()
        trial = _d_step(plant, omega, d_orders, responses, mu)
        if trial is None:
            break
        record = Iteration(
            index,
            trial.d_order,
            trial.synthesis.gamma,
            trial.mu.peak,
            trial.synthesis.controller.nstates,
            time.perf_counter() - step_start,
        )
        iterations.append(record)
        if progress:
            progress(record)
        improved = trial.mu.peak < best_mu.peak * (1.0 - tolerance)
        if trial.mu.peak < best_mu.peak:
            best_controller, best_mu = trial.synthesis.controller, trial.mu
        if not improved:
            break
        responses, mu = trial.responses, trial.mu
    return MusynResult(
        controller=best_controller,
        mu=best_mu,
        omega=omega,
        iterations=iterations,
        hinf_gamma_first=first.gamma,
    )
