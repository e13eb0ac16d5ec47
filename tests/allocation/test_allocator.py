"""Thruster-level allocation, staging and fuel tracking, checked against independent computations.

References: scipy's HiGHS linear programs on the same problem (least fuel,
largest alpha), the geometry's torque-authority LP, and closed-form stage
depletion times. The LPs are posed in mN and mNm (or finer units for tiny
demands) so that HiGHS' absolute tolerances are small against the numbers.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from casadi_debris.allocation import (
    Allocator,
    NoEngineError,
    PropulsionState,
    PseudoInverseAllocator,
    UnknownSolverError,
    available_solvers,
)
from casadi_debris.cli import main
from casadi_debris.config import SIGNED_AXES, Problem
from casadi_debris.errors import AllocationError, CasadiDebrisError, InputShapeError
from casadi_debris.geometry import Geometry, torque_authority
from lp_reference import MN, largest_alpha, least_fuel_N

TORQUE_RTOL = 1e-9
FUEL_RTOL = 1e-6
ANGLE_TOL_RAD = 1e-6
ALPHA_TOL = 1e-9
# Resolution floor relative to one engine's full torque or thrust: the QP
# solvers' zero tolerance (DAQP: 1e-11) leaves thrusts of up to about 1e-12 of
# the limit when warm-started, far below any physical demand (1e-14 N m here)
# but above the demands of 1e-300 N m Hypothesis tries.
ROUND_OFF = 1e-11
N_CUBESATS = 24


# ----------------------------------------------------------------------------- references


def angle_rad(a: np.ndarray, b: np.ndarray) -> float:
    return math.atan2(float(np.linalg.norm(np.cross(a, b))), float(a @ b))


@pytest.fixture(scope="module")
def allocator(problem: Problem, geometry: Geometry) -> Allocator:
    return Allocator.from_problem(problem, geometry)


@pytest.fixture(scope="module")
def stage_limit_N(problem: Problem) -> float:
    return problem.engine.thrust_per_stage_mN / MN


def check_against_lp(
    allocator: Allocator,
    geometry: Geometry,
    torque: np.ndarray,
    force: np.ndarray | None,
) -> None:
    """Every property of the issue for one demand with the allocator's current limits."""
    limits = allocator.max_thrust_N
    result = allocator.allocate(torque, force, free_force=force is None)

    assert np.all(result.thrust_N >= 0.0)
    assert np.all(result.thrust_N <= limits)
    assert np.all(np.isfinite(result.thrust_N))
    np.testing.assert_array_equal(result.torque_Nm, geometry.torque_map @ result.thrust_N)

    alpha_lp = largest_alpha(geometry, limits, torque, force)
    torque_norm = float(np.linalg.norm(torque))
    if result.feasible:
        assert result.scale == 1.0
        assert alpha_lp >= 1.0 - ALPHA_TOL
    else:
        assert abs(result.scale - alpha_lp) <= ALPHA_TOL
    # Achieved torque = alpha * demand: exact when feasible, direction kept when not.
    # Relative to the demand, or to the engines' own torques when these are larger
    # (round-off of B f when their sum nearly cancels, as for a pure force demand),
    # with a floor at the solvers' resolution (see ROUND_OFF).
    stage_torque = float(np.abs(geometry.torque_map).max() * limits.max())
    engine_torques = float(np.abs(geometry.torque_map) @ result.thrust_N @ np.ones(3))
    torque_scale = max(torque_norm, engine_torques, ROUND_OFF * stage_torque / TORQUE_RTOL)
    assert np.linalg.norm(result.torque_Nm - result.scale * torque) <= TORQUE_RTOL * torque_scale
    if force is not None:
        force_scale = max(
            float(np.linalg.norm(force)),
            float(result.thrust_N.sum()),
            ROUND_OFF * float(limits.max()) / TORQUE_RTOL,
        )
        assert np.linalg.norm(result.force_N - result.scale * force) <= TORQUE_RTOL * force_scale
    if not result.feasible and result.scale * torque_norm > ROUND_OFF * stage_torque:
        assert angle_rad(result.torque_Nm, torque) < ANGLE_TOL_RAD

    # Least fuel among the thrusts that give the wrench achieved (alpha times the
    # demand, checked above): a wrench our thrust makes, so the LP is feasible.
    reference = least_fuel_N(
        geometry, limits, result.torque_Nm, None if force is None else result.force_N
    )
    assert reference is not None
    fuel = float(result.thrust_N.sum())
    assert abs(fuel - reference) <= FUEL_RTOL * reference + ROUND_OFF * float(limits.max())
    mass_flow = float(result.thrust_N @ (1.0 / allocator.exhaust_velocity_m_s))
    assert result.fuel_rate_kg_s == pytest.approx(mass_flow, rel=1e-12)


