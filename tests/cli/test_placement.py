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
from casadi_debris.studies.placement import ParetoPointSummary, PlacementSummary
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


FIGURE_KEYS = {
    "count",
    "torque_max_zero_force_mNm",
    "ratio_to_disturbance",
    "worst_axis",
    "worst_ratio",
    "rigid_slew_s",
    "slowest_slew_s",
    "dv_one_stage_m_s",
    "weakest_dv_one_stage_m_s",
    "added_inertia_kgm2",
    "mass_kg",
}
FAILURE_KEYS = {"failures", "sets", "torque_min_zero_force_mNm", "worst_ratio", "failed"}
SUMMARY_KEYS = FIGURE_KEYS | {
    "problem",
    "problem_sha256",
    "objective",
    "count_limits",
    "candidates",
    "limits",
    "solver",
    "chosen",
    "worst_failure",
    "input_layout",
    "pareto",
    "out_dir",
}
SOLVER_KEYS = {
    "backend",
    "optimal",
    "objective",
    "upper_bound",
    "gap",
    "mip_rel_gap",
    "method",
    "blocks_extensive",
    "blocks_used",
    "time_s",
    "solves",
}
SOLVE_KEYS = {"status", "message", "time_s", "variables", "binaries", "rows", "blocks"} | {
    "nodes",
    "mip_gap",
}


def test_the_json_keeps_its_keys_and_is_the_written_summary(placed):
    """Other tools read these names: the typed summary writes exactly them."""
    out, summary = placed
    assert json.loads((out / "summary.json").read_text()) == summary
    assert set(summary) == SUMMARY_KEYS
    assert set(summary["input_layout"]) == FIGURE_KEYS | {"among_candidates", "worst_failure"}
    assert set(summary["worst_failure"]) == set(summary["input_layout"]["worst_failure"])
    assert set(summary["worst_failure"]) == FAILURE_KEYS
    assert set(summary["solver"]) == SOLVER_KEYS
    assert {frozenset(s) for s in summary["solver"]["solves"]} == {frozenset(SOLVE_KEYS)}
    assert set(summary["candidates"]) == {"grid_per_face", "mounts", "candidates", "side_engines"}
    assert set(summary["limits"]) == {"max_added_inertia_kgm2", "max_slew_s", "slew_angle_deg"}
    assert {frozenset(c) for c in summary["chosen"]} == {
        frozenset({"cubesat", "candidate", "mount", "face", "template", "position_corner_m"})
    }
    assert summary["pareto"] == [] and summary["out_dir"] == str(out.absolute())
    assert [c["cubesat"] for c in summary["chosen"]] == list(range(1, 13))


def test_the_summary_reads_back_into_its_record(placed):
    _, summary = placed
    record = PlacementSummary.from_json(summary)
    assert record.to_json() == summary
    assert record.figures.count == summary["count"] == len(record.chosen)
    assert record.solver.solves[0].status == summary["solver"]["solves"][0]["status"]
    assert (
        record.input_layout.worst_failure.failed
        == summary["input_layout"]["worst_failure"]["failed"]
    )
    with pytest.raises(ValueError, match="unknown field"):
        PlacementSummary.from_json({**summary, "extra": 1})


def test_pareto_points_keep_their_keys_and_read_back():
    point = ParetoPointSummary("N=8", 8, 1.44, "+y", 2319.2, 0.0, None, True, True, (2, 3, 5))
    written = point.to_json()
    assert set(written) == {
        "label",
        "count",
        "worst_ratio",
        "worst_axis",
        "slowest_slew_s",
        "weakest_dv_one_stage_m_s",
        "max_slew_s",
        "optimal",
        "on_front",
        "candidates",
    }
    assert written["candidates"] == [2, 3, 5] and written["max_slew_s"] is None
    assert ParetoPointSummary.from_json(written) == point
    assert ParetoPointSummary.from_json({**written, "candidates": None}).candidates is None


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
    from casadi_debris.studies.placement import OBJECTIVES

    assert tuple(OBJECTIVES) == OBJECTIVE_NAMES


_CHATTY_PLACEMENT = """
import os, sys
import casadi_debris.studies.placement._milp as placement_milp
from casadi_debris.cli import main

real = placement_milp.milp

def chatty(*args, **kwargs):
    # What HiGHS does at times whatever its log options: print from C on descriptor 1.
    os.write(1, b"Running HiGHS 9.9.9: chatter\\nPresolving model\\n")
    return real(*args, **kwargs)

placement_milp.milp = chatty
main(sys.argv[1:])
"""


# Quiet by default; the verbose run (the same placement, its log shown) under -m slow.
@pytest.mark.parametrize("verbose", [False, pytest.param(True, marks=pytest.mark.slow)])
def test_solver_log_lines_stay_quiet_unless_verbose(tmp_path, verbose):
    """The solver's own lines reach neither stdout nor the terminal, except with -v."""
    args = ["-v"] if verbose else []
    # The smallest placement that still runs the solver: the log's way is checked, not the answer.
    args += ["placement", "--count", "4", "--candidates", "1", "--out", str(tmp_path / "r")]
    for json_flag in ([], ["--json"]):
        run = subprocess.run(
            [sys.executable, "-c", _CHATTY_PLACEMENT, *args, *json_flag],
            capture_output=True,
            text=True,
            check=False,
        )
        assert run.returncode == 0, run.stderr
        assert "chatter" not in run.stdout and "Presolving" not in run.stdout
        assert ("chatter" in run.stderr) == verbose, run.stderr
        assert ("HiGHS: Running HiGHS 9.9.9: chatter" in run.stderr) == verbose, run.stderr
        if json_flag:
            assert json.loads(run.stdout)["count"] == 4
        args = [*args[:-1], str(tmp_path / "r2")]


def test_the_failure_row_says_what_it_counts(runner, tmp_path):
    """Text output of a small single-failure placement: the row names the failures it is
    the worst over, and equals the least authority over disturbance the JSON gives; with no
    failure objective there is no such row (it would repeat the nominal one)."""
    args = ["placement", "--count", "6", "--candidates", "2x2"]
    single = runner.invoke(
        main, [*args, "--objective", "worst-single-failure", "--out", str(tmp_path / "a")]
    )
    assert single.exit_code == 0, single.output
    summary = json.loads((tmp_path / "a" / "summary.json").read_text())
    worst = summary["worst_failure"]
    (row,) = [line for line in single.stdout.splitlines() if "failed" in line]
    assert row.startswith("worst authority / disturbance, any one CubeSat failed")
    ratio = min(worst["torque_min_zero_force_mNm"].values()) / 0.7
    assert float(row.split()[-2]) == pytest.approx(ratio, rel=1e-3)
    assert "any one CubeSat failed" in (tmp_path / "a" / "report.md").read_text()
    nominal = runner.invoke(main, [*args, "--out", str(tmp_path / "b")])
    assert nominal.exit_code == 0, nominal.output
    assert not [line for line in nominal.stdout.splitlines() if "failed" in line]
