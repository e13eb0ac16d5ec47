"""The cases of ``[[montecarlo.vary]]``: seeded draws of the asked distributions, every corner
combination, model parameters in the parameter vector and file keys kept for a rebuild."""

from __future__ import annotations

import copy
import itertools
from typing import Any

import numpy as np
import pytest
from scipy import stats

from casadi_debris.campaigns import varied_case, varied_cases, varied_count
from casadi_debris.campaigns._sampling import corner_row, corner_values, draw, draws
from casadi_debris.config import VariedQuantity, problem_from_dict
from casadi_debris.dynamics import build_model
from casadi_debris.errors import ProblemFileError


def _problem(paper: dict[str, Any], *entries: dict[str, Any]):
    data = copy.deepcopy(paper)
    data["montecarlo"]["vary"] = list(entries)
    return problem_from_dict(data)


def test_uniform_draws_fill_their_interval_uniformly() -> None:
    quantity = VariedQuantity("x.y", "uniform", low=-2.0, high=5.0)
    values = np.array([draws([quantity], 9, j)[0] for j in range(4000)])
    assert values.min() >= -2.0 and values.max() <= 5.0
    # Kolmogorov-Smirnov against scipy's uniform on [-2, 5].
    assert stats.kstest(values, stats.uniform(loc=-2.0, scale=7.0).cdf).pvalue > 1e-3


def test_truncated_normal_draws_follow_scipys_truncated_normal() -> None:
    quantity = VariedQuantity("x.y", "normal", low=0.5, high=3.0, mean=1.0, sigma=0.8)
    values = np.array([draws([quantity], 4, j)[0] for j in range(4000)])
    assert values.min() >= 0.5 and values.max() <= 3.0
    a, b = (0.5 - 1.0) / 0.8, (3.0 - 1.0) / 0.8
    reference = stats.truncnorm(a, b, loc=1.0, scale=0.8)
    assert stats.kstest(values, reference.cdf).pvalue > 1e-3
    assert abs(values.mean() - reference.mean()) < 4 * reference.std() / np.sqrt(len(values))


def test_an_untruncated_normal_has_its_mean_and_sigma() -> None:
    quantity = VariedQuantity("x.y", "normal", low=-1e12, high=1e12, mean=3.0, sigma=0.25)
    u = np.random.default_rng(0).uniform(size=20000)
    values = np.array([draw(quantity, x) for x in u])
    assert values.mean() == pytest.approx(3.0, abs=4 * 0.25 / np.sqrt(len(u)))
    assert values.std(ddof=1) == pytest.approx(0.25, rel=0.03)
    # The quantile at u is scipy's normal quantile.
    assert draw(quantity, 0.975) == pytest.approx(stats.norm(3.0, 0.25).ppf(0.975), rel=1e-12)


def test_corners_are_every_combination_once() -> None:
    quantities = [
        VariedQuantity(f"q{k}.v", "corners", low=float(k), high=float(k) + 0.5) for k in range(4)
    ]
    quantities.insert(2, VariedQuantity("r.v", "uniform", low=0.0, high=1.0))
    rows = corner_values(quantities)
    # One row at a time, as a case takes it, is the same row.
    assert all(corner_row(quantities, c) == rows[c].tolist() for c in range(len(rows)))
    expected = set(
        itertools.product(
            *[
                (q.low, q.high)
                for q in quantities
                if q.low is not None and q.distribution == "corners"
            ]
        )
    )
    assert rows.shape == (16, 4) and {tuple(r) for r in rows.tolist()} == expected


def test_a_corner_campaign_runs_every_combination_of_the_file(paper_data) -> None:
    entries = [
        {"path": "mass_kg", "distribution": "corners", "low": 600.0, "high": 700.0},
        {"path": "disturbance.amplitude_mNm[0]", "distribution": "corners"}
        | {"low": 0.2, "high": 2.0},
        {"path": "inertia_scale_z", "distribution": "corners", "low": 0.9, "high": 1.1},
    ]
    model = build_model(_problem(paper_data, *entries))
    problem = model.problem
    cases = varied_cases(model, samples=5, seed=1)  # no random quantity: one draw
    assert varied_count(problem, 5) == len(cases) == 8
    got = {tuple(v for _, v in c.varied) for c in cases}
    assert got == set(itertools.product((600.0, 700.0), (0.2, 2.0), (0.9, 1.1)))
    layout = model.parameter_layout
    for case in cases:
        named = dict(case.varied)
        # Model parameters go into the vector, by name; the file key waits for a rebuild.
        assert case.parameters[layout.index("mass_kg")] == named["mass_kg"]
        assert case.parameters[layout.index("inertia_scale_z")] == named["inertia_scale_z"]
        assert case.file_values == (
            ("disturbance.amplitude_mNm[0]", named["disturbance.amplitude_mNm[0]"]),
        )
        others = [n for n in layout.names if n not in ("mass_kg", "inertia_scale_z")]
        for name in others:
            assert (
                case.parameters[layout.index(name)] == model.nominal_parameters[layout.index(name)]
            )


def test_samples_are_seeded_bounded_and_independent_of_the_count(paper_data) -> None:
    entries = [
        {"path": "environment.density_kg_m3", "distribution": "uniform"}
        | {"low": 1e-13, "high": 5e-12},
        {"path": "mass_kg", "distribution": "normal", "mean": 668.0, "sigma": 30.0}
        | {"low": 640.0},
        {"path": "inertia_scale_x", "distribution": "corners", "low": 0.9, "high": 1.1},
    ]
    model = build_model(_problem(paper_data, *entries))
    cases = varied_cases(model, samples=6, seed=21)
    assert len(cases) == 12 and all(c.seed == 21 and c.kind == "varied" for c in cases)
    again = varied_cases(model, samples=6, seed=21)
    assert [c.varied for c in cases] == [c.varied for c in again]
    assert [c.varied for c in cases] != [c.varied for c in varied_cases(model, 6, 22)]
    # Case i alone is case i of any longer campaign: it re-runs from its index and seed.
    longer = varied_cases(model, samples=9, seed=21)
    assert [c.varied for c in longer[:12]] == [c.varied for c in cases]
    assert varied_case(model, 7, 21).varied == cases[7].varied
    values = np.array([[v for _, v in c.varied] for c in longer])
    assert np.all((values[:, 0] >= 1e-13) & (values[:, 0] <= 5e-12))
    assert np.all(values[:, 1] >= 640.0)
    # Both corners meet the same draws (common random numbers).
    assert np.array_equal(values[0::2, :2], values[1::2, :2])
    assert set(values[:, 2]) == {0.9, 1.1}


@pytest.mark.parametrize(
    ("entry", "field", "words"),
    [
        (
            {"path": "array3_angle_offset_rad", "distribution": "uniform", "low": 0.0, "high": 1.0},
            "montecarlo.vary[0].path",
            "not a parameter of this model",
        ),
        (
            {"path": "mass_kg", "distribution": "uniform", "low": -5.0, "high": 1.0},
            "montecarlo.vary[0].low",
            "positive",
        ),
    ],
)
def test_model_parameters_the_model_refuses_are_named(paper_data, entry, field, words) -> None:
    model = build_model(_problem(paper_data, entry))
    with pytest.raises(ProblemFileError, match=words) as caught:
        varied_cases(model, samples=2, seed=1)
    assert caught.value.field == field
