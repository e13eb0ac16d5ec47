"""Uncertainty sampling and relative errors, checked against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from casadi_debris.dynamics import build_model, linearize
from casadi_debris.robust.plant import (
    box_corners,
    diagonal_cover,
    relative_errors,
    sample_uncertainty,
)


@pytest.fixture(scope="module")
def first_mode_model(problem):
    return build_model(problem, modes="first")


def test_corners_first_and_seeded(problem, first_mode_model):
    a = sample_uncertainty(first_mode_model, count=80, seed=3)
    b = sample_uncertainty(first_mode_model, count=80, seed=3)
    c = sample_uncertainty(first_mode_model, count=80, seed=4)
    assert a.n_corners == 64 and len(a.parameters) == 80
    np.testing.assert_array_equal(a.normalized[:64], box_corners(6))
    np.testing.assert_array_equal(a.parameters, b.parameters)
    assert not np.allclose(a.parameters[64:], c.parameters[64:])
    assert a.seed == 3


def test_parameter_ranges(problem, first_mode_model):
    samples = sample_uncertainty(first_mode_model)
    p, nominal = samples.parameters, first_mode_model.nominal_parameters
    assert len(p) == problem.uncertainty.samples == 200
    assert np.allclose(p[:, 0:3].min(), 0.83) and np.allclose(p[:, 0:3].max(), 1.17)
    assert np.allclose(p[:, 3].min() / nominal[3], 0.8) and np.allclose(
        p[:, 3].max() / nominal[3], 1.2
    )
    assert np.allclose(np.abs(p[:, 4] - nominal[4]).max(), np.pi)
    # The first bending frequency as a factor on the problem's 5.6 rad/s.
    assert np.allclose(p[:, 5].min(), 0.8) and np.allclose(p[:, 5].max(), 1.2)


def test_rigid_relative_error_is_inertia_ratio(problem):
    # Rigid body: P = J^-1 / s^2 (times the unit change), so P_c^-1 P_k - I = J_c J_k^-1 - I.
    rigid = build_model(problem, modes=[])
    p = rigid.parameters(inertia_scale_x=1.17, inertia_scale_z=0.83)
    errors = relative_errors(rigid, p[None, :], np.array([1e-3, 0.1, 10.0]))
    j_c = np.array(rigid.rigid_inertia(rigid.nominal_parameters))
    j_k = np.array(rigid.rigid_inertia(p))
    for e in errors[0]:
        np.testing.assert_allclose(e, j_c @ np.linalg.inv(j_k) - np.eye(3), atol=1e-9)


def test_flexible_relative_error_matches_python_control(problem, first_mode_model):
    # An independent evaluation: python-control's frequency response of the same plants.
    samples = sample_uncertainty(first_mode_model, count=68, seed=1)
    omega = np.logspace(-3, 2, 40)
    errors = relative_errors(first_mode_model, samples.parameters[-4:], omega)

    def response(parameters):
        plant = linearize(first_mode_model, parameters, units="deg_mNm")
        return np.moveaxis(plant.frequency_response(omega).frdata, 2, 0)

    nominal = response(None)
    for e, p in zip(errors, samples.parameters[-4:], strict=True):
        expected = np.linalg.solve(nominal, response(p)) - np.eye(3)
        np.testing.assert_allclose(e, expected, atol=1e-9 * np.abs(expected).max())


def test_nominal_has_zero_error(first_mode_model):
    errors = relative_errors(
        first_mode_model, first_mode_model.nominal_parameters[None, :], np.logspace(-2, 1, 20)
    )
    assert np.max(np.abs(errors)) < 1e-9


def test_diagonal_cover_bounds_every_sample():
    rng = np.random.default_rng(0)
    errors = rng.normal(size=(30, 5, 3, 3)) + 1j * rng.normal(size=(30, 5, 3, 3))
    bound = diagonal_cover(errors)
    scaled = errors / bound[None, :, :, None]
    sigma = np.linalg.norm(scaled, ord=2, axis=(2, 3))
    assert sigma.max() <= 1 + 1e-12
    # and not loose: the worst sample reaches at least 1/sqrt(3) of the bound
    assert np.all(sigma.max(axis=0) >= 1 / np.sqrt(3) - 1e-12)
