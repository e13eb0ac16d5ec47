"""`casadi-debris reproduce --quick` in CI: every row of the paper's table
(casadi_debris/data/paper_reference.toml) that a quick run can decide reproduces,
and the report holds the paper's figures redrawn; the table's rows built from
made-up results."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris.cli import main
from casadi_debris.report import (
    CampaignRun,
    CampaignSummary,
    ControllerSummary,
    DiskMargin,
    Margins,
    MarginsSummary,
    ModelSummary,
    ReproductionRow,
    ReproductionSummary,
    WorstValueSummary,
    paper_figure,
    report_markdown,
    reproduction_rows,
    table_figures,
)

# Rows that need all 256 corners: a quick run (8 slew, 4 pointing corners) cannot pass them.
NEEDS_EVERY_CORNER = ("slew_envelope_cases", "pointing")
SLEW_ERROR = paper_figure("slew_max_error_deg")
POINTING = paper_figure("pointing")


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("reproduce") / "report"
    # One process: the test workers already fill the cores (campaigns on worker processes
    # are checked in tests/cli/test_simulation.py).
    arguments = ["reproduce", "--quick", "--workers", "1", "--out", str(out), "--json"]
    result = CliRunner().invoke(main, arguments, catch_exceptions=False)
    assert result.exit_code == 0, result.stderr
    return out


def test_quick_reproduction_passes_every_row_it_can_decide(quick_report: Path) -> None:
    summary = json.loads((quick_report / "summary.json").read_text())
    assert [r["key"] for r in summary["table"]] == [f.key for f in table_figures()]
    decided = [r for r in summary["table"] if r["key"] not in NEEDS_EVERY_CORNER]
    failed = [r["result"] for r in decided if r["reproduced"] is not True]
    assert not failed, failed
    assert len(decided) == summary["rows"] - len(NEEDS_EVERY_CORNER)
    assert summary["reproduced"] == len(decided)
    for row in summary["table"]:
        assert set(row) >= {"result", "paper", "accepted", "ours", "verdict", "reproduced"}
        assert row["verdict"].startswith("✅" if row["reproduced"] else "❌")


def test_quick_pointing_corners_meet_the_requirement(quick_report: Path) -> None:
    """The pointing row fails a quick run only for want of corners, not on error or torque."""
    pointing = json.loads((quick_report / "pointing" / "summary.json").read_text())
    worst = POINTING.component("worst_error_arcsec")
    assert worst.accepts(pointing["worst"]["max_error_arcsec"]["value"])
    assert POINTING.component("nominal_error_arcsec").accepts(
        pointing["nominal"]["max_error_arcsec"]
    )


def test_report_has_the_table_and_the_figures(quick_report: Path) -> None:
    report = (quick_report / "report.md").read_text()
    assert "| result | paper | accepted | ours | verdict |" in report
    for figure in ("slew/envelope.png", "pointing/envelope.png", "margins/mu.png"):
        assert f"]({figure})" in report
        assert (quick_report / figure).stat().st_size > 10_000


@pytest.mark.slow
@pytest.mark.parametrize("name", ["paper_pointing", "paper_slew"])
def test_every_corner(name: str, tmp_path: Path) -> None:
    """The full 256-corner campaigns (minutes): pointing within 60 arcsec at every corner
    with the torque inside the authority; the slew within 0.6 deg nominal and every corner
    run."""
    from casadi_debris.config import default_problem_path

    problem = default_problem_path().parent / f"{name}.toml"
    out = tmp_path / name
    result = CliRunner().invoke(
        main, ["montecarlo", str(problem), "--out", str(out), "--json"], catch_exceptions=False
    )
    assert result.exit_code == 0, result.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert POINTING.component("cases").accepts(summary["cases"])
    nominal = json.loads((out / "nominal" / "summary.json").read_text())
    if name == "paper_pointing":
        worst = POINTING.component("worst_error_arcsec")
        assert worst.accepts(summary["worst"]["max_error_arcsec"]["value"])
        assert summary["worst"]["torque_saturated_s"]["value"] == 0.0
    else:
        assert SLEW_ERROR.accepts(nominal["max_error_deg"])


# ------------------------------------------------------------ the table from made-up results

LIMITS_MNM = np.array([4.6, 2.0, 4.3])


def _results() -> dict[str, Any]:
    """Results that reproduce every row, in the shapes the workflow passes."""
    torque = {"+x": 4.62, "-x": 4.7, "+y": 1.97, "-y": 2.0, "+z": 4.3, "-z": 4.27}
    return {
        "model": _model(668.2, np.diag([250.0, 68.0, 250.0]), torque),
        "budgets": {
            "dv_one_stage_one_face_m_s": 6.9,
            "dv_three_stages_one_face_m_s": 20.7,
            "dv_one_stage_all_faces_m_s": 41.5,
            "dv_all_stages_all_faces_m_s": 125.0,
            "dv_cubesat_one_stage_m_s": 335.0,
            "dv_transfer_m_s": 144.0,
            "detumble_time_h": 16.5,
        },
        "controller": ControllerSummary(
            mu_peak=0.92, mu_peak_reduced=0.93, order_full=49, order_reduced=25
        ),
        "margins": {
            "nominal": {"gain_margin_db": 14.0, "phase_margin_deg": 47.5, "delay_margin_s": 9.0},
            "sampled_min": {
                "gain_margin_db": 13.4,
                "phase_margin_deg": 47.3,
                "delay_margin_s": 8.2,
            },
            "samples": 3000,
        },
        "slew": _campaign({"max_error_deg": 0.45, "fuel_slew_kg": 3.3e-4}, "max_error_deg", 0.65),
        "slew_duration_s": 1228.0,
        "pointing": _campaign({"max_error_arcsec": 26.9}, "max_error_arcsec", 27.0),
    }


def _model(mass_kg: float, inertia: np.ndarray, torque: dict[str, float]) -> ModelSummary:
    """A description holding only the figures the rows read."""
    return ModelSummary(
        problem="paper", problem_path="", problem_sha256="", mass_kg=mass_kg, cog_m=(),
        inertia_hub_cubesats_kgm2=tuple(map(tuple, inertia.tolist())), inertia_total_kgm2=(),
        array_angle_deg=(), arrays=(), torque_max_mNm=torque, torque_max_zero_force_mNm={},
        modes=(), thrusters=(), notes=(),
    )  # fmt: skip


def _campaign(nominal: dict[str, float], worst_key: str, worst: float) -> CampaignSummary:
    """A 256-corner campaign summary holding only the figures the rows read."""
    return CampaignSummary(
        problem="paper", problem_sha256="", cases=256,
        worst={worst_key: WorstValueSummary(worst, "corner-0001")},
        max_torque_mNm=(LIMITS_MNM * 0.5).tolist(), fuel_kg_range=[0.0, 0.0],
        envelope_bin_s=1.0, nominal=dict(nominal),
        run=CampaignRun(
            controller_path="", controller_sha256="", plant_sha256="",
            controller_plant_sha256="", out_dir="", case_kind="corner", seed=None,
            workers=1, scheduler=None, resumed_cases=0, compiled_step=True, failed_cases=[],
        ),
    )  # fmt: skip


def _margin_report(margins: dict[str, Any]) -> MarginsSummary:
    """The figures the rows read, the rest of the report left empty."""
    return MarginsSummary(
        problem="paper", problem_sha256="", controller_path="", controller_order=25,
        plant_sha256="", controller_plant_sha256="", analysis_plant_modes="all",
        nominal=Margins(**margins["nominal"]), sampled_min=Margins(**margins["sampled_min"]),
        nominal_sampled_data=Margins(**margins["nominal"]), control_rate_hz=10.0,
        per_channel={}, disk_margin=DiskMargin(0.0, 0.0, 0.0), samples=margins["samples"],
        corner_samples=0, unstable_samples=0, seed=0, time_s=0.0, required={}, paper={},
        out_dir="",
    )  # fmt: skip


def _rows(results: dict[str, Any]) -> dict[str, ReproductionRow]:
    results = {**results, "margins": _margin_report(results["margins"])}
    rows = reproduction_rows(**results, torque_limits_mNm=LIMITS_MNM)
    return {row.key: row for row in rows}


def test_rows_follow_the_papers_table_and_reproduce():
    rows = _rows(_results())
    assert list(rows) == [f.key for f in table_figures()] and len(rows) == 19
    assert all(row.reproduced is True for row in rows.values())
    assert rows["torque_max_mNm"].ours_values == (4.62, 1.97, 4.27)  # the smaller of + and -
    assert rows["margins_sampled"].result == "margins over 3000 sampled plants [dB, deg, s]"
    assert rows["slew_envelope_cases"].ours == "256 (worst error 0.65°)"
    assert rows["pointing"].ours == "26.9 / 27 (256 cases)"
    assert rows["mass_kg"].entry().to_json() == {
        "key": "mass_kg",
        "result": "total mass [kg]",
        "paper": "668",
        "accepted": "±0.5",
        "ours": "668.2",
        "verdict": "✅ reproduced",
        "reproduced": True,
        "ours_values": [668.2],
    }


@pytest.mark.parametrize(
    ("group", "field", "value", "key"),
    [
        ("model", "mass_kg", 667.4, "mass_kg"),
        ("controller", "order_reduced", 26, "controller_order"),
        ("controller", "mu_peak", 1.01, "mu_peak"),
        ("margins", "samples", 200, None),  # the count is only in the title
        (None, "slew_duration_s", 1229.0, "slew_duration_s"),
        ("slew", "cases", 8, "slew_envelope_cases"),
        ("pointing", "cases", 4, "pointing"),
        ("pointing", "max_torque_mNm", (LIMITS_MNM * [1.0, 1.01, 1.0]).tolist(), "pointing"),
    ],
)
def test_a_result_outside_fails_its_row_only(group, field, value, key):
    results = _results()
    if group is None:
        results[field] = value
    elif isinstance(results[group], CampaignSummary | ModelSummary | ControllerSummary):
        results[group] = dataclasses.replace(results[group], **{field: value})
    else:
        results[group][field] = value
    rows = _rows(results)
    failed = [k for k, row in rows.items() if row.reproduced is not True]
    assert failed == ([] if key is None else [key])
    if key is not None:
        assert rows[key].entry().reproduced is False
        assert rows[key].verdict == "❌ not reproduced"


def test_a_controller_without_its_full_order_still_reproduces():
    results = _results()
    results["controller"] = dataclasses.replace(results["controller"], order_full=None)
    row = _rows(results)["controller_order"]
    assert row.reproduced is True and row.ours == "— / 25"
    assert row.ours_values == (None, 25.0)


def test_report_renders_the_verdict_from_the_boolean():
    row = ReproductionRow("mass_kg", "total mass [kg]", "668", "±0.5", "1", (1.0,), False)
    undecided = ReproductionRow("x", "x", "1", "—", "1", (1.0,), None)
    summary = ReproductionSummary(
        problem="paper", problem_sha256="0" * 64, controller_path="/c.json", quick=True,
        workers=1, time_s=1.0, reproduced=0, rows=2,
        table=(row.entry(), undecided.entry()), out_dir="/report",
    )  # fmt: skip
    # One JSON form: the table's rows keep their keys, the verdict as printed, and read back.
    data = json.loads(json.dumps(summary.to_json()))
    assert list(data["table"][0]) == [
        "key", "result", "paper", "accepted", "ours", "verdict", "reproduced", "ours_values",
    ]  # fmt: skip
    assert [r["verdict"] for r in data["table"]] == ["❌ not reproduced", "—"]
    assert ReproductionSummary.from_json(data) == summary
    report = report_markdown([row, undecided], summary, [])
    assert "| total mass [kg] | 668 | ±0.5 | 1 | ❌ not reproduced |" in report
    assert "| x | 1 | — | 1 | — |" in report
