"""Every slew profile within the engines' authority, gyroscopic torque included, or refused.

The references here are computed in the test: the engines' torque set from the
allocator's facets (not the slew check's LP), the eigenaxis bang-bang time from
its closed form on those facets, the body's equation J alpha + omega x J omega.
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris import load_problem
from casadi_debris.cli import main
from casadi_debris.config import Problem
from casadi_debris.dynamics import build_model
from casadi_debris.slews import (
    OptimalSlewSettings,
    RigidBody,
    bang_bang_slew,
    eigenaxis_acceleration_limit,
    fuel_optimal_slew,
    rigid_limit_duration,
    time_optimal_slew,
)
from shared_results import paper_z_time_optimal
from slew_reference import (  # noqa: F401 (every_profile_checked: autouse)
    _polytope,
    assert_checked,
    every_profile_checked,
    torque_set_gauge,
)

DIAGONAL = (1.0, 1.0, 1.0)


def _use(problem: Problem, torque_Nm: np.ndarray) -> np.ndarray:
    """Share of the authority each torque needs: its gauge in the torque set (the allocator's
    facets at zero net force)."""
    _, polytope = _polytope(problem, zero_net_force=True)
    return torque_set_gauge(polytope, np.atleast_2d(torque_Nm))


def eigenaxis_time(problem: Problem, axis: Any, angle_rad: float = math.pi) -> float:
    """Closed form: a = 1 / max use(+-J e, +-J e + Theta e x J e), T = 2 sqrt(Theta / a)."""
    model = build_model(problem, [])
    inertia = np.array(model.rigid_inertia(model.nominal_parameters))
    e = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    moment = inertia @ e
    gyro = angle_rad * np.cross(e, moment)
    need = float(np.max(_use(problem, np.array([moment, -moment, moment + gyro, gyro - moment]))))
    return 2.0 * math.sqrt(angle_rad * need)


@pytest.mark.parametrize("axis", [DIAGONAL, (1.0, -2.0, 0.5), (0.0, 0.0, 1.0)])
def test_bang_bang_fits_the_authority_about_any_axis(problem: Problem, axis: Any) -> None:
    slew = bang_bang_slew(problem, axis, math.pi, check_vibration=False)
    figures = assert_checked(problem, slew)
    assert slew.limits.limits_ok and figures["ok"]
    # it uses the authority, not less: the worst instant is at its edge (sampled)
    assert figures["gauge"] == pytest.approx(1.0, abs=2e-3)
    assert slew.duration_s == pytest.approx(eigenaxis_time(problem, axis), rel=1e-9)
    assert slew.eigenaxis_duration_s == pytest.approx(slew.duration_s, rel=1e-9)


def test_paper_diagonal_slew_no_longer_needs_two_and_a_half_times_the_y_authority(
    problem: Problem,
) -> None:
    slew = bang_bang_slew(problem, DIAGONAL, math.pi, check_vibration=False)
    authority_y = slew.limits.limits_authority_Nm["+y"]
    assert authority_y == pytest.approx(2.016e-3, rel=1e-6)
    assert slew.max_torque_Nm[1] <= authority_y * (1 + 1e-6)
    # Sized from J e alone (the old rule) it was 1274 s and asked 5.16 mNm about y.
    assert slew.duration_s > 1274.0


@pytest.mark.parametrize(
    "options",
    [
        {"torque_fraction": 0.5},
        {"torque_fraction": 0.9, "rate_limit_rad_s": 0.002, "smoothing_s": 20.0},
        {"duration_s": 2500.0},
        {"duration_s": 2600.0, "torque_fraction": 0.8, "smoothing_s": 5.0},
    ],
)
def test_bang_bang_options_keep_the_torque_fraction(problem: Problem, options: dict) -> None:
    slew = bang_bang_slew(problem, DIAGONAL, math.pi, check_vibration=False, **options)
    figures = assert_checked(problem, slew)
    fraction = options.get("torque_fraction", 1.0)
    assert figures["gauge"] <= fraction * (1 + 1e-6)
    assert slew.settings["torque_fraction"] <= fraction * (1 + 1e-9)
    if "duration_s" in options:
        assert slew.duration_s == pytest.approx(options["duration_s"], rel=1e-9)


@pytest.mark.parametrize("name", ["three_faces", "side_engines_12", "differential_2u"])
def test_bang_bang_fits_on_other_swarms(name: str) -> None:
    problem = load_problem(name)
    for axis in (DIAGONAL, (-0.3, 1.0, 0.7)):
        slew = bang_bang_slew(problem, axis, math.radians(120.0), check_vibration=False)
        assert assert_checked(problem, slew)["ok"]
        assert slew.duration_s == pytest.approx(
            eigenaxis_time(problem, axis, math.radians(120.0)), rel=1e-9
        )


def test_too_short_diagonal_slew_is_refused_with_its_minimum(problem: Problem) -> None:
    fastest = eigenaxis_time(problem, DIAGONAL)
    result = CliRunner().invoke(
        main, ["slew", "--method", "bang-bang", "--axis", "1,1,1", "--duration-s", "1300"]
    )
    assert result.exit_code == 2, result.output
    lines = [line for line in result.output.splitlines() if line.strip()]
    assert len(lines) == 1 and "--duration-s" in lines[0]
    assert f"minimum is {fastest:.6g} s" in lines[0]
    assert "Traceback" not in result.output


@pytest.fixture(scope="module")
def paper_z_slew(problem: Problem) -> Any:
    # time_optimal_slew(problem, "z", math.pi, check_vibration=False), solved once a session.
    return paper_z_time_optimal(problem)


def test_torque_level_time_optimal_keeps_to_the_engines_torque_set(
    problem: Problem, paper_z_slew: Any
) -> None:
    """The per-axis box's corners need about 1.5 times the engines' torque set at zero net
    force (its time-optimal slew is 903.0 s): the torque-level time-optimal slew keeps to
    the set instead, as the independent check computes it, and is slower than the box's."""
    slew = paper_z_slew
    figures = assert_checked(problem, slew)
    assert slew.limits.limits_ok and figures["gauge"] <= 1.0 + 1e-6
    assert slew.duration_s >= slew.settings["box_duration_s"]
    assert slew.summary().to_json()["limits_ok"] is True


