"""The lifetime Monte Carlo: bracketed by the constant levels, reproducible run by run."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from casadi_debris.orbit import DeorbitModel, DeorbitSettings, SolarActivity
from casadi_debris.orbit._lifetime_mc import (
    CYCLE_MIN_SFU,
    CYCLE_PEAK_SFU,
    DRAG_COEFFICIENT_RANGE,
    LifetimeDraw,
    _Chunk,
    _run_chunk,
    lifetime_monte_carlo,
)

SETTINGS = DeorbitSettings(minimum_swarm=False)


@pytest.fixture(scope="module")
def low_orbit(problem):
    return dataclasses.replace(problem, orbit=dataclasses.replace(problem.orbit, altitude_km=500.0))


@pytest.fixture(scope="module")
def campaign(low_orbit):
    return lifetime_monte_carlo(low_orbit, runs=12, seed=11, settings=SETTINGS)


def _constant(model: DeorbitModel, f107: float, cd: float) -> float:
    decay = dataclasses.replace(model.decay, drag_coefficient=cd)
    fixed = dataclasses.replace(model, decay=decay)
    density = fixed.density(SolarActivity("fixed", f107, f107, 0.0))
    return fixed.fly(0.0, density, 180.0, 200.0).reentry_years


def test_every_run_lies_between_the_extreme_constant_levels(low_orbit, campaign) -> None:
    model = DeorbitModel.from_problem(low_orbit, SETTINGS)
    longest = _constant(model, CYCLE_MIN_SFU, DRAG_COEFFICIENT_RANGE[0])
    shortest = _constant(model, CYCLE_PEAK_SFU[1], DRAG_COEFFICIENT_RANGE[1])
    years = np.array(campaign.reentry_years)
    assert np.all(np.isfinite(years))
    assert np.all((shortest <= years) & (years <= longest))
    assert campaign.p05_years <= campaign.median_years <= campaign.p95_years
    assert campaign.within_limit_fraction == pytest.approx(np.mean(years <= 5.0))


def test_a_run_is_reproduced_alone(low_orbit, campaign) -> None:
    model = DeorbitModel.from_problem(low_orbit, SETTINGS)
    alone = _run_chunk(None, _Chunk(model, 11, (7,), 0.0, 180.0, 200.0))
    assert alone[0] == campaign.reentry_years[6]
    draw = LifetimeDraw.draw(11, 7)
    assert draw == LifetimeDraw.draw(11, 7) != LifetimeDraw.draw(12, 7)
    assert CYCLE_MIN_SFU <= draw.f107(0.0) <= draw.cycle_peak_sfu


def test_the_cycle_spans_minimum_to_peak() -> None:
    draw = LifetimeDraw(run=1, cycle_peak_sfu=200.0, cycle_phase=0.0, drag_coefficient=2.2)
    year = 365.25 * 86400.0
    assert draw.f107(0.0) == pytest.approx(CYCLE_MIN_SFU)
    assert draw.f107(5.5 * year) == pytest.approx(200.0)
    assert draw.f107(11.0 * year) == pytest.approx(CYCLE_MIN_SFU)
    assert math.isclose(draw.f107(2.75 * year), 0.5 * (CYCLE_MIN_SFU + 200.0))
