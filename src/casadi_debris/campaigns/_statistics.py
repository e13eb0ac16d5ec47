"""Statistics of a campaign: pass rate, moments, percentiles, and what drives the worst cases.

Over the cases that finished, for every figure of merit of the case table
(largest error, fuel, settling time, ...):

- mean, standard deviation (``ddof = 1``), ``3 sigma`` and ``mean + 3 sigma``,
  smallest and largest value, percentiles 50, 90, 95 and 99 (numpy's linear
  interpolation); a case without the figure (a run that never settles)
  is left out of that figure's numbers and counted apart;
- the pass rate against ``[requirements]``: the largest attitude error in
  degrees against ``slew_error_deg`` for a slew, in arcseconds against
  ``pointing_arcsec`` for a hold; a case that raised counts as failed;
- Spearman's rank correlation (``scipy.stats.spearmanr``) of every varied
  quantity with every figure, and per figure the quantities ordered by
  ``|rho|``: which drive the worst cases (for a monotonic effect the rank
  correlation is the share of the ordering a quantity explains, whatever its
  unit or the figure's scale). A quantity that does not vary over the cases
  has no correlation (``null``);
- beside it, a first-order variance-based index (:func:`first_order_index`):
  the share of the figure's variance the quantity explains alone, which also
  sees effects that are not monotonic.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from scipy import stats

from casadi_debris.campaigns._monte_carlo import CaseResult
from casadi_debris.config import Problem
from casadi_debris.records import Record
from casadi_debris.simulation import RunSummary

# Figures of merit of a case (fields of RunSummary, unit in the name).
FIGURES = (
    "max_error_deg",
    "max_error_arcsec",
    "settle_time_s",
    "fuel_kg",
    "fuel_slew_kg",
    "fuel_worst_cubesat_kg",
    "dv_used_m_s",
    "torque_saturated_s",
    "min_scale",
)
# Figures whose worst case is the smallest value.
LOWER_IS_WORSE = frozenset({"min_scale"})
PERCENTILES = (50, 90, 95, 99)
MIN_CASES_INDEX = 20
"""Cases below which no variance-based index is estimated (too few per group)."""
MAX_INDEX_BINS = 20


@dataclass(frozen=True)
class FigureStatistics(Record):
    """One figure of merit over the cases of a campaign (in the figure's unit).

    Attributes
    ----------
    figure : str
        Name, unit included (``max_error_deg``).
    cases, missing : int
        Cases with the figure, and without it (a run that never settles).
    mean, std, three_sigma, mean_plus_3sigma, min, max : float
        ``std`` with ``ddof = 1``; ``three_sigma = 3 std``.
    p50, p90, p95, p99 : float
        Percentiles (linear interpolation between cases).
    requirement : float or None
        The upper bound ``[requirements]`` sets on it, if any.
    passed : int or None
        Cases within ``requirement``.
    """

    figure: str
    cases: int
    missing: int
    mean: float
    std: float
    three_sigma: float
    mean_plus_3sigma: float
    min: float
    max: float
    p50: float
    p90: float
    p95: float
    p99: float
    requirement: float | None = None
    passed: int | None = None


@dataclass(frozen=True)
class Driver(Record):
    """The varied quantities ordered by how strongly they rank one figure.

    Attributes
    ----------
    figure : str
    quantities : tuple of str
        By decreasing ``|spearman_rho|`` (quantities without one left out).
    spearman_rho : tuple of float
        Of each, in that order.
    first_order_index : tuple of float or None
        Of each, in that order (None: too few cases).
    worst_case_id : str
        The case with the worst value (largest; smallest for ``min_scale``).
    worst_value : float
    worst_case_values : dict of str to float
        Every varied quantity in that case.
    """

    figure: str
    quantities: tuple[str, ...]
    spearman_rho: tuple[float, ...]
    first_order_index: tuple[float | None, ...]
    worst_case_id: str
    worst_value: float
    worst_case_values: dict[str, float]


@dataclass(frozen=True)
class Sensitivity(Record):
    """How one quantity acts on one figure over the cases.

    Attributes
    ----------
    quantity, figure : str
    spearman_rho, p_value : float or None
        Spearman's rank correlation and its p-value; None (``null``) when either
        does not vary.
    first_order_index : float or None
        Share of the figure's variance its mean given the quantity explains
        (a first-order, variance-based sensitivity index, estimated from the
        cases: see :func:`first_order_index`); None with fewer than
        :data:`MIN_CASES_INDEX` cases or when either does not vary.
    """

    quantity: str
    figure: str
    spearman_rho: float | None
    p_value: float | None
    first_order_index: float | None = None


@dataclass(frozen=True)
class CampaignStatistics(Record):
    """Statistics of a campaign (see the module's description).

    Attributes
    ----------
    cases : int
        Cases that finished.
    failed_cases : int
        Cases that raised (counted as not passing).
    quantities : tuple of str
        What varied: the ``[[montecarlo.vary]]`` paths, or the model
        parameters for a campaign over the uncertainty set.
    requirement_figure : str
    requirement : float
        Upper bound on ``requirement_figure``.
    passed : int
    pass_rate : float
        ``passed / (cases + failed_cases)``.
    figures : tuple of FigureStatistics
    drivers : tuple of Driver
        One per figure.
    sensitivity : tuple of Sensitivity
        Every quantity with every figure.
    """

    cases: int
    failed_cases: int
    quantities: tuple[str, ...]
    requirement_figure: str
    requirement: float
    passed: int
    pass_rate: float
    figures: tuple[FigureStatistics, ...]
    drivers: tuple[Driver, ...]
    sensitivity: tuple[Sensitivity, ...]

    def figure(self, name: str) -> FigureStatistics:
        """The statistics of figure ``name`` (KeyError if the campaign has none)."""
        for item in self.figures:
            if item.figure == name:
                return item
        raise KeyError(name)


def requirement_of(problem: Problem) -> tuple[str, float]:
    """The figure ``[requirements]`` bounds for the problem's run, and the bound."""
    if problem.simulation.reference == "hold":
        return "max_error_arcsec", problem.requirements.pointing_arcsec
    return "max_error_deg", problem.requirements.slew_error_deg


def requirement_shortfalls(problem: Problem, run: RunSummary) -> tuple[str, ...]:
    """How one run misses the problem's ``[requirements]``, one sentence each (none: met).

    A hold is judged by its largest pointing error against ``pointing_arcsec``; a
    slew or a sequence by its largest error against ``slew_error_deg`` and by where
    it ends: a run that ends farther from its reference than the slew bound has lost
    it (a saturated loop that never turned), whatever its peak said on the way.
    """
    figure, bound = requirement_of(problem)
    value = float(getattr(run, figure))
    shortfalls = []
    if not value <= bound:  # NaN fails too
        if figure == "max_error_arcsec":
            what = f"largest pointing error {value:.4g} arcsec"
            needed = f"{bound:g} arcsec ([requirements] pointing_arcsec)"
        else:
            what = f"largest attitude error {value:.4g} deg"
            needed = f"{bound:g} deg ([requirements] slew_error_deg)"
        shortfalls.append(f"{what} exceeds {needed}")
    final_deg = run.final_error_arcsec / 3600.0
    if figure == "max_error_deg" and not final_deg <= bound:
        shortfalls.append(
            f"ends {final_deg:.4g} deg off its reference, outside the slew bound {bound:g} deg"
        )
    if shortfalls and run.min_scale < 1.0:
        # Saturation alone is no shortfall, but beside one it is the likely cause.
        shortfalls.append(
            f"the engines could not give the torque asked for {run.torque_saturated_s:.1f} s"
        )
    return tuple(shortfalls)


def case_quantities(
    outcomes: Sequence[CaseResult], parameter_names: Sequence[str]
) -> dict[str, np.ndarray]:
    """What varied over the cases, by name, shape (n_cases,) each.

    The ``[[montecarlo.vary]]`` values when the cases carry them, else the
    model parameters (``parameter_names``, the order of ``Case.parameters``).
    """
    if outcomes and all(o.case.varied for o in outcomes):
        names = [name for name, _ in outcomes[0].case.varied]
        rows = [[value for _, value in o.case.varied] for o in outcomes]
    else:
        names = list(dict.fromkeys(parameter_names))
        index = [list(parameter_names).index(n) for n in names]
        rows = [np.asarray(o.case.parameters)[index].tolist() for o in outcomes]
    matrix = np.array(rows, dtype=float).reshape(len(outcomes), len(names))
    return {name: matrix[:, k] for k, name in enumerate(names)}


def case_figures(outcomes: Sequence[CaseResult]) -> dict[str, np.ndarray]:
    """Every figure of :data:`FIGURES` over the cases (None: NaN), those some case has."""
    table = {
        name: np.array([_number(getattr(o.summary.run, name)) for o in outcomes], dtype=float)
        for name in FIGURES
    }
    return {name: values for name, values in table.items() if np.isfinite(values).any()}


def _number(value: float | None) -> float:
    return math.nan if value is None else float(value)


def campaign_statistics(
    case_ids: Sequence[str],
    figures: Mapping[str, np.ndarray],
    quantities: Mapping[str, np.ndarray],
    requirement: tuple[str, float],
    failed_cases: int = 0,
) -> CampaignStatistics:
    """Statistics of a case table (see the module's description).

    Parameters
    ----------
    case_ids : sequence of str
        Shape (n_cases,).
    figures : mapping of str to ndarray
        Figure name -> values per case, shape (n_cases,); NaN where a case has none.
    quantities : mapping of str to ndarray
        Varied quantity -> its value per case, shape (n_cases,).
    requirement : (str, float)
        The figure bounded by ``[requirements]`` and its upper bound.
    failed_cases : int
        Cases that raised (not in the table; they count as not passing).

    Returns
    -------
    CampaignStatistics
    """
    figure_name, bound = requirement
    if figure_name not in figures:
        raise ValueError(f"the case table has no {figure_name}")
    passed = int(np.sum(np.asarray(figures[figure_name]) <= bound))
    sensitivity = tuple(
        _spearman(name, figure, quantities[name], values)
        for figure, values in figures.items()
        for name in quantities
    )
    return CampaignStatistics(
        cases=len(case_ids),
        failed_cases=failed_cases,
        quantities=tuple(quantities),
        requirement_figure=figure_name,
        requirement=float(bound),
        passed=passed,
        pass_rate=passed / (len(case_ids) + failed_cases),
        figures=tuple(
            _figure(name, np.asarray(values, dtype=float), bound if name == figure_name else None)
            for name, values in figures.items()
        ),
        drivers=tuple(
            _driver(figure, values, case_ids, quantities, sensitivity)
            for figure, values in figures.items()
        ),
        sensitivity=sensitivity,
    )


def _figure(name: str, values: np.ndarray, bound: float | None) -> FigureStatistics:
    finite = values[np.isfinite(values)]
    std = float(np.std(finite, ddof=1)) if len(finite) > 1 else 0.0
    mean = float(np.mean(finite))
    p50, p90, p95, p99 = (float(v) for v in np.percentile(finite, PERCENTILES))
    return FigureStatistics(
        figure=name,
        cases=len(finite),
        missing=len(values) - len(finite),
        mean=mean,
        std=std,
        three_sigma=3.0 * std,
        mean_plus_3sigma=mean + 3.0 * std,
        min=float(np.min(finite)),
        max=float(np.max(finite)),
        p50=p50,
        p90=p90,
        p95=p95,
        p99=p99,
        requirement=bound,
        passed=None if bound is None else int(np.sum(values <= bound)),
    )


def _spearman(quantity: str, figure: str, x: np.ndarray, y: np.ndarray) -> Sensitivity:
    keep = np.isfinite(x) & np.isfinite(y)
    x, y = x[keep], y[keep]
    if len(x) < 3 or np.ptp(x) == 0.0 or np.ptp(y) == 0.0:
        return Sensitivity(quantity, figure, None, None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", stats.ConstantInputWarning)
        result = stats.spearmanr(x, y)
    rho, p = float(result.statistic), float(result.pvalue)
    return Sensitivity(
        quantity,
        figure,
        rho if math.isfinite(rho) else None,
        p if math.isfinite(p) else None,
        first_order_index(x, y),
    )


def first_order_index(x: np.ndarray, y: np.ndarray) -> float | None:
    """First-order sensitivity index of ``y`` to ``x``, ``Var(E[y | x]) / Var(y)``, from data.

    The cases are grouped by ``x``: by its values when it takes at most
    ``sqrt(n)`` of them (corners), else into ``sqrt(n)`` (at most
    :data:`MAX_INDEX_BINS`) groups of equal count. The share of the variance
    between the groups' means is corrected for the share groups of pure noise
    would show (the epsilon-squared of an analysis of variance,
    ``(SS_between - (k - 1) MS_within) / SS_total``, at least 0), so that a
    quantity without effect reads about 0. Unlike a rank correlation it sees
    an effect that is not monotonic (worst in the middle of the range, or
    periodic as an array angle).

    Parameters
    ----------
    x, y : ndarray, shape (n,)
        Finite values of the quantity and of the figure in each case.

    Returns
    -------
    float or None
        In [0, 1]; None with fewer than :data:`MIN_CASES_INDEX` cases or when
        either does not vary.
    """
    n = len(x)
    if n < MIN_CASES_INDEX or np.ptp(x) == 0.0 or np.ptp(y) == 0.0:
        return None
    values, groups = np.unique(x, return_inverse=True)
    bins = min(MAX_INDEX_BINS, int(math.sqrt(n)))
    if len(values) > bins:
        order = np.argsort(x, kind="stable")
        groups = np.empty(n, dtype=int)
        groups[order] = np.arange(n) * bins // n
    k = int(groups.max()) + 1
    counts = np.bincount(groups, minlength=k)
    means = np.bincount(groups, weights=y, minlength=k) / counts
    total = float(np.sum((y - y.mean()) ** 2))
    between = float(np.sum(counts * (means - y.mean()) ** 2))
    within = (total - between) / (n - k)
    return float(min(1.0, max(0.0, (between - (k - 1) * within) / total)))


def _driver(
    figure: str,
    values: np.ndarray,
    case_ids: Sequence[str],
    quantities: Mapping[str, np.ndarray],
    sensitivity: Sequence[Sensitivity],
) -> Driver:
    ranked = sorted(
        (s for s in sensitivity if s.figure == figure and s.spearman_rho is not None),
        key=lambda s: -abs(s.spearman_rho or 0.0),
    )
    filled = np.where(np.isfinite(values), values, -np.inf)
    worst = int(np.argmin(values) if figure in LOWER_IS_WORSE else np.argmax(filled))
    return Driver(
        figure=figure,
        quantities=tuple(s.quantity for s in ranked),
        spearman_rho=tuple(float(s.spearman_rho or 0.0) for s in ranked),
        first_order_index=tuple(s.first_order_index for s in ranked),
        worst_case_id=case_ids[worst],
        worst_value=float(values[worst]),
        worst_case_values={name: float(v[worst]) for name, v in quantities.items()},
    )


def statistics_of(
    problem: Problem,
    outcomes: Sequence[CaseResult],
    parameter_names: Sequence[str],
    failed_cases: int = 0,
) -> CampaignStatistics:
    """:func:`campaign_statistics` of finished cases against the problem's requirement."""
    return campaign_statistics(
        [o.case.case_id for o in outcomes],
        case_figures(outcomes),
        case_quantities(outcomes, parameter_names),
        requirement_of(problem),
        failed_cases,
    )
