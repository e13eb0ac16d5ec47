"""Problem files: strict types, the range of every number, and the checks across tables."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import pytest

from casadi_debris import load_problem
from casadi_debris.config import limits, problem_from_dict
from casadi_debris.errors import ProblemFileError

ROOT = Path(__file__).parents[2]
SHIPPED = sorted((ROOT / "problems").glob("*.toml")) + sorted(
    (ROOT / "src" / "casadi_debris" / "problems").glob("*.toml")
)


def _numeric_leaves(data: Any, prefix: str = "") -> list[tuple[str, Any]]:
    """(dotted key, value) of every number or array of numbers in a parsed problem."""
    found = []
    for key, value in data.items():
        dotted = f"{prefix}{key}"
        if isinstance(value, dict):
            found += _numeric_leaves(value, dotted + ".")
        elif isinstance(value, list) and value and isinstance(value[0], dict):
            for i, item in enumerate(value):
                found += _numeric_leaves(item, f"{dotted}[{i}].")
        elif not isinstance(value, str | bool) and not (
            isinstance(value, list) and value and isinstance(value[0], str)
        ):
            found.append((dotted, value))
    return found


def _set(data: dict[str, Any], dotted: str, value: Any) -> None:
    *parents, last = dotted.split(".")
    for part in parents:
        if part.endswith("]"):
            name, index = part[:-1].split("[")
            data = data[name][int(index)]
        else:
            data = data[part]
    data[last] = value


def _like(original: Any, scalar: Any) -> Any:
    """``scalar`` in every entry of ``original``'s shape."""
    if isinstance(original, list):
        return [_like(item, scalar) for item in original]
    return scalar


def _refused(data: dict[str, Any], key: str, words: str = "") -> str:
    with pytest.raises(ProblemFileError) as caught:
        problem_from_dict(data, "bad.toml")
    message = str(caught.value)
    # The key itself, or a key inside it (a table's missing key, an array's entry).
    assert any(message.startswith(f"bad.toml: {key}{end}") for end in (": ", ".", "[")), message
    assert words in message, message
    assert "\n" not in message and len(message) < 400
    return message


@pytest.fixture(scope="module")
def leaves(paper_data: dict[str, Any]) -> list[tuple[str, Any]]:
    return _numeric_leaves(paper_data)


def test_every_number_of_the_paper_is_found(leaves):
    keys = {key for key, _ in leaves}
    assert {"hub.mass_kg", "arrays[1].modes[2].omega_rad_s", "montecarlo.seed"} <= keys
    assert len(keys) > 50


@pytest.mark.parametrize(
    ("bad", "words"),
    [
        ("5", "string"),
        (True, "true/false"),
        (math.nan, "finite"),
        (-math.inf, "finite"),
        (10**400, ""),
        (1e308, ""),
        (-1e308, ""),
    ],
    ids=["string", "bool", "nan", "-inf", "int-1e400", "1e308", "-1e308"],
)
def test_every_number_refuses_bad_values_naming_its_key(paper_data, leaves, bad, words):
    for key, original in leaves:
        data = copy.deepcopy(paper_data)
        _set(data, key, _like(original, bad))
        # An integer key names what it wants instead of "finite".
        integer_key = isinstance(original, int) and words == "finite"
        _refused(data, key, "integer" if integer_key else words)


def test_numeric_strings_are_not_numbers(fresh_data):
    # "5" used to be read as 5.0 (np.array("5", dtype=float)): a 173 kg body.
    fresh_data["cubesat_layout"]["mass_kg"] = "5"
    _refused(fresh_data, "cubesat_layout.mass_kg", "not a string")
    fresh_data["cubesat_layout"]["mass_kg"] = 3.5
    fresh_data["hub"]["size_m"] = [0.75, "3", 1.0]
    _refused(fresh_data, "hub.size_m", "not strings")


def test_integers_must_be_integers(fresh_data):
    fresh_data["simulation"]["integrator_steps"] = 4.0
    _refused(fresh_data, "simulation.integrator_steps", "integer")


