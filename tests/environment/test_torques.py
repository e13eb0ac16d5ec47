"""A problem's environment torques together: numeric = CasADi, switches, sizes at 685 km."""

from __future__ import annotations

import dataclasses

import casadi as ca
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from casadi_debris.config import ENVIRONMENT_TORQUES
from casadi_debris.environment import EnvironmentTorques, gravity_gradient_torque


@pytest.fixture(scope="module")
def every_torque(problem, geometry) -> EnvironmentTorques:
    settings = dataclasses.replace(problem.environment, torques=ENVIRONMENT_TORQUES)
    return EnvironmentTorques.of(dataclasses.replace(problem, environment=settings), geometry)


def test_the_paper_has_none(problem, geometry) -> None:
    environment = EnvironmentTorques.of(problem, geometry)
    assert not environment.active
    total = environment.total(100.0, np.eye(3), geometry.inertia_total_kgm2)
    assert np.all(total == 0.0)


def test_numeric_and_compiled_function_agree(every_torque: EnvironmentTorques, geometry) -> None:
    function = every_torque.function()
    rng = np.random.default_rng(2)
    inertia = geometry.inertia_total_kgm2
    for t in rng.uniform(0.0, 2 * every_torque.orbit.period_s, 6):
        dcm = Rotation.random(random_state=rng).as_matrix()
        angles = rng.uniform(-3.0, 3.0, 2)
        numeric = every_torque.torques(t, dcm, inertia, list(angles))
        assert set(numeric) == set(ENVIRONMENT_TORQUES)
        np.testing.assert_allclose(
            np.array(function(t, dcm, inertia, angles)).ravel(),
            sum(numeric.values()),
            rtol=1e-10,
            atol=1e-15,
        )


def test_gravity_gradient_through_the_orbit(every_torque: EnvironmentTorques, geometry) -> None:
    # The position in body axes is the attitude's transpose applied to r_N.
    dcm = Rotation.from_euler("xyz", [10.0, -20.0, 35.0], degrees=True).as_matrix()
    t = 777.0
    r_body = dcm.T @ every_torque.orbit.position_m(t)
    torques = every_torque.torques(t, dcm, geometry.inertia_total_kgm2)
    np.testing.assert_allclose(
        torques["gravity_gradient"],
        gravity_gradient_torque(geometry.inertia_total_kgm2, r_body),
        rtol=1e-14,
    )


def test_sizes_at_685_km_are_below_the_paper_sine(
    every_torque: EnvironmentTorques, geometry
) -> None:
    # The paper's 0.7 mNm per axis is its worst-case sum of these sources.
    rng = np.random.default_rng(4)
    peaks = dict.fromkeys(ENVIRONMENT_TORQUES, 0.0)
    for t in np.linspace(0.0, every_torque.orbit.period_s, 40):
        dcm = Rotation.random(random_state=rng).as_matrix()
        for name, tau in every_torque.torques(t, dcm, geometry.inertia_total_kgm2).items():
            peaks[name] = max(peaks[name], float(np.abs(tau).max()))
    # Gravity gradient: at most 3/2 n^2 (I_max - I_min) = 1.5 * 1.13e-6 * 386 = 0.66 mNm.
    n2 = every_torque.orbit.mean_motion_rad_s**2
    spread = np.ptp(np.linalg.eigvalsh(geometry.inertia_total_kgm2))
    assert 0.2e-3 < peaks["gravity_gradient"] <= 1.5 * n2 * spread * (1 + 1e-12)
    for name in ("aerodynamic", "solar_pressure", "magnetic"):
        assert 0.0 < peaks[name] < 0.1e-3, name


def test_symbolic_attitude_from_a_quaternion(every_torque: EnvironmentTorques, geometry) -> None:
    # MX inputs too (the closed loop's CVODES step builds MX graphs).
    t, dcm = ca.MX.sym("t"), ca.MX.sym("dcm", 3, 3)
    inertia = ca.DM(geometry.inertia_total_kgm2)
    f = ca.Function("env", [t, dcm], [every_torque.total(t, dcm, inertia)])
    rotation = Rotation.from_rotvec([0.1, 0.2, -0.3]).as_matrix()
    np.testing.assert_allclose(
        np.array(f(500.0, rotation)).ravel(),
        every_torque.total(500.0, rotation, geometry.inertia_total_kgm2),
        rtol=1e-10,
    )
