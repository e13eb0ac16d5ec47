"""``[[montecarlo.vary]]``: what a campaign varies, checked against the problem's own readers."""

from __future__ import annotations

import copy
from typing import Any

import pytest

from casadi_debris.config import (
    key_of,
    limits,
    parse_path,
    problem_from_dict,
    problem_with_values,
    with_duration,
    with_value,
)
from casadi_debris.errors import ProblemFileError


def _with_vary(paper: dict[str, Any], *entries: dict[str, Any]) -> dict[str, Any]:
    data = copy.deepcopy(paper)
    data["montecarlo"]["vary"] = list(entries)
    return data


UNIFORM_DENSITY = {
    "path": "environment.density_kg_m3",
    "distribution": "uniform",
    "low": 1e-13,
    "high": 5e-12,
}


@pytest.mark.parametrize(
    "path",
    ["environment.density_kg_m3", "arrays[1].modes[0].omega_rad_s", "hub.inertia_kgm2[0][2]"],
)
def test_paths_parse_and_print_back_as_the_loader_names_keys(path: str) -> None:
    assert key_of(parse_path(path)) == path


def test_a_valid_list_loads_and_a_normal_is_truncated_to_the_keys_range(paper_data) -> None:
    normal = {"path": "environment.drag_coefficient", "distribution": "normal"}
    normal |= {"mean": 2.2, "sigma": 0.1}
    corners = {"path": "mass_kg", "distribution": "corners", "low": 600.0, "high": 700.0}
    problem = problem_from_dict(_with_vary(paper_data, UNIFORM_DENSITY, normal, corners))
    vary = problem.montecarlo.vary
    assert [q.path for q in vary] == [e["path"] for e in (UNIFORM_DENSITY, normal, corners)]
    assert (vary[0].low, vary[0].high) == (1e-13, 5e-12)
    # The truncation is the reader's own range of drag_coefficient.
    assert (vary[1].low, vary[1].high) == (
        limits.DRAG_COEFFICIENT.low,
        limits.DRAG_COEFFICIENT.high,
    )
    assert vary[2].is_parameter and not vary[0].is_parameter


def _entry(**change: Any) -> dict[str, Any]:
    return {**UNIFORM_DENSITY, **change}


BAD_ENTRIES = [
    ("unknown key", _entry(path="environment.densty_kg_m3"), "vary[0].path", "unknown key"),
    ("a whole array", _entry(path="disturbance.amplitude_mNm"), "vary[0].path", "one element"),
    ("a text key", _entry(path="simulation.reference"), "vary[0].path", "not a number"),
    ("an integer key", _entry(path="simulation.integrator_steps"), "vary[0].path", "integer"),
    ("an index past the end", _entry(path="arrays[7].mass_kg"), "vary[0].path", "no entry"),
    ("not a path", _entry(path="hub..mass_kg"), "vary[0].path", "dotted key"),
    ("not a parameter", _entry(path="hub"), "vary[0].path", "model parameter"),
    ("the campaign itself", _entry(path="montecarlo.seed"), "vary[0].path", "own settings"),
    ("below the key's range", _entry(low=-1.0), "vary[0].low", "must not be negative"),
    ("high below low", _entry(low=1e-12, high=1e-13), "vary[0].high", "above low"),
    ("unknown distribution", _entry(distribution="lognormal"), "vary[0].distribution", "one of"),
    ("missing high", {**_entry(), "high": None}, "vary[0].high", "missing"),
    (
        "a normal without sigma",
        {"path": "mass_kg", "distribution": "normal", "mean": 600.0},
        "vary[0].sigma",
        "missing",
    ),
    (
        "a zero sigma",
        {"path": "mass_kg", "distribution": "normal", "mean": 600.0, "sigma": 0.0},
        "vary[0].sigma",
        "positive",
    ),
    (
        "a check across keys",
        _entry(path="environment.specular_reflectivity", low=0.1, high=0.95),
        "vary[0].high",
        "at most 1",
    ),
    (
        "a step too long for the varied rate",
        _entry(path="sensor.star_tracker_bandwidth_rad_s", low=10.0, high=500.0),
        "vary[0].high",
        "integrator_steps",
    ),
    ("an unknown field", _entry(scale=2.0), "vary[0].scale", "unknown key"),
]


@pytest.mark.parametrize(
    ("label", "entry", "field", "words"), BAD_ENTRIES, ids=[b[0] for b in BAD_ENTRIES]
)
def test_bad_entries_are_refused_naming_the_field(paper_data, label, entry, field, words) -> None:
    entry = {k: v for k, v in entry.items() if v is not None}
    with pytest.raises(ProblemFileError) as caught:
        problem_from_dict(_with_vary(paper_data, entry))
    assert caught.value.field == f"montecarlo.{field}", label
    assert words in str(caught.value)


def test_a_quantity_varied_twice_is_refused(paper_data) -> None:
    with pytest.raises(ProblemFileError, match="varied twice") as caught:
        problem_from_dict(_with_vary(paper_data, UNIFORM_DENSITY, UNIFORM_DENSITY))
    assert caught.value.field == "montecarlo.vary[1].path"


def test_too_many_corner_quantities_are_refused(paper_data) -> None:
    paths = ["inertia_scale_x", "inertia_scale_y", "inertia_scale_z", "mass_kg"]
    paths += ["bending_frequency_scale", "array_angle_offset_rad", "disturbance.period_min"]
    paths += [f"disturbance.{key}[{i}]" for key in ("amplitude_mNm", "phase_deg") for i in range(3)]
    assert len(paths) == limits.MAX_VARIED_CORNERS + 1
    many = [{"path": path, "distribution": "corners", "low": 0.5, "high": 0.6} for path in paths]
    with pytest.raises(ProblemFileError, match="corners"):
        problem_from_dict(_with_vary(paper_data, *many))


def test_a_case_problem_is_the_file_read_again_with_the_keys_set(paper_data) -> None:
    problem = with_duration(problem_from_dict(_with_vary(paper_data, UNIFORM_DENSITY)), 30.0)
    values = [("environment.density_kg_m3", 2e-12), ("disturbance.amplitude_mNm[1]", 1.5)]
    varied = problem_with_values(problem, values)
    # Independently: the same keys set by hand in the parsed file.
    by_hand = copy.deepcopy(paper_data)
    by_hand.setdefault("environment", {})["density_kg_m3"] = 2e-12
    by_hand["disturbance"]["amplitude_mNm"][1] = 1.5
    expected = problem_from_dict(by_hand)
    assert varied.environment.density_kg_m3 == expected.environment.density_kg_m3 == 2e-12
    assert list(varied.disturbance.amplitude_mNm) == list(expected.disturbance.amplitude_mNm)
    assert varied.plant_sha256 == expected.plant_sha256 != problem.plant_sha256
    # What the caller changed in memory (the run's length) and the campaign stay the caller's.
    assert varied.simulation.duration_s == 30.0 and varied.name == problem.name
    assert varied.montecarlo is problem.montecarlo
    with pytest.raises(ProblemFileError, match="must not be negative"):
        problem_with_values(problem, [("environment.density_kg_m3", -1.0)])


def test_setting_a_path_never_changes_the_data_it_was_given(paper_data) -> None:
    before = copy.deepcopy(paper_data)
    after = with_value(paper_data, parse_path("arrays[0].modes[0].omega_rad_s"), 6.0)
    assert paper_data == before
    assert after["arrays"][0]["modes"][0]["omega_rad_s"] == 6.0
    with pytest.raises(ValueError, match="not a table"):
        with_value(paper_data, parse_path("hub.mass_kg.x"), 1.0)
