"""``casadi-debris detumble``: its folder, its JSON, and bad rates refused."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from casadi_debris.cli import main


def test_a_small_tumble_writes_its_folder_and_json(tmp_path: Path) -> None:
    out = tmp_path / "d"
    arguments = ["detumble", "--rate-rad-s", "0.02,0.03,-0.02", "--out", str(out), "--json"]
    result = CliRunner().invoke(main, arguments)
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary == json.loads((out / "summary.json").read_text())
    assert summary["initial_rate_rad_s"] == [0.02, 0.03, -0.02]
    assert summary["momentum_bound_h"] <= summary["time_to_threshold_h"]
    assert len(summary["fuel_per_cubesat_kg"]) == 24
    assert {p.name for p in out.iterdir()} >= {"summary.json", "series.csv", "detumble.png"}


def test_bad_rates_are_refused_in_one_line(tmp_path: Path) -> None:
    for rates in ("1,2", "1,nan,0", "1,2,1000", "a,b,c"):
        result = CliRunner().invoke(main, ["detumble", "--rate-rad-s", rates, "--out", "x"])
        assert result.exit_code == 2, result.output
        assert result.stderr.count("\n") == 1 and "--rate-rad-s" in result.stderr