# ----------------------------------------------------------------------------- properties

# Components of 0 or of 1e-9 .. 8e-3 N m either sign (1e-6 to 2x an engine's
# torque): the allocator stretches tinier demands itself, but HiGHS, the
# reference, cannot check them.
demand_magnitude = st.floats(min_value=1e-9, max_value=8e-3)
demand_component = st.one_of(
    st.just(0.0), demand_magnitude, demand_magnitude.map(lambda value: -value)
)


@settings(
    max_examples=150,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(
    torque=st.tuples(demand_component, demand_component, demand_component),
    failed=st.sets(st.integers(0, N_CUBESATS - 1), max_size=14),
    free_force=st.booleans(),
)
def test_random_demands_and_failures_match_linear_programs(
    allocator: Allocator,
    geometry: Geometry,
    stage_limit_N: float,
    torque: tuple[float, float, float],
    failed: set[int],
    free_force: bool,
) -> None:
    limits = np.full(N_CUBESATS, stage_limit_N)
    limits[list(failed)] = 0.0
    allocator.set_max_thrust(limits)
    try:
        check_against_lp(allocator, geometry, np.array(torque), None if free_force else np.zeros(3))
    finally:
        allocator.set_max_thrust(np.full(N_CUBESATS, stage_limit_N))


@settings(max_examples=40, deadline=None)
@given(
    torque=st.tuples(demand_component, demand_component, demand_component),
    force=st.tuples(
        *[
            st.floats(min_value=-1.5e-3, max_value=1.5e-3).filter(
                lambda value: value == 0.0 or abs(value) >= 1e-9
            )
        ]
        * 3
    ),
)
def test_requested_force_is_met_or_scaled_with_the_torque(
    allocator: Allocator,
    geometry: Geometry,
    torque: tuple[float, float, float],
    force: tuple[float, float, float],
) -> None:
    check_against_lp(allocator, geometry, np.array(torque), np.array(force))


@pytest.mark.parametrize("solver", ["daqp", "osqp", "qpsolvers:daqp"])
def test_back_ends_meet_the_same_tolerances(
    problem: Problem, geometry: Geometry, solver: str
) -> None:
    allocator = Allocator.from_problem(problem, geometry, solver=solver)
    rng = np.random.default_rng(20240404)
    for torque in rng.uniform(-8e-3, 8e-3, size=(12, 3)):
        check_against_lp(allocator, geometry, torque, np.zeros(3))


def test_every_installed_back_end_is_selectable_and_keeps_limits(
    problem: Problem, geometry: Geometry
) -> None:
    demand = np.array([1e-3, -0.5e-3, 0.8e-3])
    for solver in available_solvers():
        allocator = Allocator.from_problem(problem, geometry, solver=solver)
        for scale in (1.0, 10.0):
            result = allocator.allocate(scale * demand)
            # A back-end whose answer fails the allocator's own check is rescued by HiGHS
            # and says so ("scs+highs": SCS is a first-order solver, accurate to ~1e-4).
            assert result.solver in (solver, f"{solver}+highs")
            assert np.all(result.thrust_N >= 0) and np.all(
                result.thrust_N <= allocator.max_thrust_N
            )
        assert result.feasible is False


# ----------------------------------------------------------------------------- saturation


def test_unit_demand_per_axis_gives_the_geometry_torque_authority(
    allocator: Allocator, geometry: Geometry
) -> None:
    authority = torque_authority(geometry, zero_net_force=True)
    for name in SIGNED_AXES:
        axis = "xyz".index(name[1])
        demand = np.zeros(3)
        demand[axis] = 1.0 if name[0] == "+" else -1.0
        result = allocator.allocate(demand)
        assert not result.feasible
        assert abs(result.torque_Nm[axis]) == pytest.approx(authority[name], rel=TORQUE_RTOL)
        off_axis = np.delete(result.torque_Nm, axis)
        assert np.all(np.abs(off_axis) <= TORQUE_RTOL * authority[name])
        assert np.linalg.norm(result.force_N) <= TORQUE_RTOL * result.thrust_N.sum()


@pytest.mark.parametrize("failed", [(), (3, 17), (0, 1, 2, 3), (8, 9, 12, 13, 20)])
def test_reduced_authority_after_failures_matches_the_geometry_lp(
    problem: Problem, geometry: Geometry, failed: tuple[int, ...]
) -> None:
    allocator = Allocator.from_problem(problem, geometry)
    allocator.set_failed(failed)
    available = np.ones(N_CUBESATS, dtype=bool)
    available[list(failed)] = False
    for free_force in (False, True):
        expected = torque_authority(geometry, zero_net_force=not free_force, available=available)
        found = allocator.torque_authority(free_force=free_force)
        for name in SIGNED_AXES:
            assert found[name] == pytest.approx(expected[name], rel=TORQUE_RTOL, abs=1e-15)
    assert np.all(allocator.allocate([1.0, 1.0, 1.0]).thrust_N[list(failed)] == 0.0)


def test_least_squares_mode_is_exact_when_feasible_and_closest_when_not(
    problem: Problem, geometry: Geometry
) -> None:
    scaled = Allocator.from_problem(problem, geometry)
    least_squares = Allocator.from_problem(problem, geometry, saturation="least_squares")
    feasible = np.array([1e-3, -0.4e-3, 0.7e-3])
    a, b = scaled.allocate(feasible), least_squares.allocate(feasible)
    assert b.feasible and b.mode == "exact"
    assert b.thrust_N.sum() == pytest.approx(a.thrust_N.sum(), rel=FUEL_RTOL)

    rng = np.random.default_rng(7)
    for demand in rng.uniform(-2e-2, 2e-2, size=(10, 3)):
        a, b = scaled.allocate(demand), least_squares.allocate(demand)
        assert not b.feasible and b.mode == "least_squares"
        assert np.all(b.thrust_N >= 0) and np.all(b.thrust_N <= least_squares.max_thrust_N)
        assert np.linalg.norm(b.force_N) <= TORQUE_RTOL * b.thrust_N.sum()
        # The projection of the demand is at least as close as its scaled copy.
        error_ls = np.linalg.norm(b.torque_Nm - demand)
        error_scaled = np.linalg.norm(a.torque_Nm - demand)
        assert error_ls <= error_scaled * (1.0 + 1e-9)
        # and it is the least-fuel way to make that torque.
        reference = least_fuel_N(geometry, least_squares.max_thrust_N, b.torque_Nm, np.zeros(3))
        assert reference is not None
        assert b.thrust_N.sum() == pytest.approx(reference, rel=FUEL_RTOL)


def test_batch_matches_single_calls(allocator: Allocator) -> None:
    rng = np.random.default_rng(3)
    torques = rng.uniform(-6e-3, 6e-3, size=(20, 3))
    batch = allocator.allocate_batch(torques)
    assert batch.thrust_N.shape == (20, N_CUBESATS)
    for i, torque in enumerate(torques):
        single = allocator.allocate(torque)
        assert batch.feasible[i] == single.feasible
        assert batch.scale[i] == pytest.approx(single.scale, rel=1e-12)
        np.testing.assert_allclose(batch.torque_Nm[i], single.torque_Nm, rtol=0, atol=1e-15)


def test_pseudo_inverse_baseline_is_exact_small_and_short_when_saturated(
    allocator: Allocator, geometry: Geometry
) -> None:
    baseline = PseudoInverseAllocator(allocator)
    small = np.array([0.2e-3, -0.1e-3, 0.15e-3])
    result = baseline.allocate(small)
    assert result.feasible
    np.testing.assert_allclose(result.torque_Nm, small, rtol=0, atol=TORQUE_RTOL * 1e-3)
    big = baseline.allocate([1.0, 0.0, 0.0])
    assert np.all(big.thrust_N <= allocator.max_thrust_N) and np.all(big.thrust_N >= 0)
    assert big.torque_Nm[0] < torque_authority(geometry, zero_net_force=True)["+x"]


# ----------------------------------------------------------------------------- staging


def test_stage_propellant_by_hand(problem: Problem) -> None:
    state = PropulsionState.from_problem(problem)
    # 0.64 mN x 500 h / (1000 s x 9.80665 m/s^2)
    np.testing.assert_allclose(state.stage_capacity_kg, 0.64e-3 * 500 * 3600 / 9806.65, rtol=1e-12)
    assert state.propellant_kg.shape == (N_CUBESATS, problem.engine.stages)
    np.testing.assert_array_equal(state.active_stage, 0)


def test_first_stage_switches_at_the_analytic_time(problem: Problem, geometry: Geometry) -> None:
    state = PropulsionState.from_problem(problem)
    allocator = Allocator.from_problem(problem, geometry, state=state)
    thrust = allocator.allocate([1.2e-3, 0.6e-3, -1.0e-3]).thrust_N
    engine, g0 = problem.engine, problem.constants.standard_gravity_m_s2
    stage_thrust = engine.thrust_per_stage_mN / MN
    stage_kg = stage_thrust * engine.stage_life_h * 3600.0 / (engine.isp_s * g0)
    # Closed form: a stage holding m_stage burns m_dot = F / (Isp g0), so it lasts m_stage / m_dot.
    expected_switch_s = stage_kg * engine.isp_s * g0 / thrust.max()

    dt_s, elapsed_s = 3600.0, 0.0
    events = []
    while not events:
        assert elapsed_s < 2 * expected_switch_s
        events = state.advance(thrust, dt_s)
        allocator.update_from_state(state)
        if not events:
            elapsed_s += dt_s
    first = [e for e in events if e.stage == 0]
    assert first, events
    hottest = set(np.flatnonzero(thrust >= thrust.max() * (1 - 1e-12)))
    assert {e.cubesat for e in first} == hottest
    for event in first:
        assert elapsed_s + event.time_s == pytest.approx(expected_switch_s, rel=1e-9)
        assert event.next_stage == 1
        assert state.active_stage[event.cubesat] == 1
        assert state.propellant_kg[event.cubesat, 0] == 0.0
        # The rest of the step came out of stage 1.
        burnt_next = state.fuel_used_kg[event.cubesat, 1]
        expected_next = thrust[event.cubesat] / (engine.isp_s * g0) * (dt_s - event.time_s)
        assert burnt_next == pytest.approx(expected_next, rel=1e-9)
    total_time = elapsed_s + dt_s
    np.testing.assert_allclose(
        state.fuel_used_kg.sum(axis=1), thrust * total_time / (engine.isp_s * g0), rtol=1e-9
    )
    # The next stage has the same thrust: the allocation is unchanged.
    np.testing.assert_allclose(allocator.max_thrust_N, stage_thrust)


def test_cubesat_drops_out_after_its_last_stage(problem: Problem, geometry: Geometry) -> None:
    state = PropulsionState.from_problem(problem)
    life_s = problem.engines[5].stage_life_h * 3600.0
    thrust = np.zeros(N_CUBESATS)
    thrust[5] = state.stage_thrust_N[5, 0]
    events = state.advance(thrust, 4 * life_s)
    assert [e.stage for e in events] == [0, 1, 2]
    assert [e.next_stage for e in events] == [1, 2, None]
    for k, event in enumerate(events, start=1):
        assert event.time_s == pytest.approx(k * life_s, rel=1e-12)
    np.testing.assert_allclose(state.firing_time_s[5], life_s, rtol=1e-12)
    assert not state.available[5] and state.max_thrust_N()[5] == 0.0
    assert state.active_stage[5] == problem.engine.stages
    allocator = Allocator.from_problem(problem, geometry, state=state)
    available = np.ones(N_CUBESATS, dtype=bool)
    available[5] = False
    expected = torque_authority(geometry, zero_net_force=True, available=available)
    found = allocator.torque_authority()
    for name in SIGNED_AXES:
        assert found[name] == pytest.approx(expected[name], rel=TORQUE_RTOL)


def test_failed_stage_hands_over_and_state_round_trips(problem: Problem) -> None:
    state = PropulsionState.from_problem(problem)
    state.fail_stage(2, 0)
    state.fail_cubesat(7)
    assert state.active_stage[2] == 1 and state.active_stage[7] == problem.engine.stages
    # What a user reads numbers CubeSats and stages from 1.
    written = state.to_dict()
    assert written["failed_cubesats"] == [8] and written["failed_stages"] == [[3, 1]]
    restored = PropulsionState.from_problem(problem).updated_from_dict(
        json.loads(json.dumps(state.to_dict()))
    )
    np.testing.assert_array_equal(restored.active_stage, state.active_stage)
    np.testing.assert_array_equal(restored.max_thrust_N(), state.max_thrust_N())


# ----------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "torque", [[1e-3, 0.0], [[1e-3, 0.0, 0.0]], [np.nan, 0.0, 0.0], [np.inf, 0.0, 0.0]]
)
def test_bad_demand_is_a_named_error(allocator: Allocator, torque: list) -> None:
    with pytest.raises(InputShapeError):
        allocator.allocate(torque)


