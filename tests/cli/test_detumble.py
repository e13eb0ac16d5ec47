"""``casadi-debris detumble``: its folder, its JSON, and bad rates refused."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import pytest
from click.testing import CliRunner

from casadi_debris import load_problem
from casadi_debris.cli import main
from casadi_debris.geometry import build_geometry, torque_authority


def test_a_small_tumble_writes_its_folder_and_json(tmp_path: Path) -> None:
    out = tmp_path / "d"
    arguments = ["detumble", "--rate-rad-s", "0.02,0.03,-0.02", "--no-ocp", "--out", str(out)]
    arguments.append("--json")
    result = CliRunner().invoke(main, arguments)
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary == json.loads((out / "summary.json").read_text())
    assert summary["initial_rate_rad_s"] == [0.02, 0.03, -0.02]
    assert summary["momentum_bound_h"] <= summary["time_to_threshold_h"]
    assert summary["ocp_time_h"] is None and summary["ocp_method"] is None
    assert len(summary["fuel_per_cubesat_kg"]) == 24
    # The budget's per-axis braking is for the tumble flown, not the problem file's.
    geometry = build_geometry(load_problem())
    authority = torque_authority(geometry)
    inertia = geometry.inertia_hub_cubesats_kgm2
    braking_s = max(
        inertia[i, i] * abs(w) / authority[("-" if w > 0 else "+") + "xyz"[i]]
        for i, w in enumerate([0.02, 0.03, -0.02])
    )
    assert summary["budget_time_h"] == pytest.approx(braking_s / 3600.0, rel=1e-12)
    assert {p.name for p in out.iterdir()} >= {"summary.json", "series.csv", "detumble.png"}


def test_bad_rates_are_refused_in_one_line(tmp_path: Path) -> None:
    for rates in ("1,2", "1,nan,0", "1,2,1000", "a,b,c"):
        result = CliRunner().invoke(main, ["detumble", "--rate-rad-s", rates, "--out", "x"])
        assert result.exit_code == 2, result.output
        assert result.stderr.count("\n") == 1 and "--rate-rad-s" in result.stderr


@pytest.mark.slow
def test_the_time_optimal_detumble_lies_between_the_bound_and_the_closed_loop(
    tmp_path: Path,
) -> None:
    out = tmp_path / "d"
    arguments = ["detumble", "--rate-rad-s", "0.05,0.05,0.05", "--out", str(out), "--json"]
    result = CliRunner().invoke(main, arguments)
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["ocp_method"].startswith("time-optimal OCP")
    assert summary["momentum_bound_h"] < summary["ocp_averaged_bound_h"]
    assert summary["ocp_averaged_bound_h"] < summary["ocp_time_h"]
    assert summary["ocp_time_h"] < summary["ocp_greedy_time_h"] < summary["time_to_threshold_h"]
    assert 0.0 < summary["ocp_fuel_kg"] < summary["fuel_kg"]
    table = CliRunner().invoke(main, [*arguments[:-1], "--overwrite"])
    assert "time-optimal detumble, averaged OCP [h]" in table.stdout


def test_a_body_at_rest_draws_its_figure_without_warnings(tmp_path: Path) -> None:
    arguments = ["detumble", "--rate-rad-s", "0,0,0", "--no-ocp", "--out", str(tmp_path / "d")]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        result = CliRunner().invoke(main, arguments)
    assert result.exit_code == 0, result.output
    assert (tmp_path / "d" / "detumble.png").stat().st_size > 0
