"""``model``'s description: engines with their CubeSats, notes on what a debris does not use,
and the one JSON form ``model --json`` prints."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris import load_problem
from casadi_debris.budgets import compute_budgets
from casadi_debris.cli import main
from casadi_debris.config import default_problem_path
from casadi_debris.geometry import build_geometry, max_thrust_N
from casadi_debris.report.describe import (
    BudgetReport,
    ModelDescription,
    budget_report,
    describe_model,
    model_text,
)

GALLERY = default_problem_path().parent / "gallery"

# Every key ``model --json`` writes: scripts read them, so they stay.
DESCRIPTION_KEYS = {
    "problem", "problem_path", "problem_sha256", "mass_kg", "cog_m",
    "inertia_hub_cubesats_kgm2", "inertia_total_kgm2", "array_angle_deg", "torque_max_mNm",
    "torque_max_zero_force_mNm", "modes", "thrusters", "notes",
}  # fmt: skip
MODE_KEYS = {
    "array", "name", "kind", "symmetry", "omega_rad_s", "omega_free_rad_s", "zeta",
    "zeta_free", "mass_fraction", "root_inertia_fraction",
}  # fmt: skip
THRUSTER_KEYS = {
    "engine", "cubesat", "cubesat_engine", "isp_s", "face", "position_m", "direction",
    "max_thrust_mN",
}  # fmt: skip
SIGNED_AXES = {"+x", "-x", "+y", "-y", "+z", "-z"}


def test_the_papers_problem_uses_every_uncertainty() -> None:
    summary = describe_model(load_problem())
    assert summary.notes == ()
    assert [t.engine for t in summary.thrusters] == list(range(1, 25))
    assert [t.cubesat for t in summary.thrusters] == list(range(1, 25))


def test_a_rigid_debris_says_its_array_uncertainties_are_dropped() -> None:
    summary = describe_model(load_problem(GALLERY / "rigid_no_arrays.toml"))
    assert summary.modes == () and summary.array_angle_deg == ()
    [note] = summary.notes
    assert "uncertainty.array_angle_deg" in note and "bending_frequency_fraction" in note
    text = model_text(summary, show_paper=False)
    assert "Flexible modes: none" in text and text.endswith(note)


def test_an_axis_the_engines_cannot_hold_is_noted_against_an_independent_lp() -> None:
    from scipy.optimize import linprog

    problem = load_problem(GALLERY / "differential_2u.toml")
    geometry = build_geometry(problem)
    limits = max_thrust_N(geometry)
    noted = " ".join(describe_model(problem).notes)
    bounds = list(zip(np.zeros_like(limits), limits, strict=True))
    for index, axis in enumerate("xyz"):
        # Largest torque either way about the axis at zero net force, by LPs of our own.
        authority_mNm = [
            -linprog(-sign * geometry.torque_map[index], A_eq=geometry.force_map,
                     b_eq=np.zeros(3), bounds=bounds).fun * 1e3
            for sign in (1.0, -1.0)
        ]  # fmt: skip
        below = min(authority_mNm) < problem.disturbance.amplitude_mNm[index]
        assert below == (f"cannot hold the debris about {axis}" in noted), axis


def test_engines_of_one_cubesat_share_its_id() -> None:
    summary = describe_model(load_problem(GALLERY / "side_engines_12.toml"))
    cubesats = [t.cubesat for t in summary.thrusters]
    assert cubesats == sorted(cubesats) and cubesats.count(1) == 5 and max(cubesats) == 12


@pytest.mark.parametrize("name", ["paper", "rigid_no_arrays"])
def test_model_json_keeps_its_keys_and_reads_back(name: str) -> None:
    path = None if name == "paper" else GALLERY / f"{name}.toml"
    problem = load_problem(path)
    printed = CliRunner().invoke(main, ["model", *([] if path is None else [str(path)]), "--json"])
    assert printed.exit_code == 0, printed.output
    data = json.loads(printed.output)
    assert set(data) == DESCRIPTION_KEYS
    assert all(set(mode) == MODE_KEYS for mode in data["modes"])
    assert all(set(thruster) == THRUSTER_KEYS for thruster in data["thrusters"])
    assert set(data["torque_max_mNm"]) == set(data["torque_max_zero_force_mNm"]) == SIGNED_AXES
    described = ModelDescription.from_json(data)
    assert described == describe_model(problem)
    assert described.to_json() == data
    # The values against the geometry, computed apart from the description.
    geometry = build_geometry(problem)
    assert data["mass_kg"] == geometry.mass_kg
    np.testing.assert_allclose(data["inertia_total_kgm2"], geometry.inertia_total_kgm2, atol=1e-6)
    np.testing.assert_allclose(data["cog_m"], geometry.cog_corner_m, atol=1e-6)
    assert [t["max_thrust_mN"] for t in data["thrusters"]] == pytest.approx(
        [e.max_thrust_N * 1e3 for e in geometry.engines], rel=1e-12
    )


def test_budget_json_is_the_figures_by_key_with_how_and_reads_back() -> None:
    problem = load_problem()
    items = compute_budgets(problem)
    printed = CliRunner().invoke(main, ["budget", "--json"])
    assert printed.exit_code == 0, printed.output
    data = json.loads(printed.output)
    keys = [item.key for item in items]
    assert list(data) == ["problem", "problem_sha256", *keys, "how"]
    assert [data[k] for k in keys] == [item.value for item in items]
    assert data["how"] == {item.key: item.how for item in items}
    assert data["problem_sha256"] == problem.sha256
    report = BudgetReport.from_json(data)
    assert report == budget_report(problem, items) and report.to_json() == data
