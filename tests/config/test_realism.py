"""The ``[sensors.*]``, ``[estimation]``, ``[actuators]`` and ``[controller]`` tables."""

from __future__ import annotations

import numpy as np
import pytest

from casadi_debris.config import Actuators, Estimation, Sensors, load_problem, problem_from_dict
from casadi_debris.errors import ProblemFileError


def test_absent_means_ideal(problem) -> None:
    assert problem.sensors.star_tracker.ideal
    assert problem.sensors.gyro.angle_random_walk_deg_rt_h == 0.0
    assert problem.estimation.filter == "none"
    assert not problem.actuators.engine_level
    assert problem.actuators.latency_s == 0.0 and problem.controller.delay_s == 0.0


def test_keys_are_read(fresh_data) -> None:
    fresh_data["sensors"] = {
        "seed": 7,
        "star_tracker": {"noise_arcsec": 5.0, "outages_s": [[10.0, 20.0], [30.0, 31.0]]},
        "gyro": {"initial_bias_deg_h": [1.0, 2.0, 3.0]},
    }
    fresh_data["estimation"] = {"filter": "mekf"}
    fresh_data["actuators"] = {"minimum_impulse_bit_uNs": 2.0}
    fresh_data["controller"] = {"delay_s": 0.05}
    problem = problem_from_dict(fresh_data)
    tracker = problem.sensors.star_tracker
    assert problem.sensors.seed == 7 and tracker.noise_arcsec == 5.0 and not tracker.ideal
    np.testing.assert_array_equal(tracker.outages_s, [[10.0, 20.0], [30.0, 31.0]])
    assert tracker.update_rate_hz is None  # a default
    np.testing.assert_array_equal(problem.sensors.gyro.initial_bias_deg_h, [1.0, 2.0, 3.0])
    assert problem.estimation.filter == "mekf"
    assert problem.actuators.engine_level and problem.actuators.minimum_impulse_bit_uNs == 2.0
    assert problem.controller.delay_s == 0.05


def test_realism_does_not_change_the_plant(problem) -> None:
    # The shipped controller still flies with real sensors and engines.
    assert load_problem("paper_realistic").plant_sha256 == problem.plant_sha256


def test_defaults_are_the_dataclasses() -> None:
    assert Sensors().star_tracker.ideal and Estimation().filter == "none"
    assert not Actuators().engine_level


BAD = [
    (
        "sensors",
        {"star_tracker": {"noise_arcsec": -1.0}},
        "sensors.star_tracker.noise_arcsec",
        "negative",
    ),
    (
        "sensors",
        {"star_tracker": {"update_rate_hz": 0.0}},
        "sensors.star_tracker.update_rate_hz",
        "positive",
    ),
    (
        "sensors",
        {"star_tracker": {"outages_s": [[20.0, 10.0]]}},
        "sensors.star_tracker.outages_s",
        "end after",
    ),
    (
        "sensors",
        {"star_tracker": {"bias_arcsec": [1.0, 2.0]}},
        "sensors.star_tracker.bias_arcsec",
        "shape",
    ),
    (
        "sensors",
        {"gyro": {"angle_random_walk_deg_rt_h": "0.1"}},
        "sensors.gyro.angle_random_walk_deg_rt_h",
        "string",
    ),
    ("sensors", {"seed": -1}, "sensors.seed", "negative"),
    ("sensors", {"lidar": {}}, "sensors.lidar", "unknown key"),
    ("estimation", {"filter": "ukf"}, "estimation.filter", "one of"),
    ("actuators", {"thrust_noise_fraction": 2.0}, "actuators.thrust_noise_fraction", "at most 1"),
    ("actuators", {"misalignment_deg": float("nan")}, "actuators.misalignment_deg", "finite"),
    ("controller", {"delay_ms": 3.0}, "controller.delay_ms", "unknown key"),
]


@pytest.mark.parametrize(("table", "value", "key", "words"), BAD, ids=[b[2] for b in BAD])
def test_bad_value_names_the_key(fresh_data, table, value, key, words) -> None:
    fresh_data[table] = value
    with pytest.raises(ProblemFileError) as caught:
        problem_from_dict(fresh_data, "bad.toml")
    message = str(caught.value)
    assert message.startswith(f"bad.toml: {key}"), message
    assert words in message, message
    assert "\n" not in message
