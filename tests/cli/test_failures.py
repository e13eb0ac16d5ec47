"""casadi-debris failures on the command line: the folder, the JSON contract, bad input."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from casadi_debris.cli import main
from casadi_debris.config import SIGNED_AXES, default_controller_path, default_problem_path
from casadi_debris.report import write_failures
from casadi_debris.studies.failures import FailuresSummary
from tests.studies.test_failure_records import RUN_KEYS

PROBLEMS = default_problem_path().parent
FILES = {"summary.json", "cases.csv", "report.md", "reallocation.csv", "authority_loss.png"}


def invoke(*args: str) -> tuple[int, str, str]:
    result = CliRunner().invoke(main, list(args), catch_exceptions=False)
    return result.exit_code, result.stdout, result.stderr


@pytest.mark.parametrize("count", ["0", "25", "-1"])
def test_a_count_outside_the_swarm_is_one_line_and_exit_2(tmp_path: Path, count: str) -> None:
    out = tmp_path / "out"
    code, stdout, stderr = invoke("failures", "--max-failed", count, "--out", str(out))
    assert code == 2
    assert stderr.strip().count("\n") == 0
    assert "--max-failed" in stderr and "1 and 24" in stderr
    assert stdout == "" and not out.exists()


def test_a_bad_flag_value_is_one_line_and_exit_2(tmp_path: Path) -> None:
    code, _, stderr = invoke("failures", "--max-failed", "two", "--out", str(tmp_path / "o"))
    assert code == 2 and stderr.strip().count("\n") == 0


@pytest.fixture(scope="module")
def static_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict]:
    out = tmp_path_factory.mktemp("failures") / "paper"
    code, stdout, stderr = invoke(
        "failures", "--max-failed", "1", "--no-closed-loop", "--out", str(out), "--json"
    )
    assert code == 0, stderr
    return out, json.loads(stdout)


def test_the_folder_holds_every_file_and_the_json_is_the_summary(
    static_run: tuple[Path, dict],
) -> None:
    out, printed = static_run
    assert {p.name for p in out.iterdir()} >= FILES
    assert json.loads((out / "summary.json").read_text()) == printed


def test_every_case_lists_failed_ids_and_six_signed_axes(static_run: tuple[Path, dict]) -> None:
    _, summary = static_run
    cases = summary["cases"]
    # 24 single failures and 24 lost stages (--stages is the default).
    assert summary["case_count"] == len(cases) == 48
    assert sorted(c["failed"] for c in cases if c["failed"]) == [[i] for i in range(1, 25)]
    assert sorted(c["failed_stage"] for c in cases if c["failed_stage"]) == [
        [i] for i in range(1, 25)
    ]
    model = json.loads(_model_json())
    assert list(summary["baseline"]["torque_max_zero_force_mNm"]) == list(
        model["torque_max_zero_force_mNm"]
    )
    for case in cases:
        assert list(case["torque_max_zero_force_mNm"]) == list(SIGNED_AXES)
        assert case["closed_loop"]["met"] is None  # not flown
    assert summary["baseline"]["torque_max_zero_force_mNm"] == pytest.approx(
        model["torque_max_zero_force_mNm"], rel=1e-12
    )


def _model_json() -> str:
    code, stdout, stderr = invoke("model", "--json")
    assert code == 0, stderr
    return stdout


def test_the_table_is_ranked_worst_first(static_run: tuple[Path, dict]) -> None:
    out, summary = static_run
    with (out / "cases.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert [r["case_id"] for r in rows] == [c["case_id"] for c in summary["cases"]]
    ratios = [float(r["worst_ratio"]) for r in rows]
    assert ratios == sorted(ratios)
    assert [int(r["rank"]) for r in rows] == list(range(1, len(rows) + 1))
    report = (out / "report.md").read_text()
    assert "authority_loss.png" in report and rows[0]["failed"] in report


STUDY_KEYS = {
    "problem",
    "problem_sha256",
    "max_failed",
    "stages",
    "closed_loop",
    "corner_sets",
    "workers",
    "jit",
    "cubesats",
    "disturbance_mNm",
    "requirements",
    "manoeuvres",
    "corner_plants",
    "case_count",
    "cases_met",
    "cases_not_met",
    "baseline",
    "cases",
    "wall_time_s",
    "controller_path",
    "quick",
    "max_corners",
    "out_dir",
    "disturbance_period_s",
}
CASE_KEYS = {
    "case_id",
    "failed",
    "failed_stage",
    "stage",
    "label",
    "torque_max_zero_force_mNm",
    "authority_ratio",
    "worst_axis",
    "worst_ratio",
    "authority_loss",
    "holding",
    "reallocation",
    "closed_loop",
}
HOLDING_KEYS = {
    "period_s",
    "fuel_per_period_kg",
    "fuel_per_cubesat_kg",
    "fuel_spread",
    "thrust_per_cubesat_mN",
    "saturated_fraction",
    "depletion_time_s",
    "first_depleted_cubesat",
}


def test_the_json_keeps_its_keys_and_reads_back_into_its_record(
    static_run: tuple[Path, dict],
) -> None:
    """Other tools read these names: the typed record writes exactly them."""
    out, summary = static_run
    assert set(summary) == STUDY_KEYS and summary["out_dir"] == str(out.absolute())
    for case in [summary["baseline"], *summary["cases"]]:
        assert set(case) == CASE_KEYS
        assert set(case["holding"]) == HOLDING_KEYS
        assert case["closed_loop"] == {"met": None, "nominal": {}, "corners": {}}
        for change in case["reallocation"]:
            assert set(change) == {"cubesat", "thrust_before_mN", "thrust_after_mN"}
    record = FailuresSummary.from_json(summary)
    assert record.to_json() == summary
    assert [c.case_id for c in record.cases] == [c["case_id"] for c in summary["cases"]]
    assert record.baseline.holding is not None
    assert record.baseline.holding.thrust_per_cubesat_mN == tuple(
        summary["baseline"]["holding"]["thrust_per_cubesat_mN"]
    )


def test_the_files_redraw_from_the_written_summary(
    static_run: tuple[Path, dict], tmp_path: Path
) -> None:
    """A script rebuilds the record from ``summary.json`` and writes the same tables."""
    out, summary = static_run
    write_failures(tmp_path, FailuresSummary.from_json(summary))
    for name in ("cases.csv", "reallocation.csv", "report.md"):
        assert (tmp_path / name).read_text() == (out / name).read_text()
    assert json.loads((tmp_path / "summary.json").read_text()) == summary


def test_an_existing_folder_it_did_not_write_is_refused(tmp_path: Path) -> None:
    out = tmp_path / "theirs"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    code, _, stderr = invoke("failures", "--no-closed-loop", "--max-failed", "1", "--out", str(out))
    assert code == 2 and stderr.strip().count("\n") == 0
    assert [p.name for p in out.iterdir()] == ["keep.txt"]


@pytest.mark.slow
def test_closed_loop_on_two_workers_shows_progress_and_judges_every_case(tmp_path: Path) -> None:
    """The paper's swarm with a one-minute disturbance period (so that the pointing run
    lasts a minute) and its slew cut to two minutes, flown by the paper's controller."""
    problem = tmp_path / "short.toml"
    problem.write_text(
        f'extends = "{PROBLEMS / "paper_slew.toml"}"\nname = "short"\n'
        "[simulation]\nduration_s = 120.0\n[disturbance]\nperiod_min = 1.0\n"
    )
    out = tmp_path / "out"
    args = ["--max-failed", "1", "--no-stages", "--workers", "2"]
    args += ["--controller", str(default_controller_path()), "--allow-mismatch"]
    args += ["--corner-sets", "1", "--max-corners", "2", "--out", str(out)]
    code, stdout, stderr = invoke("failures", str(problem), *args)
    assert code == 0, stderr
    assert "slew, nominal plant: 25 cases" in stderr and "25/25" in stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["case_count"] == 24
    assert [m["duration_s"] for m in summary["manoeuvres"]] == [120.0, 60.0]
    assert summary["disturbance_period_s"] == 60.0
    assert "covers one whole period of the disturbance (60 s)" in (out / "report.md").read_text()
    for case in summary["cases"]:
        nominal = case["closed_loop"]["nominal"]
        assert set(nominal) == {"slew", "pointing"}
        met = nominal["slew"]["met"] and nominal["pointing"]["met"]
        if case["closed_loop"]["corners"]:
            met = met and all(v["met"] for v in case["closed_loop"]["corners"].values())
        assert case["closed_loop"]["met"] is met
    assert len([c for c in summary["cases"] if c["closed_loop"]["corners"]]) == 1
    runs = [r for c in summary["cases"] for r in c["closed_loop"]["nominal"].values()]
    assert {frozenset(r) for r in runs} == {frozenset(RUN_KEYS)}
    assert FailuresSummary.from_json(summary).to_json() == summary
    assert "cases meet the requirements" in stdout


@pytest.mark.parametrize("value", ["0", "25", "3,x", ""])
def test_simulate_refuses_bad_failed_ids_in_one_line(value: str) -> None:
    code, _, stderr = invoke("simulate", "--failed", value, "--duration-s", "1")
    assert code == 2 and stderr.strip().count("\n") == 0 and "--failed" in stderr
