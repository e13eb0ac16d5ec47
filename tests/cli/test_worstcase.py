"""``worstcase`` and ``simulate --parameters`` on the command line."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from casadi_debris.cli import main
from casadi_debris.config import default_problem_path
from casadi_debris.report import WorstCaseSummary

IDENTITY_KEYS = {
    "problem", "problem_sha256", "plant_sha256", "controller_path", "controller_plant_sha256",
    "out_dir",
}  # fmt: skip
SEARCH_KEYS = {
    "max_error_deg", "source", "evaluation", "normalized", "parameters", "simulations",
    "screen_worst_corners", "seed", "final_step", "time_s", "local_search",
}  # fmt: skip
SLEW = default_problem_path().parent / "paper_slew.toml"


def invoke(*args: str) -> tuple[int, str, str]:
    result = CliRunner().invoke(main, list(args), catch_exceptions=False)
    return result.exit_code, result.stdout, result.stderr


@pytest.fixture(scope="module")
def short_slew(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("problems") / "short_slew.toml"
    path.write_text(f'extends = "{SLEW}"\nname = "short_slew"\n[simulation]\nduration_s = 120.0\n')
    return path


@pytest.mark.parametrize(
    ("content", "needle"),
    [
        ('{"parameters": {"mass_kg": 600}}', "missing"),
        ('{"parameters": {"inertia_scale_x": "a"}}', "number"),
        ("[1, 2]", "'parameters'"),
        ("{not json", "not JSON"),
    ],
)
def test_simulate_parameters_bad_file_is_one_line(
    short_slew: Path, tmp_path: Path, content: str, needle: str
) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text(content)
    code, out, err = invoke("simulate", str(short_slew), "--parameters", str(bad))
    assert code == 2 and needle in err and "--parameters" in err
    assert len(err.strip().splitlines()) == 1 and out == ""


@pytest.mark.slow
def test_worstcase_parameters_rerun_by_simulate_give_the_reported_error(
    short_slew: Path, tmp_path: Path
) -> None:
    out = tmp_path / "wc"
    code, stdout, err = invoke(
        "worstcase", str(short_slew), "--no-mu", "--budget", "3", "--out", str(out), "--json"
    )
    assert code == 0, err
    summary = json.loads(stdout)
    assert summary["search"]["simulations"] <= 3
    for name in ("summary.json", "worst_parameters.json", "evaluations.csv", "worstcase.png"):
        assert (out / name).is_file()
    # The JSON keeps its keys (no mu: none of its key), on stdout and on disk, and reads back.
    assert set(summary) == IDENTITY_KEYS | {"search"} and set(summary["search"]) == SEARCH_KEYS
    assert json.loads((out / "summary.json").read_text()) == summary
    assert WorstCaseSummary.from_json(summary).to_json() == summary
    worst = json.loads((out / "worst_parameters.json").read_text())
    assert set(worst) == {"case_id", "parameters", "normalized", "max_error_deg"}
    with (out / "evaluations.csv").open() as handle:
        errors = [float(row["max_error_deg"]) for row in csv.DictReader(handle)]
    assert len(errors) == summary["search"]["simulations"]
    assert max(errors) == summary["search"]["max_error_deg"] == worst["max_error_deg"]
    code, stdout, err = invoke(
        "simulate", str(short_slew), "--parameters", str(out / "worst_parameters.json"), "--json"
    )
    assert code == 0, err
    rerun = json.loads(stdout)
    assert rerun["case_id"] == "worstcase"
    assert rerun["max_error_deg"] == pytest.approx(summary["search"]["max_error_deg"], rel=1e-9)


def test_both_stages_skipped_say_so_instead_of_an_empty_table(tmp_path: Path) -> None:
    out = tmp_path / "skipped"
    code, stdout, _ = invoke("worstcase", "--no-mu", "--no-search", "--out", str(out))
    assert code == 0, stdout
    rows = {line.split("  ")[0]: line for line in stdout.splitlines()}
    assert "skipped" in rows["mu robust stability, performance"]
    assert "--no-mu" in rows["mu robust stability, performance"]
    assert (
        "skipped" in rows["worst max error [deg]"]
        and "--no-search" in rows["worst max error [deg]"]
    )
    summary = json.loads((out / "summary.json").read_text())
    assert "mu" not in summary and "search" not in summary  # the JSON keys stay out
