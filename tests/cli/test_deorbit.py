"""``casadi-debris deorbit``: its folder, its JSON keys with units, and bad input refused."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from casadi_debris.cli import main


def test_one_case_writes_its_folder_and_json(tmp_path: Path) -> None:
    out = tmp_path / "d"
    arguments = ["deorbit", "--solar", "high", "--no-minimum-swarm", "--out", str(out), "--json"]
    result = CliRunner().invoke(main, arguments)
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary == json.loads((out / "summary.json").read_text())
    assert set(summary["reentry_years"]) == {"high"}
    assert summary["reentry_years"]["high"] <= 5.0 < summary["natural_lifetime_years"]["high"]
    assert summary["meets_five_year_rule"] is True
    assert 0.0 < summary["deorbit_dv_m_s"] < summary["capacity_dv_m_s"] < summary["budget_dv_m_s"]
    assert summary["minimum_swarm"] is None and summary["monte_carlo"] is None
    assert {p.name for p in out.iterdir()} >= {
        "summary.json",
        "decay_high.csv",
        "lifetime_vs_dv.csv",
        "decay.png",
        "lifetime_vs_dv.png",
    }

    text = CliRunner().invoke(main, [*arguments[:-3], "--out", str(tmp_path / "t")])
    assert text.exit_code == 0, text.output
    assert "5-year rule under high solar activity only" in text.stdout


def test_bad_input_is_refused_in_one_line_naming_the_option(tmp_path: Path) -> None:
    for arguments, name in (
        (["--solar", "extreme"], "--solar"),
        (["--solar", "low,,high"], "--solar"),
        (["--solar", "low,low"], "--solar"),
        (["--limit-years", "-1"], "--limit-years"),
        (["--drag-coefficient", "nan"], "--drag-coefficient"),
        (["--samples", "-3"], "--samples"),
    ):
        out = tmp_path / "never"
        result = CliRunner().invoke(main, ["deorbit", *arguments, "--out", str(out)])
        assert result.exit_code == 2, result.output
        assert result.stderr.count("\n") == 1 and name in result.stderr
        assert not out.exists()
