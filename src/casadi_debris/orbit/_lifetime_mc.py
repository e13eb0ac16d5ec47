"""A lifetime Monte Carlo over solar activity and drag coefficient, seeded.

The constant levels of :mod:`~casadi_debris.orbit._atmosphere` bracket the
decay; a real lifetime sees solar cycles. Each run draws

- a solar cycle: F10.7 (= F10.7a) following
  ``F_min + (F_max - F_min) (1 - cos(2 pi (t / P + phase))) / 2`` with
  P = 11 years, F_min = 65 sfu (the low level), F_max uniform in
  [:data:`CYCLE_PEAK_SFU`] (monthly-mean peaks of recent cycles lie in this
  range) and the phase uniform in [0, 1) (where in its cycle the burn starts);
  Ap follows F10.7 as in the density table;
- C_D uniform in [:data:`DRAG_COEFFICIENT_RANGE`] (free-molecular values for
  satellite shapes),

and flies the same plan (a burn of a given Δv, or none) to re-entry. Every
run's draws come from the campaign's seed and its index (a
:class:`numpy.random.SeedSequence` child per run), so that one run can be
re-run alone; the runs are spread over worker processes in chunks.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.orbit._atmosphere import density_table, log_interp
from casadi_debris.orbit._deorbit import DeorbitModel, DeorbitSettings
from casadi_debris.orbit._lifetime import DensityFunction
from casadi_debris.parallel import ItemFailure, no_context, parallel_map
from casadi_debris.records import Record
from casadi_debris.units import SECONDS_PER_YEAR

CYCLE_YEARS = 11.0
CYCLE_MIN_SFU = 65.0
CYCLE_PEAK_SFU = (130.0, 250.0)
DRAG_COEFFICIENT_RANGE = (2.0, 2.5)
CHUNK = 25


@dataclass(frozen=True)
class LifetimeDraw(Record):
    """One run's draws: the seed and index re-create them.

    Attributes
    ----------
    run : int
        1-based.
    cycle_peak_sfu, cycle_phase, drag_coefficient : float
    """

    run: int
    cycle_peak_sfu: float
    cycle_phase: float
    drag_coefficient: float

    @classmethod
    def draw(cls, seed: int, run: int) -> LifetimeDraw:
        """The draws of run ``run`` (1-based) of a campaign seeded ``seed``."""
        rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(run,)))
        return cls(
            run=run,
            cycle_peak_sfu=float(rng.uniform(*CYCLE_PEAK_SFU)),
            cycle_phase=float(rng.uniform(0.0, 1.0)),
            drag_coefficient=float(rng.uniform(*DRAG_COEFFICIENT_RANGE)),
        )

    def f107(self, time_s: float) -> float:
        """F10.7 of this run's cycle at ``time_s`` after the start [sfu]."""
        angle = 2.0 * math.pi * (time_s / (CYCLE_YEARS * SECONDS_PER_YEAR) + self.cycle_phase)
        return CYCLE_MIN_SFU + (self.cycle_peak_sfu - CYCLE_MIN_SFU) * 0.5 * (1.0 - math.cos(angle))


@dataclass(frozen=True)
class LifetimeCampaign(Record):
    """Re-entry times of one plan over solar cycles and C_D.

    Attributes
    ----------
    runs, seed : int
    dv_m_s : float
        Of the burn flown in every run (0: natural decay).
    arc_half_width_deg : float
    limit_years : float
    reentry_years : tuple of float
        Per run (NaN/null beyond the horizon).
    within_limit_fraction : float
    median_years, p05_years, p95_years : float
        Of the re-entry times (beyond the horizon counts as longest).
    failed_runs : tuple of int
        1-based runs whose integration raised (left out of the statistics).
    """

    runs: int
    seed: int
    dv_m_s: float
    arc_half_width_deg: float
    limit_years: float
    reentry_years: tuple[float, ...]
    within_limit_fraction: float
    median_years: float
    p05_years: float
    p95_years: float
    failed_runs: tuple[int, ...] = ()


