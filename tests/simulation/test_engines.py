"""Closed-loop runs with engines of different Isp and an engine failed on its own.

The twin swarm of tests/allocation/test_isp.py (every paper CubeSat with its
iESE and a twin of Isp 250 s at the same point) flies the first 400 s of the
paper's slew with the paper's controller. At 300 s the iESE of the eight
CubeSats on +x and +z (1 to 4, 17 to 20) fail: the twins, idle until then
(the iESE reach every demand at a quarter of the propellant), must fill in.
References: propellant as sums of the logged thrust over each engine's own
exhaust velocity, and the thrust log itself.
"""

from __future__ import annotations

import copy
import json
import math
import tomllib
from typing import Any

import numpy as np
import pytest

from casadi_debris.config import (
    Problem,
    default_controller_path,
    default_problem_path,
    problem_from_dict,
)
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import Reference, scenario_reference
from casadi_debris.robust.plant import Controller
from casadi_debris.simulation import ClosedLoopResult, simulate_closed_loop
from tests.allocation.test_isp import twin_data

RUN_S = 400.0
FAILURE_S = 300.0
# The +x and +z CubeSats; 1 fires before and after 300 s in the nominal run.
FAILED = (1, 2, 3, 4, 17, 18, 19, 20)
CUBESAT = 1
MAIN_ROW, TWIN_ROW = 2 * (CUBESAT - 1), 2 * (CUBESAT - 1) + 1
TWIN_ROWS = slice(1, None, 2)


@pytest.fixture(scope="module")
def problem(paper_data: dict[str, Any]) -> Problem:
    data = twin_data(paper_data)
    with (default_problem_path().parent / "paper_slew.toml").open("rb") as handle:
        data["simulation"] = copy.deepcopy(tomllib.load(handle)["simulation"])
    data["simulation"]["duration_s"] = RUN_S
    data["simulation"]["failures"] = [
        {"time_s": FAILURE_S, "cubesat": cubesat, "engine": 1} for cubesat in FAILED
    ]
    return problem_from_dict(data, "twins")


@pytest.fixture(scope="module")
def run(problem: Problem) -> ClosedLoopResult:
    record = Controller.from_dict(json.loads(default_controller_path().read_text()))
    reference = scenario_reference(problem)
    keep = reference.time_s <= RUN_S + 1e-9
    reference = Reference(
        reference.time_s[keep], reference.quaternion_BN[keep], reference.slew, reference.start_s
    )
    return simulate_closed_loop(build_model(problem), record.reduced, reference)


def exhaust(problem: Problem) -> np.ndarray:
    g0 = problem.constants.standard_gravity_m_s2
    return np.array([engine.isp_s * g0 for engine in problem.engines])


def test_the_failed_engine_stops_and_its_cubesat_fires_on(run: ClosedLoopResult) -> None:
    step = round(FAILURE_S / run.control_period_s)
    assert [(e.time_s, e.text) for e in run.events] == [
        (FAILURE_S, f"CubeSat {cubesat} engine 1 failed") for cubesat in FAILED
    ]
    assert run.summary().events[0].engine == 1
    assert run.thrust_N[:step, MAIN_ROW].max() > 0.0
    np.testing.assert_array_equal(run.thrust_N[step:, MAIN_ROW], 0.0)
    assert run.propulsion.failed_engines[MAIN_ROW]
    assert not run.propulsion.failed_cubesats[CUBESAT - 1]
    # While the iESE fired, no twin had to; afterwards CubeSat 1's fills in.
    np.testing.assert_array_equal(run.thrust_N[:step, TWIN_ROWS], 0.0)
    assert run.thrust_N[step:, TWIN_ROW].max() > 0.0


def test_each_engine_burns_at_its_own_isp(run: ClosedLoopResult, problem: Problem) -> None:
    step = round(FAILURE_S / run.control_period_s)
    dt = run.control_period_s
    c = exhaust(problem)
    burnt = run.thrust_N.sum(axis=0) * dt / c
    capacity = float(run.propulsion.stage_capacity_kg.max())
    atol = np.spacing(capacity) * (len(run.thrust_N) / 100 + 10)
    np.testing.assert_allclose(run.fuel_per_engine_kg, burnt, rtol=1e-12, atol=atol)
    # The failed engine's propellant stops at the failure.
    main_before = run.thrust_N[:step, MAIN_ROW].sum() * dt / c[MAIN_ROW]
    assert run.fuel_per_engine_kg[MAIN_ROW] == pytest.approx(main_before, rel=1e-12, abs=atol)
    summary = run.summary()
    assert summary.fuel_kg == pytest.approx(float(burnt.sum()), rel=1e-12)
    effective = float(np.sum(burnt * c) / burnt.sum())
    assert run.exhaust_velocity_m_s == pytest.approx(effective, rel=1e-12)
    assert c.min() < effective < c.max()
    mass = run.total_mass_kg
    expected_dv = effective * math.log(mass / (mass - burnt.sum()))
    assert summary.dv_used_m_s == pytest.approx(expected_dv, rel=1e-9)
