"""``model``'s description: engines with their CubeSats, and notes on what a debris does not use."""

from __future__ import annotations

from casadi_debris import load_problem
from casadi_debris.config import default_problem_path
from casadi_debris.report.describe import describe_model, model_text

GALLERY = default_problem_path().parent / "gallery"


def test_the_papers_problem_uses_every_uncertainty() -> None:
    summary = describe_model(load_problem())
    assert summary["notes"] == []
    assert [t["engine"] for t in summary["thrusters"]] == list(range(1, 25))
    assert [t["cubesat"] for t in summary["thrusters"]] == list(range(1, 25))


def test_a_rigid_debris_says_its_array_uncertainties_are_dropped() -> None:
    summary = describe_model(load_problem(GALLERY / "rigid_no_arrays.toml"))
    assert summary["modes"] == [] and summary["array_angle_deg"] == []
    [note] = summary["notes"]
    assert "uncertainty.array_angle_deg" in note and "bending_frequency_fraction" in note
    text = model_text(summary, show_paper=False)
    assert "Flexible modes: none" in text and text.endswith(note)


def test_engines_of_one_cubesat_share_its_id() -> None:
    summary = describe_model(load_problem(GALLERY / "side_engines_12.toml"))
    cubesats = [t["cubesat"] for t in summary["thrusters"]]
    assert cubesats == sorted(cubesats) and cubesats.count(1) == 5 and max(cubesats) == 12
