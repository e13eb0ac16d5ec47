"""Campaign statistics against numpy and scipy computed directly on the case table, and the
quantity that drives a figure found at the top of the rank correlations."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from casadi_debris.campaigns import campaign_statistics, first_order_index
from casadi_debris.campaigns._statistics import PERCENTILES


def _table(n: int = 200, seed: int = 5):
    rng = np.random.default_rng(seed)
    quantities = {
        "environment.density_kg_m3": rng.uniform(1e-13, 5e-12, n),
        "mass_kg": rng.normal(668.0, 20.0, n),
        "sensor.star_tracker_bandwidth_rad_s": rng.uniform(20.0, 80.0, n),
        "fixed": np.full(n, 3.0),
    }
    # The error grows with the density (a monotonic, nonlinear law) and a little noise.
    error = 0.3 + np.sqrt(quantities["environment.density_kg_m3"] * 1e11) + rng.normal(0, 0.02, n)
    fuel = 1e-4 * (1.0 + 0.01 * rng.standard_normal(n)) * quantities["mass_kg"] / 668.0
    settle = rng.uniform(100.0, 900.0, n)
    settle[::7] = np.nan  # never settled
    figures = {"max_error_deg": error, "fuel_kg": fuel, "settle_time_s": settle}
    ids = [f"varied-{i:04d}" for i in range(n)]
    return ids, figures, quantities


def test_moments_percentiles_and_pass_rate_are_numpys_on_the_table() -> None:
    ids, figures, quantities = _table()
    result = campaign_statistics(ids, figures, quantities, ("max_error_deg", 0.6), failed_cases=4)
    for name, values in figures.items():
        finite = values[~np.isnan(values)]
        item = result.figure(name)
        assert item.cases == len(finite) and item.missing == len(values) - len(finite)
        assert item.mean == pytest.approx(np.mean(finite), rel=1e-12)
        assert item.std == pytest.approx(np.std(finite, ddof=1), rel=1e-12)
        assert item.three_sigma == pytest.approx(3 * np.std(finite, ddof=1), rel=1e-12)
        assert item.mean_plus_3sigma == pytest.approx(item.mean + item.three_sigma, rel=1e-12)
        assert (item.min, item.max) == (finite.min(), finite.max())
        for q in PERCENTILES:
            assert getattr(item, f"p{q}") == pytest.approx(np.percentile(finite, q), rel=1e-12)
    passed = int(np.count_nonzero(figures["max_error_deg"] <= 0.6))
    assert 0 < passed < len(ids)
    assert result.passed == result.figure("max_error_deg").passed == passed
    assert result.pass_rate == pytest.approx(passed / (len(ids) + 4))  # a raised case fails
    assert result.figure("fuel_kg").requirement is None


def test_rank_correlations_are_pearsons_of_the_ranks() -> None:
    ids, figures, quantities = _table()
    result = campaign_statistics(ids, figures, quantities, ("max_error_deg", 0.6))
    by_pair = {(s.quantity, s.figure): s for s in result.sensitivity}
    assert len(by_pair) == len(quantities) * len(figures)
    for (quantity, figure), item in by_pair.items():
        x, y = quantities[quantity], figures[figure]
        keep = ~np.isnan(y)
        if quantity == "fixed":  # does not vary: no correlation
            assert item.spearman_rho is None and item.p_value is None
            continue
        ranks = np.corrcoef(stats.rankdata(x[keep]), stats.rankdata(y[keep]))[0, 1]
        assert item.spearman_rho == pytest.approx(ranks, abs=1e-12)
        assert item.p_value == pytest.approx(stats.spearmanr(x[keep], y[keep]).pvalue)


def test_the_quantity_that_drives_a_figure_ranks_first() -> None:
    ids, figures, quantities = _table()
    result = campaign_statistics(ids, figures, quantities, ("max_error_deg", 0.6))
    drivers = {d.figure: d for d in result.drivers}
    error = drivers["max_error_deg"]
    assert error.quantities[0] == "environment.density_kg_m3" and error.spearman_rho[0] > 0.95
    assert all(abs(r) < 0.25 for r in error.spearman_rho[1:])
    assert drivers["fuel_kg"].quantities[0] == "mass_kg"
    worst = int(np.argmax(figures["max_error_deg"]))
    assert error.worst_case_id == ids[worst]
    assert error.worst_value == figures["max_error_deg"][worst]
    assert error.worst_case_values["mass_kg"] == quantities["mass_kg"][worst]
    assert "fixed" not in error.quantities


def test_the_record_round_trips_through_json() -> None:
    ids, figures, quantities = _table(20)
    result = campaign_statistics(ids, figures, quantities, ("max_error_deg", 0.6))
    again = type(result).from_json(result.to_json())
    assert again.to_json() == result.to_json()
    assert again.figure("fuel_kg").p95 == result.figure("fuel_kg").p95


def test_the_variance_based_index_sees_a_hump_the_rank_correlation_misses() -> None:
    rng = np.random.default_rng(12)
    x1, x2 = rng.uniform(-1.0, 1.0, 3000), rng.uniform(0.0, 1.0, 3000)
    y = x1**2 + 0.02 * rng.standard_normal(3000)  # worst at both ends, best in the middle
    result = campaign_statistics(
        [str(i) for i in range(3000)], {"fuel_kg": y}, {"a": x1, "b": x2}, ("fuel_kg", 1.0)
    )
    by_name = {s.quantity: s for s in result.sensitivity}
    assert abs(by_name["a"].spearman_rho) < 0.1 and by_name["a"].first_order_index > 0.9
    assert by_name["b"].first_order_index < 0.02


def test_the_index_of_an_additive_law_is_each_terms_share_of_the_variance() -> None:
    rng = np.random.default_rng(13)
    x1, x2 = rng.uniform(size=4000), rng.uniform(size=4000)
    y = 2.0 * x1 + x2  # Var(2 x1) = 4/12, Var(x2) = 1/12: shares 0.8 and 0.2
    assert first_order_index(x1, y) == pytest.approx(0.8, abs=0.03)
    assert first_order_index(x2, y) == pytest.approx(0.2, abs=0.03)
    assert first_order_index(x1[:19], y[:19]) is None  # too few cases


def test_grouped_by_values_the_index_is_the_epsilon_squared_of_scipys_anova() -> None:
    rng = np.random.default_rng(14)
    x = rng.choice([0.9, 1.0, 1.1, 1.2], 60)  # corners-like: four values, grouped by value
    y = 3.0 * (x > 1.05) + rng.standard_normal(60)
    f = stats.f_oneway(*(y[x == v] for v in np.unique(x))).statistic
    k, n = 4, 60
    expected = (k - 1) * (f - 1) / ((k - 1) * f + n - k)
    assert first_order_index(x, y) == pytest.approx(expected, rel=1e-10)
