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
from casadi_debris.geometry import build_geometry
from casadi_debris.orbit import DeorbitSettings
from casadi_debris.studies.mission import (
    MissionSummary,
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


@pytest.mark.slow
def test_the_propellant_books_balance(paper_mission):
    """Each phase's books against its own independent sum, stage by stage within capacity."""
    summary, problem = paper_mission.summary, load_problem()
    g0 = problem.constants.standard_gravity_m_s2
    pages = {book.phase: book for book in summary.books}
    phases = {p.name: p for p in summary.phases}
    # transfer: the rocket equation per CubeSat; detumble: the run's own fuel
    dv = summary.transfer_dv_m_s
    transfer = sum(c.mass_kg * (1 - math.exp(-dv / (1000.0 * g0))) for c in problem.cubesats)
    assert pages["transfer"].propellant_kg == pytest.approx(transfer, rel=1e-12)
    np.testing.assert_allclose(
        pages["detumble"].per_cubesat_kg, paper_mission.detumble.summary.fuel_per_cubesat_kg,
        rtol=1e-12,
    )  # fmt: skip
    # deorbit: the engines' impulse over the exhaust speed, the directions flown in order
    # until the governing case's impulse; through the force map, those engine impulses give
    # that impulse along the directions (a little more propellant: the torque-free mixes
    # fire some engines across each other)
    governing = next(c for c in paper_mission.plan.cases if c.solar == summary.governing_case)
    force_map = build_geometry(problem).force_map
    left, along, engines = governing.impulse_Ns, 0.0, 0.0
    for segment in paper_mission.model.thrust.segments:
        share = min(1.0, left / segment.impulse_Ns)
        along += segment.direction_body @ force_map @ (share * segment.engine_impulse_Ns)
        engines += share * segment.engine_impulse_Ns.sum()
        left -= share * segment.impulse_Ns
    assert along == pytest.approx(governing.impulse_Ns, rel=1e-9)
    booked = pages["deorbit burn"].propellant_kg
    assert booked == pytest.approx(engines / (1000.0 * g0), rel=1e-9)
    assert 1.0 <= booked / (governing.impulse_Ns / (1000.0 * g0)) < 1.01
    for name, book in pages.items():
        per_stage = np.asarray(book.per_stage_kg)
        np.testing.assert_allclose(per_stage.sum(axis=1), book.per_cubesat_kg, rtol=1e-12)
        assert phases[name].propellant_kg == pytest.approx(book.propellant_kg, rel=1e-12)
        assert summary.propellant_per_cubesat_kg[name] == book.per_cubesat_kg
    burnt = sum(np.asarray(b.per_stage_kg) for b in summary.books)
    capacity = np.asarray(summary.capacity_per_stage_kg)
    assert np.all(burnt <= capacity * (1 + 1e-9))  # no stage (one engine each) overdrawn
    assert capacity.sum(axis=1) == pytest.approx(propellant_per_cubesat_kg(problem), rel=1e-12)
    assert burnt.sum() == pytest.approx(summary.propellant_used_kg, rel=1e-12)
    assert summary.propellant_used_kg + summary.propellant_left_kg == pytest.approx(
        summary.propellant_total_kg, rel=1e-12
    )
    assert 0.0 <= summary.propellant_stranded_kg <= summary.propellant_left_kg + 1e-12
    # the stages begun are those that have burnt anything, 1-based
    started = [[s + 1 for s in np.flatnonzero(row > 0)] for row in burnt]
    assert pages["deorbit burn"].stages_started == started


@pytest.mark.slow
def test_what_is_left_buys_the_available_dv(paper_mission):
    """The rocket equation on the books: usable impulse over the docked mass left."""
    summary = paper_mission.summary
    plan = paper_mission.plan
    problem = load_problem()
    g0 = problem.constants.standard_gravity_m_s2
    used_before = summary.books[0].propellant_kg + summary.books[1].propellant_kg
    combined = problem.hub.mass_kg + sum(a.mass_kg for a in problem.arrays)
    combined += sum(c.mass_kg for c in problem.cubesats)
    mass = combined - used_before  # docked, less what transfer and detumble burnt
    assert plan.mass_kg == pytest.approx(mass, rel=1e-12)
    usable = summary.propellant_total_kg - used_before - summary.propellant_stranded_kg
    ve = 1000.0 * g0
    # The directions' mixes give along them a little less than their engines' impulse.
    along = paper_mission.model.thrust.impulse_Ns
    assert 0.99 * usable * ve <= along <= usable * ve * (1 + 1e-9)
    assert summary.deorbit_dv_available_m_s == pytest.approx(
        -ve * math.log(1.0 - along / (mass * ve)), rel=1e-9
    )
    assert summary.deorbit_dv_available_m_s < summary.deorbit_dv_capacity_m_s


@pytest.mark.slow
def test_a_case_the_swarm_can_pay_for_re_enters_as_its_plan_says(paper_mission):
    summary = paper_mission.summary
    for case, item in zip(paper_mission.plan.cases, paper_mission.trajectories, strict=True):
        years = summary.reentry_years[case.solar]
        assert item.history.reentry_years == pytest.approx(case.reentry_years, rel=1e-9)
        if case.deorbit_dv_m_s <= summary.deorbit_dv_available_m_s:
            assert years is not None and years <= summary.limit_years
        else:  # flies what is left: later than the limit it needed more Δv for
            assert years is None or years > summary.limit_years
    assert summary.meets_five_year_rule == all(
        y is not None and y <= summary.limit_years for y in summary.reentry_years.values()
    )


@pytest.mark.slow
def test_the_command_writes_the_folder(tmp_path: Path):
    out = tmp_path / "mission"
    result = CliRunner().invoke(
        main, ["-q", "mission", "--solar", "high", "--out", str(out), "--json"]
    )
    assert result.exit_code == 0, result.output
    summary = json.loads(result.output)
    assert set(summary) >= {"detumble_time_h", "transfer_dv_m_s", "deorbit_dv_m_s",
                            "reentry_years", "meets_five_year_rule"}  # fmt: skip
    assert list(summary["reentry_years"]) == ["high"]
    assert summary["problem_sha256"] == load_problem().sha256
    assert MissionSummary.from_json(summary).to_json() == summary
    assert {p.name for p in out.iterdir()} >= {"summary.json", "phases.csv", "propellant.csv",
                                               "mission.png", "mission.pdf", "altitude.png",
                                               "altitude.pdf", "decay.png"}  # fmt: skip


def test_the_command_refuses_bad_cases(tmp_path: Path):
    bad = CliRunner().invoke(main, ["mission", "--solar", "medium", "--out", str(tmp_path / "b")])
    assert bad.exit_code == 2 and "--solar" in bad.output and not (tmp_path / "b").exists()


def test_a_transfer_that_does_not_end_on_the_debris_orbit_is_refused(tmp_path: Path):
    problem = tmp_path / "p.toml"
    problem.write_text('extends = "paper"\n\n[orbit]\naltitude_km = 600.0\n')
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["mission", str(problem), "--out", str(out)])
    assert result.exit_code == 2 and result.stderr.count("\n") == 1
    assert "transfer.to_altitude_km" in result.stderr and "600" in result.stderr
    assert not out.exists()


def test_an_existing_folder_is_refused_before_any_progress_line(tmp_path: Path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    result = CliRunner().invoke(main, ["mission", "--out", str(out)])
    assert result.exit_code == 2 and result.stderr.count("\n") == 1, result.stderr
    assert "--out" in result.stderr and (out / "notes.txt").read_text() == "mine"


@pytest.mark.slow
def test_the_extra_stages_asked_for_make_a_swarm_that_meets_the_rule(tmp_path: Path, paper_mission):
    summary = paper_mission.summary
    extra = summary.extra_stages_needed
    assert not summary.meets_five_year_rule and extra is not None and extra >= 1
    # Built independently: a swarm whose engines carry that many more stages from launch.
    path = tmp_path / "more_stages.toml"
    path.write_text(f'extends = "paper"\nname = "more"\n\n[engine]\nstages = {3 + extra}\n')
    topped = plan_mission(load_problem(path), DeorbitSettings(minimum_swarm=False, samples=0))
    assert topped.summary.meets_five_year_rule and topped.summary.extra_stages_needed == 0
