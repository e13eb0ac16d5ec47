"""The allocator at the ends of the float range: never NaN, inf or an unlabelled wrong answer.

Demands from the smallest subnormal (5e-324 N m) to 1e308 N m in any direction,
with the net force zero, free or given, and with CubeSats failed:

- a demand with a component beyond 1e6 times the largest that any thrust
  within the limits makes (computed here from the maps) is refused with an
  AllocationError naming the argument, as is a NaN or inf;
- every other one gets finite thrust within ``0 <= f <= f_max``;
- ``feasible`` only when the torque (and force) meet the demand within the
  tolerance ``allocate``'s docstring promises,
  ``1e-9 max(|tau|_inf, l sum f) + n (l + 2) 2**-1074``, written out again here;
- the answer agrees with scipy's HiGHS on the same problem (tests/lp_reference.py):
  reachable exactly when the LP says so, alpha to 1e-9, and least fuel to 1e-6
  where the demand is a normal float (below about 1e-290 N m the thrusts are
  subnormal and carry fewer digits than the comparison).
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from casadi_debris.allocation import AllocationInternalError, Allocator, DemandError, QpSolution
from casadi_debris.cli import main
from casadi_debris.config import Problem
from casadi_debris.errors import AllocationError
from casadi_debris.geometry import Geometry
from lp_reference import largest_alpha, least_fuel_N

N_CUBESATS = 24
RTOL = 1e-9  # the documented relative tolerance
ALPHA_TOL = 1e-9
FUEL_RTOL = 1e-6
SMALLEST_SUBNORMAL = 2.0**-1074
ABSURD_FACTOR = 1e6
# Below this the thrusts of a least-fuel answer are subnormal (fewer than 16
# digits): the fuel is not compared with the LP there.
NORMAL_DEMAND_Nm = 1e-290


# ----------------------------------------------------------------------------- references


def promised_tolerance(rows: np.ndarray, thrust: np.ndarray, wanted: np.ndarray) -> float:
    """The documented tolerance on ``rows @ thrust - wanted`` (torque or force rows)."""
    lever = float(np.abs(rows).max())
    floor = rows.shape[1] * (lever + 2.0) * SMALLEST_SUBNORMAL
    return RTOL * max(float(np.abs(wanted).max()), lever * float(thrust.sum())) + floor


def largest_component(rows: np.ndarray, limits: np.ndarray) -> float:
    """Largest value any component of ``rows @ f`` takes over 0 <= f <= limits."""
    return float((np.abs(rows) @ limits).max())


def check_answer(
    allocator: Allocator,
    geometry: Geometry,
    torque: np.ndarray,
    force: np.ndarray | None,
) -> None:
    """Refused when absurd or non-finite; otherwise finite, within limits, honest, and
    in agreement with the LPs."""
    limits = allocator.max_thrust_N
    absurd_torque = float(np.abs(torque).max()) > ABSURD_FACTOR * largest_component(
        geometry.torque_map, limits
    )
    absurd_force = force is not None and float(np.abs(force).max()) > (
        ABSURD_FACTOR * largest_component(geometry.force_map, limits)
    )
    if absurd_torque or absurd_force:
        with pytest.raises(AllocationError, match="torque_Nm" if absurd_torque else "force_N"):
            allocator.allocate(torque, force, free_force=force is None)
        return
    result = allocator.allocate(torque, force, free_force=force is None)

    assert np.all(np.isfinite(result.thrust_N)), result
    assert np.all(result.thrust_N >= 0.0) and np.all(result.thrust_N <= limits)
    assert math.isfinite(result.scale) and 0.0 <= result.scale <= 1.0
    assert math.isfinite(result.fuel_rate_kg_s)
    assert result.feasible == (result.mode == "exact")
    np.testing.assert_array_equal(result.torque_Nm, geometry.torque_map @ result.thrust_N)

    # Whatever the mode claims (alpha times the demand) holds within the promise.
    wanted = result.scale * torque
    error = float(np.abs(result.torque_Nm - wanted).max())
    assert error <= promised_tolerance(geometry.torque_map, result.thrust_N, wanted), (
        f"torque {result.torque_Nm} for {wanted} ({result.mode})"
    )
    if force is not None:
        wanted_force = result.scale * force
        error = float(np.abs(result.force_N - wanted_force).max())
        assert error <= promised_tolerance(geometry.force_map, result.thrust_N, wanted_force)

    alpha_lp = largest_alpha(geometry, limits, torque, force)
    if result.feasible:
        assert result.scale == 1.0
        assert alpha_lp >= 1.0 - ALPHA_TOL
    else:
        assert abs(result.scale - alpha_lp) <= ALPHA_TOL
    if float(np.abs(torque).max()) >= NORMAL_DEMAND_Nm:
        reference = least_fuel_N(
            geometry, limits, result.torque_Nm, None if force is None else result.force_N
        )
        assert reference is not None
        fuel = float(result.thrust_N.sum())
        # Relative only: an absolute floor at the engines' scale would pass anything tiny.
        assert abs(fuel - reference) <= FUEL_RTOL * reference, (fuel, reference)


@pytest.fixture(scope="module")
def allocator(problem: Problem, geometry: Geometry) -> Allocator:
    return Allocator.from_problem(problem, geometry)


@pytest.fixture(scope="module")
def stage_limit_N(problem: Problem) -> float:
    return problem.engine.thrust_per_stage_mN / 1e3


# ----------------------------------------------------------------------------- properties

unit_component = st.one_of(st.just(0.0), st.floats(min_value=-1.0, max_value=1.0))
direction = st.tuples(unit_component, unit_component, unit_component).filter(
    lambda d: max(map(abs, d)) > 0.0
)
# 10**exponent: 1e-320 (subnormal) to 1e308 N m.
magnitude = st.floats(min_value=-320.0, max_value=308.0).map(lambda e: 10.0**e)


def demand(unit: tuple[float, float, float], size: float) -> np.ndarray:
    d = np.array(unit)
    return d / float(np.abs(d).max()) * size


def run_property(
    allocator: Allocator,
    geometry: Geometry,
    stage_limit_N: float,
    torque: np.ndarray,
    force: np.ndarray | None,
    failed: set[int],
) -> None:
    limits = np.full(N_CUBESATS, stage_limit_N)
    limits[list(failed)] = 0.0
    allocator.set_max_thrust(limits)
    try:
        check_answer(allocator, geometry, torque, force)
    finally:
        allocator.set_max_thrust(np.full(N_CUBESATS, stage_limit_N))


demands = {
    "torque_dir": direction,
    "torque_size": magnitude,
    "force_dir": direction,
    "force_size": magnitude,
    "force_mode": st.sampled_from(["zero", "free", "given"]),
    "failed": st.sets(st.integers(0, N_CUBESATS - 1), max_size=14),
}


def _force(mode: str, unit: tuple[float, float, float], size: float) -> np.ndarray | None:
    return {"zero": np.zeros(3), "free": None, "given": demand(unit, size)}[mode]


def _any_demand(
    allocator: Allocator,
    geometry: Geometry,
    stage_limit_N: float,
    torque_dir: tuple[float, float, float],
    torque_size: float,
    force_dir: tuple[float, float, float],
    force_size: float,
    force_mode: str,
    failed: set[int],
) -> None:
    torque = demand(torque_dir, torque_size)
    force = _force(force_mode, force_dir, force_size)
    run_property(allocator, geometry, stage_limit_N, torque, force, failed)


def _property_test(examples: int) -> Any:
    """The property over ``examples`` drawn demands (one body for the fast and long runs)."""
    checks = settings(
        max_examples=examples,
        deadline=None,
        suppress_health_check=[HealthCheck.function_scoped_fixture],
    )
    return checks(given(**demands)(_any_demand))


test_any_demand_is_refused_or_answered_within_the_promise = _property_test(150)
test_any_demand_long_run = pytest.mark.slow(_property_test(3000))


# ----------------------------------------------------------------------------- examples


@pytest.mark.parametrize(
    "torque",
    [
        [5e-321, 0.0, 0.0],  # the reported bug: NaN thrust called exact
        [5e-324, -5e-324, 0.0],
        [1e-310, 3e-311, -2e-312],
        [2.2250738585072014e-308, 0.0, 1e-320],
        [1e-300, 2e-300, -3e-300],
        [1e-100, 0.0, 0.0],
        [1e-13, 4e-14, -7e-14],  # "marked exact with up to 100 % error"
        [3e-9, 0.0, 0.0],
    ],
)
@pytest.mark.parametrize("free_force", [False, True])
def test_tiny_demands_are_met_to_the_promise(
    allocator: Allocator, geometry: Geometry, torque: list[float], free_force: bool
) -> None:
    torque_Nm = np.array(torque)
    force = None if free_force else np.zeros(3)
    result = allocator.allocate(torque_Nm, force, free_force=free_force)
    assert result.feasible and result.mode == "exact"
    check_answer(allocator, geometry, torque_Nm, force)
    if float(np.abs(torque_Nm).max()) >= NORMAL_DEMAND_Nm:
        # A normal float: the promise is 1e-9 relative to the demand (the engines'
        # own torques are of its size for a pure torque).
        relative = float(np.abs(result.torque_Nm - torque_Nm).max() / np.abs(torque_Nm).max())
        assert relative <= 1e-12


def test_a_zero_demand_gets_exactly_zero_thrust(allocator: Allocator) -> None:
    for free_force in (False, True):
        result = allocator.allocate([0.0, -0.0, 0.0], free_force=free_force)
        assert result.feasible and result.mode == "exact"
        assert np.all(result.thrust_N == 0.0) and result.fuel_rate_kg_s == 0.0


def test_tiny_demands_scale_with_the_demand(allocator: Allocator) -> None:
    """Positive homogeneity: the thrust of 2**-k tau is 2**-k times that of tau."""
    torque = np.array([1.3e-4, -0.4e-4, 0.9e-4])
    reference = allocator.allocate(torque).thrust_N
    for k in (20, 200, 900):
        thrust = allocator.allocate(np.ldexp(torque, -k)).thrust_N
        np.testing.assert_allclose(np.ldexp(thrust, k), reference, rtol=1e-9, atol=0.0)


@pytest.mark.parametrize(
    ("torque", "force", "named"),
    [
        ([np.nan, 0.0, 0.0], None, "torque_Nm"),
        ([0.0, np.inf, 0.0], None, "torque_Nm"),
        ([0.0, 0.0, -np.inf], None, "torque_Nm"),
        ([1.7e305, 1.7e305, 1.7e305], None, "torque_Nm"),
        ([1.7e308, 0.0, 0.0], None, "torque_Nm"),
        ([1e4, 0.0, 0.0], None, "torque_Nm"),  # 1e6 x 9.2 mN m is 9216 N m
        ([1e-3, 0.0, 0.0], [0.0, np.nan, 0.0], "force_N"),
        ([1e-3, 0.0, 0.0], [1e4, 0.0, 0.0], "force_N"),
    ],
)
def test_absurd_or_non_finite_demands_are_refused_by_name(
    allocator: Allocator, torque: list[float], force: list[float] | None, named: str
) -> None:
    with pytest.raises(AllocationError, match=f"^{named}: ") as caught:
        allocator.allocate(torque, force)
    assert isinstance(caught.value, DemandError) and caught.value.argument == named
    rows = np.array([[1e-3, 0.0, 0.0], torque])
    forces = None if force is None else np.array([[0.0, 0.0, 0.0], force])
    batch_name = "torques_Nm[1]" if named == "torque_Nm" else "forces_N[1]"
    with pytest.raises(AllocationError, match=f"^{re.escape(batch_name)}: "):
        allocator.allocate_batch(rows, forces)
    if force is None:
        with pytest.raises(AllocationError, match=r"^torques_Nm\[1\]: "):
            allocator.allocate_series(rows)


def test_the_bound_follows_the_limits(problem: Problem, geometry: Geometry) -> None:
    """With CubeSats failed the largest reachable component shrinks, and so does the bound."""
    allocator = Allocator.from_problem(problem, geometry)
    demand_Nm = np.array([4000.0, 0.0, 0.0])
    assert not allocator.allocate(demand_Nm).feasible
    allocator.set_failed(range(20))
    bound = ABSURD_FACTOR * largest_component(geometry.torque_map, allocator.max_thrust_N)
    assert bound < 4000.0
    with pytest.raises(DemandError, match="torque_Nm"):
        allocator.allocate(demand_Nm)


def test_batch_and_series_of_tiny_demands_match_single_calls(allocator: Allocator) -> None:
    rng = np.random.default_rng(11)
    directions = rng.normal(size=(40, 3))
    sizes = 10.0 ** rng.uniform(-320, -2, size=(40, 1))
    torques = directions / np.abs(directions).max(axis=1, keepdims=True) * sizes
    torques[5] = 0.0
    batch = allocator.allocate_batch(torques)
    series = allocator.allocate_series(torques)
    for i, torque in enumerate(torques):
        single = allocator.allocate(torque)
        assert single.feasible and batch.feasible[i] and series.scale[i] == 1.0
        # Not bit for bit: the workspaces are warm-started from other demands.
        np.testing.assert_allclose(batch.thrust_N[i], single.thrust_N, rtol=1e-9, atol=0.0)
        for thrust in (batch.thrust_N[i], series.thrust_N[i]):
            assert np.all(np.isfinite(thrust))
            achieved = allocator.torque_map @ thrust
            tolerance = promised_tolerance(allocator.torque_map, thrust, torque)
            assert float(np.abs(achieved - torque).max()) <= tolerance
            force_tolerance = promised_tolerance(allocator.force_map, thrust, np.zeros(3))
            assert float(np.abs(allocator.force_map @ thrust).max()) <= force_tolerance


@pytest.mark.parametrize("scale", [1e-6, 1e-150, 1e-318])
@pytest.mark.parametrize("free_force", [False, True])
def test_series_of_a_tiny_history_is_met_without_a_solve_per_step(
    problem: Problem, geometry: Geometry, scale: float, free_force: bool
) -> None:
    allocator = Allocator.from_problem(problem, geometry)
    t = np.linspace(0.0, 1.0, 600)[:, None]
    torques = scale * np.sin(2 * np.pi * np.array([3.0, 2.0, 1.5]) * t + [0.0, 0.7, 1.77])
    series = allocator.allocate_series(torques, free_force=free_force)
    assert np.all(series.scale == 1.0)
    assert series.point_solves < 60
    for thrust, torque in zip(series.thrust_N, torques, strict=True):
        assert np.all(np.isfinite(thrust)) and np.all(thrust <= allocator.max_thrust_N)
        achieved = geometry.torque_map @ thrust
        assert float(np.abs(achieved - torque).max()) <= promised_tolerance(
            geometry.torque_map, thrust, torque
        )


# ----------------------------------------------------------------------------- final check


def _broken_solve(workspace: Any, x_of: Callable[[int], np.ndarray]) -> None:
    """Make a back-end workspace's ``solve`` report ``x_of(n_engines)`` as optimal."""
    real = workspace.solve

    def solve() -> QpSolution:
        solution = real()
        return QpSolution(x_of(N_CUBESATS), "optimal", solution.iterations, 0.0)

    workspace.solve = solve