def test_bad_calls_are_named_errors(
    problem: Problem, geometry: Geometry, allocator: Allocator
) -> None:
    with pytest.raises(UnknownSolverError, match="daqp"):
        Allocator.from_problem(problem, geometry, solver="no-such-solver")
    with pytest.raises(AllocationError, match="saturation"):
        Allocator.from_problem(problem, geometry, saturation="clip")  # type: ignore[arg-type]
    with pytest.raises(AllocationError):
        allocator.allocate([0.0, 0.0, 1e-3], [0.0, 0.0, 0.0], free_force=True)
    with pytest.raises(InputShapeError):
        allocator.allocate([0.0, 0.0, 1e-3], [0.0, np.nan, 0.0])
    with pytest.raises(InputShapeError):
        allocator.allocate_batch(np.zeros((4, 2)))
    fresh = Allocator.from_problem(problem, geometry)
    with pytest.raises(NoEngineError):
        fresh.set_failed(range(N_CUBESATS))
    with pytest.raises(NoEngineError):
        Allocator(
            geometry.torque_map, geometry.force_map, np.zeros(N_CUBESATS), exhaust_velocity_m_s=1e4
        )
    with pytest.raises(InputShapeError):
        Allocator(
            geometry.torque_map[:2],
            geometry.force_map,
            np.ones(N_CUBESATS),
            exhaust_velocity_m_s=1e4,
        )
    assert issubclass(NoEngineError, CasadiDebrisError)


