"""The gallery of non-paper problems (``problems/gallery/*.toml``), checked independently.

For every file: it loads and builds a model; its mass is the hand sum of the
file's own numbers (read with :mod:`tomllib`, following ``extends`` here, not
through the package); its torque authority with zero net force is positive
about all six signed axes and equals a linear program written here over the
engines ``describe_model`` lists; the allocator meets half that authority
exactly; the command line describes it. The rigid one's linear plant is the
double integrator J^-1 / s^2.
"""

from __future__ import annotations

import json
import tomllib
from collections.abc import Sequence
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner
from scipy.optimize import linprog

from casadi_debris import load_problem
from casadi_debris.allocation import Allocator
from casadi_debris.cli import main
from casadi_debris.config import Problem, default_problem_path
from casadi_debris.dynamics import build_model, linearize
from casadi_debris.geometry import build_geometry, torque_authority
from casadi_debris.report import Thruster, describe_model

GALLERY = default_problem_path().parent / "gallery"
FILES = sorted(GALLERY.glob("*.toml"))
SIGNED_AXES = ("+x", "-x", "+y", "-y", "+z", "-z")
ALL_FACES = ["+x", "-x", "+y", "-y", "+z", "-z"]
REQUIRED = {
    "rigid_no_arrays",
    "one_array",
    "three_faces",
    "two_per_face",
    "side_engines_12",
    "differential_2u",
}
RTOL = 1e-9

gallery_file = pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])


@cache
def _problem(path: Path) -> Problem:
    return load_problem(path)


@cache
def _authority(path: Path) -> dict[str, float]:
    """The package's torque authority with zero net force [N m]."""
    return torque_authority(build_geometry(_problem(path)), zero_net_force=True)


# ------------------------------------------------------------------ hand computations


def _bodies(path: Path) -> dict[str, Any]:
    """Hub, arrays and CubeSats of a file as it gives them, ``extends`` followed by hand.

    Tables merge key by key (only the hub's matter here), lists replace the
    parent's whole, and CubeSats given in either form drop the parent's.
    """
    with path.open("rb") as handle:
        data = tomllib.load(handle)
    base = _bodies(path.parent / data["extends"]) if "extends" in data else {}
    swarm_keys = ("cubesats", "cubesat_layout")
    own_swarm = {key: data[key] for key in swarm_keys if key in data}
    return {
        "hub": {**base.get("hub", {}), **data.get("hub", {})},
        "arrays": data.get("arrays", base.get("arrays", [])),
        "swarm": own_swarm or base.get("swarm", {}),
    }


def _hand_count_and_mass(path: Path) -> tuple[int, float]:
    """Number of CubeSats and total mass: hub + arrays + CubeSats [kg]."""
    bodies = _bodies(path)
    swarm = bodies["swarm"]
    if "cubesats" in swarm:
        count = len(swarm["cubesats"])
        cubesats_kg = sum(c["mass_kg"] for c in swarm["cubesats"])
    else:
        layout = swarm["cubesat_layout"]
        count = len(layout.get("faces", ALL_FACES)) * layout["per_face"]
        cubesats_kg = count * layout["mass_kg"]
    arrays_kg = sum(a["mass_kg"] for a in bodies["arrays"])
    return count, bodies["hub"]["mass_kg"] + arrays_kg + cubesats_kg


def _lp_authority(thrusters: Sequence[Thruster]) -> dict[str, float]:
    """Largest pure torque per signed axis with zero net force, by an LP written here [N m].

    Torque of an engine: r x F, r its ``position_m`` (from the CoG), F its
    ``direction`` times its thrust in [0, ``max_thrust_mN``].
    """
    r = np.array([t.position_m for t in thrusters], dtype=float)
    d = np.array([t.direction for t in thrusters], dtype=float)
    f_max = np.array([t.max_thrust_mN for t in thrusters], dtype=float) * 1e-3
    torque_per_N = np.cross(r, d).T  # (3, n)
    authority = {}
    for name in SIGNED_AXES:
        axis = "xyz".index(name[1])
        sign = 1.0 if name[0] == "+" else -1.0
        others = [a for a in range(3) if a != axis]
        equalities = np.vstack([torque_per_N[others], d.T])  # no other torque, no net force
        result = linprog(
            -sign * torque_per_N[axis],
            A_eq=equalities,
            b_eq=np.zeros(len(equalities)),
            bounds=[(0.0, f) for f in f_max],
            method="highs",
        )
        assert result.status == 0, result.message
        authority[name] = -result.fun
    return authority


