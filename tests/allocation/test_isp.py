"""Engines of different Isp, and engines failed one by one, against independent LPs.

The twin swarm: every CubeSat of the paper carries its iESE (Isp 1000 s) and, at
the same point and along the same direction, a twin of Isp 250 s. A newton from
the twin costs four times the propellant, so the least-fuel allocation must
leave the twins off whenever the iESE alone reach the demand, and fire them
only for what the iESE cannot give. Mass flows are checked against scipy's
HiGHS on ``sum f_i / (Isp_i g0)`` (tests/lp_reference.py).
"""

from __future__ import annotations

import copy
import json
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris.allocation import Allocator, PropulsionState
from casadi_debris.cli import main
from casadi_debris.config import Problem, load_problem, problem_from_dict
from casadi_debris.errors import AllocationError, ProblemFileError
from casadi_debris.geometry import Geometry, build_geometry
from casadi_debris.slews import axis_fuel_rates, fuel_weights
from lp_reference import least_mass_flow_kg_s

TWIN_ISP_S = 250.0
# The QP's proximal term moves the least-fuel point of the paper's swarm by far less.
MASS_FLOW_RTOL = 1e-6
TORQUE_RTOL = 1e-9


def twin_data(paper_data: dict[str, Any]) -> dict[str, Any]:
    """The paper's CubeSats written out, each with its iESE and a low-Isp twin."""
    paper = load_problem()
    data = {k: copy.deepcopy(v) for k, v in paper_data.items() if k != "cubesat_layout"}
    data["cubesats"] = []
    for cubesat in paper.cubesats:
        [engine] = cubesat.engines
        main = {"direction": engine.direction.tolist(), "offset_m": engine.offset_m.tolist()}
        data["cubesats"].append(
            {
                "position_corner_m": cubesat.position_corner_m.tolist(),
                "mass_kg": cubesat.mass_kg,
                "inertia_kgm2": cubesat.inertia_kgm2.tolist(),
                "engines": [main, {**main, "isp_s": TWIN_ISP_S}],
            }
        )
    return data


@pytest.fixture(scope="module")
def twins(paper_data: dict[str, Any]) -> tuple[Problem, Geometry, Allocator]:
    problem = problem_from_dict(twin_data(paper_data))
    geometry = build_geometry(problem)
    return problem, geometry, Allocator.from_problem(problem, geometry)


def exhaust(problem: Problem) -> np.ndarray:
    g0 = problem.constants.standard_gravity_m_s2
    return np.array([engine.isp_s * g0 for engine in problem.engines])


def demands(seed: int, size_Nm: float, count: int = 40) -> np.ndarray:
    rng = np.random.default_rng(seed)
    directions = rng.normal(size=(count, 3))
    return size_Nm * directions / np.linalg.norm(directions, axis=1, keepdims=True)


def test_the_low_isp_twins_stay_off_while_the_main_engines_suffice(twins) -> None:
    problem, geometry, allocator = twins
    main, twin = slice(0, None, 2), slice(1, None, 2)
    paper = Allocator.from_problem(load_problem())
    authority = min(paper.torque_authority().values())
    limits = allocator.max_thrust_N
    for demand in demands(1, 0.5 * authority):
        result = allocator.allocate(demand)
        assert result.feasible
        np.testing.assert_allclose(result.torque_Nm, demand, rtol=0, atol=TORQUE_RTOL * authority)
        np.testing.assert_array_equal(result.thrust_N[twin], 0.0)
        # The main engines do what the paper's swarm does alone.
        np.testing.assert_allclose(
            result.thrust_N[main], paper.allocate(demand).thrust_N, atol=1e-9 * limits.max()
        )
        reference = least_mass_flow_kg_s(geometry, limits, exhaust(problem), demand, np.zeros(3))
        assert result.fuel_rate_kg_s == pytest.approx(reference, rel=MASS_FLOW_RTOL)