@pytest.mark.slow
def test_torque_level_time_optimal_flies_as_fast_as_the_thruster_level(problem: Problem) -> None:
    """Thrust at zero net force reaches exactly the torque set {B f : 0 <= f <= f_max,
    F f = 0}, so the thruster-level time-optimal slew, solved on the engines apart, and the
    torque-level one within the set (and the box, which only cuts more) agree: equal within
    the collocation's accuracy, the thruster-level one not slower."""
    torque = time_optimal_slew(problem, "z", math.pi, check_vibration=False, starts=1, workers=1)
    thrust = time_optimal_slew(
        problem,
        "z",
        math.pi,
        thrusters=True,
        zero_net_force=True,
        check_vibration=False,
        starts=1,
        workers=1,
    )
    assert thrust.duration_s <= torque.duration_s * (1 + 1e-6)
    assert torque.duration_s == pytest.approx(thrust.duration_s, rel=1e-3)


def test_time_optimal_is_no_longer_than_the_eigenaxis_bang_bang() -> None:
    # Bilimoria & Wie (1993): J = I, |u_i| <= 1, 180 deg about z: 3.2431 s; eigenaxis 3.5449 s.
    body = RigidBody(inertia_kgm2=np.eye(3), torque_max_Nm=(1, 1, 1))
    slew = time_optimal_slew(body, axis=(0, 0, 1), angle_rad=math.pi, workers=1, starts=4)
    assert slew.eigenaxis_duration_s == pytest.approx(2.0 * math.sqrt(math.pi), rel=1e-12)
    assert slew.duration_s < slew.eigenaxis_duration_s
    assert slew.limits.limits_ok


def test_thruster_level_zero_net_force_slew_is_within_limits(problem: Problem) -> None:
    slew = time_optimal_slew(
        problem,
        "z",
        math.pi,
        thrusters=True,
        zero_net_force=True,
        check_vibration=False,
        starts=1,
        workers=1,
        sample_s=10.0,
    )
    figures = assert_checked(problem, slew)
    assert slew.limits.limits_ok and figures["ok"]
    assert slew.limits.limits_zero_net_force
    assert figures["net_force_N"] <= 1e-9
    assert slew.duration_s <= slew.eigenaxis_duration_s * (1 + 1e-3)


