"""The real-parametric model of the paper's uncertainty and its mu bounds.

Checked independently: the LFT closed over z reproduces the affine matrices;
the fit is exact at the nominal grid point against the CasADi linearisation;
the worst perturbation makes det(I - M Delta) vanish, its real blocks are real
scalars, lower <= upper, and the CasADi plant at the perturbation's parameters
reaches the predicted performance level at the predicted frequency.
"""

from __future__ import annotations

import dataclasses
import json

import control
import numpy as np
import pytest

from casadi_debris import load_problem
from casadi_debris.dynamics import build_model, linearize
from casadi_debris.robust.mu import (
    ParametricMu,
    ParametricMuSummary,
    ParametricPlant,
    fit_parametric_plant,
    parametric_closed_loop,
    parametric_mu,
)
from casadi_debris.robust.plant import (
    frequency_response,
    parameters_from_normalized,
    recorded_performance_weights,
)
from casadi_debris.workflows import load_controller


@pytest.fixture(scope="module")
def setting():
    problem = load_problem()
    record, _ = load_controller()
    weights = recorded_performance_weights(problem, record.details.get("weights", {}))
    model = build_model(problem, modes="all")
    return problem, model, record.reduced, weights


def test_the_lft_closed_over_z_is_the_affine_model(setting) -> None:
    _, model, _, _ = setting
    plant = fit_parametric_plant(model, 0.25)
    nominal = linearize(
        model,
        parameters_from_normalized(model, plant.fixed_normalized),
        sensor=True,
        units="deg_mNm",
    )
    assert np.allclose(plant.a0, nominal.A) and np.allclose(plant.b0, nominal.B)
    z = np.random.default_rng(3).uniform(-1, 1, len(plant.ranks))
    a, b = plant.matrices(z)
    system = plant.system()
    r = plant.n_real
    delta = np.diag(np.repeat(z, plant.ranks))
    # Upper LFT by hand: w = Delta q, q = C1 x + D12 u (D11 = 0).
    c1, d12 = system.C[:r], system.D[:r, r:]
    b1 = system.B[:, :r]
    assert np.allclose(system.A + b1 @ delta @ c1, a, atol=1e-9 * np.abs(a).max())
    assert np.allclose(system.B[:, r:] + b1 @ delta @ d12, b, atol=1e-9 * np.abs(b).max())
    assert 0 < plant.residual < 0.2


def _casadi_loop(problem, model, controller, weights, normalized) -> control.StateSpace:
    p = parameters_from_normalized(model, normalized)
    plant = linearize(model, p, sensor=True, units="deg_mNm")
    exact = ParametricPlant((), (), normalized, plant.A, plant.B, plant.C, (), (), 0.0)
    return parametric_closed_loop(exact, controller, weights)


@pytest.fixture(scope="module")
def one_angle(setting) -> ParametricMu:
    problem, _, controller, weights = setting
    omega = np.logspace(-3, 1, 12)
    return parametric_mu(problem, controller, weights, angles=1, omega=omega, lmi_points=1)


@pytest.mark.slow
def test_bounds_and_worst_perturbations_on_one_angle(setting, one_angle) -> None:
    problem, model, controller, weights = setting
    result = one_angle
    for bounds in (result.stability, result.performance):
        assert np.all(bounds.lower <= bounds.upper * (1 + 1e-6))
        assert 0 < bounds.peak_lower <= bounds.peak_upper
        worst = bounds.worst
        assert worst is not None and worst.determinant < 1e-6
        assert np.linalg.norm(worst.perturbation, 2) == pytest.approx(1 / worst.mu_lower, rel=1e-6)
        assert np.all(np.abs(worst.normalized) <= 1)
    # Robust stability: the destabilising parameters lie outside the box (the loop is
    # stable at every corner), so mu < 1 and the perturbation was clipped.
    assert result.stability.peak_upper < 1 and result.stability.worst.clipped
    # Robust performance at the worst real parameters, on the CasADi plant itself: the
    # performance channel's gain at the worst frequency reaches mu_lower (exactly so on
    # the fitted model; the fit's residual allows a few per cent).
    worst = result.performance.worst
    loop = _casadi_loop(problem, model, controller, weights, worst.normalized_unclipped)
    gain = np.linalg.norm(frequency_response(loop, np.array([worst.omega_rad_s]))[0], 2)
    assert gain == pytest.approx(worst.mu_lower, rel=0.05)


# The keys ``worstcase``'s summary.json holds under "mu": scripts read them, so they stay.
SUMMARY_KEYS = {
    "real_parameters", "real_block_sizes", "array_angles_deg", "frequencies", "fit_residual",
    "analysis_plant_modes", "seed", "time_s", "stability", "performance",
}  # fmt: skip
BOUNDS_KEYS = {"mu_upper", "mu_lower", "gap", "margin_upper", "margin_lower", "lmi_points"}
WORST_KEYS = {
    "omega_rad_s", "array_angle_deg", "determinant", "clipped", "normalized_unclipped",
    "normalized",
}  # fmt: skip


@pytest.mark.slow
def test_the_summary_keeps_its_keys_and_reads_back(one_angle) -> None:
    result = one_angle
    summary = result.summary()
    data = json.loads(json.dumps(summary.to_json()))
    assert set(data) == SUMMARY_KEYS and data["frequencies"] == 12
    assert ParametricMuSummary.from_json(data) == summary
    for kind in ("stability", "performance"):
        bounds, entry = getattr(result, kind), data[kind]
        assert set(entry) == BOUNDS_KEYS | {"worst"} and set(entry["worst"]) == WORST_KEYS
        # The figures from the grids themselves.
        upper, lower = float(np.max(bounds.upper)), float(np.max(bounds.lower))
        assert entry["mu_upper"] == upper and entry["mu_lower"] == lower
        assert entry["gap"] == pytest.approx((upper - lower) / upper, rel=1e-12)
        assert entry["margin_upper"] * upper == pytest.approx(1.0, rel=1e-12)
        assert entry["margin_lower"] * lower == pytest.approx(1.0, rel=1e-12)
        worst = bounds.worst
        assert list(entry["worst"]["normalized"]) == list(result.parameter_names)
        assert list(entry["worst"]["normalized"].values()) == worst.normalized.tolist()
        assert entry["worst"]["clipped"] == bool(np.any(np.abs(worst.normalized_unclipped) > 1))
        assert entry["worst"]["array_angle_deg"] == result.angle_deg[worst.angle_index]
    # A structure without a perturbation writes no "worst" key and reads back as None.
    bare = dataclasses.replace(result.stability, worst=None)
    data["stability"] = dataclasses.replace(result, stability=bare).summary().to_json()["stability"]
    assert "worst" not in data["stability"]
    assert ParametricMuSummary.from_json(data).stability.worst is None