def test_the_twins_fire_only_for_what_the_main_engines_cannot_give(twins) -> None:
    problem, geometry, allocator = twins
    paper = Allocator.from_problem(load_problem())
    authority = paper.torque_authority()
    for axis, name in enumerate(("+x", "+y", "+z")):
        demand = np.zeros(3)
        demand[axis] = 1.5 * authority[name]  # beyond the iESE, within iESE + twins
        result = allocator.allocate(demand)
        assert result.feasible
        assert result.thrust_N[1::2].sum() > 0.0
        limits = allocator.max_thrust_N
        reference = least_mass_flow_kg_s(geometry, limits, exhaust(problem), demand, np.zeros(3))
        assert result.fuel_rate_kg_s == pytest.approx(reference, rel=MASS_FLOW_RTOL)
        # Least total thrust is not least fuel here: it would use the twins more.
        assert result.fuel_rate_kg_s <= float(np.sum(result.thrust_N)) / exhaust(problem).min()


def test_series_and_batch_agree_with_allocate_for_mixed_isp(twins) -> None:
    _, _, allocator = twins
    rng = np.random.default_rng(3)
    size = 1.2 * max(Allocator.from_problem(load_problem()).torque_authority().values())
    history = np.cumsum(rng.normal(size=(400, 3)), axis=0)
    history *= size / np.abs(history).max()
    series = allocator.allocate_series(history)
    batch = allocator.allocate_batch(history[::20])
    one = [allocator.allocate(t) for t in history[::20]]
    np.testing.assert_allclose(
        series.fuel_rate_kg_s[::20], [r.fuel_rate_kg_s for r in one], rtol=1e-6
    )
    np.testing.assert_allclose(batch.fuel_rate_kg_s, [r.fuel_rate_kg_s for r in one], rtol=1e-14)
    np.testing.assert_allclose(
        series.fuel_rate_kg_s, series.thrust_N @ (1.0 / allocator.exhaust_velocity_m_s), rtol=1e-12
    )


def test_one_exhaust_velocity_per_engine_or_for_all_is_the_same_allocator() -> None:
    problem = load_problem()
    geometry = build_geometry(problem)
    c = problem.engine.isp_s * problem.constants.standard_gravity_m_s2
    limits = np.array([engine.max_thrust_N for engine in geometry.engines])
    scalar = Allocator(geometry.torque_map, geometry.force_map, limits, exhaust_velocity_m_s=c)
    per_engine = Allocator.from_problem(problem, geometry)
    for demand in demands(4, 3e-3, 30):
        a, b = scalar.allocate(demand), per_engine.allocate(demand)
        np.testing.assert_array_equal(a.thrust_N, b.thrust_N)
        assert a.fuel_rate_kg_s == b.fuel_rate_kg_s == float(a.thrust_N.sum()) / c
    with pytest.raises(AllocationError, match="exhaust_velocity_m_s"):
        Allocator(geometry.torque_map, geometry.force_map, limits, exhaust_velocity_m_s=-c)


# --------------------------------------------------------------------------- engine failures


def test_a_failed_engine_loses_exactly_its_authority(twins) -> None:
    problem, geometry, _ = twins
    state = PropulsionState.from_problem(problem)
    state.fail_engine(4, 0)  # CubeSat 5's iESE; its twin fires on
    allocator = Allocator.from_problem(problem, geometry, state=state)
    limits = allocator.max_thrust_N
    failed = state.engine_index(4, 0)
    assert limits[failed] == 0.0
    assert np.count_nonzero(limits == 0.0) == 1
    assert limits[failed + 1] > 0.0
    for demand in demands(5, 2e-3):
        result = allocator.allocate(demand)
        assert result.thrust_N[failed] == 0.0
        reference = least_mass_flow_kg_s(geometry, limits, exhaust(problem), demand, np.zeros(3))
        if reference is None:
            assert not result.feasible
            continue
        assert result.feasible
        assert result.fuel_rate_kg_s == pytest.approx(reference, rel=MASS_FLOW_RTOL)