def test_bad_propulsion_steps_are_named_errors(problem: Problem) -> None:
    state = PropulsionState.from_problem(problem)
    with pytest.raises(InputShapeError):
        state.advance(np.zeros(5), 1.0)
    with pytest.raises(InputShapeError):
        state.advance(np.full(N_CUBESATS, np.nan), 1.0)
    with pytest.raises(AllocationError, match="above"):
        state.advance(np.full(N_CUBESATS, 1.0), 1.0)
    state.fail_cubesat(0)
    thrust = np.zeros(N_CUBESATS)
    thrust[0] = 1e-4
    with pytest.raises(AllocationError):
        state.advance(thrust, 1.0)
    with pytest.raises(AllocationError, match="unknown"):
        state.updated_from_dict({"fuel": 1})
    # Ids in a state file are 1-based: 0 is out of range, n_cubesats is the last.
    with pytest.raises(AllocationError, match=r"CubeSat 0 out of range 1\.\.24"):
        state.updated_from_dict({"failed_cubesats": [0]})
    with pytest.raises(AllocationError, match=r"stage 4 out of range 1\.\.3"):
        state.updated_from_dict({"failed_stages": [[1, 4]]})
    assert state.updated_from_dict({"failed_cubesats": [24]}).failed_cubesats[23]


