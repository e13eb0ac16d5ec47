"""``casadi-debris burn``: its folder, its JSON, and bad input refused in one line."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from casadi_debris.cli import main
from casadi_debris.report import BurnSummary


def test_a_short_burn_writes_its_folder_and_json(tmp_path: Path) -> None:
    out = tmp_path / "b"
    arguments = ["burn", "--hours", "0.005", "--direction", "normal", "--out", str(out), "--json"]
    arguments += ["--thrust-fraction", "0.5", "--first-stage-left-s", "3"]
    result = CliRunner().invoke(main, arguments)
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary == json.loads((out / "summary.json").read_text())
    assert BurnSummary.from_json(summary).to_json() == summary
    assert summary["direction"] == "normal" and summary["first_stage_left_s"] == 3.0
    assert abs(summary["thrust_mN"] - 0.5 * 2.56) <= 1e-12
    assert summary["burn_s"] == 18.0
    assert summary["stage_switches"] > 0
    split = summary["fuel_dv_kg"] + summary["fuel_attitude_kg"]
    assert abs(split - summary["fuel_kg"]) <= 1e-9 * summary["fuel_kg"]
    assert {p.name for p in out.iterdir()} >= {"summary.json", "series.csv", "burn.png"}
    header = (out / "series.csv").read_text().splitlines()[0].split(",")
    assert header[:3] == ["time_s", "pointing_error_arcsec", "thrust_along_mN"]


def test_bad_input_is_refused_in_one_line(tmp_path: Path) -> None:
    out = str(tmp_path / "x")
    cases = [
        (["--direction", "up"], "--direction"),
        (["--hours", "-1"], "--hours"),
        (["--body-axis", "0,0,0"], "--body-axis"),
        (["--body-axis", "w"], "--body-axis"),
        (["--thrust-fraction", "0.5", "--thrust-mN", "1"], "--thrust-mN"),
        (["--thrust-mN", "100", "--hours", "0.001"], "thrust_mN"),
    ]
    for extra, name in cases:
        result = CliRunner().invoke(main, ["burn", *extra, "--out", out])
        assert result.exit_code == 2, result.output
        assert result.stderr.count("\n") == 1 and name in result.stderr, result.stderr
    assert not (tmp_path / "x").exists()
