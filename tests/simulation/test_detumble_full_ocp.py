"""The full transcription of the time-optimal detumble: a spherical body against the
exact answer, and the paper's body at a small tumble against the averaged OCP."""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest

from casadi_debris import load_problem
from casadi_debris.allocation import Allocator
from casadi_debris.geometry import build_geometry
from casadi_debris.simulation.detumble import (
    full_time_optimal_detumble,
    problem_time_optimal_detumble,
)
from casadi_debris.workflows import momentum_bound_s


@pytest.fixture(scope="module")
def problem():
    return load_problem()


@pytest.fixture(scope="module")
def polytope(problem):
    return Allocator.from_problem(problem).authority_polytope()


def _least_time_without_precession(vertices: np.ndarray, momentum0: np.ndarray, h_end: float):
    """min T with H0 + T tau_mean in the ball |H| <= h_end, tau_mean in the polytope: with
    d = T c (c the weights of the vertices), min sum d s.t. |H0 + V^T d| <= h_end, an SOCP."""
    weights = cp.Variable(len(vertices), nonneg=True)
    final = momentum0 + vertices.T @ weights
    problem = cp.Problem(cp.Minimize(cp.sum(weights)), [cp.norm(final) <= h_end])
    problem.solve(solver=cp.CLARABEL)
    return float(problem.value)


def test_a_spherical_body_brakes_along_minus_its_momentum(polytope) -> None:
    """No precession (omega parallel to H): only the torque's mean over the manoeuvre
    counts, and it lies in the polytope; with a point as the target the time would be
    |H0| over the largest torque along -H0."""
    inertia = np.eye(3) * 400.0
    rate0 = np.array([0.01, -0.02, 0.015])
    momentum0 = inertia @ rate0
    h_end = 1e-3
    solved = full_time_optimal_detumble(
        inertia,
        polytope.normals,
        polytope.offsets,
        polytope.vertices,
        rate0,
        h_end,
        n_intervals=20,
    )
    exact = _least_time_without_precession(polytope.vertices, momentum0, h_end)
    assert solved.solver_status == "Solve_Succeeded"
    # IPOPT's tolerance lets the torque pass its facets by about 1e-8 N m (of 5e-3).
    assert solved.time_s == pytest.approx(exact, rel=1e-5)
    assert solved.time_s <= solved.greedy_time_s


@pytest.mark.slow
def test_at_a_small_tumble_the_full_and_the_averaged_optimum_agree(problem, polytope) -> None:
    """0.02 rad/s: the rates precess a few times, the averaging error is about 1 %."""
    rate0 = np.array([0.02, 0.02, 0.02])
    averaged = problem_time_optimal_detumble(problem, rate0, 1e-4).summary
    solved = full_time_optimal_detumble(
        build_geometry(problem).inertia_total_kgm2,
        polytope.normals,
        polytope.offsets,
        polytope.vertices,
        rate0,
        averaged.final_momentum_Nms,
        n_intervals=150,
    )
    assert momentum_bound_s(problem, rate0) < solved.time_s < solved.greedy_time_s
    assert solved.time_s == pytest.approx(averaged.time_s, rel=0.02)
