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
from casadi_debris.report import (
    BudgetSummary,
    ModelSummary,
    budget_summary,
    describe_model,
    model_text,
)

GALLERY = default_problem_path().parent / "gallery"

# Every key ``model --json`` writes: scripts read them, so they stay.
DESCRIPTION_KEYS = {
    "problem", "problem_path", "problem_sha256", "mass_kg", "cog_m",
    "inertia_hub_cubesats_kgm2", "inertia_total_kgm2", "array_angle_deg", "arrays",
    "torque_max_mNm",
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
    described = ModelSummary.from_json(data)
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
    report = BudgetSummary.from_json(data)
    assert report == budget_summary(problem, items) and report.to_json() == data


ARRAYS_TOML = """
extends = "paper"

[[arrays]]                 # along +y from the +y face: faces z at angle 0
hinge_corner_m = [0.4, 3.0, 0.5]
direction = "+y"
mass_kg = 30.0
length_m = 6.0
width_m = 1.5
inertia_kgm2 = [90.0, 6.0, 96.0]
angle_deg = 0.0
damping_ratio = 0.005

[[arrays]]                 # along -x from the -x face, turned 30 deg about +x
hinge_corner_m = [0.0, 1.0, 0.5]
direction = "-x"
mass_kg = 20.0
length_m = 3.0
width_m = 1.0
inertia_kgm2 = [15.0, 2.0, 17.0]
angle_deg = 30.0
damping_ratio = 0.005

[[arrays]]                 # oblique, in the x-z plane from the +z face's edge
hinge_corner_m = [0.75, 2.0, 1.0]
direction = [1.0, 0.0, 2.0]
mass_kg = 10.0
length_m = 2.0
width_m = 1.0
inertia_kgm2 = [3.0, 1.0, 4.0]
angle_deg = -50.0
damping_ratio = 0.005
"""


def _expected_axes(direction: np.ndarray, angle_deg: float) -> tuple[np.ndarray, ...]:
    """The documented rule, computed here: at angle 0 the normal is the hub axis after the
    extent's main axis in cyclic order (made normal to the extent), then the angle turns
    it about the extent's positive-pointing axis (a rotation by scipy, not our code)."""
    from scipy.spatial.transform import Rotation

    extent = direction / np.linalg.norm(direction)
    main = int(np.argmax(np.abs(extent)))
    hinge_axis = extent if extent[main] > 0 else -extent
    normal0 = np.eye(3)[(main + 1) % 3]
    normal0 = normal0 - (normal0 @ extent) * extent
    normal0 /= np.linalg.norm(normal0)
    normal = Rotation.from_rotvec(np.radians(angle_deg) * hinge_axis).apply(normal0)
    return hinge_axis, extent, np.cross(normal, extent), normal


def test_model_prints_each_arrays_hinge_extent_and_normal_as_the_guide_says(tmp_path) -> None:
    path = tmp_path / "arrays.toml"
    path.write_text(ARRAYS_TOML)
    problem = load_problem(path)
    summary = describe_model(problem)
    geometry = build_geometry(problem)
    directions = [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [1.0, 0.0, 2.0]]
    angles = [0.0, 30.0, -50.0]
    assert [a.array for a in summary.arrays] == [1, 2, 3]
    # The guide's examples: along +y faces +z; along -x turned 30 deg about +x.
    np.testing.assert_allclose(summary.arrays[0].normal, [0.0, 0.0, 1.0], atol=1e-9)
    half = np.sqrt(3.0) / 2.0
    np.testing.assert_allclose(summary.arrays[1].normal, [0.0, half, 0.5], atol=1e-6)
    rigid = np.array(geometry.inertia_hub_cubesats_kgm2)
    for printed, direction, angle, array in zip(
        summary.arrays, directions, angles, problem.arrays, strict=True
    ):
        expected = _expected_axes(np.array(direction), angle)
        got = [printed.hinge_axis, printed.extent, printed.width, printed.normal]
        for want, have in zip(expected, got, strict=True):
            np.testing.assert_allclose(have, want, atol=2e-6)
        np.testing.assert_allclose(printed.hinge_corner_m, array.hinge_corner_m)
        hinge = np.array(array.hinge_corner_m) - geometry.cog_corner_m
        np.testing.assert_allclose(printed.hinge_m, hinge, atol=1e-6)
        # The printed axes are those the model's inertia uses: rebuild it from them.
        axes = np.array([printed.extent, printed.width, printed.normal]).T
        cog = hinge + 0.5 * array.length_m * axes[:, 0]
        rigid = rigid + axes @ np.diag(array.inertia_kgm2) @ axes.T
        rigid = rigid + array.mass_kg * (cog @ cog * np.eye(3) - np.outer(cog, cog))
    np.testing.assert_allclose(rigid, geometry.inertia_total_kgm2, atol=1e-4)
    text = model_text(summary, show_paper=False)
    assert "along ±y faces +z" in text and "[0, 0.866, 0.5]" in text


def test_a_rigid_debris_prints_no_array_table() -> None:
    summary = describe_model(load_problem(GALLERY / "rigid_no_arrays.toml"))
    assert summary.arrays == ()
    assert "hinge axis" not in model_text(summary, show_paper=False)