# ----------------------------------------------------------------------------- command line


def test_cli_json_has_the_documented_fields(tmp_path) -> None:
    runner = CliRunner()
    result = runner.invoke(main, ["allocate", "--torque-mNm", "1", "0.5", "-0.8", "--json"])
    assert result.exit_code == 0, result.output
    payload = json.loads(result.output)
    for key in (
        "thrust_mN",
        "torque_achieved_mNm",
        "force_achieved_mN",
        "feasible",
        "scale",
        "fuel_rate_kg_s",
        "solver",
        "solve_time_us",
        "iterations",
    ):
        assert key in payload
    assert len(payload["thrust_mN"]) == N_CUBESATS
    np.testing.assert_allclose(payload["torque_achieved_mNm"], [1, 0.5, -0.8], rtol=1e-9)
    assert payload["feasible"] is True and payload["solver"] == "daqp"

    state_file = tmp_path / "state.json"
    state_file.write_text(json.dumps({"failed_cubesats": [4], "failed_stages": [[5, 1]]}))
    result = runner.invoke(
        main,
        ["allocate", "--torque-mNm", "20", "0", "0", "--failed", "18",
         "--stage-state", str(state_file), "--free-force", "--json"],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    payload = json.loads(result.output)
    assert payload["feasible"] is False and 0 < payload["scale"] < 1
    assert payload["thrust_mN"][3] == 0 and payload["thrust_mN"][17] == 0
    # Ids are 1-based everywhere (index 17 is CubeSat 18), the state file's too: CubeSat 5
    # lost stage 1, so stage 2 fires.
    assert payload["failed_cubesats"] == [4, 18] and payload["active_stage"][4] == 2
    assert payload["force_demand_mN"] is None

    text = runner.invoke(main, ["allocate", "--torque-mNm", "1", "2", "3"])
    assert text.exit_code == 0 and "saturated" in text.output


@pytest.mark.parametrize(
    "arguments",
    [
        ["--torque-mNm", "1", "0", "0", "--solver", "nope"],
        ["--torque-mNm", "1", "0", "0", "--failed", "a,b"],
        ["--torque-mNm", "1", "0", "0", "--failed", ",".join(map(str, range(1, N_CUBESATS + 1)))],
        ["--torque-mNm", "1", "0", "0", "--failed", "0"],
        ["--torque-mNm", "1", "0", "0", "--force-mN", "0", "0", "0", "--free-force"],
        ["--torque-mNm", "nan", "0", "0"],
        ["--torque-mNm", "1", "0", "0", "--stage-state", "/nonexistent/state.json"],
    ],
)
def test_cli_bad_input_is_one_line_and_exit_2(arguments: list[str]) -> None:
    result = CliRunner().invoke(main, ["allocate", *arguments])
    assert result.exit_code == 2, result.output
    assert result.output.count("\n") == 1 and result.output.startswith("error:")


def test_small_demand_with_few_engines_left_is_least_fuel(
    problem: Problem, geometry: Geometry
) -> None:
    """A small demand is solved stretched and scaled back, unless a limit binds when
    stretched (found by hypothesis: nine CubeSats failed, force free, 6.7 % extra fuel)."""
    allocator = Allocator.from_problem(problem)
    allocator.set_failed([0, 2, 3, 7, 11, 12, 16, 18, 21])
    torque = np.array([0.0, 0.0, 5.960464477539063e-08])
    result = allocator.allocate(torque, free_force=True)
    limits = allocator.max_thrust_N
    reference = least_fuel_N(geometry, limits, torque, None)
    assert reference is not None
    assert result.thrust_N.sum() == pytest.approx(reference, rel=1e-6)
