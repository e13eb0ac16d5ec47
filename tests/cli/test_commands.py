"""The command line: JSON keys, readable tables, and bad input without tracebacks."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from casadi_debris.cli import main

MODEL_KEYS = {
    "mass_kg",
    "inertia_hub_cubesats_kgm2",
    "inertia_total_kgm2",
    "cog_m",
    "torque_max_mNm",
    "modes",
    "thrusters",
}
MODE_KEYS = {
    "array",
    "name",
    "omega_rad_s",
    "omega_free_rad_s",
    "zeta",
    "mass_fraction",
    "root_inertia_fraction",
}
THRUSTER_KEYS = {"cubesat", "face", "position_m", "direction", "max_thrust_mN"}
BUDGET_KEYS = {
    "dv_one_stage_one_face_m_s",
    "dv_three_stages_one_face_m_s",
    "dv_one_stage_all_faces_m_s",
    "dv_all_stages_all_faces_m_s",
    "dv_cubesat_one_stage_m_s",
    "dv_transfer_m_s",
    "detumble_time_h",
    "detumble_dv_m_s",
    "stage_propellant_kg",
    "stage_life_h",
}


@pytest.fixture(scope="module")
def runner():
    return CliRunner()


@pytest.fixture(scope="module")
def model_json(runner):
    result = runner.invoke(main, ["model", "--json"])
    assert result.exit_code == 0, result.output
    return json.loads(result.output)


def test_model_json_keys(model_json):
    assert set(model_json) >= MODEL_KEYS
    assert set(model_json["torque_max_mNm"]) == {"+x", "-x", "+y", "-y", "+z", "-z"}
    assert len(model_json["inertia_total_kgm2"]) == 3
    assert len(model_json["modes"]) == 6
    assert all(set(m) >= MODE_KEYS for m in model_json["modes"])
    assert len(model_json["thrusters"]) == 24
    assert all(set(t) >= THRUSTER_KEYS for t in model_json["thrusters"])


def test_model_json_is_consistent_with_positions(model_json):
    # Torque authority about +x from the thruster list, by the same LP written independently.
    import numpy as np
    from scipy.optimize import linprog

    positions = np.array([t["position_m"] for t in model_json["thrusters"]])
    directions = np.array([t["direction"] for t in model_json["thrusters"]])
    limits = np.array([t["max_thrust_mN"] for t in model_json["thrusters"]])
    torque_map = np.cross(positions, directions).T
    result = linprog(
        -torque_map[0], A_eq=torque_map[1:], b_eq=[0, 0], bounds=[(0, f) for f in limits]
    )
    assert -result.fun == pytest.approx(model_json["torque_max_mNm"]["+x"], rel=1e-5)


def test_model_table_compares_with_paper(runner):
    result = runner.invoke(main, ["model"])
    assert result.exit_code == 0
    assert "paper" in result.output
    assert "OUTSIDE" not in result.output
    assert "bending1" in result.output and "omega_free" in result.output


def test_budget_json_and_table(runner):
    result = runner.invoke(main, ["budget", "--json"])
    assert result.exit_code == 0
    payload = json.loads(result.output)
    assert set(payload) >= BUDGET_KEYS
    assert set(payload["how"]) >= BUDGET_KEYS
    table = runner.invoke(main, ["budget"])
    assert table.exit_code == 0
    assert "Edelbaum" in table.output
    assert "OUTSIDE" not in table.output


def test_explicit_problem_file(runner):
    paper = Path(__file__).parents[2] / "problems" / "paper.toml"
    result = runner.invoke(main, ["budget", str(paper), "--json"])
    assert result.exit_code == 0


@pytest.mark.parametrize(
    ("content", "words"),
    [
        ('extends = "{paper}"\n[hub]\nmass_kg = -1.0\n', "hub.mass_kg: must be positive"),
        ('extends = "{paper}"\n[hub]\nmass_kg = nan\n', "hub.mass_kg: must be finite"),
        ('extends = "{paper}"\n[hub]\ncolour = "grey"\n', "hub.colour: unknown key"),
        ("[hub\n", "not valid TOML"),
    ],
)
def test_bad_problem_file_one_line_exit_2(runner, tmp_path, content, words):
    paper = Path(__file__).parents[2] / "problems" / "paper.toml"
    bad = tmp_path / "bad.toml"
    bad.write_text(content.format(paper=paper))
    for command in ("model", "budget"):
        result = runner.invoke(main, [command, str(bad)])
        assert result.exit_code == 2
        assert words in result.output
        assert "Traceback" not in result.output
        assert result.output.count("\n") == 1


def test_missing_problem_file(runner, tmp_path):
    result = runner.invoke(main, ["model", str(tmp_path / "nope.toml")])
    assert result.exit_code == 2
    assert "no such problem file" in result.output


def test_console_script_installed():
    result = subprocess.run(
        [sys.executable, "-m", "casadi_debris.cli", "budget", "--json"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    assert "dv_transfer_m_s" in json.loads(result.stdout)


def test_synthesize_quick_writes_a_loadable_controller(runner, tmp_path):
    out = tmp_path / "k"
    arguments = ["synthesize", "--out", str(out), "--json", "--mu-points", "10"]
    arguments += ["--max-iterations", "0", "--samples", "1"]
    result = runner.invoke(main, arguments)
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    for key in ("mu_peak", "order_full", "order_reduced", "mu_peak_reduced", "hinf_gamma_first",
                "iterations", "time_s", "w_fit_order", "w_fit_samples"):  # fmt: skip
        assert key in summary
    data = json.loads((out / "controller.json").read_text())
    assert json.loads((out / "summary.json").read_text()) == summary
    assert summary["controller_path"] == str((out / "controller.json").absolute())
    for key in ("A", "B", "C", "D", "mu_peak", "mu_peak_reduced", "order_full", "order_reduced",
                "problem_sha256", "seed"):  # fmt: skip
        assert key in data
    assert len(data["A"]) == data["order_reduced"]


def test_margins_json_and_plots(runner, tmp_path):
    out = tmp_path / "run"
    result = runner.invoke(main, ["margins", "--samples", "70", "--out", str(out), "--json"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    for block in ("nominal", "sampled_min"):
        assert set(summary[block]) >= {"gain_margin_db", "phase_margin_deg", "delay_margin_s"}
    assert summary["samples"] == 70 and "controller_path" in summary and "seed" in summary
    assert set(summary["per_channel"]) == {"x", "y", "z"}
    for name in (
        "mu.png",
        "uncertainty_weight.png",
        "loop_shapes.png",
        "margins.png",
        "summary.json",
    ):
        assert (out / name).stat().st_size > 0


@pytest.mark.parametrize(
    ("content", "words"),
    [("{", "not a readable JSON"), ('{"A": []}', "B: missing"), ("[1, 2]", "JSON object")],
)
def test_margins_bad_controller_file(runner, tmp_path, content, words):
    bad = tmp_path / "k.json"
    bad.write_text(content)
    result = runner.invoke(main, ["margins", "--controller", str(bad), "--samples", "5"])
    assert result.exit_code == 2
    assert words in result.output and "Traceback" not in result.output
