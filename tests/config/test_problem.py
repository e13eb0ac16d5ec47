"""Problem files: loading, freezing, and one test per validation rule."""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from casadi_debris import load_problem
from casadi_debris.config import problem_from_dict
from casadi_debris.errors import ProblemFileError


def test_default_problem_is_the_paper(problem):
    assert problem.name == "paper"
    assert problem.hub.mass_kg == 500.0
    np.testing.assert_array_equal(problem.hub.inertia_kgm2, [[75, 1, 2], [1, 40, -1], [2, -1, 80]])
    assert len(problem.arrays) == 2 and len(problem.cubesats) == 24
    assert [m.omega_rad_s for m in problem.arrays[1].modes] == [5.6, 19.3, 35.4]
    assert problem.engine.thrust_per_stage_mN == 0.64
    assert len(problem.sha256) == 64


def test_problem_is_frozen(problem):
    with pytest.raises(dataclasses.FrozenInstanceError):
        problem.hub.mass_kg = 1.0  # type: ignore[misc]
    with pytest.raises(ValueError):
        problem.hub.inertia_kgm2[0, 0] = 1.0


def test_paper_file_shipped_at_top_level_is_the_package_copy():
    top_level = Path(__file__).parents[2] / "problems" / "paper.toml"
    assert load_problem(top_level).sha256 == load_problem().sha256


def _set(data: dict[str, Any], dotted: str, value: Any) -> None:
    *parents, last = dotted.split(".")
    for part in parents:
        data = data[part[:-3]][int(part[-2])] if part.endswith("]") else data[part]
    data[last] = value


def _delete(data: dict[str, Any], dotted: str) -> None:
    *parents, last = dotted.split(".")
    for part in parents:
        data = data[part[:-3]][int(part[-2])] if part.endswith("]") else data[part]
    del data[last]


BAD_VALUES = [
    # (key, bad value, words expected in the message)
    ("hub.mass_kg", 0.0, "at least 0.001"),
    ("hub.mass_kg", -500.0, "at least 0.001"),
    ("hub.mass_kg", math.nan, "finite"),
    ("hub.mass_kg", math.inf, "finite"),
    ("hub.mass_kg", "heavy", "not a string"),
    ("hub.mass_kg", True, "true/false"),
    ("hub.size_m", [0.75, 3.0], "shape"),
    ("hub.cog_corner_m", [2.0, 1.5, 0.5], "inside the hub"),
    ("hub.inertia_kgm2", [[75, 5, 2], [1, 40, -1], [2, -1, 80]], "symmetric"),
    ("hub.inertia_kgm2", [[75, 0, 0], [0, -40, 0], [0, 0, 80]], "positive definite"),
    ("hub.inertia_kgm2", [[10, 0, 0], [0, 10, 0], [0, 0, 80]], "triangle inequality"),
    ("hub.inertia_kgm2", [[75, 1], [1, 40]], "shape"),
    ("arrays[0].inertia_kgm2", [17.0, 62.0, 90.0], "triangle inequality"),
    ("arrays[0].mass_kg", 0.0, "at least 0.001"),
    ("arrays[1].damping_ratio", 1.5, "below"),
    ("arrays[0].direction", "+w", "signed axis"),
    ("arrays[0].direction", [0.0, 0.0, 0.0], "must not be zero"),
    ("arrays[0].direction", "+z", "does not point out of the hub"),
    ("arrays[0].hinge_corner_m", [0.4, 1.4, 0.3], "not on the hub's surface"),
    ("arrays[1].hinge_corner_m", [0.4, 5.0, 1.0], "not on the hub's surface"),
    ("cubesat_layout.per_face", 3, "face_corners places 4"),
    ("cubesat_layout.kind", "ring", "must be one of"),
    ("cubesat_layout.faces", ["+x", "+x"], "at most once"),
    ("cubesat_layout.side_engines", 3, "0, 2 or 4"),
    ("cubesat_layout.main_engine", False, "needs an engine"),
    ("cubesat_layout.mass_kg", -3.5, "at least 0.001"),
    ("cubesat_layout.edge_margin_fraction", 1.0, "below"),
    ("cubesat_layout.standoff_m", -0.1, "negative"),
    ("requirements.pointing_arcsec", 0.0, "at least 0.001"),
    ("engine.stages", 0, "at least 1"),
    ("engine.stages", 2.5, "integer"),
    ("engine.isp_s", 0.0, "at least 1"),
    ("disturbance.amplitude_mNm", [0.7, 0.7], "shape"),
    ("uncertainty.array_angle_deg", 270.0, "at most 180"),
    ("uncertainty.inertia_fraction", 1.2, "below"),
    ("weights.epsilon", 0.0, "at least 1e-06"),
    ("weights.error_scaling_deg", [0.0022, 0.0, 0.011], "at least 1e-06"),
    ("detumble.initial_rate_rad_s", [1.0, math.nan, 1.0], "finite"),
]


@pytest.mark.parametrize(
    ("key", "value", "words"), BAD_VALUES, ids=[f"{k}={v}" for k, v, _ in BAD_VALUES]
)
def test_bad_value_names_the_key(fresh_data, key, value, words):
    _set(fresh_data, key, value)
    with pytest.raises(ProblemFileError) as caught:
        problem_from_dict(fresh_data, "bad.toml")
    message = str(caught.value)
    assert key in message
    assert words in message
    assert message.startswith("bad.toml: ")