@pytest.mark.parametrize(
    ("key", "value", "words"),
    [
        ("simulation.integrator_steps", 1_000_000_000, "at most 1000"),
        ("simulation.control_rate_hz", 1e-9, "at least 0.01"),
        ("simulation.control_rate_hz", 1e6, "at most 1000"),
        ("simulation.duration_s", 1e9, "at most 1e+07"),
        ("montecarlo.samples", 10**9, "at most 100000"),
        ("montecarlo.corner_array_angles", 1000, "at most 64"),
        ("montecarlo.seed", 2**32, "at most 4294967295"),
        ("montecarlo.seed", -1, "negative"),
        ("uncertainty.samples", 10**6, "at most 10000"),
        ("uncertainty.seed", 2**64, "at most 4294967295"),
        ("hub.mass_kg", 1e308, "at most 1e+06"),
        ("hub.size_m", [0.75, 0.0, 1.0], "at least 0.01"),
        ("hub.inertia_kgm2", [[1e-9, 0, 0], [0, 1e-9, 0], [0, 0, 1e-9]], "below 1e-06"),
        ("arrays[0].modes[0].order", 7, "at most 6"),
        ("arrays[1].modes[0].omega_rad_s", 1e308, "at most 10000"),
        ("arrays[0].hinge_corner_m", [0.4, 1.4, 1e308], "at most 200"),
        ("arrays[0].direction", [0.0, 0.0, -1e308], "at least -1000"),
        ("arrays[0].angle_deg", 1e308, "at most 360"),
        ("cubesat_layout.per_face", 10**6, "at most 256"),
        ("engine.thrust_per_stage_mN", 5e-324, "at least 1e-06"),
        ("engine.stages", 10**20, "at most 16"),
        ("detumble.initial_rate_rad_s", [1.0, 100.0, 1.0], "at most 10"),
        ("orbit.altitude_km", 0.0, "at least 100"),
        ("orbit.inclination_deg", 200.0, "at most 180"),
        ("constants.standard_gravity_m_s2", 1e-300, "at least 9.7"),
        ("disturbance.period_min", 1e-300, "at least 1"),
        ("sensor.star_tracker_bandwidth_rad_s", 0.0, "at least 1e-06"),
    ],
)
def test_bounds_name_the_key(fresh_data, key, value, words):
    _set(fresh_data, key, value)
    _refused(fresh_data, key, words)


@pytest.mark.parametrize(
    "table",
    [[], [[]], {}, "[hub]", [{"mass_kg": 500.0}], 5.0],
    ids=["empty-array", "nested-array", "empty-table", "string", "array-of-tables", "number"],
)
def test_wrong_nesting_names_the_table(fresh_data, table):
    fresh_data["hub"] = table
    _refused(fresh_data, "hub", "")


@pytest.mark.parametrize(
    ("key", "value", "words"),
    [
        ("hub.size_m", [[0.75, 3.0, 1.0]], "shape (3,)"),
        ("hub.size_m", {"x": 1.0}, "shape (3,)"),
        ("hub.inertia_kgm2", [75.0, 40.0, 80.0], "shape (3, 3)"),
        ("hub.mass_kg", [500.0], "a number"),
        ("arrays[0].modes", {"name": "bending1"}, "non-empty array of tables"),
        ("arrays[0].modes", [1.0], "must be a table"),
        ("arrays", {"mass_kg": 42.0}, "must be an array of tables"),
        ("arrays", [1.0], "must be a table"),
        ("arrays[0].hinge_corner_m", [0.4, 1.4], "shape (3,)"),
        ("simulation", [], "must be a table"),
        ("simulation.slew", {}, "only allowed"),
        ("simulation.failures", [{"time_s": 1.0, "cubesat": 1}] * 1001, "at most 1000"),
    ],
)
def test_wrong_shapes_and_nesting_name_the_key(fresh_data, key, value, words):
    _set(fresh_data, key, value)
    _refused(fresh_data, key, words)


def test_propellant_heavier_than_the_cubesat_is_refused(fresh_data):
    # 3 stages x 0.64 mN x 500 h / (1000 s g0) = 0.35 kg; 5000 h is 3.5 kg, the CubeSat's mass.
    fresh_data["engine"]["stage_life_h"] = 5000.0
    message = _refused(fresh_data, "engine.stage_life_h", "below the CubeSat's mass")
    assert "3.524 kg" in message and "cubesat_layout.mass_kg" in message
    fresh_data["engine"]["stage_life_h"] = 4900.0
    assert problem_from_dict(fresh_data).engine.stage_life_h == 4900.0