# ------------------------------------------------------------------ the gallery as a whole


def test_gallery_holds_the_required_configurations():
    assert {p.stem for p in FILES} >= REQUIRED
    assert len(FILES) >= len(REQUIRED) + 1  # and at least one real-life-like debris


@gallery_file
def test_name_is_the_file_stem_and_there_is_a_description(path):
    problem = _problem(path)
    assert problem.name == path.stem
    assert len(problem.description) > 100


# ------------------------------------------------------------------ per file


@gallery_file
def test_loads_and_builds_a_model(path):
    problem = _problem(path)
    model = build_model(problem)
    modes = sum(len(a.modes) for a in problem.arrays)
    assert model.layout.n_eta == modes
    assert len(problem.engines) == len(build_geometry(problem).engines) > 0


@gallery_file
def test_mass_is_the_hand_sum_of_the_file(path):
    problem = _problem(path)
    count, mass_kg = _hand_count_and_mass(path)
    assert len(problem.cubesats) == count
    assert build_geometry(problem).mass_kg == pytest.approx(mass_kg, rel=1e-12)


@gallery_file
def test_torque_authority_matches_an_independent_lp(path):
    authority = _authority(path)
    assert all(authority[name] > 0.0 for name in SIGNED_AXES), authority
    # describe_model rounds positions to 1 um; the optimal firings pair engines that share
    # their rounded coordinates, so the rounding cancels to round-off on these files.
    ours = _lp_authority(describe_model(_problem(path)).thrusters)
    for name in SIGNED_AXES:
        assert ours[name] == pytest.approx(authority[name], rel=RTOL), name


@gallery_file
def test_allocation_meets_half_the_authority_exactly(path):
    problem = _problem(path)
    allocator = Allocator.from_problem(problem)
    limits = allocator.max_thrust_N
    for name, tau_max in _authority(path).items():
        demand = np.zeros(3)
        demand["xyz".index(name[1])] = (0.5 if name[0] == "+" else -0.5) * tau_max
        result = allocator.allocate(demand)
        assert result.feasible and result.mode == "exact", name
        assert np.all(result.thrust_N >= 0.0) and np.all(result.thrust_N <= limits)
        tolerance = RTOL * np.abs(demand).max()
        np.testing.assert_allclose(result.torque_Nm, demand, rtol=0.0, atol=tolerance)
        assert np.abs(result.force_N).max() <= RTOL * max(result.thrust_N.sum(), 1e-12)


@gallery_file
def test_command_line_model_and_budget(path):
    runner = CliRunner()
    described = runner.invoke(main, ["model", str(path), "--json"])
    assert described.exit_code == 0, described.output
    summary = json.loads(described.output)
    assert summary["problem"] == path.stem
    for name, tau in _authority(path).items():
        assert summary["torque_max_zero_force_mNm"][name] == pytest.approx(tau * 1e3, rel=RTOL)
    budget = runner.invoke(main, ["budget", str(path), "--json"])
    assert budget.exit_code == 0, budget.output
    figures = json.loads(budget.output)
    assert figures["problem"] == path.stem
    assert all(np.isfinite(v) and v > 0 for k, v in figures.items() if k.endswith("_m_s"))


# ------------------------------------------------------------------ the rigid debris


def test_rigid_debris_is_a_double_integrator():
    problem = _problem(GALLERY / "rigid_no_arrays.toml")
    assert problem.arrays == ()
    model = build_model(problem)
    assert model.layout.n_eta == 0
    plant = linearize(model)
    inertia = build_geometry(problem).inertia_total_kgm2
    assert plant.A.shape == (6, 6)
    expected_a = np.zeros((6, 6))
    expected_a[0:3, 3:6] = np.eye(3)  # d theta / dt = omega
    np.testing.assert_allclose(plant.A, expected_a, rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(plant.B[0:3], 0.0, rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(plant.B[3:6], np.linalg.inv(inertia), rtol=1e-12)
