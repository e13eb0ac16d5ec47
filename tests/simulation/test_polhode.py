"""Polhodes against a numerical integration of the torque-free Euler equations, and their
averages against a loop written out point by point."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from casadi_debris.simulation.detumble import PrincipalBody, polhode_averages, polhode_points

INERTIA = np.array([[677.3, 1.2, 2.0], [1.2, 450.8, -1.0], [2.0, -1.0, 291.0]])


@pytest.fixture(scope="module")
def body() -> PrincipalBody:
    return PrincipalBody.from_inertia(INERTIA)


def _time_average(body: PrincipalBody, start: np.ndarray, values) -> np.ndarray:
    """Mean of ``values(m)`` over one period of ``m' = m x (J^-1 m)``, from an ODE solver."""
    a = body.inverse_moments

    def crossing(_t, m):
        return m[1]

    crossing.direction = 1.0
    solution = solve_ivp(
        lambda _t, m: np.cross(m, a * m),
        (0.0, 6e4),
        start,
        method="DOP853",
        rtol=1e-11,
        atol=1e-13,
        events=crossing,
        dense_output=True,
    )
    first, second = solution.t_events[0][:2]
    times = np.linspace(first, second, 20001)[:-1]
    return np.mean(values(solution.sol(times).T), axis=0)


@pytest.mark.parametrize("fraction", [0.05, 0.4, 0.45, 0.55, 0.7, 0.97])
def test_equal_steps_of_the_points_are_equal_steps_of_time(body, fraction) -> None:
    """Both families (around the largest and the smallest axis) against the ODE's time mean."""
    a1, a2, a3 = body.inverse_moments
    label = a3 + fraction * (a1 - a3)
    assert (label < a2) == (fraction < (a2 - a3) / (a1 - a3))
    points = polhode_points(body, label, 4000)
    np.testing.assert_allclose(np.linalg.norm(points, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(np.einsum("ij,j,ij->i", points, body.inverse_moments, points), label)

    def values(m: np.ndarray) -> np.ndarray:
        return np.stack([m[:, 0] ** 2, m[:, 1] ** 2, m[:, 0] ** 2 * m[:, 2] ** 2, m[:, 1] ** 4], 1)

    expected = _time_average(body, points[7], values)
    np.testing.assert_allclose(np.mean(values(points), axis=0), expected, rtol=1e-5, atol=1e-9)


def test_an_axisymmetric_body_has_circular_polhodes() -> None:
    body = PrincipalBody.from_inertia(np.diag([300.0, 300.0, 500.0]))
    label = 0.8 / 300.0 + 0.2 / 500.0
    points = polhode_points(body, label, 64)
    np.testing.assert_allclose(points[:, 2] ** 2, 0.2, rtol=1e-12)
    assert not body.spherical and PrincipalBody.from_inertia(np.eye(3) * 400.0).spherical


def test_the_averages_are_the_mean_of_the_vertex_each_point_picks(body) -> None:
    rng = np.random.default_rng(3)
    vertices = rng.normal(size=(12, 3))
    vertices = np.vstack([vertices, -vertices]) * 1e-3
    fuel = rng.uniform(1e-7, 2e-7, len(vertices))
    a1, _, a3 = body.inverse_moments
    labels, angles = np.array([a3 + 0.3 * (a1 - a3), a3 + 0.8 * (a1 - a3)]), np.array([-0.5, 0.2])
    table = polhode_averages(body, vertices, fuel, labels=labels, angles=angles, n_phase=300)
    for i, label in enumerate(labels):
        points = polhode_points(body, label, 300)
        for j, angle in enumerate(angles):
            brake, drift, flow = [], [], []
            for m in points:
                steer = m * body.inverse_moments - label * m
                w = np.cos(angle) * m + np.sin(angle) * steer / (a1 - a3)
                best = min(range(len(vertices)), key=lambda k, w=w: float(w @ vertices[k]))
                brake.append(m @ vertices[best])
                drift.append(2.0 * steer @ vertices[best])
                flow.append(fuel[best])
            assert table.braking_Nm[i, j] == pytest.approx(np.mean(brake), rel=1e-12)
            assert table.drift_Nm_per_kgm2[i, j] == pytest.approx(np.mean(drift), rel=1e-10)
            assert table.fuel_kg_s[i, j] == pytest.approx(np.mean(flow), rel=1e-12)
