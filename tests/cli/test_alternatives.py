"""``casadi-debris alternatives``: the run folder, its JSON, and bad input."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from casadi_debris.cli import main
from casadi_debris.config import load_problem
from casadi_debris.studies.alternatives import swarm_figures


def test_alternatives_writes_the_figures_of_each_design(tmp_path: Path) -> None:
    out = tmp_path / "alt"
    designs = ["paper", "fewer_stronger"]
    arguments = ["--max-failed", "1", "--out", str(out), "--json"]
    result = CliRunner().invoke(main, ["-q", "alternatives", *designs, *arguments])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.output)
    assert json.loads((out / "summary.json").read_text()) == summary
    assert [d["problem"] for d in summary["designs"]] == ["paper", "fewer_stronger"]
    expected = swarm_figures(load_problem("fewer_stronger"), max_failed=1).to_json()
    assert summary["designs"][1] == json.loads(json.dumps(expected))
    assert summary["designs"][0]["double_failure"] is None
    with (out / "alternatives.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert [r["problem"] for r in rows] == ["paper", "fewer_stronger"]
    assert float(rows[0]["torque_max_+y_mNm"]) == pytest.approx(
        summary["designs"][0]["torque_max_zero_force_mNm"]["+y"]
    )
    numeric = [
        c for c in rows[0] if c not in {"problem", "weakest_axis"} and "worst_cubesats" not in c
    ]
    units = ("_kg", "_mNm", "_g_per_mNm_h", "_ratio", "_disturbance", "cubesats", "engines")
    assert all(c.endswith(units) for c in numeric), numeric
    assert (out / "alternatives.png").stat().st_size > 0
    assert "| `paper` | 24 / 24 | 84 |" in (out / "alternatives.md").read_text()


@pytest.mark.parametrize(
    ("arguments", "field"),
    [
        (["--max-failed", "3"], "--max-failed"),
        (["no_such_problem"], "no_such_problem"),
    ],
)
def test_bad_input_names_the_field_and_writes_nothing(tmp_path: Path, arguments, field) -> None:
    out = tmp_path / "alt"
    result = CliRunner().invoke(main, ["alternatives", *arguments, "--out", str(out)])
    assert result.exit_code == 2, result.output
    assert field in result.output and "Traceback" not in result.output
    assert not out.exists()


def test_an_existing_folder_is_left_alone(tmp_path: Path) -> None:
    out = tmp_path / "alt"
    out.mkdir()
    (out / "mine.txt").write_text("keep")
    result = CliRunner().invoke(
        main, ["alternatives", "paper", "--max-failed", "0", "--out", str(out)]
    )
    assert result.exit_code == 2, result.output
    assert (out / "mine.txt").read_text() == "keep"
