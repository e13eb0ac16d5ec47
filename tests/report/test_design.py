"""A design's summary.json reads back into the DesignSummary it was written from."""

from __future__ import annotations

import json

from casadi_debris import load_problem
from casadi_debris.report import (
    DesignSummary,
    RequirementRow,
    VerificationSummary,
    WorstValueSummary,
    binding_lines,
    body_lines,
)
from casadi_debris.robust.requirements import body_weights, derived_scalings, slew_limit
from casadi_debris.robust.synthesis import DesignAttempt


def test_a_design_summary_reads_back_from_its_json() -> None:
    problem = load_problem()
    row = RequirementRow("pointing_arcsec", "pointing [arcsec]", "≤ 60", "55", (55.0,), True)
    campaign = VerificationSummary(
        8, {"max_error_deg": WorstValueSummary(0.6, "corner-0003")}, {"max_error_deg": 0.45}
    )
    summary = DesignSummary(
        problem="paper", problem_sha256="a" * 64, plant_sha256="b" * 64, requirements_met=False,
        requirements_passed=3, requirements=4, method="mu", mu_peak=0.92, mu_peak_reduced=0.93,
        guaranteed_pointing_arcsec=[55.0, 60.0, 55.0], required_pointing_arcsec=60.0,
        scalings=derived_scalings(problem).figures(),
        attempts=(DesignAttempt(1.0, 0.92, 0.93, (55.0, 60.0, 55.0), 3, 100.0),),
        seed=0, slew=campaign, pointing=campaign, rows=(row.entry(),),
        time_s=300.0, out_dir="/d", quick=True, workers=1, controller_path="/d/controller.json",
        binding=(slew_limit(0.9, 0.6, 0.5, 12.0),), body=body_weights(problem, "derived").figures,
    )  # fmt: skip
    data = json.loads(json.dumps(summary.to_json()))
    assert data["attempts"][0]["guaranteed_pointing_arcsec"] == [55.0, 60.0, 55.0]
    assert data["slew"]["worst"]["max_error_deg"] == {
        "value": 0.6,
        "case_id": "corner-0003",
        "cases_without": 0,
    }
    assert data["rows"] == [
        {
            "key": "pointing_arcsec",
            "result": "pointing [arcsec]",
            "required": "≤ 60",
            "ours": "55",
            "verdict": "✅ met",
            "met": True,
            "values": [55.0],
        }
    ]
    assert DesignSummary.from_json(data) == summary
    assert data["requirements_met"] is False and data["binding"][0]["requirement"] == (
        "slew_max_error_deg"
    )


def test_the_report_says_loudly_when_requirements_are_not_met() -> None:
    problem = load_problem()
    limit = slew_limit(0.9, 0.6, 0.5, 12.0)
    lines = "\n".join(binding_lines((limit,)))
    assert "## What binds" in lines and "torque fraction 0.333" in lines
    assert binding_lines(()) == []
    body = "\n".join(body_lines(body_weights(problem, "derived").figures))
    assert "derived from this body" in body and "0.028" in body
