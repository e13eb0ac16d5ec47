"""The paper's robust design end to end: samples -> W -> generalised plant -> D-K ->
reduction -> robust-performance check of the reduced controller.

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.robust.synthesis import design_controller
>>> design = design_controller(load_problem())  # doctest: +SKIP
>>> design.summary().mu_peak  # doctest: +SKIP
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

import control
import numpy as np

from casadi_debris.config import Problem, limits
from casadi_debris.dynamics import Model, build_model, linearize
from casadi_debris.errors import SynthesisError
from casadi_debris.records import Record
from casadi_debris.robust.mu import MuBound
from casadi_debris.robust.plant import (
    W_ORDER,
    Controller,
    GeneralizedPlant,
    PerformanceWeights,
    UncertaintySamples,
    UncertaintyWeight,
    diagonal_cover,
    fit_uncertainty_weight,
    generalized_plant,
    performance_weights,
    relative_errors,
    sample_uncertainty,
)
from casadi_debris.robust.synthesis._musyn import (
    Iteration,
    MusynResult,
    closed_loop_mu,
    dk_iteration,
)
from casadi_debris.robust.synthesis._reduce import reduce_controller


@dataclass(frozen=True)
class SynthesisSettings:
    """Knobs of the design; the defaults reproduce the paper's procedure.

    Attributes
    ----------
    modes : str
        Modes of the design plant ("first": the paper's 10-state truncation).
    samples : int or None
        Models for the weight fit (default: the problem's, 200).
    seed : int or None
        Their seed (default: the problem's).
    mu_points : int
        Log-spaced frequencies for mu and the D fit, 1e-4 .. 1e2 rad/s.
    d_orders : tuple of int
        D-scale orders tried at each D-K step.
    max_iterations : int
    reduced_order : int
        Target order of the balanced truncation (the paper: 25).

    Raises
    ------
    SynthesisError
        A knob outside its range (:data:`limits.MU_POINTS`, :data:`limits.D_ORDER`, ...), named.
    """

    modes: str = "first"
    samples: int | None = None
    seed: int | None = None
    mu_points: int = 150
    d_orders: tuple[int, ...] = (1, 2, 4)
    max_iterations: int = 8
    reduced_order: int = 25

    def __post_init__(self) -> None:
        checks = {
            "samples": (self.samples, limits.UNCERTAINTY_SAMPLES),
            "seed": (self.seed, limits.SEED),
            "mu_points": (self.mu_points, limits.MU_POINTS),
            "max_iterations": (self.max_iterations, limits.DK_ITERATIONS),
            "reduced_order": (self.reduced_order, limits.REDUCED_ORDER),
        }
        for name, (value, allowed) in checks.items():
            if value is None and name in ("samples", "seed"):
                continue
            if isinstance(value, bool) or not isinstance(value, int | np.integer):
                raise SynthesisError(f"{name}: must be an integer, got {value!r}")
            problem = allowed.violation(value)
            if problem:
                raise SynthesisError(f"{name}: {problem}, got {value}")
        orders = tuple(self.d_orders)
        if not 1 <= len(orders) <= limits.MAX_D_ORDERS_TRIED or any(
            isinstance(o, bool)
            or not isinstance(o, int | np.integer)
            or limits.D_ORDER.violation(o)
            for o in orders
        ):
            raise SynthesisError(
                f"d_orders: 1 to {limits.MAX_D_ORDERS_TRIED} integers "
                f"in {limits.D_ORDER}, got {orders!r}"
            )


@dataclass(frozen=True, eq=False)
class UncertaintyFit:
    """The design model, its sampled plants and the uncertainty weight that covers them.

    It does not depend on the performance weights, so designs at several
    performance levels share one.

    Attributes
    ----------
    model : Model
    samples : UncertaintySamples
    grid : ndarray, shape (n_omega,)
        Frequencies of the fit [rad/s].
    bound : ndarray, shape (n_omega, 3)
        What |W_i| must reach there.
    weight : UncertaintyWeight
    design_plant : control.StateSpace
        Torque [mNm] to measured attitude [deg] of the nominal design model.
    time_s : float
        Wall time of sampling and fit [s].
    """

    model: Model
    samples: UncertaintySamples
    grid: np.ndarray
    bound: np.ndarray
    weight: UncertaintyWeight
    design_plant: control.StateSpace
    time_s: float


def fit_uncertainty(problem: Problem, settings: SynthesisSettings | None = None) -> UncertaintyFit:
    """Sample the problem's uncertainty set and fit the weight W that covers it."""
    settings = settings or SynthesisSettings()
    start = time.perf_counter()
    model = build_model(problem, modes=settings.modes)
    samples = sample_uncertainty(model, settings.samples, settings.seed)
    grid = weight_fit_grid(problem)
    bound = diagonal_cover(relative_errors(model, samples.parameters, grid))
    weight = fit_uncertainty_weight(grid, bound)
    design_plant = linearize(model, sensor=True, units="deg_mNm")
    return UncertaintyFit(
        model, samples, grid, bound, weight, design_plant, time.perf_counter() - start
    )


@dataclass(frozen=True, eq=False)
class ControllerDesign:
    """Everything a design produced."""

    problem: Problem
    settings: SynthesisSettings
    model: Model
    samples: UncertaintySamples
    weight_grid: np.ndarray
    weight_bound: np.ndarray
    weight: UncertaintyWeight
    performance: PerformanceWeights
    plant: GeneralizedPlant
    musyn: MusynResult
    mu_reduced: MuBound
    record: Controller
    timings_s: dict[str, float] = field(default_factory=dict)

    def summary(self) -> SynthesisSummary:
        """The figures ``casadi-debris synthesize`` prints."""
        return SynthesisSummary(
            mu_peak=self.musyn.mu_peak,
            mu_peak_reduced=self.mu_reduced.peak,
            order_full=self.musyn.controller.nstates,
            order_reduced=self.record.reduced.nstates,
            hinf_gamma_first=self.musyn.hinf_gamma_first,
            iterations=len(self.musyn.iterations) - 1,
            time_s=sum(self.timings_s.values()),
            w_fit_order=W_ORDER,
            w_fit_samples=len(self.samples.parameters),
            w_fit_margin=float(np.min(self.weight.margin)),
            seed=self.samples.seed,
        )


@dataclass(frozen=True, kw_only=True)
class SynthesisSummary(Record):
    """The figures of a μ-synthesis.

    Attributes
    ----------
    mu_peak, mu_peak_reduced : float
        Peak μ upper bound of the full-order and the reduced controller.
    order_full, order_reduced : int
        Controller states.
    hinf_gamma_first : float
        γ of the first H∞ step.
    iterations : int
        D-K steps after the first H∞ synthesis.
    time_s : float
        Wall time of the design.
    w_fit_order, w_fit_samples : int
        Order of the fitted uncertainty weight and the sampled plants it covers.
    w_fit_margin : float
        Smallest ratio of the weight to the sampled relative error (≥ 1: covered).
    seed : int
        Seed of the sampled plants.
    controller_path : str or None
        Where the controller was written, once it is.
    """

    mu_peak: float
    mu_peak_reduced: float
    order_full: int
    order_reduced: int
    hinf_gamma_first: float
    iterations: int
    time_s: float
    w_fit_order: int
    w_fit_samples: int
    w_fit_margin: float
    seed: int
    controller_path: str | None = None


def weight_fit_grid(problem: Problem) -> np.ndarray:
    """Log grid 1e-3 .. 1e2 rad/s, dense (1500 points) over the flexible band.

    Lightly damped modes (zeta = 0.005) make narrow peaks in the relative error:
    the band from half the lowest to 2.5 times the highest first-bending
    frequency of the uncertainty set is sampled linearly.
    """
    first = [
        m.omega_rad_s
        for array in problem.arrays
        for m in array.modes
        if (m.kind, m.order) == ("bending", 1)
    ]
    coarse = np.logspace(-3, 2, 300)
    if not first:  # a rigid debris: nothing narrow to resolve
        return coarse
    spread = problem.uncertainty.bending_frequency_fraction
    band = np.linspace(0.5 * min(first) * (1 - spread), 2.5 * max(first) * (1 + spread), 1500)
    return np.unique(np.concatenate([coarse, band]))


def design_controller(
    problem: Problem,
    settings: SynthesisSettings | None = None,
    progress: Callable[[str, Iteration | None], None] | None = None,
    *,
    performance: PerformanceWeights | None = None,
    uncertainty: UncertaintyFit | None = None,
) -> ControllerDesign:
    """Run the whole robust design for a problem.

    Parameters
    ----------
    problem : Problem
    settings : SynthesisSettings, optional
    progress : callable, optional
        ``progress(stage, iteration)``: called at each stage ("samples",
        "weight", "hinf", "dk", "reduce") and after every D-K iteration.
    performance : PerformanceWeights, optional
        Instead of the problem's ``[weights]`` (e.g. :mod:`~casadi_debris.robust.requirements`).
    uncertainty : UncertaintyFit, optional
        A fit of this problem made before (:func:`fit_uncertainty` with the same settings).

    Returns
    -------
    ControllerDesign
    """
    settings = settings or SynthesisSettings()

    def report(stage: str, iteration: Iteration | None = None) -> None:
        if progress:
            progress(stage, iteration)

    timings: dict[str, float] = {}
    if uncertainty is None:
        uncertainty = fit_uncertainty(problem, settings)
        timings["uncertainty_s"] = uncertainty.time_s
    report("samples")
    performance = performance or performance_weights(problem)
    plant = generalized_plant(uncertainty.design_plant, uncertainty.weight.system, performance)
    report("weight")

    with _timed(timings, "dk_s"):
        omega = np.logspace(-4, 2, settings.mu_points)
        musyn = dk_iteration(
            plant,
            omega,
            d_orders=settings.d_orders,
            max_iterations=settings.max_iterations,
            progress=lambda it: report("dk", it),
        )

    with _timed(timings, "reduce_s"):
        reduced = reduce_controller(musyn.controller, settings.reduced_order)
        _, mu_reduced = closed_loop_mu(plant, reduced, omega)
    report("reduce")

    record = Controller(
        reduced=reduced,
        full=musyn.controller,
        mu_peak=musyn.mu_peak,
        mu_peak_reduced=mu_reduced.peak,
        problem_sha256=problem.plant_sha256,
        seed=uncertainty.samples.seed,
        details=_record_details(problem, settings, uncertainty, performance, musyn, timings),
    )
    return ControllerDesign(
        problem=problem,
        settings=settings,
        model=uncertainty.model,
        samples=uncertainty.samples,
        weight_grid=uncertainty.grid,
        weight_bound=uncertainty.bound,
        weight=uncertainty.weight,
        performance=performance,
        plant=plant,
        musyn=musyn,
        mu_reduced=mu_reduced,
        record=record,
        timings_s=timings,
    )


@contextmanager
def _timed(timings: dict[str, float], key: str) -> Iterator[None]:
    """Store the wall time of the block under ``timings[key]`` [s] (not if it raises)."""
    start = time.perf_counter()
    yield
    timings[key] = time.perf_counter() - start


def _record_details(
    problem: Problem,
    settings: SynthesisSettings,
    uncertainty: UncertaintyFit,
    performance: PerformanceWeights,
    musyn: MusynResult,
    timings: dict[str, float],
) -> dict[str, Any]:
    """How the controller was designed, as its file records it."""
    weight = uncertainty.weight
    return {
        "hinf_gamma_first": musyn.hinf_gamma_first,
        "mu_per_iteration": [it.mu_peak for it in musyn.iterations],
        "d_order_per_iteration": [it.d_order for it in musyn.iterations],
        "uncertainty_weight": {
            "form": "k (s^2 + 2 zeta_z w_z s + w_z^2) / (s^2 + 2 zeta_p w_p s + w_p^2)",
            "coefficients_k_wz_zetaz_wp_zetap": weight.coefficients.tolist(),
            "fit_margin": weight.margin.tolist(),
            "samples": len(uncertainty.samples.parameters),
        },
        "weights": _weight_settings(problem, performance),
        "design_plant_modes": settings.modes,
        "timings_s": timings,
    }


def _weight_settings(problem: Problem, performance: PerformanceWeights) -> dict[str, Any]:
    """The performance weights the design used, as the controller file records them."""
    weights = problem.weights
    dynamic = {
        "closed_loop_bandwidth_rad_s": weights.closed_loop_bandwidth_rad_s,
        "epsilon": weights.epsilon,
        "control_rolloff_rad_s": weights.control_rolloff_rad_s,
        "control_rolloff_high_frequency_gain": weights.control_rolloff_high_frequency_gain,
    }
    return {
        **dynamic,
        **(performance.parameters or {}),
        "error_scaling_deg": np.diag(performance.error_scaling).tolist(),
        "control_scaling_mNm": np.diag(performance.control_scaling).tolist(),
        "disturbance_scaling_mNm": np.diag(performance.disturbance_scaling).tolist(),
        "reference_scaling_deg": np.diag(performance.reference).tolist(),
    }
