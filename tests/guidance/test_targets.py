"""Smooth joins and frame attitudes, against closed forms."""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

from casadi_debris.environment import CircularOrbit
from casadi_debris.guidance import (
    blend,
    continuous_sign,
    frame_attitude,
    lvlh_matrices,
    smoothstep,
    smoothstep_integral,
)


def test_smoothstep_and_its_integral() -> None:
    f = np.linspace(0.0, 1.0, 2001)
    s = smoothstep(f)
    assert s[0] == 0.0 and s[-1] == 1.0
    slope = np.gradient(s, f)
    assert abs(slope[0]) < 1e-5 and abs(slope[-1]) < 1e-5
    assert abs(slope.max() - 1.875) < 1e-5  # 30 f^2 (1 - f)^2 at f = 1/2 (central differences)
    integral = np.concatenate([[0.0], np.cumsum((s[1:] + s[:-1]) / 2 * np.diff(f))])
    assert np.abs(smoothstep_integral(f) - integral).max() < 1e-7
    assert smoothstep_integral(np.array([3.0]))[0] == 2.5  # slope 1 past the end


def test_blend_meets_both_references_with_their_rates() -> None:
    times = np.linspace(0.0, 100.0, 10001)
    old = Rotation.from_rotvec(np.outer(times, [0.0, 0.0, 0.002])).as_quat()[:, [3, 0, 1, 2]]
    rotvec = np.outer(times, [0.001, 0.0, 0.0]) + np.array([0.0, 0.3, 0.0])
    new = Rotation.from_rotvec(rotvec).as_quat()[:, [3, 0, 1, 2]]
    joined = blend(old, new, times / 100.0)
    assert np.allclose(joined[0], old[0], atol=1e-15) or np.allclose(joined[0], -old[0])
    end = Rotation.from_quat(joined[-1, [1, 2, 3, 0]])
    assert (end.inv() * Rotation.from_quat(new[-1, [1, 2, 3, 0]])).magnitude() < 1e-12
    q = continuous_sign(joined)
    rate = np.gradient(q, times, axis=0)
    old_rate = np.gradient(continuous_sign(old), times, axis=0)
    new_rate = np.gradient(continuous_sign(new), times, axis=0)
    sign_new = np.sign(np.dot(q[-1], new[-1]))
    assert np.abs(rate[1] - old_rate[1]).max() < 1e-6
    assert np.abs(rate[-2] - sign_new * new_rate[-2]).max() < 1e-6


def test_lvlh_frame_of_a_polar_orbit_by_hand() -> None:
    """Polar orbit, node on x, at u = 90 deg: r along +z, v along -x, normal along -y."""
    orbit = CircularOrbit(radius_m=7e6, inclination_rad=math.pi / 2)
    quarter = orbit.period_s / 4
    c_on = lvlh_matrices(orbit, np.array([quarter]))[0]
    expected = np.array([[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]])
    assert np.abs(c_on - expected).max() < 1e-12
    q = frame_attitude(orbit, np.array([1.0, 0.0, 0.0, 0.0]), np.array([quarter]))[0]
    c_nb = Rotation.from_quat(q[[1, 2, 3, 0]]).as_matrix()
    assert np.abs(c_nb - expected.T).max() < 1e-12