@pytest.mark.parametrize(
    "x_of",
    [
        lambda n: np.full(n, np.nan),
        lambda n: np.full(n, np.inf),
        lambda n: np.zeros(n),  # finite but wrong: no torque at all
    ],
    ids=["nan", "inf", "wrong"],
)
@pytest.mark.parametrize("torque", [[1e-3, -2e-4, 5e-4], [3e-14, 0.0, 0.0], [5e-321, 0.0, 0.0]])
def test_a_back_end_answer_failing_the_final_check_goes_to_highs(
    problem: Problem,
    geometry: Geometry,
    x_of: Callable[[int], np.ndarray],
    torque: list[float],
) -> None:
    allocator = Allocator.from_problem(problem, geometry)
    _broken_solve(allocator._qp.workspace("exact", False), x_of)
    result = allocator.allocate(torque)
    assert result.solver == "daqp+highs"
    assert result.feasible and np.all(np.isfinite(result.thrust_N))
    check_answer(allocator, geometry, np.array(torque), np.zeros(3))


def test_no_answer_passing_the_final_check_is_an_internal_error(
    problem: Problem, geometry: Geometry, monkeypatch: pytest.MonkeyPatch
) -> None:
    import casadi_debris.allocation._paths as paths

    allocator = Allocator.from_problem(problem, geometry)
    _broken_solve(allocator._qp.workspace("exact", False), lambda n: np.full(n, np.nan))
    monkeypatch.setattr(paths, "rescue", lambda qp, target, free: (np.full(qp.n, np.nan), 1.0, 0.0))
    with pytest.raises(AllocationInternalError, match="neither daqp nor HiGHS"):
        allocator.allocate([1e-3, 0.0, 0.0])
    assert not issubclass(AllocationInternalError, AllocationError)  # exit 3, not 2


