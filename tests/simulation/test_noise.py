"""The seeded noise streams, against hand-computed flags and sample statistics."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from casadi_debris.config import Actuators, Gyro, Sensors, StarTracker, load_problem
from casadi_debris.dynamics import build_model
from casadi_debris.simulation import draw_noise
from casadi_debris.simulation._noise import reading_flags

PERIOD_S = 0.1


@pytest.fixture(scope="module")
def paper():
    problem = load_problem()
    return problem, build_model(problem).geometry


def test_reading_flags_at_3_hz_seen_at_10_hz() -> None:
    # Readings at 0, 1/3, 2/3, 1 s reach the loop at 0, 0.4, 0.7, 1.0 s.
    t = np.arange(11) * PERIOD_S
    flags = reading_flags(t, 3.0, np.zeros((0, 2)))
    np.testing.assert_array_equal(np.flatnonzero(flags), [0, 4, 7, 10])


def test_outages_remove_readings() -> None:
    t = np.arange(20) * PERIOD_S
    flags = reading_flags(t, None, np.array([[0.5, 1.0], [1.75, 5.0]]))
    np.testing.assert_array_equal(np.flatnonzero(flags == 0), [5, 6, 7, 8, 9, 18, 19])


def test_gyro_and_star_tracker_statistics(paper) -> None:
    problem, geometry = paper
    tracker = StarTracker(noise_arcsec=10.0, bias_arcsec=np.array([1.0, -2.0, 3.0]))
    gyro = Gyro(angle_random_walk_deg_rt_h=0.15, bias_random_walk_deg_h_rt_h=2.0)
    problem = dataclasses.replace(problem, sensors=Sensors(tracker, gyro, seed=5))
    n = 200_000
    noise = draw_noise(problem, geometry, np.arange(n) * PERIOD_S)
    arcsec = math.pi / 180 / 3600
    reading = noise.star_tracker_rad / arcsec
    np.testing.assert_allclose(reading.mean(axis=0), [1.0, -2.0, 3.0], atol=0.1)
    np.testing.assert_allclose(reading.std(axis=0), 10.0, rtol=0.01)
    # 0.15 deg/sqrt(h) = 0.15 pi/180 / 60 rad/sqrt(s); over 0.1 s a rate noise of that / sqrt(0.1).
    white = noise.gyro_error_rad_s - noise.gyro_bias_rad_s
    np.testing.assert_allclose(
        white.std(axis=0), 0.15 * math.pi / 180 / 60 / math.sqrt(0.1), rtol=0.01
    )
    # 2 deg/h/sqrt(h) = 2 pi/180 / 3600 / 60 rad/s/sqrt(s); steps of that times sqrt(0.1).
    steps = np.diff(noise.gyro_bias_rad_s, axis=0)
    np.testing.assert_allclose(
        steps.std(axis=0), 2 * math.pi / 180 / 3600 / 60 * math.sqrt(0.1), rtol=0.01
    )
    assert noise.seed == 5


def test_misalignment_tilts_and_torques(paper) -> None:
    problem, geometry = paper
    problem = dataclasses.replace(problem, actuators=Actuators(misalignment_deg=0.5))
    tilts, torque_errors = [], []
    for seed in range(40):
        noise = draw_noise(problem, geometry, np.arange(3) * PERIOD_S, seed)
        for engine in geometry.engines:
            d = noise.force_map[:, engine.index]
            assert np.linalg.norm(d) == pytest.approx(1.0, abs=1e-12)
            tilts.append(math.degrees(math.acos(min(1.0, float(d @ engine.direction)))))
            torque_errors.append(
                np.abs(noise.torque_map[:, engine.index] - np.cross(engine.position_m, d)).max()
            )
    # Two normal angles of 0.5 deg: the tilt is Rayleigh, mean 0.5 sqrt(pi / 2).
    assert np.mean(tilts) == pytest.approx(0.5 * math.sqrt(math.pi / 2), rel=0.05)
    assert max(torque_errors) < 1e-14


def test_streams_are_independent_and_seeded(paper) -> None:
    problem, geometry = paper
    noisy = dataclasses.replace(problem, sensors=Sensors(StarTracker(noise_arcsec=5.0), seed=2))
    t = np.arange(100) * PERIOD_S
    first = draw_noise(noisy, geometry, t)
    engines = dataclasses.replace(noisy, actuators=Actuators(thrust_noise_fraction=0.1))
    second = draw_noise(engines, geometry, t)
    np.testing.assert_array_equal(first.star_tracker_rad, second.star_tracker_rad)
    assert np.all(first.thrust_factor == 1.0) and second.thrust_factor.std() > 0.05
    other = draw_noise(noisy, geometry, t, seed=3)
    assert not np.array_equal(first.star_tracker_rad, other.star_tracker_rad)


def test_every_campaign_case_has_its_own_noise_and_keeps_it() -> None:
    """Cases draw their noise seed from the problem's, their kind and index: distinct
    across a campaign, the same when a case is built again (a re-run alone), the problem's
    own for the nominal case."""
    from casadi_debris.campaigns import corner_cases, nominal_case, sample_cases

    problem = load_problem("paper_realistic")
    model = build_model(problem)
    corners = corner_cases(model)
    seeds = [case.noise_seed(problem) for case in corners]
    assert len(set(seeds)) == len(seeds) == 256
    assert seeds == [case.noise_seed(problem) for case in corner_cases(model)]
    samples = [c.noise_seed(problem) for c in sample_cases(model, 8, seed=3)]
    assert len(set(samples + seeds)) == len(samples) + len(seeds)
    assert nominal_case(model).noise_seed(problem) is None
    other = dataclasses.replace(problem.sensors, seed=problem.sensors.seed + 1)
    assert corners[0].noise_seed(dataclasses.replace(problem, sensors=other)) != seeds[0]
