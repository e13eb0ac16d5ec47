"""D-K iteration (mu-synthesis) on any generalised plant and block structure.

K step: H-infinity synthesis on the D-scaled plant (:mod:`.hinf`). D step: mu
upper bound of the closed loop on a frequency grid (:mod:`.mu`) and fitted
D_b(s), one per block but the last (:mod:`.dscale`). The best controller
(lowest peak mu on the *unscaled* closed loop) is kept. The iteration stops
when mu no longer improves by the relative ``tolerance`` (converged), after
``max_iterations``, or when every K step of a D step fails; the result says
which, and a warning is logged when it stops above mu = 1.

Why not dkpy: it calls ``control.hinfsyn`` (SLICOT's gamma search from
1e100, 15 s per step on the paper's 25-state plant, and unreliable on
D-scaled plants), computes mu by an LMI through cvxpy (an extra heavy
dependency, slower than SLICOT AB13MD) and fits the pointwise D by least
squares (SB10YD), which stalls on the paper's problem.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import control
import numpy as np

from casadi_debris.errors import SynthesisError
from casadi_debris.robust.mu import (
    Block,
    BlockLike,
    MuBound,
    block_structure,
    expanded,
    mu_upper_bound,
    total_size,
)
from casadi_debris.robust.plant import GeneralizedPlant, frequency_response, static_gain
from casadi_debris.robust.synthesis._dscale import fit_d_scales, inverse
from casadi_debris.robust.synthesis._hinf import NORM_TOLERANCE, HinfResult, hinf_synthesis

_log = logging.getLogger(__name__)

STOP_CONVERGED = "converged"
STOP_MAX_ITERATIONS = "max_iterations"
STOP_K_STEP_FAILED = "k_step_failed"


@dataclass(frozen=True)
class Iteration:
    """One D-K step.

    Attributes
    ----------
    index : int
        0 for the plain H-infinity design.
    d_order : int
        Order of the D-scales used (0 for none).
    gamma : float
        H-infinity norm of the scaled closed loop.
    mu_peak : float
        Peak mu of the unscaled closed loop.
    controller_order : int
    time_s : float
        Wall time of the step [s].
    controller : control.StateSpace or None
        The step's controller (to score it otherwise, e.g. by a mixed bound).
    """

    index: int
    d_order: int
    gamma: float
    mu_peak: float
    controller_order: int
    time_s: float
    controller: control.StateSpace | None = field(default=None, repr=False, compare=False)


@dataclass(frozen=True, eq=False)
class MusynResult:
    """Outcome of the D-K iteration.

    Attributes
    ----------
    controller : control.StateSpace
        Best controller found, from the measurements to the controls (error
        [deg] -> torque [mNm] when the plant is in design units).
    mu : MuBound
        Its mu upper bound on ``omega``.
    omega : ndarray, shape (n_omega,)
        Frequency grid [rad/s].
    iterations : list of Iteration
        Every step, the plain H-infinity design first.
    hinf_gamma_first : float
        H-infinity norm of the first (unscaled) design.
    stop_reason : str
        "converged" (mu improved by less than the tolerance), "max_iterations"
        (still improving when the iterations ran out) or "k_step_failed" (no
        D-scale order gave a stabilising controller).
    blocks : tuple of Block
        The structure mu was computed for.
    """

    controller: control.StateSpace
    mu: MuBound
    omega: np.ndarray
    iterations: list[Iteration] = field(default_factory=list)
    hinf_gamma_first: float = float("nan")
    stop_reason: str = STOP_CONVERGED
    blocks: tuple[Block, ...] = ()

    @property
    def mu_peak(self) -> float:
        """Peak mu of the controller kept."""
        return self.mu.peak

    @property
    def robust(self) -> bool:
        """Whether the peak mu is at most 1 (robust performance or stability reached)."""
        return self.mu.peak <= 1.0


@dataclass(frozen=True)
class _Problem:
    """A generalised plant with its block structure and controller channels."""

    system: control.StateSpace
    structure: tuple[Block, ...]
    n_measurements: int
    n_controls: int

    @property
    def sizes(self) -> list[int]:
        return [int(k) for k in expanded(self.structure)[0]]

    def closed_loop_mu(
        self, controller: control.StateSpace, omega: np.ndarray
    ) -> tuple[np.ndarray, MuBound]:
        closed = self.system.lft(controller, self.n_controls, self.n_measurements)
        if closed.nstates and np.max(np.linalg.eigvals(closed.A).real) >= 0:
            raise SynthesisError("closed loop is unstable")
        responses = frequency_response(closed, omega)
        return responses, mu_upper_bound(responses, self.structure)

    def scaled(self, d_scales: Sequence[control.StateSpace]) -> control.StateSpace:
        """diag(D_b I, I) P diag(D_b^-1 I, I), the last block and the controller's
        channels unscaled."""
        sizes = self.sizes
        rest_out = int(sizes[-1]) + self.n_measurements
        rest_in = int(sizes[-1]) + self.n_controls
        left = [d for d, k in zip(d_scales, sizes, strict=False) for _ in range(k)]
        right = [inverse(d) for d, k in zip(d_scales, sizes, strict=False) for _ in range(k)]
        system = self.system
        bare = control.ss(system.A, system.B, system.C, system.D)
        return (
            control.append(*left, static_gain(np.eye(rest_out)))
            * bare
            * control.append(*right, static_gain(np.eye(rest_in)))
        )


def closed_loop_mu(
    plant: GeneralizedPlant, controller: control.StateSpace, omega: np.ndarray
) -> tuple[np.ndarray, MuBound]:
    """Closed-loop response and its mu bound; raises if the loop is unstable.

    Parameters
    ----------
    plant : GeneralizedPlant
    controller : control.StateSpace
    omega : ndarray, shape (n_omega,)
        Frequencies [rad/s].

    Returns
    -------
    responses : ndarray, shape (n_omega, n, n)
    bound : MuBound
    """
    return _as_problem(plant).closed_loop_mu(controller, omega)


def _as_problem(plant: GeneralizedPlant) -> _Problem:
    return _Problem(
        plant.system, block_structure(plant.blocks), plant.n_measurements, plant.n_controls
    )


@dataclass(frozen=True, eq=False)
class _Trial:
    """A controller designed against one D-scale order, with its unscaled closed loop."""

    d_order: int
    synthesis: HinfResult
    responses: np.ndarray
    mu: MuBound


def _d_step(
    problem: _Problem,
    omega: np.ndarray,
    d_orders: Sequence[int],
    responses: np.ndarray,
    mu: MuBound,
    realisation: str | None = None,
) -> _Trial | None:
    """One D-K step: D-scales of each order fitted to the current closed loop, a
    controller for each, and the one of lowest peak mu (None if every order failed)."""
    trials = []
    for order in d_orders:
        d_scales = fit_d_scales(omega, responses, mu.mu, mu.scales, problem.sizes, order)
        try:
            result = hinf_synthesis(
                problem.scaled(d_scales),
                problem.n_measurements,
                problem.n_controls,
                gamma_start=mu.peak,
                first_realisation=realisation,
            )
            realisation = result.realisation
            trial_responses, trial_mu = problem.closed_loop_mu(result.controller, omega)
        except SynthesisError as error:
            _log.debug("D-scale order %d: %s", order, error)
            continue
        trials.append(_Trial(order, result, trial_responses, trial_mu))
    return min(trials, key=lambda trial: trial.mu.peak, default=None)


def dk_iteration(
    plant: GeneralizedPlant,
    omega: np.ndarray,
    *,
    d_orders: Sequence[int] = (1, 2, 4),
    max_iterations: int = 8,
    tolerance: float = 0.005,
    progress: Callable[[Iteration], None] | None = None,
    patience: int = 1,
) -> MusynResult:
    """mu-synthesis by D-K iteration on the design's generalised plant.

    The keyword arguments are those of :func:`musyn`.

    Parameters
    ----------
    plant : GeneralizedPlant
        Full complex blocks ``plant.blocks`` (uncertainty, then performance).
    omega : ndarray
        Frequency grid [rad/s] for mu and the D fit.

    Returns
    -------
    MusynResult
    """
    return _iterate(
        _as_problem(plant), omega, d_orders, max_iterations, tolerance, progress, patience
    )


def musyn(
    plant: control.StateSpace,
    blocks: Sequence[BlockLike],
    n_measurements: int,
    n_controls: int,
    *,
    omega: np.ndarray | None = None,
    d_orders: Sequence[int] = (1, 2, 4),
    max_iterations: int = 10,
    tolerance: float = 0.005,
    progress: Callable[[Iteration], None] | None = None,
    patience: int = 1,
    initial_controller: control.StateSpace | None = None,
) -> MusynResult:
    """mu-synthesis by D-K iteration on any generalised plant.

    Parameters
    ----------
    plant : control.StateSpace
        Generalised plant P, continuous time. Inputs: the perturbations' outputs
        (ordered as ``blocks``), then the controls (last ``n_controls``).
        Outputs: the perturbations' inputs, then the measurements (last
        ``n_measurements``). Performance channels are a full complex block of
        the structure (usually the last).
    blocks : sequence
        The structure, e.g. ``[("complex", 1), ("complex", 1), ("complex", 2)]``:
        ``("complex", k)`` a full complex k x k block, ``("real", k)`` a real
        scalar repeated k times (bounded as k independent real scalars, and
        scaled as complex ones in the K step), a bare integer k a full complex
        block.
    n_measurements, n_controls : int
        Number of measured outputs and of control inputs.
    omega : ndarray, optional
        Frequency grid [rad/s] for mu and the D fit (default: 20 points per
        decade from a decade below the plant's slowest pole above 1e-3 rad/s
        to a decade above its fastest).
    d_orders : sequence of int
        D-scale orders tried at every step (the best resulting mu is kept).
    max_iterations : int
        D-K steps after the first H-infinity design.
    tolerance : float
        Converged when the peak mu improves by less than this fraction.
    progress : callable, optional
        Called with each :class:`Iteration` as it completes.
    patience : int
        Steps in a row without improvement before stopping (more can leave a
        stall at the cost of a step each).
    initial_controller : control.StateSpace, optional
        Start from this stabilising controller (measurements to controls) instead
        of the plain H-infinity design: the first D-scales are fitted to its
        closed loop. Useful when the plant's channels are scaled so unevenly that
        the unscaled design is poor (a real-parametric LFT's), or to continue a
        design. Its closed-loop H-infinity norm is ``hinf_gamma_first``.

    Returns
    -------
    MusynResult
        The controller of lowest peak mu, its bound, the history and why the
        iteration stopped.

    Raises
    ------
    SynthesisError
        Inconsistent dimensions, or no stabilising H-infinity controller.

    Examples
    --------
    >>> import control
    >>> from casadi_debris.robust.examples import DISTILLATION_BLOCKS, distillation_column
    >>> result = musyn(distillation_column(), DISTILLATION_BLOCKS, 2, 2)  # doctest: +SKIP
    >>> round(result.mu_peak, 2), result.stop_reason  # doctest: +SKIP
    (1.04, 'converged')
    """
    problem = _checked_problem(plant, blocks, n_measurements, n_controls, patience)
    grid = default_frequency_grid(plant) if omega is None else np.asarray(omega, dtype=float)
    return _iterate(
        problem, grid, d_orders, max_iterations, tolerance, progress, patience, initial_controller
    )


def _closed_loop_norm(problem: _Problem, controller: control.StateSpace) -> float:
    """H-infinity norm of the plant closed by ``controller`` (raises if unstable)."""
    closed = problem.system.lft(controller, problem.n_controls, problem.n_measurements)
    if closed.nstates and np.max(np.linalg.eigvals(closed.A).real) >= 0:
        raise SynthesisError("initial_controller: the closed loop is unstable")
    return float(control.linfnorm(closed, tol=NORM_TOLERANCE)[0])


def _checked_problem(
    plant: control.StateSpace,
    blocks: Sequence[BlockLike],
    n_measurements: int,
    n_controls: int,
    patience: int,
) -> _Problem:
    """musyn's arguments, checked, as one problem."""
    structure = block_structure(blocks)
    n = total_size(structure)
    if plant.ninputs != n + n_controls or plant.noutputs != n + n_measurements:
        raise SynthesisError(
            f"plant: blocks take {n} channels, so {n} + n_controls = {n + n_controls} inputs and "
            f"{n} + n_measurements = {n + n_measurements} outputs are expected, got "
            f"{plant.ninputs} inputs and {plant.noutputs} outputs"
        )
    if not plant.isctime():
        raise SynthesisError("plant: musyn needs a continuous-time plant")
    if isinstance(patience, bool) or not isinstance(patience, int) or patience < 1:
        raise SynthesisError(f"patience: a positive integer, got {patience!r}")
    return _Problem(control.ss(plant), structure, n_measurements, n_controls)


def default_frequency_grid(plant: control.StateSpace, per_decade: int = 20) -> np.ndarray:
    """Log-spaced grid [rad/s] spanning the plant's poles, a decade either side.

    Poles below 1e-3 rad/s (integrators, weights' near-integrators) are left out of
    the span; the grid is at least 1e-3 .. 1e2 rad/s wide around them.

    Parameters
    ----------
    plant : control.StateSpace
    per_decade : int
        Points per decade.

    Returns
    -------
    ndarray
    """
    magnitudes = np.abs(np.linalg.eigvals(plant.A)) if plant.nstates else np.array([])
    magnitudes = magnitudes[magnitudes >= 1e-3]
    slow = float(np.min(magnitudes)) if magnitudes.size else 1.0
    fast = float(np.max(magnitudes)) if magnitudes.size else 1.0
    low = np.floor(np.log10(slow)) - 1.0
    high = max(np.ceil(np.log10(fast)) + 1.0, low + 3.0)
    return np.logspace(low, high, round((high - low) * per_decade) + 1)


def _iterate(
    problem: _Problem,
    omega: np.ndarray,
    d_orders: Sequence[int],
    max_iterations: int,
    tolerance: float,
    progress: Callable[[Iteration], None] | None,
    patience: int = 1,
    initial: control.StateSpace | None = None,
) -> MusynResult:
    """The D-K loop: first H-infinity design (or the initial controller), then D steps
    until a stop rule holds."""
    start = time.perf_counter()
    realisation: str | None
    if initial is None:
        first = hinf_synthesis(problem.system, problem.n_measurements, problem.n_controls)
        controller, gamma, realisation = first.controller, first.gamma, first.realisation
    else:
        controller = initial
        realisation = None
        gamma = _closed_loop_norm(problem, initial)
    responses, mu = problem.closed_loop_mu(controller, omega)
    record = Iteration(
        0, 0, gamma, mu.peak, controller.nstates, time.perf_counter() - start, controller
    )
    iterations = [record]
    if progress:
        progress(record)
    best_controller, best_mu = controller, mu
    reason = STOP_MAX_ITERATIONS
    stalled = 0
    for index in range(1, max_iterations + 1):
        step_start = time.perf_counter()
        trial = _d_step(problem, omega, d_orders, responses, mu, realisation)
        if trial is None:
            reason = STOP_K_STEP_FAILED
            break
        record = Iteration(
            index,
            trial.d_order,
            trial.synthesis.gamma,
            trial.mu.peak,
            trial.synthesis.controller.nstates,
            time.perf_counter() - step_start,
            trial.synthesis.controller,
        )
        iterations.append(record)
        if progress:
            progress(record)
        improved = trial.mu.peak < best_mu.peak * (1.0 - tolerance)
        if trial.mu.peak < best_mu.peak:
            best_controller, best_mu = trial.synthesis.controller, trial.mu
        stalled = 0 if improved else stalled + 1
        if stalled >= patience:
            reason = STOP_CONVERGED
            break
        responses, mu = trial.responses, trial.mu
        realisation = trial.synthesis.realisation
    if best_mu.peak > 1.0:
        _log.warning(
            "D-K iteration stopped (%s) after %d steps at peak mu %.4g > 1: robust "
            "performance is not reached",
            reason,
            len(iterations) - 1,
            best_mu.peak,
        )
    return MusynResult(
        controller=best_controller,
        mu=best_mu,
        omega=omega,
        iterations=iterations,
        hinf_gamma_first=gamma,
        stop_reason=reason,
        blocks=problem.structure,
    )
