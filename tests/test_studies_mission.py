"""The mission's phases against their parts computed on their own, and its bookkeeping."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris.budgets import budgets_as_dict, compute_budgets
from casadi_debris.cli import main
from casadi_debris.config import load_problem
from casadi_debris.orbit import DeorbitSettings
from casadi_debris.studies.mission import (
    plan_mission,
    propellant_per_cubesat_kg,
    transfer_per_cubesat,
)


@pytest.fixture(scope="module")
def paper_mission():
    return plan_mission(load_problem(), DeorbitSettings(minimum_swarm=False, samples=0))


def test_each_cubesats_transfer_is_edelbaum_and_the_rocket_equation():
    problem = load_problem()
    dv, propellant, time_s = transfer_per_cubesat(problem)
    assert dv == pytest.approx(budgets_as_dict(compute_budgets(problem))["dv_transfer_m_s"])
    # 3.5 kg, 0.64 mN, Isp 1000 s: by hand
    exhaust = 1000.0 * problem.constants.standard_gravity_m_s2
    used = 3.5 * (1 - math.exp(-dv / exhaust))
    np.testing.assert_allclose(propellant, used, rtol=1e-12)
    np.testing.assert_allclose(time_s, used * exhaust / 0.64e-3, rtol=1e-12)
    # less than one stage of the three each carries (the paper: 150 of ~300 m/s a stage)
    assert np.all(propellant < propellant_per_cubesat_kg(problem) / 3)


def test_the_propellant_books_balance(paper_mission):
    summary = paper_mission.summary
    problem = load_problem()
    per_cubesat = sum(np.asarray(v) for v in summary.propellant_per_cubesat_kg.values())
    assert np.all(per_cubesat <= propellant_per_cubesat_kg(problem) * (1 + 1e-9))
    assert per_cubesat.sum() == pytest.approx(summary.propellant_used_kg, rel=1e-9)
    phases = {p.name: p for p in summary.phases}
    assert sum(p.propellant_kg for p in phases.values()) == pytest.approx(
        summary.propellant_used_kg, rel=1e-9
    )
    assert phases["detumble"].propellant_kg == paper_mission.detumble.summary.fuel_kg
    assert summary.detumble_time_h == paper_mission.detumble.summary.time_to_threshold_h
    # What is left buys less than the full capacity, by the rocket equation on the plan's
    # own exhaust speed.
    mass, total = paper_mission.plan.mass_kg, summary.propellant_total_kg
    exhaust = summary.deorbit_dv_capacity_m_s / math.log(mass / (mass - total))
    left = total - phases["transfer"].propellant_kg - phases["detumble"].propellant_kg
    assert summary.deorbit_dv_available_m_s == pytest.approx(
        exhaust * math.log(mass / (mass - left)), rel=1e-12
    )


def test_a_case_the_swarm_can_pay_for_re_enters_as_its_plan_says(paper_mission):
    summary = paper_mission.summary
    for case in paper_mission.plan.cases:
        years = summary.reentry_years[case.solar]
        if case.deorbit_dv_m_s <= summary.deorbit_dv_available_m_s:
            assert years == pytest.approx(case.reentry_years, rel=1e-6)
        else:  # flies what is left: later than the limit it needed more Δv for
            assert years is None or years > summary.limit_years
    assert summary.meets_five_year_rule == all(
        y is not None and y <= summary.limit_years for y in summary.reentry_years.values()
    )


def test_the_command_writes_the_folder_and_refuses_bad_cases(tmp_path: Path):
    out = tmp_path / "mission"
    result = CliRunner().invoke(
        main, ["-q", "mission", "--solar", "high", "--out", str(out), "--json"]
    )
    assert result.exit_code == 0, result.output
    summary = json.loads(result.output)
    assert set(summary) >= {"detumble_time_h", "transfer_dv_m_s", "deorbit_dv_m_s",
                            "reentry_years", "meets_five_year_rule"}  # fmt: skip
    assert list(summary["reentry_years"]) == ["high"]
    assert {p.name for p in out.iterdir()} >= {"summary.json", "phases.csv", "propellant.csv",
                                               "mission.png", "decay.png"}  # fmt: skip
    bad = CliRunner().invoke(main, ["mission", "--solar", "medium", "--out", str(tmp_path / "b")])
    assert bad.exit_code == 2 and "--solar" in bad.output and not (tmp_path / "b").exists()
