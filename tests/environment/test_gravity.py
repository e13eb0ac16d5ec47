"""The gravity-gradient torque: the LVLH formula, a hand-computed case, numeric = symbolic."""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from casadi_debris.environment import CircularOrbit, gravity_gradient_torque

MU = 3.986004418e14


def test_a_principal_axis_body_pitched_45_degrees_by_hand() -> None:
    # LVLH: the body's z along nadir, then pitched 45 deg about y. Nadir in body axes is
    # o3 = [-s, 0, c] (s = c = sqrt(1/2)); with I = diag(100, 200, 300) kg m^2,
    # I o3 = [-100 s, 0, 300 c] and o3 x I o3 = [0, -100 s c + 300 s c, 0] = [0, 100, 0].
    # At r = 7000 km, 3 mu / r^3 = 3 * 3.986004418e14 / 3.43e20 = 3.486301e-6 1/s^2:
    # tau = [0, 3.486301e-4, 0] N m.
    inertia = np.diag([100.0, 200.0, 300.0])
    r_body = -7.0e6 * np.array([-math.sqrt(0.5), 0.0, math.sqrt(0.5)])
    tau = gravity_gradient_torque(inertia, r_body)
    np.testing.assert_allclose(tau, [0.0, 3.486301240e-4, 0.0], rtol=1e-9, atol=1e-18)
    # The textbook pitch equation: tau_y = 3/2 n^2 (I_z - I_x) sin(2 theta), n^2 = mu / r^3.
    assert tau[1] == pytest.approx(1.5 * MU / 7.0e6**3 * (300.0 - 100.0) * math.sin(math.pi / 2))


def test_against_the_lvlh_formula_for_any_attitude_and_inertia() -> None:
    rng = np.random.default_rng(7)
    orbit = CircularOrbit(radius_m=7.063137e6, inclination_rad=math.radians(98.1), raan_rad=0.3)
    for _ in range(20):
        t = rng.uniform(0.0, orbit.period_s)
        attitude = Rotation.random(random_state=rng)  # takes body components to inertial
        a = rng.normal(size=(3, 3))
        inertia = a @ a.T + 50.0 * np.eye(3)
        r_n = orbit.position_m(t)
        r_b = attitude.inv().apply(r_n)
        o3 = attitude.inv().apply(orbit.lvlh_matrix(t)[2])  # nadir, body axes
        expected = 3 * MU / np.linalg.norm(r_n) ** 3 * np.cross(o3, inertia @ o3)
        np.testing.assert_allclose(
            gravity_gradient_torque(inertia, r_b), expected, rtol=1e-10, atol=1e-15
        )


def test_no_torque_along_a_principal_axis() -> None:
    inertia = np.diag([100.0, 200.0, 300.0])
    for axis in np.eye(3):
        np.testing.assert_allclose(gravity_gradient_torque(inertia, 7e6 * axis), 0.0, atol=1e-18)


@pytest.mark.parametrize("kind", [ca.SX, ca.MX])
def test_numeric_and_symbolic_agree(kind: type) -> None:
    rng = np.random.default_rng(3)
    inertia_sym, r_sym = kind.sym("J", 3, 3), kind.sym("r", 3)
    function = ca.Function(
        "gg", [inertia_sym, r_sym], [gravity_gradient_torque(inertia_sym, r_sym)]
    )
    for _ in range(5):
        a = rng.normal(size=(3, 3))
        inertia = a @ a.T + np.eye(3)
        r = rng.normal(size=3) * 7e6
        np.testing.assert_allclose(
            np.array(function(inertia, r)).ravel(),
            gravity_gradient_torque(inertia, r),
            rtol=1e-13,
        )