# ----------------------------------------------------------------------------- command line


@pytest.mark.parametrize(
    ("arguments", "start"),
    [
        (["--torque-mNm", "1.7e308", "1.7e308", "1.7e308"], "error: --torque-mNm 1.7e+308"),
        (["--torque-mNm", "nan", "0", "0"], "error: --torque-mNm nan 0 0: must be finite"),
        (["--torque-mNm", "1e309", "0", "0"], "error: --torque-mNm inf 0 0: must be finite"),
        (["--torque-mNm", "1", "0", "0", "--force-mN", "1e12", "0", "0"], "error: --force-mN"),
    ],
)
def test_cli_refuses_absurd_demands_in_one_line(arguments: list[str], start: str) -> None:
    result = CliRunner().invoke(main, ["allocate", *arguments, "--json"])
    assert result.exit_code == 2, result.output
    assert result.output.count("\n") == 1 and result.output.startswith(start), result.output


def test_cli_answers_a_subnormal_demand_with_finite_thrust() -> None:
    result = CliRunner().invoke(main, ["allocate", "--torque-mNm", "5e-318", "0", "0", "--json"])
    assert result.exit_code == 0, result.output
    payload = json.loads(result.output)
    assert None not in payload["thrust_mN"]
    assert payload["feasible"] is True and payload["mode"] == "exact"
    demanded = np.array(payload["torque_demand_mNm"])
    achieved = np.array(payload["torque_achieved_mNm"])
    # 5e-321 N m carries three digits; the promise adds 24 (l + 2) 2**-1074 N m.
    assert np.abs(achieved - demanded).max() <= 1e3 * 24 * 4 * SMALLEST_SUBNORMAL