def test_propellant_check_counts_every_stage(fresh_data):
    fresh_data["engine"]["stages"] = 16  # 16 x 0.1175 kg = 1.88 kg < 3.5 kg
    problem_from_dict(fresh_data)
    fresh_data["cubesat_layout"]["mass_kg"] = 1.8
    _refused(fresh_data, "engine.stage_life_h", "1.88 kg")


def test_runs_are_bounded_as_a_whole(fresh_data):
    simulation = fresh_data["simulation"]
    simulation["duration_s"], simulation["control_rate_hz"] = 1e7, 1.0
    simulation["integrator_steps"] = 50
    _refused(fresh_data, "simulation.duration_s", "1 to 1000000")
    simulation["duration_s"] = 0.01  # below one control period
    _refused(fresh_data, "simulation.duration_s", "control periods")
    simulation["duration_s"], simulation["control_rate_hz"] = 1e6, 1.0
    _refused(fresh_data, "simulation.integrator_steps", "integration steps")


def test_integration_step_must_resolve_the_fastest_dynamics(fresh_data):
    # 1 Hz with 4 RK4 steps: 0.25 s x 50 rad/s (star tracker) = 12.5, RK4 diverges past 2.8.
    fresh_data["simulation"]["control_rate_hz"] = 1.0
    message = _refused(fresh_data, "simulation.integrator_steps", "star_tracker_bandwidth_rad_s")
    assert "integrator_steps >= 25" in message
    fresh_data["simulation"]["integrator_steps"] = 25
    problem_from_dict(fresh_data)
    fresh_data["arrays"][1]["modes"][2]["omega_rad_s"] = 60.0  # now the fastest
    _refused(fresh_data, "simulation.integrator_steps", "arrays[1].modes[2].omega_rad_s")
    fresh_data["simulation"]["control_rate_hz"] = 0.01  # 1000 steps cannot make it
    _refused(fresh_data, "simulation.integrator_steps", "raise control_rate_hz")


def test_slew_must_start_within_the_run(fresh_data):
    fresh_data["simulation"]["reference"] = "slew"
    fresh_data["simulation"]["slew"] = {"axis": "z", "angle_deg": 90.0, "start_s": 1e4}
    _refused(fresh_data, "simulation.slew.start_s", "at most 5908")


@pytest.mark.parametrize(
    "name",
    ["../../somewhere", "..", ".", "a/b", "a\\b", "", "-x", "x" * 65, "a\nb", "é", "a b", "~x"],
)
def test_name_is_a_label_not_a_path(fresh_data, name):
    fresh_data["name"] = name
    _refused(fresh_data, "name", "label")


@pytest.mark.parametrize("name", ["paper", "heavy-hub", "slew.v2", "x" * 64, "0"])
def test_labels_are_accepted(fresh_data, name):
    fresh_data["name"] = name
    assert problem_from_dict(fresh_data).name == name


def test_mode_names_are_labels(fresh_data):
    fresh_data["arrays"][0]["modes"][0]["name"] = "../bending"
    _refused(fresh_data, "arrays[0].modes[0].name", "label")


@pytest.mark.parametrize(
    ("text", "words"), [("x" * 1001, "at most 1000"), ("a\x1b[2Jb", "control characters")]
)
def test_description_is_bounded_prose(fresh_data, text, words):
    fresh_data["description"] = text
    _refused(fresh_data, "description", words)


def test_messages_stay_on_one_short_line(fresh_data):
    fresh_data["hub"]["mass_kg"] = "5" * 100_000
    assert len(_refused(fresh_data, "hub.mass_kg")) < 200
    fresh_data["hub"]["mass_kg"] = 500.0
    fresh_data["hub"]["odd\nkey"] = 1.0
    _refused(fresh_data, 'hub."odd\\nkey"', "unknown key")


def test_range_messages():
    assert limits.Range(0.0, 1.0, low_open=True).violation(0.0) == "must be positive"
    assert limits.Range(0.0, 1.0).violation(-1.0) == "must not be negative"
    assert limits.Range(0.0, 1.0, high_open=True).violation(1.0) == "must be below 1"
    assert limits.SEED.violation(2**32) == "must be at most 4294967295"
    assert limits.Range(1, 4).violation(2) is None
    assert str(limits.Range(0.0, 1.0, low_open=True)) == "(0, 1]"


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_shipped_problems_load(path):
    problem = load_problem(path)
    assert problem.name == path.stem
    assert len(problem.sha256) == 64
