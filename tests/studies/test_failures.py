"""A failure campaign in closed loop: the campaign's numbers are those of ``simulate`` with the
same failures, verdicts against the requirements, ranking and the summary's contract."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris import load_problem
from casadi_debris.campaigns import corner_case
from casadi_debris.cli import main
from casadi_debris.config import SIGNED_AXES, default_problem_path, with_duration
from casadi_debris.dynamics import build_model
from casadi_debris.geometry import torque_authority
from casadi_debris.report import pointing_window
from casadi_debris.studies.failures import (
    FailureCase,
    FailureSettings,
    FailuresSummary,
    FailureStudy,
    RunCheckSummary,
    failure_study,
    manoeuvres,
)
from casadi_debris.units import MN_PER_N
from casadi_debris.workflows import controller_for, failures

PROBLEMS = default_problem_path().parent
SLEW_S = 120.0  # the first two minutes of the paper's slew
HOLD_S = 50.0
CASES = (FailureCase(cubesats=(2, 16)), FailureCase(stage_of=(2,)))
LONG_SLEW_S = 800.0  # far enough into the paper's slew for the failures 3 and 17 to show


def _study(cases: tuple[FailureCase, ...], slew_s: float, hold_s: float | None) -> FailureStudy:
    """``cases`` flying the paper's slew cut to ``slew_s`` (and ``hold_s`` of pointing)."""
    problem = load_problem(PROBLEMS / "paper_slew.toml")
    model = build_model(problem)
    record, _ = controller_for(problem)
    slew = with_duration(problem, slew_s)
    pointing = with_duration(load_problem(PROBLEMS / "paper_pointing.toml"), hold_s or 1.0)
    return failure_study(
        model,
        FailureSettings(corner_sets=1),
        controller=record.reduced,
        manoeuvres=manoeuvres(slew, pointing)[: 2 if hold_s else 1],
        corner_plants=[corner_case(model, 255)],
        cases=cases,
    )


@pytest.fixture(scope="module")
def study() -> FailureStudy:
    return _study(CASES, SLEW_S, HOLD_S)


def _simulate(*args: str) -> dict:
    result = CliRunner().invoke(main, ["simulate", *args, "--json"], catch_exceptions=False)
    assert result.exit_code == 0, result.stderr
    return json.loads(result.stdout)


EXACT_KEYS = ("fuel_kg", "fuel_per_cubesat_kg", "torque_saturated_s", "settle_time_s")


def _figure(verdict: RunCheckSummary, key: str) -> object:
    """A verdict's figure as the run's JSON gives it."""
    return verdict.to_json()[key]


def test_a_case_rerun_alone_with_simulate_gives_the_campaigns_numbers(
    study: FailureStudy, tmp_path: Path
) -> None:
    by_id = {r.case.case_id: r for r in study.cases}
    slew = _simulate(str(PROBLEMS / "paper_slew.toml"), "--failed", "3,17", "--duration-s", "120")
    verdict = by_id["failed-3-17"].runs["slew"]
    assert verdict.error == slew["max_error_deg"]
    assert {k: _figure(verdict, k) for k in EXACT_KEYS} == {k: slew[k] for k in EXACT_KEYS}
    # A lost stage through the problem file's own failures, as a user would write it.
    staged = tmp_path / "staged.toml"
    staged.write_text(
        f'extends = "{PROBLEMS / "paper_pointing.toml"}"\nname = "staged"\n'
        "[simulation]\nduration_s = 50.0\n"
        "[[simulation.failures]]\ntime_s = 0.0\ncubesat = 3\nstage = 1\n"
    )
    hold = _simulate(str(staged))
    verdict = by_id["stage-3"].runs["pointing"]
    assert verdict.error == hold["max_error_arcsec"]
    assert {k: _figure(verdict, k) for k in EXACT_KEYS} == {k: hold[k] for k in EXACT_KEYS}
    # The worst corner: corner 255 of the same plant set.
    worst = study.cases[0]
    assert worst.corners["slew"].worst_case_id == f"{worst.case.case_id}@corner-0255"
    ids = ",".join(str(i + 1) for i in worst.case.cubesats) or "3"
    args = ["--duration-s", "120", "--corner", "255"]
    corner = _simulate(str(PROBLEMS / "paper_slew.toml"), "--failed", ids, *args)
    assert worst.corners["slew"].error == corner["max_error_deg"]


@pytest.mark.slow
def test_verdicts_rank_the_pair_that_loses_the_z_slew_first() -> None:
    study = _study(
        (FailureCase(cubesats=(16, 18)), FailureCase(cubesats=(2, 16))), LONG_SLEW_S, None
    )
    first = study.cases[0]
    assert first.case.cubesats == (2, 16)
    assert study.cases[1].met is True
    slew = first.runs["slew"]
    # Against the requirement as the problem states it.
    required = load_problem(PROBLEMS / "paper_slew.toml").requirements.slew_error_deg
    assert slew.required == required
    assert slew.met is (slew.error <= required)
    assert first.met is False
    assert first.excess == pytest.approx(max(v.error / v.required for v in first.runs.values()))
    # Ranked by how far the requirements are missed, then by authority.
    excess = [r.excess for r in study.cases]
    assert excess == sorted(excess, reverse=True)