def test_cli_reports_the_check_and_no_false_limit() -> None:
    runner = CliRunner()
    plain = runner.invoke(main, ["slew", "--method", "bang-bang", "--axis", "1,1,1"])
    assert plain.exit_code == 0, plain.output
    assert "rigid eigenaxis limit" not in plain.stdout
    assert "eigenaxis bang-bang time at this authority" in plain.stdout
    assert "within the engines' limits" in plain.stdout
    as_json = runner.invoke(main, ["slew", "--method", "bang-bang", "--axis", "1,1,1", "--json"])
    summary = json.loads(as_json.stdout)
    assert summary["limits_ok"] is True
    assert "limit_duration_s" not in summary
    assert summary["limits_authority_mNm"]["+y"] == pytest.approx(2.016, rel=1e-6)
    assert max(summary["max_torque_mNm"]) <= 4.608 * (1 + 1e-6)
    assert summary["max_torque_mNm"][1] <= 2.016 * (1 + 1e-6)


# -- the gauge is the test, the per-axis ratio information -----------------------------------


def _old_sizing_diagonal(problem: Problem) -> Any:
    """The paper's 180 deg slew about (1, 1, 1) with its acceleration sized from J e alone
    within the per-axis box (the rule before the gyroscopic torque was counted)."""
    from casadi_debris.slews import slew_about_axis, torque_limits
    from casadi_debris.slews._bang_bang import eigenaxis_guess

    model = build_model(problem, [])
    inertia = np.array(model.rigid_inertia(model.nominal_parameters))
    target = slew_about_axis(DIAGONAL, math.pi)
    alpha = eigenaxis_acceleration_limit(inertia, target.axis_B, *torque_limits(model.geometry))
    return eigenaxis_guess(model, target, rigid_limit_duration(math.pi, alpha))


def test_diagonal_slew_sized_on_j_e_alone_is_still_refused(problem: Problem) -> None:
    """It asked 2.6 x the y authority: its gauge in the torque set, found here by an LP on the
    engines (not the check's LP, nor the facets), is above 1, so the check refuses it."""
    from casadi_debris.geometry import build_geometry, max_thrust_N
    from lp_reference import largest_alpha

    slew = _old_sizing_diagonal(problem)
    assert slew.duration_s == pytest.approx(1274.0, abs=1.0)
    assert slew.max_torque_Nm[1] / 2.016e-3 == pytest.approx(2.56, abs=0.01)
    geometry = build_geometry(problem)
    limits = max_thrust_N(geometry)
    # Every 20th sample and the check's worst one: 1 / (largest s with s tau reachable).
    worst = int(np.argmin(np.abs(slew.time_s - slew.limits.worst_ratio_time_s)))
    samples = sorted({*range(0, len(slew.time_s) - 1, 20), worst})
    gauges = [
        1.0 / largest_alpha(geometry, limits, slew.torque_Nm[k], np.zeros(3), at_most=None)
        for k in samples
        if np.any(slew.torque_Nm[k] != 0.0)
    ]
    assert max(gauges) > 1.5
    assert slew.limits.worst_torque_set_ratio == pytest.approx(max(gauges), rel=1e-6)
    assert not slew.limits.limits_ok
    assert "torque set" in slew.limits.limits_note


def _random_problem(data: dict[str, Any]) -> tuple[Problem, Any]:
    from hypothesis import assume

    from casadi_debris.config import problem_from_dict
    from valid_problems import reference, with_disturbance

    ref = reference(data)
    assume(min(ref.authority_Nm(zero_net_force=True).values()) > 1e-9)
    return problem_from_dict(with_disturbance(data, ref), "valid"), ref


def _axis_extreme(ref: Any, axis: int, sign: float) -> np.ndarray:
    """The torque of the set (zero net force) with the largest sign * tau_axis, by an LP
    over the test's own engine columns, posed in mN (HiGHS' tolerances are absolute: in
    newtons a swarm of weak levers came out 1.8 % beyond the set)."""
    from scipy.optimize import linprog

    result = linprog(
        -sign * ref.torque_per_N[axis],
        A_eq=ref.direction,
        b_eq=np.zeros(3),
        bounds=[(0.0, f * 1e3) for f in ref.max_thrust_N],
        method="highs",
    )
    assert result.status == 0, result.message
    return ref.torque_per_N @ result.x * 1e-3


