"""The dipole field at the equator and the pole, against the magnetic-moment formula, and m x B."""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

from casadi_debris.environment import (
    EARTH_ROTATION_RAD_S,
    dipole_axis,
    dipole_field_T,
    magnetic_torque,
)

MU0 = 4e-7 * math.pi
EARTH = 6.378137e6
B0 = 2.98e-5
R = EARTH + 685e3


def _moment_formula(r: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """B = mu0 / (4 pi) [3 r_hat (m . r_hat) - m] / r^3 with the Earth's moment m = -M k,
    M = 4 pi B0 R^3 / mu0 (a field B0 at the equator's surface)."""
    moment = -4 * math.pi * B0 * EARTH**3 / MU0 * axis
    radius = np.linalg.norm(r)
    r_hat = r / radius
    return MU0 / (4 * math.pi) * (3 * r_hat * (moment @ r_hat) - moment) / radius**3


def test_aligned_dipole_at_the_equator_and_the_pole() -> None:
    north = np.array([0.0, 0.0, 1.0])
    scale = B0 * (EARTH / R) ** 3  # 2.98e-5 * (6378.137 / 7063.137)^3 = 2.1944e-5 T
    assert scale == pytest.approx(2.1944e-5, rel=1e-4)
    # Equator: horizontal, pointing north, B0 (R_E / r)^3.
    np.testing.assert_allclose(
        dipole_field_T(np.array([R, 0.0, 0.0]), north, B0, EARTH), [0, 0, scale], atol=1e-20
    )
    # North pole: vertical, into the Earth, twice as strong.
    np.testing.assert_allclose(
        dipole_field_T(np.array([0.0, 0.0, R]), north, B0, EARTH), [0, 0, -2 * scale], atol=1e-20
    )


def test_tilted_dipole_anywhere_matches_the_moment_formula() -> None:
    rng = np.random.default_rng(11)
    for _ in range(10):
        axis = dipole_axis(rng.uniform(0, 86400), math.radians(9.41), math.radians(-72.68))
        r = rng.normal(size=3)
        r *= rng.uniform(6.6e6, 8e6) / np.linalg.norm(r)
        np.testing.assert_allclose(
            dipole_field_T(r, axis, B0, EARTH), _moment_formula(r, axis), rtol=1e-12
        )


def test_the_dipole_turns_with_the_earth() -> None:
    tilt, longitude = math.radians(10.0), math.radians(-70.0)
    quarter_day = 0.5 * math.pi / EARTH_ROTATION_RAD_S
    k0, k1 = dipole_axis(0.0, tilt, longitude), dipole_axis(quarter_day, tilt, longitude)
    assert math.degrees(math.atan2(k0[1], k0[0])) == pytest.approx(-70.0)
    assert math.degrees(math.atan2(k1[1], k1[0])) == pytest.approx(20.0)
    assert math.degrees(math.acos(k1[2])) == pytest.approx(10.0)


def test_torque_is_m_cross_b_by_hand() -> None:
    # m = 1 A m^2 along x in a field B along z: m x B = [0, -B, 0].
    field = np.array([0.0, 0.0, 3.0e-5])
    np.testing.assert_allclose(magnetic_torque(np.array([1.0, 0.0, 0.0]), field), [0, -3e-5, 0])
    # Along the field: none.
    np.testing.assert_allclose(magnetic_torque(np.array([0.0, 0.0, 2.0]), field), 0.0)


def test_numeric_and_symbolic_agree() -> None:
    r, t, m = ca.SX.sym("r", 3), ca.SX.sym("t"), ca.SX.sym("m", 3)
    axis = dipole_axis(t, 0.2, -1.2, 0.4)
    f = ca.Function("mag", [r, t, m], [magnetic_torque(m, dipole_field_T(r, axis, B0, EARTH))])
    position, time, dipole = np.array([3e6, -5e6, 4e6]), 1234.0, np.array([0.3, -1.0, 2.0])
    numeric = magnetic_torque(
        dipole, dipole_field_T(position, dipole_axis(time, 0.2, -1.2, 0.4), B0, EARTH)
    )
    np.testing.assert_allclose(np.array(f(position, time, dipole)).ravel(), numeric, rtol=1e-13)
