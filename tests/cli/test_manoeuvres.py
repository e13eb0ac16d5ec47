"""Manoeuvres from the command line: any axis, sequences in slew and simulate, bad segments."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from scipy.spatial.transform import Rotation

from casadi_debris.cli import main
from casadi_debris.config import default_problem_path
from workflow_files import SEQUENCE

PROBLEMS = default_problem_path().parent


def invoke(*args: str) -> tuple[int, str, str]:
    result = CliRunner().invoke(main, list(args), catch_exceptions=False)
    return result.exit_code, result.stdout, result.stderr


def problem_file(folder: Path, body: str, name: str = "manoeuvre") -> Path:
    path = folder / f"{name}.toml"
    path.write_text(f'extends = "{PROBLEMS / "paper.toml"}"\nname = "{name}"\n{body}')
    return path


def test_slew_takes_any_axis() -> None:
    code, stdout, stderr = invoke("slew", "paper", "--axis", "1,1,1", "--angle-deg", "30", "--json")
    assert code == 0, stderr
    summary = json.loads(stdout)
    assert np.allclose(summary["axis_B"], np.ones(3) / math.sqrt(3.0), atol=1e-12)
    assert summary["angle_deg"] == pytest.approx(30.0)


def test_simulate_takes_any_axis(tmp_path: Path) -> None:
    """paper_slew about [1, 1, 1] by 10 deg: the reference ends at scipy's rotation."""
    out = tmp_path / "run"
    code, _, stderr = invoke(
        "simulate", "paper_slew", "--axis", "1,1,1", "--angle-deg", "10", "--duration-s", "600",
        "--out", str(out), "--no-plots", "--json",
    )  # fmt: skip
    assert code == 0, stderr
    assert "torque fraction 0.561" in stderr
    with (out / "series.csv").open() as handle:
        last = list(csv.DictReader(handle))[-1]
    expected = Rotation.from_rotvec(math.radians(10.0) * np.ones(3) / math.sqrt(3.0))
    yaw, pitch, roll = expected.as_euler("ZYX", degrees=True)
    written = [float(last[f"reference_{name}_deg"]) for name in ("roll", "pitch", "yaw")]
    assert np.allclose(written, [roll, pitch, yaw], atol=1e-7)


def test_simulate_axis_needs_a_slew() -> None:
    code, stdout, stderr = invoke("simulate", "paper_pointing", "--axis", "1,1,1")
    assert code == 2 and "Traceback" not in stdout + stderr
    assert stderr.startswith("error: --axis: paper_pointing flies no slew")


def test_slew_of_a_sequence_writes_every_segment(tmp_path: Path) -> None:
    path = problem_file(tmp_path, SEQUENCE)
    out = tmp_path / "reference"
    code, stdout, stderr = invoke("slew", str(path), "--out", str(out), "--json")
    assert code == 0, stderr
    summary = json.loads(stdout)
    rows = [(s["segment"], s["kind"], s["start_s"], s["end_s"]) for s in summary["segments"]]
    assert rows == [(1, "slew", 0.0, 600.0), (2, "hold", 600.0, 700.0), (3, "track", 700.0, 2000.0)]
    assert summary["segments"][0]["angle_deg"] == pytest.approx(30.0)
    assert {p.name for p in out.iterdir()} >= {"summary.json", "profile.csv", "reference.png"}
    with (out / "profile.csv").open() as handle:
        rows_csv = list(csv.DictReader(handle))
    hold = [r for r in rows_csv if 610.0 <= float(r["time_s"]) <= 690.0]
    assert all(float(r["yaw_deg"]) == pytest.approx(30.0, abs=1e-9) for r in hold)
    code, _, stderr = invoke("slew", str(path), "--duration-s", "100")
    assert code == 2 and "--duration-s: manoeuvre's [[simulation.segments]] set each slew" in stderr


@pytest.mark.parametrize(
    ("segments", "key", "words"),
    [
        ('kind = "spin"\nduration_s = 10.0', "simulation.segments[0].kind", "must be one of"),
        (
            'kind = "slew"\nquaternion = [0.9, 0.1, 0.0, 0.0]',
            "simulation.segments[0].quaternion",
            "unit norm",
        ),
        ('kind = "hold"\nduration_s = -10.0', "simulation.segments[0].duration_s", "positive"),
        (
            'kind = "hold"\nduration_s = 100.0\n[[simulation.segments]]\nkind = "hold"\n'
            "start_s = 50.0\nduration_s = 10.0",
            "simulation.segments[1].start_s",
            "overlaps",
        ),
    ],
)
def test_bad_segments_exit_2_naming_the_field(
    tmp_path: Path, segments: str, key: str, words: str
) -> None:
    body = '[simulation]\nreference = "sequence"\n[[simulation.segments]]\n' + segments + "\n"
    path = problem_file(tmp_path, body)
    for command in ("simulate", "slew"):
        code, stdout, stderr = invoke(command, str(path), "--out", str(tmp_path / command))
        assert code == 2, stdout
        assert "Traceback" not in stdout + stderr and len(stderr.strip().splitlines()) == 1
        assert f": {key}: " in stderr and words in stderr
        assert not (tmp_path / command).exists()


@pytest.mark.slow  # the shipped sequence: 4800 s of closed loop and eight slew solves
def test_the_shipped_sequence_is_flown_within_the_requirement(tmp_path: Path) -> None:
    code, stdout, stderr = invoke("simulate", "paper_sequence", "--no-plots", "--json")
    assert code == 0, stderr
    summary = json.loads(stdout)
    assert summary["max_error_deg"] < 0.6  # the slews' requirement, through every segment
    assert summary["final_error_arcsec"] < 60.0  # pointing while tracking nadir
    assert summary["torque_saturated_s"] == 0.0


def test_simulate_of_a_sequence_figures_every_segment(tmp_path: Path) -> None:
    path = problem_file(tmp_path, SEQUENCE)
    out = tmp_path / "run"
    code, stdout, stderr = invoke("simulate", str(path), "--out", str(out), "--no-plots")
    assert code == 0, stderr
    assert "max error [deg]" in stdout and "track" in stdout
    segments = json.loads((out / "segments.json").read_text())["segments"]
    assert [(s["segment"], s["kind"]) for s in segments] == [(1, "slew"), (2, "hold"), (3, "track")]
    summary = json.loads((out / "summary.json").read_text())
    assert sum(s["fuel_kg"] for s in segments) == pytest.approx(summary["fuel_kg"], rel=1e-12)
    assert max(s["max_error_deg"] for s in segments) == pytest.approx(summary["max_error_deg"])
