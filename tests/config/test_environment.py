"""The ``[environment]`` table and the orbit's optional node and phase."""

from __future__ import annotations

import numpy as np
import pytest

from casadi_debris.config import ENVIRONMENT_TORQUES, problem_from_dict
from casadi_debris.errors import ProblemFileError


def test_absent_means_no_torque(problem) -> None:
    assert problem.environment.torques == ()
    assert problem.orbit.raan_deg == 0.0 and problem.orbit.argument_of_latitude_deg == 0.0


def test_keys_are_read(fresh_data) -> None:
    fresh_data["environment"] = {
        "torques": ["magnetic", "gravity_gradient"],
        "density_kg_m3": 3e-13,
        "residual_dipole_Am2": [0.5, -1.0, 2.0],
        "eclipse": False,
        "dipole_tilt_deg": 0.0,
    }
    fresh_data["orbit"] |= {"raan_deg": 120.0, "argument_of_latitude_deg": -30.0}
    problem = problem_from_dict(fresh_data)
    environment = problem.environment
    assert environment.torques == ("magnetic", "gravity_gradient")
    assert environment.acts("magnetic") and not environment.acts("aerodynamic")
    assert environment.density_kg_m3 == 3e-13 and environment.eclipse is False
    np.testing.assert_array_equal(environment.residual_dipole_Am2, [0.5, -1.0, 2.0])
    assert environment.drag_coefficient == 2.2  # a default
    assert (problem.orbit.raan_deg, problem.orbit.argument_of_latitude_deg) == (120.0, -30.0)


def test_an_empty_list_or_table_is_none(fresh_data) -> None:
    fresh_data["environment"] = {"torques": []}
    assert problem_from_dict(fresh_data).environment.torques == ()
    fresh_data["environment"] = {}
    assert problem_from_dict(fresh_data).environment.torques == ()


def test_the_environment_does_not_change_the_plant(problem, fresh_data) -> None:
    # A controller designed for the paper still flies with environment torques on.
    fresh_data["environment"] = {"torques": list(ENVIRONMENT_TORQUES)}
    assert problem_from_dict(fresh_data).plant_sha256 == problem.plant_sha256


BAD = [
    ("torques", ["drag"], "must be among"),
    ("torques", "gravity_gradient", "array of strings"),
    ("torques", ["magnetic", "magnetic"], "twice"),
    ("density_kg_m3", -1e-13, "negative"),
    ("density_kg_m3", 1.0, "at most 1e-06"),
    ("drag_coefficient", 0.0, "at least 0.5"),
    ("specular_reflectivity", 1.5, "at most 1"),
    ("solar_pressure_N_m2", "4.56e-6", "not a string"),
    ("residual_dipole_Am2", [1.0, 2.0], "shape"),
    ("residual_dipole_Am2", [1.0, float("nan"), 2.0], "finite"),
    ("eclipse", 1, "true or false"),
    ("dipole_tilt_deg", 200.0, "at most 180"),
    ("field_equator_T", 1.0, "at most"),
    ("colour", 1.0, "unknown key"),
]


@pytest.mark.parametrize(("key", "value", "words"), BAD, ids=[f"{k}={v}" for k, v, _ in BAD])
def test_bad_value_names_the_key(fresh_data, key, value, words) -> None:
    fresh_data["environment"] = {key: value}
    with pytest.raises(ProblemFileError) as caught:
        problem_from_dict(fresh_data, "bad.toml")
    message = str(caught.value)
    assert message.startswith(f"bad.toml: environment.{key}: ")
    assert words in message
    assert "\n" not in message


def test_reflectivities_above_one_together(fresh_data) -> None:
    fresh_data["environment"] = {"specular_reflectivity": 0.7, "diffuse_reflectivity": 0.4}
    with pytest.raises(ProblemFileError, match=r"environment\.diffuse_reflectivity: .*at most 1"):
        problem_from_dict(fresh_data)


def test_not_a_table(fresh_data) -> None:
    fresh_data["environment"] = 3
    with pytest.raises(ProblemFileError, match="environment: must be a table"):
        problem_from_dict(fresh_data)


@pytest.mark.parametrize("key", ["raan_deg", "argument_of_latitude_deg"])
def test_bad_orbit_angles(fresh_data, key) -> None:
    fresh_data["orbit"][key] = 1000.0
    with pytest.raises(ProblemFileError, match=f"orbit.{key}: must be at most 360"):
        problem_from_dict(fresh_data)
