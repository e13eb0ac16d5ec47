"""The failure campaign's records: the keys ``summary.json`` promises, and a JSON round trip."""

from __future__ import annotations

import json

from casadi_debris.studies.failures import (
    ClosedLoopCheckSummary,
    FailureCaseSummary,
    HoldingSummary,
    RunCheckSummary,
    ThrustChange,
)

RUN_KEYS = {
    "manoeuvre",
    "error_key",
    "error",
    "required",
    "met",
    "runs",
    "worst_case_id",
    "fuel_kg",
    "fuel_worst_cubesat_kg",
    "fuel_per_cubesat_kg",
    "fuel_spread",
    "torque_saturated_s",
    "settle_time_s",
    "stage_switches",
    "wall_time_s",
    "error_message",
}
"""What ``summary.json`` promises of every run verdict (a closed-loop ``failures`` test
checks them on a flown campaign)."""


def _case(met: bool) -> FailureCaseSummary:
    slew = RunCheckSummary(
        manoeuvre="slew",
        error_key="max_error_deg",
        error=0.45 if met else 3.0,
        required=1.0,
        met=met,
        runs=2,
        worst_case_id="failed-3@corner-2",
        fuel_kg=0.01,
        fuel_per_cubesat_kg=(0.004, 0.006),
        stage_switches=1,
    )
    return FailureCaseSummary(
        case_id="failed-3",
        failed=(3,),
        failed_stage=(),
        stage=None,
        label="CubeSat 3",
        torque_max_zero_force_mNm={
            "+x": 4.0,
            "-x": 4.0,
            "+y": 2.0,
            "-y": 2.0,
            "+z": 4.0,
            "-z": 4.0,
        },
        authority_ratio={"+x": 5.7, "-x": 5.7, "+y": 2.8, "-y": 2.8, "+z": 5.7, "-z": 5.7},
        worst_axis="+y",
        worst_ratio=2.8,
        authority_loss={"+x": 0.1, "-x": None, "+y": 0.0, "-y": 0.0, "+z": 0.0, "-z": 0.0},
        holding=HoldingSummary(600.0, 1e-3, (5e-4, 5e-4), 1.0, (0.05, 0.05), 0.0, 3.2e7, 2),
        reallocation=(ThrustChange(2, 0.05, 0.1),),
        closed_loop=ClosedLoopCheckSummary(met, {"slew": slew}, {}),
    )


def test_a_case_with_closed_loop_verdicts_reads_back_from_its_json_text():
    for met in (True, False):
        case = _case(met)
        text = json.dumps(case.to_json())
        assert FailureCaseSummary.from_json(json.loads(text)) == case


def test_a_run_verdict_writes_every_figure_it_promises():
    written = _case(True).to_json()["closed_loop"]["nominal"]["slew"]
    assert set(written) == RUN_KEYS
    assert written["fuel_per_cubesat_kg"] == [0.004, 0.006] and written["error_message"] is None