def test_engine_failures_round_trip_with_1_based_ids(twins) -> None:
    problem, _, _ = twins
    state = PropulsionState.from_problem(problem)
    state.fail_engine(2, 1)
    assert state.to_dict()["failed_engines"] == [[3, 2]]
    again = PropulsionState.from_problem(problem).updated_from_dict({"failed_engines": [[3, 2]]})
    np.testing.assert_array_equal(again.failed_engines, state.failed_engines)
    with pytest.raises(AllocationError, match=r"failed_engines: engine 3 out of range 1\.\.2"):
        state.updated_from_dict({"failed_engines": [[3, 3]]})
    with pytest.raises(AllocationError, match=r"CubeSat 3 has engines 1\.\.2"):
        state.fail_engine(2, 2)


def test_a_failure_entry_names_one_engine_of_its_cubesat(twins, paper_data) -> None:
    data = twin_data(paper_data)
    data["simulation"]["failures"] = [{"time_s": 5.0, "cubesat": 3, "engine": 2}]
    [failure] = problem_from_dict(data).simulation.failures
    assert (failure.cubesat, failure.engine, failure.stage) == (2, 1, None)
    for entry, words in (
        ({"cubesat": 3, "engine": 3}, "CubeSat 3 has 2 engine(s), numbered 1..2; got 3"),
        ({"cubesat": 3, "engine": 0}, "at least 1"),
        ({"cubesat": 3, "engine": 1, "stage": 1}, "give stage or engine, not both"),
    ):
        data["simulation"]["failures"] = [{"time_s": 5.0, **entry}]
        with pytest.raises(ProblemFileError) as caught:
            problem_from_dict(data)
        assert caught.value.field == "simulation.failures[0].engine"
        assert words in str(caught.value)


def test_allocate_takes_failed_engines_by_cubesat_and_engine() -> None:
    args = ["allocate", "--torque-mNm", "1", "0", "0", "--json"]
    runner = CliRunner()
    result = runner.invoke(main, [*args, "--failed-engines", "3:1,17:1"])
    assert result.exit_code == 0, result.output
    payload = json.loads(result.stdout)
    assert payload["failed_engines"] == [[3, 1], [17, 1]]
    assert payload["thrust_limit_mN"][2] == payload["thrust_limit_mN"][16] == 0.0
    assert payload["thrust_mN"][2] == payload["thrust_mN"][16] == 0.0
    # The paper's CubeSats have one engine each: failing it is failing the CubeSat.
    same = json.loads(runner.invoke(main, [*args, "--failed", "3,17"]).stdout)
    assert same["thrust_mN"] == payload["thrust_mN"]
    for value, words in (("3:2", "CubeSat 3 has engines 1..1"), ("3", "CUBESAT:ENGINE")):
        refused = runner.invoke(main, [*args, "--failed-engines", value])
        assert refused.exit_code == 2
        [line] = refused.output.strip().splitlines()
        assert "--failed-engines" in line and words in line


def test_the_slews_fuel_rates_per_axis_weigh_engines_by_their_isp(twins) -> None:
    # The torque-level fuel objective's cost per N m about each signed axis is the least
    # mass flow for that torque (an LP over the engines, here), in best-engine newtons.
    problem, geometry, _ = twins
    weights = fuel_weights(problem)
    assert weights is not None and set(np.round(weights, 12)) == {1.0, 4.0}
    plus, minus = axis_fuel_rates(geometry, weights)
    c = exhaust(problem)
    limits = np.array([engine.max_thrust_N for engine in geometry.engines])
    small = 1e-4
    for axis in range(3):
        for sign, rate in ((1.0, plus[axis]), (-1.0, minus[axis])):
            torque = np.zeros(3)
            torque[axis] = sign * small
            mass_flow = least_mass_flow_kg_s(geometry, limits, c, torque, None)
            assert rate == pytest.approx(mass_flow * c.max() / small, rel=1e-6)
    # the twins are never worth it for a small torque: same rates as the iESE alone
    alone_plus, alone_minus = axis_fuel_rates(geometry)
    np.testing.assert_allclose(plus, alone_plus, rtol=1e-6)
    np.testing.assert_allclose(minus, alone_minus, rtol=1e-6)