def test_the_summary_names_failed_ids_and_six_signed_axes(study: FailureStudy) -> None:
    summary = study.record().to_json()
    assert summary["case_count"] == len(CASES)
    problem = load_problem(PROBLEMS / "paper_slew.toml")
    geometry = build_model(problem).geometry
    for case in summary["cases"]:
        assert set(case["torque_max_zero_force_mNm"]) == set(SIGNED_AXES)
        assert case["closed_loop"]["met"] in (True, False)
        alive = np.ones(24, dtype=bool)
        alive[[i - 1 for i in case["failed"]]] = False
        expected = torque_authority(geometry, zero_net_force=True, available=alive)
        for axis in SIGNED_AXES:
            assert case["torque_max_zero_force_mNm"][axis] == pytest.approx(
                expected[axis] * MN_PER_N, rel=1e-12
            )
    pair = next(c for c in summary["cases"] if c["case_id"] == "failed-3-17")
    assert pair["closed_loop"]["nominal"]["slew"]["error"] is not None
    assert pair["failed"] == [3, 17] and pair["failed_stage"] == []
    staged = next(c for c in summary["cases"] if c["case_id"] == "stage-3")
    assert staged["failed"] == [] and staged["failed_stage"] == [3]
    # The lost stage leaves the runs as the whole swarm flies them: same thrust, same loop.
    assert staged["closed_loop"]["nominal"]["slew"]["error"] == pytest.approx(
        summary["baseline"]["closed_loop"]["nominal"]["slew"]["error"], rel=0, abs=0
    )
    # Re-allocation: the CubeSats listed are those whose holding thrust rose.
    for entry in pair["reallocation"]:
        assert entry["thrust_after_mN"] > entry["thrust_before_mN"]


def test_the_summary_reads_back_as_the_same_record(study: FailureStudy) -> None:
    record = study.record()
    again = FailuresSummary.from_json(json.loads(json.dumps(record.to_json())))
    assert again.to_json() == record.to_json()
    assert (
        again.cases[0].closed_loop.nominal["slew"].met
        is record.cases[0].closed_loop.nominal["slew"].met
    )


# The CubeSats whose engines push about +y (ids from 1: 2, 4, 5, 7, 17, 18, 23, 24).
PLUS_Y = (1, 3, 4, 6, 16, 17, 22, 23)


def test_a_quick_campaign_sees_a_failure_of_one_signed_axis_over_the_whole_period() -> None:
    """Without +y authority the body cannot hold against the half of the disturbance's
    period that asks for +y: the pointing must come out worse than the whole swarm's. A run
    shorter than half a period (the sine keeps one sign) would not see it."""
    problem = load_problem()
    geometry = build_model(problem).geometry
    failed = FailureCase(cubesats=PLUS_Y)
    # Independently of any LP: no engine left gives a positive torque about y, so no
    # thrusts (all non-negative) can.
    alive = np.isin(geometry.engine_cubesat, PLUS_Y, invert=True)
    assert np.all(geometry.torque_map[1, alive] <= 0.0)
    assert np.any(geometry.torque_map[1] > 0.0)
    # The disturbance asks for +y (the torque that cancels it, -d_y) during half a period.
    disturbance = problem.disturbance
    period_s = disturbance.period_min * 60.0
    assert disturbance.amplitude_mNm[1] > 0.0
    study = failures(problem, corner_sets=0, quick=True, workers=1, cases=[failed]).study
    pointing = next(m for m in study.manoeuvres if m.name == "pointing")
    assert pointing.problem.simulation.duration_s >= period_s
    whole = study.baseline.runs["pointing"]
    lost = study.cases[0].runs["pointing"]
    assert study.cases[0].authority.torque_Nm["+y"] == 0.0
    assert whole.met is True
    assert lost.error is not None and lost.error > max(10.0 * whole.error, lost.required)
    assert lost.met is False and study.cases[0].met is False
    # Out of reach, the engines saturate for about the half period that asks for +y.
    assert lost.torque_saturated_s == pytest.approx(period_s / 2.0, rel=0.05)
    # The report says what window the pointing covered and that it bounds the result.
    window = pointing_window(study.record())
    assert "covers one whole period of the disturbance" in window and "every phase" in window
    short = dataclasses.replace(
        study.record(),
        manoeuvres=tuple(
            dataclasses.replace(m, duration_s=1500.0) if m.name == "pointing" else m
            for m in study.record().manoeuvres
        ),
    )
    assert "do not bound" in pointing_window(short)
