"""Aerodynamic and solar-pressure torques of single flat plates against hand-computed values."""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

from casadi_debris.environment import (
    Panel,
    aerodynamic_torque,
    debris_panels,
    solar_pressure_torque,
    sunlit,
)

PLATE = Panel("plate", 2.0, np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]))


def test_drag_on_one_plate_by_hand() -> None:
    # v = 7000 m/s at 60 deg from the normal: cos a = 0.5. |F| = 1/2 rho C_D v^2 A cos a
    # = 0.5 * 1e-12 * 2 * 4.9e7 * 2 * 0.5 = 4.9e-5 N, against the flow:
    # F = -4.9e-5 [0.5, 0, sqrt(3)/2] = [-2.45e-5, 0, -4.2435e-5] N, at c = [0, 1, 0] m:
    # c x F = [1 * Fz, 0, -1 * Fx] = [-4.2435e-5, 0, 2.45e-5] N m.
    velocity = 7000.0 * np.array([0.5, 0.0, math.sqrt(3) / 2])
    tau = aerodynamic_torque((PLATE,), velocity, density_kg_m3=1e-12, drag_coefficient=2.0)
    np.testing.assert_allclose(tau, [-4.9e-5 * math.sqrt(3) / 2, 0.0, 2.45e-5], rtol=1e-12)


def test_a_plate_facing_away_from_the_flow_feels_nothing() -> None:
    velocity = np.array([-7000.0, 100.0, 0.0])
    tau = aerodynamic_torque((PLATE,), velocity, density_kg_m3=1e-12, drag_coefficient=2.0)
    np.testing.assert_allclose(tau, 0.0, atol=0.0)


def test_solar_pressure_on_one_plate_by_hand() -> None:
    # Sun at 60 deg from the normal: cos b = 0.5; P = 4.56e-6, A = 2, rho_s = rho_d = 0.3.
    # F = -P A cos b [(1 - 0.3) s + 2 (0.3 * 0.5 + 0.1) n] = -4.56e-6 [0.7 s + 0.5 n]
    #   = -4.56e-6 [0.35 + 0.5, 0.7 sqrt(3)/2, 0] = [-3.876e-6, -2.764319e-6, 0] N.
    # At c = [0, 0, 1]: c x F = [-Fy, Fx, 0] = [2.764319e-6, -3.876e-6, 0] N m.
    plate = Panel("plate", 2.0, np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0]))
    sun = np.array([0.5, math.sqrt(3) / 2, 0.0])
    tau = solar_pressure_torque((plate,), sun, 4.56e-6, 0.3, 0.3)
    np.testing.assert_allclose(tau, [4.56e-6 * 0.7 * math.sqrt(3) / 2, -3.876e-6, 0.0], rtol=1e-12)


def test_a_black_plate_facing_the_sun_is_pushed_straight_away() -> None:
    # Absorbing, normal incidence: F = -P A s, the textbook value.
    plate = Panel("plate", 3.0, np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0]))
    tau = solar_pressure_torque((plate,), np.array([0.0, 0.0, 1.0]), 4.56e-6, 0.0, 0.0)
    force = np.array([0.0, 0.0, -3.0 * 4.56e-6])
    np.testing.assert_allclose(tau, np.cross([1.0, 0.0, 0.0], force), rtol=1e-14)


def test_no_sunlight_no_torque() -> None:
    sun = np.array([1.0, 0.0, 0.0])
    assert np.all(solar_pressure_torque((PLATE,), sun, 4.56e-6, 0.1, 0.2, sunlit=0.0) == 0.0)


def test_the_cylindrical_shadow() -> None:
    sun, earth = np.array([1.0, 0.0, 0.0]), 6.378e6
    assert sunlit(np.array([7e6, 0.0, 0.0]), sun, earth) == 1.0  # between Earth and Sun
    assert sunlit(np.array([-7e6, 0.0, 0.0]), sun, earth) == 0.0  # behind the Earth
    assert sunlit(np.array([-7e6, 6.3e6, 0.0]), sun, earth) == 0.0  # inside the cylinder
    assert sunlit(np.array([-7e6, 6.5e6, 0.0]), sun, earth) == 1.0  # outside it
    assert sunlit(np.array([0.0, 7e6, 0.0]), sun, earth) == 1.0  # terminator


def test_the_paper_debris_as_panels(problem, geometry) -> None:
    panels = debris_panels(problem, geometry)
    assert len(panels) == 6 + 2 * 2
    areas = {p.name: p.area_m2 for p in panels}
    # Hub 0.75 x 3 x 1 m; arrays 2.5 x 2 m.
    assert areas["hub +x"] == pytest.approx(3.0) and areas["hub -y"] == pytest.approx(0.75)
    assert areas["hub +z"] == pytest.approx(2.25) and areas["array 1 front"] == pytest.approx(5.0)
    for panel in panels:
        assert np.linalg.norm(panel.normal) == pytest.approx(1.0)
    # theta_SA = 0: the arrays' normals along +-x, their centres 1.25 m out from the hinges.
    front = next(p for p in panels if p.name == "array 2 front")
    np.testing.assert_allclose(front.normal, [1.0, 0.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(front.centre_m, geometry.hinges_m[1] + [0.0, 0.0, 1.25])


@pytest.mark.parametrize("kind", [ca.SX, ca.MX])
def test_numeric_and_symbolic_agree(problem, geometry, kind: type) -> None:
    angles = kind.sym("angles", 2)
    v, s = kind.sym("v", 3), kind.sym("s", 3)
    panels_sym = debris_panels(problem, geometry, [angles[0], angles[1]])
    f = ca.Function(
        "surface",
        [angles, v, s],
        [
            aerodynamic_torque(panels_sym, v, 1e-13, 2.2),
            solar_pressure_torque(panels_sym, s, 4.56e-6, 0.1, 0.2),
        ],
    )
    rng = np.random.default_rng(5)
    for _ in range(4):
        theta = rng.uniform(-math.pi, math.pi, 2)
        velocity = rng.normal(size=3) * 7000.0
        sun = rng.normal(size=3)
        sun /= np.linalg.norm(sun)
        panels = debris_panels(problem, geometry, list(theta))
        aero, srp = f(theta, velocity, sun)
        np.testing.assert_allclose(
            np.array(aero).ravel(), aerodynamic_torque(panels, velocity, 1e-13, 2.2), rtol=1e-12
        )
        np.testing.assert_allclose(
            np.array(srp).ravel(),
            solar_pressure_torque(panels, sun, 4.56e-6, 0.1, 0.2),
            rtol=1e-12,
        )
