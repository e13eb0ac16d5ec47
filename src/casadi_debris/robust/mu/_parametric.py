"""Robust stability and performance of a controller over the real parametric uncertainty.

For each array angle of a grid, the plant is fitted as a real-parametric LFT
(:mod:`.parametric`) and closed with the controller and the performance
weights (:mod:`.parametric_loop`). On a frequency grid:

- upper bound: SLICOT AB13MD's D-G bound (a repeated real scalar bounded as
  independent scalars, which can only raise it); at the peak, the D-G LMI
  with full D and G blocks on the repeated scalars, when cvxpy is installed;
- lower bound: :func:`~casadi_debris.robust.mu_bounds`'s search at the
  largest local maxima of the upper bound, with the perturbation it finds.

Robust stability takes the real blocks alone, robust performance the real
blocks and the 6 x 6 complex performance block. The worst perturbation's real
entries are the parameters' normalised positions: a destabilising (or
performance-worst) parameter set, scaled by 1 / mu, hence outside the box
when mu < 1; it is also given clipped to the box.

The bounds hold for the fitted model, whose residual is recorded; the
search for the worst slew (:mod:`casadi_debris.campaigns`) works
on the nonlinear loop itself.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import control
import numpy as np

from casadi_debris.config import Problem
from casadi_debris.dynamics import Model, build_model, linearization_function
from casadi_debris.errors import SynthesisError
from casadi_debris.records import OPTIONAL, Record
from casadi_debris.robust.mu._blocks import block_structure
from casadi_debris.robust.mu._lft import ParametricPlant, fit_parametric_plant
from casadi_debris.robust.mu._loop import N_PERFORMANCE, parametric_closed_loop
from casadi_debris.robust.mu._mixed import PeakBounds, mu_bounds
from casadi_debris.robust.mu._upper import mu_upper_bound
from casadi_debris.robust.plant import PerformanceWeights, corner_angles, frequency_response

_log = logging.getLogger(__name__)

KINDS = ("stability", "performance")


@dataclass(frozen=True, eq=False)
class WorstPerturbation:
    """The lower bound's perturbation at its worst angle and frequency, as parameters.

    Attributes
    ----------
    mu_lower : float
    omega_rad_s : float
    angle_index : int
        Into :attr:`ParametricMu.angle_normalized`.
    perturbation : ndarray, shape (n, n), complex
        Delta with det(I - M Delta) = 0, sigma_max(Delta) = 1 / mu_lower.
    determinant : float
        |det(I - M Delta)| (0 up to rounding).
    normalized_unclipped : ndarray, shape (n_parameters,)
        Every parameter's normalised position: the real entries of Delta at
        the real parameters, the angle of the grid.
    normalized : ndarray, shape (n_parameters,)
        The same clipped to the box, -1 .. 1.
    """

    mu_lower: float
    omega_rad_s: float
    angle_index: int
    perturbation: np.ndarray
    determinant: float
    normalized_unclipped: np.ndarray
    normalized: np.ndarray

    @property
    def clipped(self) -> bool:
        """Whether the perturbation lies outside the box (and was clipped)."""
        return bool(np.any(self.normalized != self.normalized_unclipped))


@dataclass(frozen=True, eq=False)
class RealMuBounds(PeakBounds):
    """Bounds of one structure over the angle and frequency grids.

    Attributes
    ----------
    upper : ndarray, shape (n_angles, n_omega)
        AB13MD's D-G bound, replaced by the LMI's where that was solved.
    lower : ndarray, shape (n_angles, n_omega)
        Lower bound where searched, 0 elsewhere.
    worst : WorstPerturbation or None
        None when no perturbation was found.
    lmi_points : int
        Grid points where the LMI tightened the upper bound.
    """

    upper: np.ndarray
    lower: np.ndarray
    worst: WorstPerturbation | None
    lmi_points: int


@dataclass(frozen=True, eq=False)
class ParametricMu:
    """Real-parametric robust stability and performance of one controller.

    Attributes
    ----------
    real_names : tuple of str
        The real parameters, in block order.
    ranks : tuple of int
        How often each repeats (per angle the fit may differ: the largest).
    parameter_names : tuple of str
        Every model parameter, as ``normalized`` vectors order them.
    angle_normalized : ndarray, shape (n_angles,)
    angle_deg : ndarray, shape (n_angles,)
        The array-angle offsets of the grid.
    omega : ndarray, shape (n_omega,)
    residual : float
        Largest relative residual of the affine fits.
    stability, performance : RealMuBounds
    seed : int
    modes : str
    time_s : float
    """

    real_names: tuple[str, ...]
    ranks: tuple[int, ...]
    parameter_names: tuple[str, ...]
    angle_normalized: np.ndarray
    angle_deg: np.ndarray
    omega: np.ndarray
    residual: float
    stability: RealMuBounds
    performance: RealMuBounds
    seed: int
    modes: str
    time_s: float

    def summary(self) -> ParametricMuSummary:
        """Figures for JSON (frequencies in rad/s, angles in deg)."""
        bounds = {kind: self._bounds_summary(getattr(self, kind)) for kind in KINDS}
        return ParametricMuSummary(
            real_parameters=self.real_names,
            real_block_sizes=self.ranks,
            array_angles_deg=tuple(self.angle_deg.tolist()),
            frequencies=len(self.omega),
            fit_residual=float(self.residual),
            analysis_plant_modes=self.modes,
            seed=self.seed,
            time_s=self.time_s,
            stability=bounds["stability"],
            performance=bounds["performance"],
        )

    def _bounds_summary(self, bounds: RealMuBounds) -> MuBoundsSummary:
        worst = bounds.worst
        return MuBoundsSummary(
            mu_upper=float(bounds.peak_upper),
            mu_lower=float(bounds.peak_lower),
            gap=float(bounds.gap),
            margin_upper=1.0 / bounds.peak_upper,
            margin_lower=1.0 / bounds.peak_lower if bounds.peak_lower else None,
            lmi_points=bounds.lmi_points,
            worst=None
            if worst is None
            else MuWorstSummary(
                omega_rad_s=worst.omega_rad_s,
                array_angle_deg=float(self.angle_deg[worst.angle_index]),
                determinant=worst.determinant,
                clipped=worst.clipped,
                normalized_unclipped=self._named(worst.normalized_unclipped),
                normalized=self._named(worst.normalized),
            ),
        )

    def _named(self, normalized: np.ndarray) -> dict[str, float]:
        return dict(zip(self.parameter_names, normalized.tolist(), strict=True))


@dataclass(frozen=True)
class MuWorstSummary(Record):
    """The lower bound's worst perturbation (:class:`WorstPerturbation`) in JSON form.

    ``array_angle_deg`` is the grid's offset [deg]; ``normalized`` and
    ``normalized_unclipped`` the parameters' box positions by name (the model's
    parameters differ from one debris to another, hence a mapping).
    """

    omega_rad_s: float
    array_angle_deg: float
    determinant: float
    clipped: bool
    normalized_unclipped: dict[str, float]
    normalized: dict[str, float]


@dataclass(frozen=True)
class MuBoundsSummary(Record):
    """Peak bounds of one structure: ``margin_* = 1 / mu_*`` (``margin_lower`` None
    when no lower bound was found); ``worst`` absent when no perturbation was found."""

    mu_upper: float
    mu_lower: float
    gap: float
    margin_upper: float
    margin_lower: float | None
    lmi_points: int
    worst: MuWorstSummary | None = field(default=None, metadata=OPTIONAL)


@dataclass(frozen=True)
class ParametricMuSummary(Record):
    """:meth:`ParametricMu.summary`: the grids, the fit and both bounds (``time_s`` [s])."""

    real_parameters: tuple[str, ...]
    real_block_sizes: tuple[int, ...]
    array_angles_deg: tuple[float, ...]
    frequencies: int
    fit_residual: float
    analysis_plant_modes: str
    seed: int
    time_s: float
    stability: MuBoundsSummary
    performance: MuBoundsSummary


def top_frequencies(curve: np.ndarray, count: int) -> list[int]:
    """Indices of the ``count`` largest local maxima of ``curve``."""
    padded = np.concatenate([[-np.inf], curve, [-np.inf]])
    peaks = np.flatnonzero((padded[1:-1] >= padded[:-2]) & (padded[1:-1] >= padded[2:]))
    return sorted(peaks[np.argsort(curve[peaks])[::-1][:count]].tolist())


def _structures(plant: ParametricPlant) -> dict[str, tuple[Any, ...]]:
    real = tuple(plant.blocks)
    return {"stability": real, "performance": (*real, ("complex", N_PERFORMANCE))}


@dataclass
class _Grid:
    """What the angle loop fills in, for one structure."""

    upper: np.ndarray
    lower: np.ndarray
    responses: list[np.ndarray]
    structures: list[tuple[Any, ...]]
    best: tuple[float, int, int, np.ndarray] | None = None  # (mu, angle, omega index, Delta)


def parametric_mu(
    problem: Problem,
    controller: control.StateSpace,
    weights: PerformanceWeights,
    *,
    angles: int | None = None,
    omega: np.ndarray | None = None,
    modes: str = "all",
    lower_points: int = 3,
    lmi_points: int = 3,
    seed: int = 0,
) -> ParametricMu:
    """Real-parametric mu bounds (stability and performance) of ``controller``.

    Parameters
    ----------
    problem : Problem
    controller : control.StateSpace
        Attitude error [deg] -> torque [mNm], u = K e.
    weights : PerformanceWeights
        The performance weights (the controller's recorded ones, say).
    angles : int, optional
        Array angles of the grid (default the corner campaign's,
        ``montecarlo.corner_array_angles``); ignored without arrays.
    omega : ndarray, optional
        Frequencies [rad/s] (default 30 from 1e-4 to 1e2).
    modes : str
        Modes of the analysis plant (default all: the plant ``simulate`` flies).
    lower_points : int
        Local maxima of the upper bound, per angle, where the lower bound is searched.
    lmi_points : int
        Largest grid points where the D-G LMI with full blocks on the repeated
        scalars replaces AB13MD's bound (0: none; skipped without cvxpy).
    seed : int
        Seed of the lower bound's random starts.

    Returns
    -------
    ParametricMu

    Raises
    ------
    SynthesisError
        The nominal loop is unstable at an angle of the grid.
    """
    start = time.perf_counter()
    omega = np.logspace(-4, 2, 30) if omega is None else np.asarray(omega, dtype=float)
    model = build_model(problem, modes=modes)
    function = linearization_function(model, sensor=True)
    positions = corner_angles(problem, angles) if model.parameter_layout.has_array_angle else [0.0]
    shape = (len(positions), len(omega))
    grids = {kind: _Grid(np.zeros(shape), np.zeros(shape), [], []) for kind in KINDS}
    request = _AngleRequest(model, function, controller, weights, omega, lower_points, seed)
    plants = [_analyse_angle(request, a, z, grids) for a, z in enumerate(positions)]
    results = {
        kind: RealMuBounds(
            grid.upper, grid.lower, _worst(grid, plants, omega), _tighten(grid, lmi_points)
        )
        for kind, grid in grids.items()
    }
    layout = model.parameter_layout
    return ParametricMu(
        real_names=plants[0].real_names,
        ranks=tuple(max(p.ranks[i] for p in plants) for i in range(len(plants[0].ranks))),
        parameter_names=layout.names,
        angle_normalized=np.asarray(positions, dtype=float),
        angle_deg=np.asarray(positions, dtype=float) * problem.uncertainty.array_angle_deg,
        omega=omega,
        residual=max(p.residual for p in plants),
        stability=results["stability"],
        performance=results["performance"],
        seed=seed,
        modes=modes,
        time_s=time.perf_counter() - start,
    )


def _balanced(m: np.ndarray, scalar_entries: int) -> np.ndarray:
    """Diagonal scalings d (one per frequency and channel) that balance |M| on its real
    channels (the first ``scalar_entries``), 1 on the complex block.

    D M D^-1 has the same mu and the same destabilising Delta (a diagonal D
    commutes with every real scalar block and, being 1 there, with the full
    complex block); AB13MD converges on it in a tenth of the time and to a
    tighter bound where M spans six decades (low frequencies).
    """
    d = np.ones(m.shape[:2])
    magnitude = np.abs(m)
    for _ in range(30):
        for i in range(scalar_entries):
            scaled = magnitude * d[:, :, None] / d[:, None, :]
            row = scaled[:, i, :].sum(axis=1) - scaled[:, i, i]
            col = scaled[:, :, i].sum(axis=1) - scaled[:, i, i]
            ok = (row > 0) & (col > 0)
            d[ok, i] *= np.sqrt(col[ok] / row[ok])
    return d


@dataclass(frozen=True, eq=False)
class _AngleRequest:
    """What every array angle of :func:`parametric_mu` shares: the model and its
    linearisation, the loop, the frequencies, and the lower bound's search."""

    model: Model
    function: ca.Function  # linearization_function(model, sensor=True)
    controller: control.StateSpace
    weights: PerformanceWeights
    omega: np.ndarray  # rad/s
    lower_points: int
    seed: int


def _analyse_angle(
    request: _AngleRequest, a: int, angle: float, grids: dict[str, _Grid]
) -> ParametricPlant:
    """Fit the plant at one angle, close the loop, fill both structures' grids at row a."""
    r = request
    plant = fit_parametric_plant(r.model, angle, function=r.function)
    closed = parametric_closed_loop(plant, r.controller, r.weights)
    if np.any(np.linalg.eigvals(closed.A).real >= 0):
        raise SynthesisError(f"the nominal closed loop is unstable at array angle {angle:+.3f}")
    response = frequency_response(closed, r.omega)
    for kind, structure in _structures(plant).items():
        m = response[:, : plant.n_real, : plant.n_real] if kind == "stability" else response
        _fill(grids[kind], a, m, structure, r.lower_points, r.seed)
    return plant


def _fill(
    grid: _Grid, a: int, m: np.ndarray, structure: tuple[Any, ...], points: int, seed: int
) -> None:
    """Upper bound on the whole grid, lower bound at its largest local maxima, for angle a."""
    d = _balanced(m, sum(size for kind, size in structure if kind == "real"))
    m = d[:, :, None] * m / d[:, None, :]
    grid.upper[a] = mu_upper_bound(m, structure).mu
    grid.responses.append(m)
    grid.structures.append(structure)
    picks = top_frequencies(grid.upper[a], points)
    found = mu_bounds(m[picks], structure, upper="ab13md", seed=seed + 1000 * a)
    grid.lower[a, picks] = found.lower
    j = int(np.argmax(found.lower))
    if found.lower[j] > 0 and (grid.best is None or found.lower[j] > grid.best[0]):
        grid.best = (float(found.lower[j]), a, picks[j], found.perturbation[j])


def _tighten(grid: _Grid, points: int) -> int:
    """Replace AB13MD's bound by the LMI's at the largest points (repeated reals only)."""
    if points <= 0:
        return 0
    try:
        import cvxpy  # noqa: F401
    except ImportError:
        _log.info("cvxpy missing: repeated real scalars bounded as independent ones")
        return 0
    from casadi_debris.robust.mu._lmi import lmi_upper_bound

    done: set[tuple[int, int]] = set()
    for _ in range(points):
        a, k = (int(i) for i in np.unravel_index(int(np.argmax(grid.upper)), grid.upper.shape))
        if (a, k) in done:
            break
        structure = block_structure(grid.structures[a])
        if not any(b.kind == "real" and b.size > 1 for b in structure):
            break
        bound = lmi_upper_bound(grid.responses[a][k], structure, float(grid.lower[a, k]))
        grid.upper[a, k] = min(grid.upper[a, k], bound)
        done.add((a, k))
    return len(done)


def _worst(
    grid: _Grid, plants: list[ParametricPlant], omega: np.ndarray
) -> WorstPerturbation | None:
    if grid.best is None:
        return None
    mu, a, k, delta = grid.best
    plant = plants[a]
    starts = np.concatenate([[0], np.cumsum(plant.ranks)[:-1]]).astype(int)
    z = np.array([delta[s, s].real for s in starts])
    m = grid.responses[a][k]
    determinant = float(abs(np.linalg.det(np.eye(len(m)) - m @ delta)))
    unclipped = plant.normalized(z)
    return WorstPerturbation(
        mu_lower=mu,
        omega_rad_s=float(omega[k]),
        angle_index=a,
        perturbation=delta,
        determinant=determinant,
        normalized_unclipped=unclipped,
        normalized=np.clip(unclipped, -1.0, 1.0),
    )