def cycle_density(model: DeorbitModel, draw: LifetimeDraw) -> DensityFunction:
    """The averaged density under this run's solar cycle."""
    table = density_table(
        round(math.degrees(model.inclination_rad), 3), radius_m=model.earth.radius_m
    )

    def rho(altitude_m: np.ndarray, time_s: float) -> np.ndarray:
        profile = table.profile(draw.f107(time_s))
        return np.exp(log_interp(table.altitudes_m, profile, np.maximum(altitude_m, 0.0)))

    return rho


@dataclass(frozen=True)
class _Chunk:
    model: DeorbitModel
    seed: int
    runs: tuple[int, ...]
    dv_m_s: float
    half_width_deg: float
    horizon_years: float


def _run_chunk(context: None, chunk: _Chunk) -> list[float]:
    """Re-entry years of the chunk's runs."""
    years = []
    for run in chunk.runs:
        draw = LifetimeDraw.draw(chunk.seed, run)
        ballistic = dataclasses.replace(chunk.model.decay, drag_coefficient=draw.drag_coefficient)
        model = dataclasses.replace(chunk.model, decay=ballistic)
        history = model.fly(
            chunk.dv_m_s, cycle_density(model, draw), chunk.half_width_deg, chunk.horizon_years
        )
        years.append(history.reentry_years)
    return years


def lifetime_monte_carlo(
    problem: Problem | DeorbitModel,
    *,
    runs: int,
    seed: int,
    dv_m_s: float = 0.0,
    arc_half_width_deg: float = 180.0,
    settings: DeorbitSettings | None = None,
    workers: int = 1,
) -> LifetimeCampaign:
    """Re-entry times of a plan (a burn of ``dv_m_s``, or none) over ``runs`` draws.

    Parameters
    ----------
    problem : Problem or DeorbitModel
        A problem, or its model already built (reused as is).
    runs, seed : int
    dv_m_s : float
        The burn's Δv [m/s] (flown with the swarm's thrust as in the plan).
    arc_half_width_deg : float
        180 for a spiral, less for apogee arcs.
    settings : DeorbitSettings, optional
        The limit and horizon (its solar cases are not used: the cycles replace them).
    workers : int
        Local worker processes.

    Returns
    -------
    LifetimeCampaign
    """
    settings = settings or DeorbitSettings()
    model = (
        problem
        if isinstance(problem, DeorbitModel)
        else DeorbitModel.from_problem(problem, settings)
    )
    ids = list(range(1, runs + 1))
    chunks = [
        _Chunk(
            model,
            seed,
            tuple(ids[i : i + CHUNK]),
            dv_m_s,
            arc_half_width_deg,
            settings.horizon_years,
        )
        for i in range(0, runs, CHUNK)
    ]
    years = np.full(runs, math.nan)
    failed: list[int] = []
    with parallel_map(_run_chunk, chunks, no_context, workers=workers) as results:
        for result in results:
            chunk = chunks[result.index]
            if isinstance(result, ItemFailure):
                failed.extend(chunk.runs)
                continue
            years[np.array(chunk.runs) - 1] = result.value
    return _campaign(runs, seed, dv_m_s, arc_half_width_deg, settings.limit_years, years, failed)


def _campaign(
    runs: int,
    seed: int,
    dv: float,
    half_width: float,
    limit: float,
    years: np.ndarray,
    failed: list[int],
) -> LifetimeCampaign:
    done = np.delete(years, np.array(failed, dtype=int) - 1)
    p05, median, p95 = np.percentile(done, [5.0, 50.0, 95.0]) if done.size else (math.nan,) * 3
    return LifetimeCampaign(
        runs=runs,
        seed=seed,
        dv_m_s=dv,
        arc_half_width_deg=half_width,
        limit_years=limit,
        reentry_years=tuple(float(y) for y in years),
        within_limit_fraction=float(np.mean(done <= limit)) if done.size else math.nan,
        median_years=float(median),
        p05_years=float(p05),
        p95_years=float(p95),
        failed_runs=tuple(sorted(failed)),
    )
