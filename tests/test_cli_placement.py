"""``casadi-debris placement``: the written problem file, the JSON contract, bad input."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris.cli import main
from casadi_debris.config import SIGNED_AXES, load_problem
from casadi_debris.geometry import build_geometry, torque_authority
from casadi_debris.units import MNM_PER_NM


@pytest.fixture(scope="module")
def runner():
    return CliRunner()


@pytest.fixture(scope="module")
def placed(runner, tmp_path_factory):
    """One run: 12 CubeSats among the paper's 24 mounts, worst single failure."""
    out = tmp_path_factory.mktemp("placement") / "run"
    args = [
        "placement",
        "--count",
        "12",
        "--candidates",
        "2x2",
        "--objective",
        "worst-single-failure",
        "--out",
        str(out),
        "--json",
    ]
    result = runner.invoke(main, args)
    assert result.exit_code == 0, result.output
    return out, json.loads(result.output)


def test_json_names_the_six_signed_axes_as_model_does(runner, placed):
    out, summary = placed
    model = json.loads(runner.invoke(main, ["model", str(out / "placement.toml"), "--json"]).output)
    assert list(summary["torque_max_zero_force_mNm"]) == list(model["torque_max_zero_force_mNm"])
    assert list(summary["torque_max_zero_force_mNm"]) == ["+x", "-x", "+y", "-y", "+z", "-z"]
    for name in SIGNED_AXES:
        assert summary["torque_max_zero_force_mNm"][name] == pytest.approx(
            model["torque_max_zero_force_mNm"][name], rel=1e-12
        )


def test_placement_toml_round_trips_through_the_loader(placed):
    out, summary = placed
    problem = load_problem(out / "placement.toml")
    assert len(problem.cubesats) == summary["count"] == 12
    assert problem.cubesat_layout is None
    paper = load_problem()
    assert problem.hub.mass_kg == paper.hub.mass_kg and len(problem.arrays) == 2
    authority = torque_authority(build_geometry(problem), zero_net_force=True)
    got = np.array([authority[n] * MNM_PER_NM for n in SIGNED_AXES])
    np.testing.assert_allclose(
        got, [summary["torque_max_zero_force_mNm"][n] for n in SIGNED_AXES], rtol=1e-12
    )
    for written, chosen in zip(problem.cubesats, summary["chosen"], strict=True):
        np.testing.assert_array_equal(written.position_corner_m, chosen["position_corner_m"])
        assert written.face == chosen["face"]


def test_summary_reports_the_solver_and_worst_failure(placed):
    out, summary = placed
    solver = summary["solver"]
    assert solver["optimal"] and solver["gap"] == 0.0
    assert solver["solves"] and solver["solves"][0]["status"] == 0
    worst = summary["worst_failure"]
    assert worst["failures"] == 1 and worst["sets"] == 12
    # The worst failure's authority is the objective, and below the nominal authority.
    ratio = min(worst["torque_min_zero_force_mNm"][n] for n in SIGNED_AXES) / 0.7
    assert ratio == pytest.approx(solver["objective"], rel=1e-9)
    for name in SIGNED_AXES:
        assert (
            worst["torque_min_zero_force_mNm"][name]
            <= summary["torque_max_zero_force_mNm"][name] + 1e-12
        )
        assert all(1 <= c <= 12 for c in worst["failed"][name])
    for name in ("summary.json", "report.md", "layout.png", "placement.toml"):
        assert (out / name).is_file()


def test_refuses_to_overwrite_a_folder_it_did_not_write(runner, tmp_path):
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("keep")
    result = runner.invoke(main, ["placement", "--candidates", "2x2", "--out", str(mine)])
    assert result.exit_code == 2
    assert (mine / "notes.txt").read_text() == "keep"


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--candidates", "4y4"], "--candidates"),
        (["--count", "30", "--candidates", "2x2"], "--count"),
        (["--count-range", "5-8"], "--count-range"),
        (["--count", "4", "--count-range", "4:8"], "--count"),
        (["--max-added-inertia", "1,2"], "--max-added-inertia"),
        (["--max-added-inertia", "-3"], "--max-added-inertia"),
        (["--side-engines", "3"], "--side-engines"),
        (["--objective", "best"], "--objective"),
        (
            ["--candidates", "2x2", "--count", "12", "--max-added-inertia", "1"],
            "--max-added-inertia",
        ),
        (["--pareto", "8,x"], "--pareto"),
    ],
)
def test_bad_input_one_line_exit_2(runner, tmp_path, args, words):
    out = tmp_path / "run"
    result = runner.invoke(main, ["placement", *args, "--out", str(out)])
    assert result.exit_code == 2, result.output
    assert words in result.output
    assert "Traceback" not in result.output
    assert result.output.count("\n") == 1
    assert not out.exists()


def test_bad_problem_file_names_the_field(runner, tmp_path):
    bad = tmp_path / "bad.toml"
    paper = load_problem().source
    bad.write_text(f'extends = "{paper}"\n[disturbance]\namplitude_mNm = [0.7, 0.0, 0.7]\n')
    result = runner.invoke(
        main, ["placement", str(bad), "--candidates", "2x2", "--out", str(tmp_path / "run")]
    )
    assert result.exit_code == 2
    assert "disturbance.amplitude_mNm" in result.output and result.output.count("\n") == 1


def test_solver_chatter_on_stdout_goes_to_stderr():
    """HiGHS at times prints to file descriptor 1 from C; --json must stay parseable."""
    code = (
        "import os\n"
        "from casadi_debris.cli.placement import solver_chatter_to_stderr\n"
        "with solver_chatter_to_stderr():\n"
        "    os.write(1, b'chatter\\n')\n"
        "print('{}')\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert json.loads(done.stdout) == {}
    assert "chatter" in done.stderr


def test_objective_names_are_the_studies_own():
    from casadi_debris.cli.placement import OBJECTIVE_NAMES
    from casadi_debris.studies.placement_milp import OBJECTIVES

    assert tuple(OBJECTIVES) == OBJECTIVE_NAMES
