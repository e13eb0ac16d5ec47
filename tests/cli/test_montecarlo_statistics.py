"""montecarlo with ``[[montecarlo.vary]]``: refused entries, and statistics that are numpy's
and scipy's on the written case table, with the quantity that drives the error on top."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from scipy import stats

from casadi_debris.cli import main
from casadi_debris.config import default_problem_path
from casadi_debris.store import open_campaign

PAPER = default_problem_path()

# The phase of the x disturbance sets how much of its 0.7 mNm acts over the first 30 s
# (sin 0 = none, sin 90 deg = all): it drives the pointing error. The transfer's target
# altitude has no part in the closed loop at all.
VARIED = f"""extends = "{PAPER}"
name = "phase"
[simulation]
duration_s = 30.0
[montecarlo]
seed = 5
samples = 8
[[montecarlo.vary]]
path = "disturbance.phase_deg[0]"
distribution = "uniform"
low = 0.0
high = 90.0
[[montecarlo.vary]]
path = "transfer.to_altitude_km"
distribution = "uniform"
low = 600.0
high = 800.0
[[montecarlo.vary]]
path = "bending_frequency_scale"
distribution = "normal"
mean = 1.0
sigma = 0.05
"""


@pytest.mark.parametrize(
    ("entry", "field"),
    [
        ('path = "environment.densty_kg_m3"\ndistribution = "uniform"\nlow = 0\nhigh = 1', "path"),
        ('path = "hub.size_m"\ndistribution = "uniform"\nlow = 1\nhigh = 2', "path"),
        ('path = "hub.mass_kg"\ndistribution = "uniform"\nlow = -1\nhigh = 2', "low"),
        ('path = "hub.mass_kg"\ndistribution = "normal"\nmean = 400', "sigma"),
        ('path = "array9_angle_offset_rad"\ndistribution = "corners"\nlow = 0\nhigh = 1', "path"),
    ],
)
def test_bad_entries_exit_2_naming_the_field_and_write_nothing(
    tmp_path: Path, entry: str, field: str
) -> None:
    problem = tmp_path / "bad.toml"
    problem.write_text(f'extends = "{PAPER}"\n[[montecarlo.vary]]\n{entry}\n')
    out = tmp_path / "out"
    args = ["montecarlo", str(problem), "--out", str(out), "--no-jit", "--json"]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 2, result.output
    assert result.stderr.count("\n") == 1 and f"montecarlo.vary[0].{field}" in result.stderr
    assert not out.exists() and not (tmp_path / "out.partial").exists()


def _column(rows: list[dict[str, str]], name: str) -> np.ndarray:
    return np.array([float(row[name]) if row[name] else np.nan for row in rows])


@pytest.mark.slow
def test_statistics_are_those_of_the_case_table_and_the_phase_drives_the_error(
    tmp_path: Path,
) -> None:
    problem = tmp_path / "phase.toml"
    problem.write_text(VARIED)
    out = tmp_path / "mc"
    args = ["montecarlo", str(problem), "--out", str(out), "--no-jit", "--workers", "1"]
    result = CliRunner().invoke(main, [*args, "--json"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    statistics = summary["statistics"]
    with (out / "cases.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == statistics["cases"] == 8
    assert {row["seed"] for row in rows} == {"5"}
    error = _column(rows, "max_error_arcsec")
    figures = {item["figure"]: item for item in statistics["figures"]}
    for name in ("max_error_arcsec", "fuel_kg", "max_error_deg"):
        values = _column(rows, name)
        assert figures[name]["mean"] == pytest.approx(np.mean(values), rel=1e-9)
        assert figures[name]["std"] == pytest.approx(np.std(values, ddof=1), rel=1e-9)
        assert figures[name]["p95"] == pytest.approx(np.percentile(values, 95), rel=1e-9)
    limit = statistics["requirement"]
    assert statistics["requirement_figure"] == "max_error_arcsec" and limit == 60.0
    assert statistics["passed"] == int(np.sum(error <= limit))
    # The rank correlations are scipy's on the table's columns, and the phase comes first.
    phase = _column(rows, "disturbance.phase_deg[0]")
    assert np.all((phase >= 0.0) & (phase <= 90.0))
    rho = {(s["quantity"], s["figure"]): s["spearman_rho"] for s in statistics["sensitivity"]}
    for quantity in ("disturbance.phase_deg[0]", "transfer.to_altitude_km"):
        expected = stats.spearmanr(_column(rows, quantity), error).statistic
        assert rho[(quantity, "max_error_arcsec")] == pytest.approx(expected, abs=1e-12)
    driver = next(d for d in statistics["drivers"] if d["figure"] == "max_error_arcsec")
    assert driver["quantities"][0] == "disturbance.phase_deg[0]"
    assert driver["spearman_rho"][0] > 0.95
    assert driver["worst_case_id"] == rows[int(np.argmax(error))]["case_id"]
    with open_campaign(out) as ds:
        assert list(ds.varied.values) == [
            "disturbance.phase_deg[0]",
            "transfer.to_altitude_km",
            "bending_frequency_scale",
        ]
        assert np.array_equal(ds.varied_value.sel(varied="disturbance.phase_deg[0]"), phase)
    assert (out / "statistics.png").stat().st_size > 10_000
    # A case re-runs alone from its index and seed, its problem rebuilt the same way.
    worst = int(np.argmax(error))
    again = CliRunner().invoke(
        main, ["simulate", str(problem), "--sample", str(worst), "--seed", "5", "--json"]
    )
    assert again.exit_code == 0, again.output
    assert json.loads(again.stdout)["max_error_arcsec"] == pytest.approx(error[worst], rel=1e-9)
