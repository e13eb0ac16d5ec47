"""mu-synthesis against the real-parametric model, scored by the mixed bound.

Checked independently: the mixed and complex bounds the synthesis reports are
recomputed by ``mu_bounds`` on the closed loop formed another way (the
generalised plant closed by an LFT, not the interconnection with the
controller inside); the kept controller stabilises the CasADi model's own
linearisation; it is never worse, by the mixed bound, than the controller the
iteration started from.
"""

from __future__ import annotations

import control
import numpy as np
import pytest

from casadi_debris import load_problem
from casadi_debris.dynamics import build_model, linearize
from casadi_debris.robust.mu import (
    N_PERFORMANCE,
    fit_parametric_plant,
    mu_bounds,
    parametric_generalized_plant,
)
from casadi_debris.robust.plant import frequency_response, recorded_performance_weights
from casadi_debris.robust.synthesis import mixed_bound, parametric_musyn
from casadi_debris.workflows import load_controller

OMEGA = np.logspace(-4, 2, 25)


@pytest.fixture(scope="module")
def setting():
    problem = load_problem()
    record, _ = load_controller()
    weights = recorded_performance_weights(problem, record.details.get("weights", {}))
    return problem, record.reduced, weights


def recomputed(plant, controller, weights, indices) -> tuple[np.ndarray, np.ndarray]:
    """Complex bound on OMEGA and mixed upper bound at ``indices``, by mu_bounds on
    the generalised plant closed by an LFT."""
    closed = parametric_generalized_plant(plant, weights).lft(controller, 3, 3)
    responses = frequency_response(closed, OMEGA)
    scalars = [("complex", 1)] * plant.n_real + [("complex", N_PERFORMANCE)]
    complex_bound = mu_bounds(responses, scalars, upper="ab13md", restarts=0).upper
    structure = [*plant.blocks, ("complex", N_PERFORMANCE)]
    mixed = mu_bounds(responses[indices], structure, upper="ab13md")
    assert np.all(mixed.lower <= mixed.upper * (1 + 1e-6))
    return complex_bound, mixed.upper


def stabilises_casadi_plant(problem, controller) -> bool:
    plant = linearize(build_model(problem, modes="first"), sensor=True, units="deg_mNm")
    loop = control.feedback(plant * controller, np.eye(3))
    return bool(np.max(np.linalg.eigvals(loop.A).real) < 0)


@pytest.mark.slow
def test_mixed_bound_of_the_shipped_controller_recomputed(setting) -> None:
    problem, controller, weights = setting
    plant = fit_parametric_plant(build_model(problem, modes="first"), 0.0)
    mu_complex, mu_mixed, indices = mixed_bound(plant, controller, weights, OMEGA, points=2)
    complex_bound, mixed = recomputed(plant, controller, weights, indices)
    assert np.allclose(mu_complex, complex_bound, rtol=1e-6)
    assert np.allclose(mu_mixed, mixed, rtol=1e-6)
    # real scalars are a subset of complex ones: the mixed bound is never above
    assert np.all(mu_mixed <= mu_complex[indices] * (1 + 1e-9))


@pytest.mark.slow
def test_parametric_musyn_reports_what_mu_bounds_recomputes(setting) -> None:
    problem, controller, weights = setting
    result = parametric_musyn(
        problem, weights, controller, omega=OMEGA, d_orders=(1,), max_iterations=1, mixed_points=2
    )
    assert len(result.mu_mixed_per_iteration) == len(result.musyn.iterations)
    assert result.mu_peak == pytest.approx(min(result.mu_mixed_per_iteration), rel=1e-12)
    assert result.mu_peak <= result.mu_mixed_per_iteration[0]
    complex_bound, mixed = recomputed(
        result.plant, result.controller, weights, result.mixed_indices
    )
    bound = complex_bound.copy()
    bound[result.mixed_indices] = np.minimum(bound[result.mixed_indices], mixed)
    assert float(np.max(bound)) == pytest.approx(result.mu_peak, rel=1e-6)
    assert stabilises_casadi_plant(problem, result.controller)
