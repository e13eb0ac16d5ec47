"""``casadi-debris transfer``: its folder and JSON, and bad problems refused in one line."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from casadi_debris.cli import main
from casadi_debris.config import default_problem_path
from casadi_debris.orbit import TransferSummary


def _problem(tmp_path: Path, transfer: str) -> Path:
    path = tmp_path / "p.toml"
    path.write_text(f'extends = "{default_problem_path()}"\n\n[transfer]\n{transfer}\n')
    return path


@pytest.mark.parametrize(
    ("orbits", "field"),
    [
        ((-10.0, 97.5, 685.0, 98.1), "from_altitude_km"),
        ((550.0, 97.5, 685.0, 190.0), "to_inclination_deg"),
        ((685.0, 98.1, 685.0, 98.1), "transfer"),  # the same orbit twice: nothing to do
        # The transfer must end on the debris' [orbit] (685 km, 98.1 deg).
        ((550.0, 97.5, 800.0, 98.1), "transfer.to_altitude_km"),
        ((550.0, 97.5, 685.0, 97.9), "transfer.to_inclination_deg"),
    ],
)
def test_bad_transfers_are_refused_in_one_line(
    tmp_path: Path, orbits: tuple[float, ...], field: str
) -> None:
    names = ("from_altitude_km", "from_inclination_deg", "to_altitude_km", "to_inclination_deg")
    problem = _problem(
        tmp_path, "\n".join(f"{n} = {v}" for n, v in zip(names, orbits, strict=True))
    )
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["transfer", str(problem), "--out", str(out)])
    assert result.exit_code == 2, result.output
    assert result.stderr.count("\n") == 1 and field in result.stderr
    assert not out.exists()


@pytest.mark.slow
def test_the_paper_transfer_writes_its_folder_and_json(tmp_path: Path) -> None:
    out = tmp_path / "t"
    result = CliRunner().invoke(main, ["transfer", "--out", str(out), "--json"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary == json.loads((out / "summary.json").read_text())
    assert TransferSummary.from_json(summary).to_json() == summary
    for key in ("transfer_dv_m_s", "transfer_time_days", "propellant_kg", "edelbaum_dv_m_s"):
        assert isinstance(summary[key], float)
    assert abs(summary["transfer_dv_m_s"] / summary["edelbaum_dv_m_s"] - 1) < 0.05
    assert [u["cubesat"] for u in summary["stages_used"]] == list(range(1, 25))
    assert {p.name for p in out.iterdir()} >= {
        "summary.json",
        "guidance.csv",
        "ocp.csv",
        "transfer.png",
    }