@pytest.mark.parametrize(
    "key", ["hub.mass_kg", "arrays[0].hinge_corner_m", "cubesat_layout.kind", "constants"]
)
def test_missing_key_is_named(fresh_data, key):
    _delete(fresh_data, key)
    with pytest.raises(ProblemFileError, match=f"{re.escape(key)}: missing"):
        problem_from_dict(fresh_data)


@pytest.mark.parametrize("key", ["hub.colour", "typo_top_level", "engine.thrust_mN"])
def test_unknown_key_is_named(fresh_data, key):
    _set(fresh_data, key, 1.0)
    with pytest.raises(ProblemFileError, match=f"{key}: unknown key"):
        problem_from_dict(fresh_data)


@pytest.mark.parametrize(
    ("key", "meant"),
    [("hub.mas_kg", "mass_kg"), ("engine.isp", "isp_s"), ("orbit.altitude_m", "altitude_km")],
)
def test_an_unknown_key_close_to_a_known_one_is_suggested(fresh_data, key, meant):
    section, wrong = key.split(".")
    fresh_data[section][wrong] = fresh_data[section][meant]  # as when a parent gives it
    with pytest.raises(ProblemFileError, match=f"{key}: unknown key; did you mean {meant}"):
        problem_from_dict(fresh_data)
    del fresh_data[section][meant]
    with pytest.raises(ProblemFileError, match=rf"{section}\.{meant}: missing \(is {wrong} a"):
        problem_from_dict(fresh_data)


def test_an_unknown_key_far_from_every_known_one_gets_no_guess(fresh_data):
    fresh_data["hub"]["zzz"] = 1.0
    with pytest.raises(ProblemFileError, match=r"hub\.zzz: unknown key$"):
        problem_from_dict(fresh_data)


def test_unknown_key_inside_a_mode_is_named(fresh_data):
    fresh_data["arrays"][0]["modes"][1]["omega_hz"] = 3.0
    with pytest.raises(ProblemFileError, match=r"arrays\[0\]\.modes\[1\]\.omega_hz: unknown key"):
        problem_from_dict(fresh_data)


def test_bad_mode_kind_is_named(fresh_data):
    fresh_data["arrays"][1]["modes"][0]["kind"] = "breathing"
    with pytest.raises(ProblemFileError, match=r"arrays\[1\]\.modes\[0\]\.kind: must be one of"):
        problem_from_dict(fresh_data)


def test_duplicate_mode_names_rejected(fresh_data):
    fresh_data["arrays"][0]["modes"][1]["name"] = "bending1"
    with pytest.raises(ProblemFileError, match=r"arrays\[0\]\.modes: mode names must be unique"):
        problem_from_dict(fresh_data)


def test_an_array_without_modes_is_rigid(fresh_data):
    fresh_data["arrays"][0]["modes"] = []
    del fresh_data["arrays"][1]["modes"]
    problem = problem_from_dict(fresh_data)
    assert [array.modes for array in problem.arrays] == [(), ()]


def test_no_arrays_is_a_rigid_debris(fresh_data):
    fresh_data["arrays"] = []
    assert problem_from_dict(fresh_data).arrays == ()
    del fresh_data["arrays"]
    assert problem_from_dict(fresh_data).arrays == ()


def test_the_old_single_tables_say_how_to_write_the_lists(fresh_data):
    fresh_data["arrays"] = {"mass_kg": 42.0}
    with pytest.raises(ProblemFileError, match=r"arrays: must be an array of tables"):
        problem_from_dict(fresh_data)


def test_cubesats_given_twice_or_never_are_refused(fresh_data):
    layout = fresh_data.pop("cubesat_layout")
    with pytest.raises(ProblemFileError, match="cubesats: missing"):
        problem_from_dict(fresh_data)
    fresh_data["cubesat_layout"] = layout
    fresh_data["cubesats"] = [{"position_corner_m": [1.0, 1.0, 1.0]}]
    with pytest.raises(ProblemFileError, match="not both"):
        problem_from_dict(fresh_data)


def test_paper_array_inertia_passes_triangle_check_within_tolerance(problem):
    # 80 > 17 + 62 by 1.3 %: a rounded thin plate; accepted within TRIANGLE_TOLERANCE.
    assert problem.arrays[0].inertia_kgm2.tolist() == [17.0, 62.0, 80.0]


def test_extends_merges_tables(tmp_path):
    child = tmp_path / "heavy.toml"
    paper = Path(__file__).parents[2] / "problems" / "paper.toml"
    child.write_text(f'extends = "{paper}"\nname = "heavy"\n[hub]\nmass_kg = 600.0\n')
    loaded = load_problem(child)
    assert loaded.name == "heavy"
    assert loaded.hub.mass_kg == 600.0
    assert loaded.hub.size_m.tolist() == [0.75, 3.0, 1.0]
    assert loaded.sha256 != load_problem(paper).sha256


def test_circular_extends_rejected(tmp_path):
    (tmp_path / "a.toml").write_text('extends = "b.toml"\n')
    (tmp_path / "b.toml").write_text('extends = "a.toml"\n')
    with pytest.raises(ProblemFileError, match="circular"):
        load_problem(tmp_path / "a.toml")


def test_invalid_toml_and_missing_file(tmp_path):
    broken = tmp_path / "broken.toml"
    broken.write_text("[hub\nmass_kg = 1")
    with pytest.raises(ProblemFileError, match="not valid TOML"):
        load_problem(broken)
    with pytest.raises(ProblemFileError, match="no such problem file"):
        load_problem(tmp_path / "absent.toml")
