"""The circular orbit against an independent Keplerian propagation and textbook formulas."""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from casadi_debris.environment import CircularOrbit

MU = 3.986004418e14
RADIUS = (6378.137 + 685.0) * 1e3


@pytest.fixture(scope="module")
def orbit() -> CircularOrbit:
    return CircularOrbit(
        radius_m=RADIUS,
        inclination_rad=math.radians(98.1),
        raan_rad=math.radians(40.0),
        argument_of_latitude_rad=math.radians(25.0),
        mu_m3_s2=MU,
    )


def _elements_to_position(a: float, inc: float, raan: float, u: float) -> np.ndarray:
    """Vallado's classical elements to position for a circle (written out, no matrices)."""
    return a * np.array(
        [
            math.cos(raan) * math.cos(u) - math.sin(raan) * math.sin(u) * math.cos(inc),
            math.sin(raan) * math.cos(u) + math.cos(raan) * math.sin(u) * math.cos(inc),
            math.sin(u) * math.sin(inc),
        ]
    )


def test_the_paper_orbit_lasts_98_5_minutes() -> None:
    # 685 km: the paper's 98.5 min (its disturbance period), 2 pi sqrt(a^3 / mu) by hand.
    orbit = CircularOrbit(radius_m=RADIUS, inclination_rad=math.radians(98.1), mu_m3_s2=MU)
    assert orbit.period_s == pytest.approx(2 * math.pi * math.sqrt(RADIUS**3 / MU), rel=1e-14)
    assert orbit.period_s / 60.0 == pytest.approx(98.5, abs=0.05)


def test_position_matches_the_classical_elements(orbit: CircularOrbit) -> None:
    n = math.sqrt(MU / RADIUS**3)
    for t in (0.0, 600.0, 0.25 * orbit.period_s, 4321.0):
        expected = _elements_to_position(
            RADIUS, math.radians(98.1), math.radians(40.0), math.radians(25.0) + n * t
        )
        np.testing.assert_allclose(orbit.position_m(t), expected, rtol=0, atol=1e-6)


def test_against_a_numerically_integrated_two_body_orbit(orbit: CircularOrbit) -> None:
    def two_body(_t: float, y: np.ndarray) -> np.ndarray:
        r = y[:3]
        return np.concatenate([y[3:], -MU * r / np.linalg.norm(r) ** 3])

    quarter = 0.25 * orbit.period_s
    start = np.concatenate([orbit.position_m(0.0), orbit.velocity_m_s(0.0)])
    times = np.linspace(0.0, quarter, 5)
    solution = solve_ivp(
        two_body, (0.0, quarter), start, t_eval=times, rtol=1e-12, atol=1e-6, method="DOP853"
    )
    np.testing.assert_allclose(solution.y[:3].T, orbit.position_m(times), atol=1e-2)
    np.testing.assert_allclose(solution.y[3:].T, orbit.velocity_m_s(times), atol=1e-5)


def test_energy_and_angular_momentum_are_those_of_a_circle(orbit: CircularOrbit) -> None:
    times = np.linspace(0.0, orbit.period_s, 17)
    r, v = orbit.position_m(times), orbit.velocity_m_s(times)
    energy = 0.5 * np.sum(v**2, axis=1) - MU / np.linalg.norm(r, axis=1)
    np.testing.assert_allclose(energy, -MU / (2 * RADIUS), rtol=1e-12)
    h = np.cross(r, v)
    np.testing.assert_allclose(
        h, np.tile(math.sqrt(MU * RADIUS) * orbit.normal, (17, 1)), rtol=1e-9
    )
    # The normal's inclination and node.
    assert math.degrees(math.acos(orbit.normal[2])) == pytest.approx(98.1)
    node = np.cross([0.0, 0.0, 1.0], orbit.normal)
    assert math.degrees(math.atan2(node[1], node[0])) == pytest.approx(40.0)


def test_a_quarter_period_later_the_debris_is_a_quarter_turn_on(orbit: CircularOrbit) -> None:
    r0, r1 = orbit.position_m(0.0), orbit.position_m(0.25 * orbit.period_s)
    assert float(r0 @ r1) / RADIUS**2 == pytest.approx(0.0, abs=1e-14)
    # Turning about the orbit normal: r0 x r1 along +normal.
    np.testing.assert_allclose(np.cross(r0, r1) / RADIUS**2, orbit.normal, atol=1e-12)


def test_lvlh_axes(orbit: CircularOrbit) -> None:
    for t in (0.0, 1234.5):
        c_on = orbit.lvlh_matrix(t)
        np.testing.assert_allclose(c_on @ c_on.T, np.eye(3), atol=1e-14)
        assert np.linalg.det(c_on) == pytest.approx(1.0)
        r, v = orbit.position_m(t), orbit.velocity_m_s(t)
        np.testing.assert_allclose(c_on[2], -r / np.linalg.norm(r), atol=1e-14)
        np.testing.assert_allclose(c_on[0], v / np.linalg.norm(v), atol=1e-12)


def test_symbolic_time_gives_the_same_orbit(orbit: CircularOrbit) -> None:
    t = ca.SX.sym("t")
    f = ca.Function("rv", [t], [orbit.position_m(t), orbit.velocity_m_s(t)])
    for time in (0.0, 2000.0):
        r, v = f(time)
        np.testing.assert_allclose(np.array(r).ravel(), orbit.position_m(time), rtol=1e-14)
        np.testing.assert_allclose(np.array(v).ravel(), orbit.velocity_m_s(time), rtol=1e-14)
