"""``casadi-debris slew`` flies the problem's own slew unless an option says otherwise."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from casadi_debris import load_problem
from casadi_debris.cli import main
from casadi_debris.guidance import scenario_reference
from slew_reference import every_profile_checked  # noqa: F401 (autouse)


def _slew(*arguments: str) -> dict:
    result = CliRunner().invoke(main, ["slew", *arguments, "--json"])
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)


def test_the_problems_slew_is_the_one_simulate_flies() -> None:
    summary = _slew("paper_slew")
    flown = scenario_reference(load_problem("paper_slew")).slew
    assert flown is not None
    assert summary["duration_s"] == pytest.approx(flown.duration_s, rel=1e-12)
    assert summary["axis_B"] == [0.0, 0.0, 1.0] and summary["method"] == "bang-bang"
    assert summary["angle_deg"] == pytest.approx(180.0)


def test_an_option_wins_over_the_file() -> None:
    assert _slew("paper_slew", "--duration-s", "1300")["duration_s"] == pytest.approx(1300.0)
    # Another axis is another slew: the file's timing is not carried over to it.
    about_x = _slew("paper_slew", "--axis", "x")
    assert about_x["axis_B"] == [1.0, 0.0, 0.0]
    assert about_x["duration_s"] == pytest.approx(_slew("paper", "--axis", "x")["duration_s"])


def test_without_a_slew_in_the_file_the_defaults_stay() -> None:
    assert load_problem("paper").simulation.slew is None
    summary = _slew("paper")
    assert summary["axis_B"] == [0.0, 0.0, 1.0] and summary["angle_deg"] == pytest.approx(180.0)
    assert summary["duration_s"] < 1228.0  # full authority, faster than the paper's 1228 s


def test_the_wall_time_is_what_the_user_waited_and_covers_the_solve() -> None:
    import time

    started = time.perf_counter()
    summary = _slew("paper")
    waited = time.perf_counter() - started
    assert summary["solve_time_s"] <= summary["wall_time_s"] <= waited


# rigid_no_arrays's thruster-level slew runs by default in tests/workflows/test_slew.py.
GALLERY_QUICK = ("side_engines_12",)
GALLERY_SLOW = (
    "rigid_no_arrays",
    "differential_2u",
    "fewer_stronger",
    "one_array",
    "three_faces",
    "two_per_face",
    "zenit2_upper_stage",
)
THRUSTER_SLEW = ("--method", "time-optimal", "--thrusters", "--starts", "1", "--sample-s", "20")


def _thruster_slew_every_way(problem: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The thruster-level time-optimal slew as a user types it: plain text, and ``--json
    --out`` (one call: the printed record, the folder it writes, and the two agree).

    The command matrix leaves its own cell of this command to the slow run: this is it.
    """
    runner = CliRunner()
    monkeypatch.chdir(tmp_path)
    plain = runner.invoke(main, ["slew", problem, *THRUSTER_SLEW])
    assert plain.exit_code == 0, plain.output
    assert "time-optimal" in plain.stdout and "duration [s]" in plain.stdout
    assert "Traceback" not in plain.output
    assert not (tmp_path / "runs").exists(), "plain text without --out wrote a folder"
    out = tmp_path / "written"  # not the problem's name: the working folder is tmp_path
    as_json = runner.invoke(main, ["slew", problem, *THRUSTER_SLEW, "--json", "--out", str(out)])
    assert as_json.exit_code == 0, as_json.output
    summary = json.loads(as_json.stdout)
    assert summary["method"] == "time-optimal" and summary["thrusters"] is True
    assert summary["problem"] == problem and summary["duration_s"] > 0.0
    saved = json.loads((out / "summary.json").read_text())
    assert saved["duration_s"] == pytest.approx(summary["duration_s"], rel=1e-6)
    assert (out / "profile.csv").is_file() and (out / "slew.png").is_file()
    header = (out / "profile.csv").read_text().splitlines()[0].split(",")
    assert sum(column.startswith("thrust_") for column in header) == len(
        load_problem(problem).engines
    )


@pytest.mark.parametrize("problem", ("paper", *GALLERY_QUICK))
def test_thruster_level_time_optimal_slew_runs_every_way(
    problem: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    _thruster_slew_every_way(problem, tmp_path, monkeypatch)


@pytest.mark.slow
@pytest.mark.parametrize("problem", GALLERY_SLOW)
def test_thruster_level_time_optimal_slew_runs_on_every_gallery_problem(
    problem: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    _thruster_slew_every_way(problem, tmp_path, monkeypatch)


def test_workers_1_solves_every_start_in_this_process(monkeypatch: pytest.MonkeyPatch) -> None:
    import casadi_debris.parallel as parallel

    def no_processes(*arguments: object, **keywords: object) -> None:
        raise AssertionError("a worker process was started")

    monkeypatch.setattr(parallel, "_process_map", no_processes)
    arguments = ["--method", "time-optimal", "--starts", "4", "--workers", "1", "--sample-s", "20"]
    result = CliRunner().invoke(main, ["slew", *arguments, "--json"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["workers"] == 1 and summary["starts"] == 4


def test_workers_below_one_is_refused_naming_the_option() -> None:
    result = CliRunner().invoke(main, ["slew", "--method", "time-optimal", "--workers", "0"])
    assert result.exit_code == 2
    assert "--workers" in result.output and "Traceback" not in result.output


def test_each_slew_of_a_sequence_reports_its_limit_check() -> None:
    result = CliRunner().invoke(main, ["slew", "paper_sequence", "--json"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    slews = [s for s in summary["segments"] if s["kind"] == "slew"]
    fractions = [
        segment.slew.torque_fraction
        for segment in load_problem("paper_sequence").simulation.segments
        if segment.slew is not None
    ]
    assert len(slews) == len(fractions) == 2
    for record, fraction in zip(slews, fractions, strict=True):
        assert record["limits_ok"] is True
        # sized to the share its file gives, gyroscopic torque included (sampled)
        assert record["worst_authority_share"] <= fraction * (1 + 1e-6)
        assert record["worst_authority_share"] == pytest.approx(fraction, rel=1e-3)
    assert summary["slews_within_limits"] is True


def test_a_thruster_level_slew_of_the_file_writes_every_engines_thrust(tmp_path: Path) -> None:
    """The file's ``thrusters = true`` makes the slew thruster level without --thrusters:
    profile.csv holds the thrust of every engine, as for the option."""
    from casadi_debris.config import default_problem_path

    gallery = default_problem_path().parent / "gallery" / "rigid_no_arrays.toml"
    path = tmp_path / "own_thrusters.toml"
    path.write_text(
        f'extends = "{gallery}"\nname = "own_thrusters"\n[simulation]\nduration_s = 1500.0\n'
        'reference = "slew"\n[simulation.slew]\naxis = "z"\nangle_deg = 30.0\n'
        'method = "time-optimal"\nthrusters = true\n'
    )
    out = tmp_path / "run"
    arguments = [str(path), "--starts", "1", "--workers", "1", "--sample-s", "20"]
    summary = _slew(*arguments, "--out", str(out))
    assert summary["thrusters"] is True and summary["limits_zero_net_force"] is True
    header = (out / "profile.csv").read_text().splitlines()[0].split(",")
    engines = len(load_problem(path).engines)
    assert [c for c in header if c.startswith("thrust_")] == [
        f"thrust_{i:02d}_mN" for i in range(1, engines + 1)
    ]