def check_inside_passes_outside_fails(
    data: dict[str, Any], directions: list[np.ndarray], shares: list[float], beyond: float
) -> None:
    """A profile of torques inside the torque set (a share of the reach an LP finds along
    random directions, and the set's extreme torque about each axis, on its boundary)
    passes whatever its per-axis ratios; the same profile with one torque ``beyond`` times
    its reach fails."""
    from casadi_debris.geometry import build_geometry
    from casadi_debris.slews import check_limits
    from valid_problems import SIGNED_AXES, lp_authority_Nm, lp_reach

    problem, ref = _random_problem(data)
    geometry = build_geometry(problem)
    reaches = [lp_reach(ref, u, zero_net_force=True) for u in directions]
    inside = [
        share * reach * u for share, reach, u in zip(shares, reaches, directions, strict=True)
    ]
    extremes = [_axis_extreme(ref, i, s) for i in range(3) for s in (1.0, -1.0)]
    torque = np.array([*inside, *extremes, np.zeros(3)])
    time = np.arange(len(torque), dtype=float)
    check = check_limits(geometry, time, torque, zero_net_force=True)
    assert check.limits_ok, check.limits_note
    assert check.worst_torque_set_ratio == pytest.approx(1.0, rel=1e-6)
    # The per-axis ratios are the extremes over the pure-axis authority (LPs here): at least
    # 1, often more, and information only.
    # The pure-axis authority by LPs here (posed in mN: a pure torque of 1e-7 N m is below
    # HiGHS' absolute tolerances in newtons).
    pure = lp_authority_Nm(ref.torque_per_N, ref.direction, ref.max_thrust_N, True)
    for k, name in enumerate(SIGNED_AXES):
        reach = abs(float(extremes[k][k // 2]))
        assert reach >= pure[name] * (1 - 1e-6)
        assert check.worst_axis_ratio[name] == pytest.approx(reach / pure[name], rel=1e-6)
    outside = torque.copy()
    outside[0] = beyond * reaches[0] * directions[0]
    failed = check_limits(geometry, time, outside, zero_net_force=True)
    assert not failed.limits_ok
    assert failed.worst_torque_set_ratio == pytest.approx(beyond, rel=1e-6)
    assert failed.worst_ratio_time_s == 0.0
    assert "torque set" in failed.limits_note


def _directions() -> Any:
    from hypothesis import strategies as st

    vector = st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3)
    unit = vector.filter(lambda v: float(np.linalg.norm(v)) > 0.2).map(
        lambda v: np.asarray(v) / np.linalg.norm(v)
    )
    return st.lists(unit, min_size=1, max_size=4)


def _inside_outside_campaign(examples: int) -> Any:
    from hypothesis import HealthCheck, Phase, given, settings
    from hypothesis import strategies as st

    from valid_problems import problems

    def wrap(test: Any) -> Any:
        return given(
            problems(),
            _directions(),
            st.lists(st.floats(0.01, 1.0), min_size=4, max_size=4),
            st.floats(1.001, 3.0),
        )(
            settings(
                max_examples=examples,
                derandomize=True,
                database=None,
                deadline=None,
                phases=(Phase.explicit, Phase.generate),
                suppress_health_check=list(HealthCheck),
            )(test)
        )

    return wrap


@_inside_outside_campaign(8)
def test_a_profile_inside_the_torque_set_passes_and_one_outside_fails(
    data, directions, shares, beyond
) -> None:
    check_inside_passes_outside_fails(data, directions, shares[: len(directions)], beyond)


@pytest.mark.slow
@_inside_outside_campaign(200)
def test_inside_passes_outside_fails_many(data, directions, shares, beyond) -> None:
    check_inside_passes_outside_fails(data, directions, shares[: len(directions)], beyond)


# -- axes with round-off ---------------------------------------------------------------------


@pytest.mark.parametrize(
    ("given", "unit"),
    [
        ((-1.0, -5.5e-306, -1.1e-56), (-1.0, 0.0, 0.0)),
        ((1e-170, 0.0, -1e-170), (math.sqrt(0.5), 0.0, -math.sqrt(0.5))),
        ((2.0, 1e-13, 2.0), (math.sqrt(0.5), 0.0, math.sqrt(0.5))),
        ((3.0, 4.0, 1e-11), (0.6, 0.8, 1e-11 / 5.0)),
    ],
)
def test_round_off_in_an_axis_is_cleared_and_tiny_axes_are_kept(given: Any, unit: Any) -> None:
    from casadi_debris.slews._maneuver import axis_vector

    vector = axis_vector(given)
    np.testing.assert_allclose(vector, unit, rtol=1e-12, atol=0.0)
    assert np.linalg.norm(vector) == pytest.approx(1.0, rel=1e-15)


def test_subnormal_axis_components_give_the_axis_slew() -> None:
    """A helper's generated axis (-1, -5.5e-306, -1.1e-56) once ended in CVODES' mxstep
    (exit 3): it is the slew about -x, the same as typed plainly."""
    runner = CliRunner()
    odd = runner.invoke(
        main, ["slew", "--method", "bang-bang", "--axis", "-1,-5.5e-306,-1.1e-56", "--json"]
    )
    plain = runner.invoke(main, ["slew", "--method", "bang-bang", "--axis", "-x", "--json"])
    assert odd.exit_code == 0 and plain.exit_code == 0, odd.output
    summary, expected = json.loads(odd.stdout), json.loads(plain.stdout)
    assert summary["axis_B"] == [-1.0, 0.0, 0.0]
    assert summary["duration_s"] == expected["duration_s"]
    assert summary["limits_ok"] is True


def test_the_gauge_of_many_samples_is_each_samples_own(problem: Problem) -> None:
    """Over several blocks of LPs (LP_BLOCK samples each), every gauge is the one an LP on
    the engines written here finds for that torque alone."""
    from casadi_debris.geometry import build_geometry, max_thrust_N
    from casadi_debris.slews._limits import LP_BLOCK, torque_set_ratio
    from lp_reference import largest_alpha

    geometry = build_geometry(problem)
    torque = np.random.default_rng(5).normal(size=(2 * LP_BLOCK + 7, 3)) * 2e-3
    gauge = torque_set_ratio(geometry, torque, zero_net_force=True)
    limits = max_thrust_N(geometry)
    for k in range(0, len(torque), 9):
        alpha = largest_alpha(geometry, limits, torque[k], np.zeros(3), at_most=None)
        assert gauge[k] == pytest.approx(1.0 / alpha, rel=1e-6)


class _AskedError(Exception):
    """Raised by the spy in place of the first solve: what the slew asked for first."""


def test_a_fuel_optimal_duration_below_the_flyable_bang_bang_is_checked_first(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The paper about (1, 1, 1): the J e-alone limit is 1274.0 s, the eigenaxis bang-bang
    that fits the torque set 2039.2 s. Between the two no eigenaxis profile is flyable, so
    a duration there is checked against the time-optimal slew first (the J e-alone rule
    went straight to the fuel OCP); above the bang-bang one is, and nothing is checked."""
    from casadi_debris.slews import _optimal

    problem = load_problem()
    axis = (1.0, 1.0, 1.0)
    # The threshold is the bang-bang the command flies (sized on the torque set), found
    # here by its own path.
    solver = _optimal._solver(problem, axis, math.pi, None, OptimalSlewSettings())
    flyable = bang_bang_slew(problem, axis, math.pi, check_vibration=False)
    assert _optimal._flyable_eigenaxis_s(solver.ocp) == pytest.approx(flyable.duration_s, rel=1e-9)
    assert solver.ocp.limit_duration_s < 1300.0 < flyable.duration_s

    asked: list[bool] = []

    def spy(self: Any, *, fuel: bool, duration_s: float | None, check_vibration: bool) -> Any:
        asked.append(fuel)
        raise _AskedError

    monkeypatch.setattr(_optimal._SlewSolver, "solve", spy)
    below, above = flyable.duration_s * (1 - 1e-6), flyable.duration_s * (1 + 1e-6)
    for duration_s, time_optimal_first in [
        (1270.0, True),
        (1300.0, True),
        (below, True),
        (above, False),
        (3000.0, False),
    ]:
        asked.clear()
        with pytest.raises(_AskedError):
            fuel_optimal_slew(problem, axis, math.pi, duration_s=duration_s)
        assert asked == [not time_optimal_first], duration_s
