"""The performance search: bracketing and bisection on a known mu(Ve), without D-K."""

from __future__ import annotations

import json
import math

import pytest

from casadi_debris.robust.synthesis import DesignAttempt, search_design
from casadi_debris.robust.synthesis import _search as performance_search


class _FakeDesign:
    def __init__(self, ve_ratio: float) -> None:
        self.ve_ratio = ve_ratio


def _fake_search(monkeypatch, critical_ratio: float, **kwargs):
    """search_design where mu = sqrt(critical / Ve ratio): guaranteed exactly from ``critical``
    up, and the guaranteed pointing 60 sqrt(critical ratio) arcsec grows with the ratio."""
    tried = []

    def design_at(problem, settings, fit, scalings, say):
        mu = math.sqrt(critical_ratio / scalings.ve_ratio)
        tried.append(scalings.ve_ratio)
        guarantee = scalings.guaranteed_pointing_arcsec(mu)
        attempt = DesignAttempt(
            scalings.ve_ratio,
            mu,
            mu,
            None if guarantee is None else tuple(guarantee.tolist()),
            1,
            0.0,
        )
        return _FakeDesign(scalings.ve_ratio), attempt

    monkeypatch.setattr(performance_search, "fit_uncertainty", lambda problem, settings: None)
    monkeypatch.setattr(performance_search, "_design_at", design_at)
    return search_design(problem=kwargs.pop("problem"), **kwargs), tried


@pytest.mark.parametrize("critical", [0.3, 0.77, 1.0, 1.6, 5.0, 40.0])
def test_search_keeps_the_tightest_guaranteeing_ve_within_the_bisection_width(
    monkeypatch, problem, critical
):
    search, tried = _fake_search(monkeypatch, critical, problem=problem)
    chosen = search.chosen
    assert chosen.guarantees and chosen.ve_ratio >= critical * (1 - 1e-12)
    # three bisections of a factor-2 bracket: within 2 ** (1 / 8)
    assert chosen.ve_ratio <= critical * 2 ** (1 / 8) * (1 + 1e-12)
    expected = 60.0 * math.sqrt(critical * chosen.ve_ratio)
    assert max(chosen.guaranteed_pointing_arcsec) == pytest.approx(expected, rel=1e-9)
    assert tried[0] == 1.0 and len(tried) == len(set(tried))


def test_no_guarantee_anywhere_keeps_the_lowest_mu(monkeypatch, problem):
    search, tried = _fake_search(monkeypatch, 1000.0, problem=problem, max_ve_ratio=8.0)
    assert tried == [1.0, 2.0, 4.0, 8.0]
    assert not search.chosen.guarantees and search.chosen.ve_ratio == 8.0


def test_a_guarantee_at_the_smallest_ratio_stops_the_halving(monkeypatch, problem):
    search, tried = _fake_search(monkeypatch, 0.01, problem=problem, min_ve_ratio=0.25)
    assert tried == [1.0, 0.5, 0.25]
    assert math.isclose(search.chosen.ve_ratio, 0.25)


@pytest.mark.parametrize("guaranteed", [(40.0, 61.5, 40.0), None])
def test_an_attempt_is_a_record_that_reads_back(guaranteed) -> None:
    attempt = DesignAttempt(1.5, 0.9, 0.95, guaranteed, 3, 12.0)
    data = json.loads(json.dumps(attempt.to_json()))
    assert data == {
        "ve_ratio": 1.5,
        "mu_peak": 0.9,
        "mu_peak_reduced": 0.95,
        "guaranteed_pointing_arcsec": None if guaranteed is None else list(guaranteed),
        "iterations": 3,
        "time_s": 12.0,
    }
    assert DesignAttempt.from_json(data) == attempt
