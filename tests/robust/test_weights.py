"""Performance weights against the paper's formulas; the W fit covers every sample."""

from __future__ import annotations

import numpy as np
import pytest

from casadi_debris.robust.plant import (
    fit_uncertainty_weight,
    frequency_response,
    performance_weights,
    second_order_magnitude,
)


def test_error_and_effort_weights(problem):
    weights = performance_weights(problem)
    w = problem.weights
    low, high = np.array([1e-9]), np.array([1e9])
    we_dc = frequency_response(weights.error, low)[0]
    we_hf = frequency_response(weights.error, high)[0]
    np.testing.assert_allclose(np.abs(we_dc), np.eye(3) / w.epsilon, rtol=1e-6)
    np.testing.assert_allclose(np.abs(we_hf), 0.5 * np.eye(3), rtol=1e-6)
    wu_dc = frequency_response(weights.control_effort, low)[0]
    wu_hf = frequency_response(weights.control_effort, high)[0]
    np.testing.assert_allclose(np.abs(wu_dc), np.eye(3), rtol=1e-6)
    np.testing.assert_allclose(np.abs(wu_hf), np.eye(3) / 0.01, rtol=1e-6)
    np.testing.assert_array_equal(np.diag(weights.control_scaling), [4.61, 1.96, 4.26])


@pytest.fixture(scope="module")
def bumpy_bound():
    omega = np.logspace(-2, 2, 400)
    # a low plateau, a resonant bump near 6 rad/s, a high-frequency plateau
    bump = 40.0 / np.sqrt((1 - (omega / 6.0) ** 2) ** 2 + (0.2 * omega / 6.0) ** 2)
    bound = np.stack(
        [
            0.1 + bump * (omega / 6) ** 2 / (1 + (omega / 6) ** 2),
            0.2 + 0 * omega,
            0.05 + 0.01 * omega,
        ],
        axis=1,
    )
    return omega, bound


def test_fit_covers_every_point_and_is_stable_minimum_phase(bumpy_bound):
    omega, bound = bumpy_bound
    weight = fit_uncertainty_weight(omega, bound)
    assert np.all(weight.coefficients > 0)  # => poles and zeros in the open left half plane
    assert np.all(np.linalg.eigvals(weight.system.A).real < 0)
    response = np.abs(np.diagonal(frequency_response(weight.system, omega), axis1=1, axis2=2))
    assert np.all(response >= bound * (1 - 1e-9))
    np.testing.assert_allclose(weight.margin, (response / bound).min(axis=0), rtol=1e-9)
    for i, c in enumerate(weight.coefficients):
        np.testing.assert_allclose(second_order_magnitude(c, omega), response[:, i], rtol=1e-9)
    # tight: somewhere the weight touches the bound
    assert np.all(weight.margin < 1.01)


def test_flat_bound_gives_a_static_weight_without_states():
    # A rigid debris' inertia and mass errors do not depend on frequency: the
    # constant cover is exact, and a second-order fit could only add poles at 0 rad/s.
    omega = np.logspace(-3, 2, 300)
    levels = np.array([0.205, 0.21, 0.19])
    weight = fit_uncertainty_weight(omega, np.tile(levels, (len(omega), 1)))
    assert weight.system.nstates == 0
    np.testing.assert_allclose(np.diag(weight.system.D), levels, rtol=1e-12)
    np.testing.assert_allclose(weight.margin, 1.0, rtol=1e-12)


def test_fitted_poles_and_zeros_stay_on_the_grid(bumpy_bound):
    omega, bound = bumpy_bound
    weight = fit_uncertainty_weight(omega, bound)
    for _, wz, _, wp, _ in weight.coefficients:
        assert omega[0] <= wz <= omega[-1]
        assert omega[0] <= wp <= omega[-1]
