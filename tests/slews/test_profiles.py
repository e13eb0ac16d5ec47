"""Slews checked against independent computations: closed-form limits, a CasADi
integrator on the model, the geometry's torque map, and each other."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris.cli import main
from casadi_debris.config import Problem, problem_from_dict
from casadi_debris.dynamics import build_model
from casadi_debris.errors import InputShapeError, SlewInfeasibleError
from casadi_debris.geometry import Geometry, max_thrust_N, torque_authority
from casadi_debris.slews import (
    COLLOCATION_DEGREE,
    OptimalSlewSettings,
    bang_bang_slew,
    fuel_optimal_slew,
    least_fuel_thrust,
    radau_coefficients,
    shape,
    slew_about_axis,
    slew_between,
    time_optimal_slew,
)
from slew_reference import every_profile_checked, final_state  # noqa: F401 (autouse)

PAPER_SLEW_DURATION_S = 1228.0  # paper, Section IV.A
PAPER_SLEW_FUEL_KG = 2.8e-4  # paper, Section IV.A; DESIGN.md accepts +-25 %


def rigid_limit(geometry: Geometry, axis: int, angle_rad: float = math.pi) -> float:
    """2 sqrt(theta J / tau) from the geometry's inertia and torque authority."""
    name = "xyz"[axis]
    tau = min(torque_authority(geometry)[f"+{name}"], torque_authority(geometry)[f"-{name}"])
    return 2.0 * math.sqrt(angle_rad * geometry.inertia_total_kgm2[axis, axis] / tau)


@pytest.fixture(scope="module")
def principal_problem(paper_data: dict[str, Any]) -> Problem:
    """The paper's setup with the hub's products of inertia removed: z is principal."""
    data = json.loads(json.dumps(paper_data))
    inertia = np.diag(np.diag(np.array(data["hub"]["inertia_kgm2"])))
    data["hub"]["inertia_kgm2"] = inertia.tolist()
    return problem_from_dict(data, "principal")


@pytest.fixture(scope="module")
def paper_bang_bang(problem: Problem) -> Any:
    return bang_bang_slew(problem, "z", math.pi, duration_s=PAPER_SLEW_DURATION_S)


# -- bang-bang ----------------------------------------------------------------------------


def test_bang_bang_full_authority_is_the_rigid_limit(problem: Problem, geometry: Geometry) -> None:
    slew = bang_bang_slew(problem, "z", math.pi, check_vibration=False)
    expected = rigid_limit(geometry, 2)
    assert slew.duration_s == pytest.approx(expected, rel=1e-6)
    assert slew.limit_duration_s == pytest.approx(expected, rel=1e-6)


def test_paper_slew_duration_and_switch_at_half_time(
    paper_bang_bang: Any, geometry: Geometry
) -> None:
    slew = paper_bang_bang
    assert slew.duration_s == pytest.approx(PAPER_SLEW_DURATION_S, rel=1e-9)
    # a (T/2)^2 = theta: the torque fraction is (T_limit / T)^2.
    fraction = (rigid_limit(geometry, 2) / PAPER_SLEW_DURATION_S) ** 2
    assert slew.settings["torque_fraction"] == pytest.approx(fraction, rel=1e-6)
    z = slew.torque_Nm[:, 2]
    half = slew.duration_s / 2.0
    assert np.all(z[(slew.time_s > 0) & (slew.time_s < half)] > 0)
    assert np.all(z[(slew.time_s > half) & (slew.time_s < slew.duration_s)] < 0)
    yaw = slew.euler_angles_rad[:, 2]
    assert np.degrees(abs(yaw[-1])) == pytest.approx(180.0, abs=1e-6)
    assert np.degrees(yaw[np.searchsorted(slew.time_s, half)]) == pytest.approx(90.0, abs=1e-6)


def test_paper_slew_fuel_within_25_percent(paper_bang_bang: Any) -> None:
    assert paper_bang_bang.fuel_kg == pytest.approx(PAPER_SLEW_FUEL_KG, rel=0.25)


@pytest.mark.parametrize(
    "options",
    [
        {"duration_s": PAPER_SLEW_DURATION_S},
        {"torque_fraction": 0.9, "rate_limit_rad_s": 0.004, "smoothing_s": 20.0},
        {"duration_s": 1300.0, "torque_fraction": 0.8, "smoothing_s": 5.0},
    ],
)
def test_bang_bang_integrates_to_target_at_rest(problem: Problem, options: dict) -> None:
    slew = bang_bang_slew(problem, "z", math.pi, check_vibration=False, **options)
    if "duration_s" in options:
        assert slew.duration_s == pytest.approx(options["duration_s"], rel=1e-9)
    model, final = final_state(problem, slew, [])
    error = np.array(model.attitude_error(slew.target.q_final_BN, final[model.layout.q]))
    assert np.linalg.norm(error) < 1e-6
    assert np.linalg.norm(final[model.layout.omega]) < 1e-9


def test_bang_bang_between_any_attitudes(problem: Problem) -> None:
    start = np.array([0.9, 0.1, -0.3, 0.2])
    end = np.array([0.2, -0.5, 0.4, 0.7])
    target = slew_between(start, end)
    slew = bang_bang_slew(problem, target=target, check_vibration=False)
    model, final = final_state(problem, slew, [])
    error = np.array(model.attitude_error(end / np.linalg.norm(end), final[model.layout.q]))
    assert np.linalg.norm(error) < 1e-6
    assert np.linalg.norm(final[model.layout.omega]) < 1e-9


def test_slew_target_quaternion() -> None:
    target = slew_about_axis("-y", math.radians(90.0))
    half = math.radians(45.0)
    assert target.q_final_BN == pytest.approx([math.cos(half), 0.0, -math.sin(half), 0.0])


# -- optimal slews -------------------------------------------------------------------------


def test_single_axis_time_optimal_is_the_rigid_limit_with_switch_at_half(
    principal_problem: Problem,
) -> None:
    from casadi_debris.geometry import build_geometry

    geometry = build_geometry(principal_problem)
    slew = time_optimal_slew(principal_problem, "z", math.pi, single_axis=True)
    expected = rigid_limit(geometry, 2)
    assert slew.duration_s == pytest.approx(expected, rel=0.01)
    tau = torque_authority(geometry)["+z"]
    z = slew.torque_Nm[:-1, 2]
    times = slew.time_s[:-1]
    half = slew.duration_s / 2.0
    # The switch is a knot at half the duration: a sample there holds the second arc, and
    # the knot's time may land a rounding below half (one part in 1e13).
    before = times < half * (1.0 - 1e-9)
    assert np.allclose(z[before], tau, rtol=1e-4)
    assert np.allclose(z[~before], -tau, rtol=1e-4)


# The paper's time-optimal slew is solved by default in tests/slews/test_global.py.
@pytest.mark.slow
def test_three_axis_time_optimal_not_longer_than_eigenaxis(problem: Problem) -> None:
    # Bilimoria & Wie (1993): with all axes free the 180 deg slew beats the eigenaxis one.
    slew = time_optimal_slew(problem, "z", math.pi, check_vibration=False)
    assert slew.duration_s <= slew.limit_duration_s
    assert slew.settings["final_attitude_error_rad"] < 1e-5
    lower = -np.array([torque_authority(build_model(problem, []).geometry)[f"-{a}"] for a in "xyz"])
    assert np.all(slew.torque_Nm >= lower * (1 + 1e-6))


def test_fuel_optimal_uses_no_more_fuel_than_bang_bang(problem: Problem, paper_bang_bang) -> None:
    slew = fuel_optimal_slew(problem, "z", math.pi, duration_s=PAPER_SLEW_DURATION_S)
    assert slew.duration_s == pytest.approx(PAPER_SLEW_DURATION_S)
    assert slew.fuel_kg <= paper_bang_bang.fuel_kg
    model, final = final_state(problem, slew, [])
    error = np.array(model.attitude_error(slew.target.q_final_BN, final[model.layout.q]))
    assert np.linalg.norm(error) < 1e-5


def test_thruster_level_fuel_optimal_respects_engines(
    problem: Problem, geometry: Geometry, paper_bang_bang: Any
) -> None:
    slew = fuel_optimal_slew(
        problem, "z", math.pi, duration_s=PAPER_SLEW_DURATION_S, thrusters=True
    )
    limits = max_thrust_N(geometry)
    assert np.all(slew.thrust_N >= -1e-12)
    assert np.all(slew.thrust_N <= limits * (1 + 1e-9))
    assert np.allclose(slew.thrust_N @ geometry.torque_map.T, slew.torque_Nm, atol=1e-12)
    # The least-fuel thrust of the bang-bang torque is one thrust history the OCP could pick.
    assert slew.fuel_kg <= paper_bang_bang.fuel_kg
    model, final = final_state(problem, slew, [])
    error = np.array(model.attitude_error(slew.target.q_final_BN, final[model.layout.q]))
    assert np.linalg.norm(error) < 1e-5


@pytest.mark.slow
def test_thruster_level_zero_net_force_at_a_torque_fraction(
    problem: Problem, geometry: Geometry
) -> None:
    fraction = 0.8
    common = {"thrusters": True, "torque_fraction": fraction, "check_vibration": False}
    slew = time_optimal_slew(problem, "z", math.pi, zero_net_force=True, **common)
    limits = fraction * max_thrust_N(geometry)
    assert np.all(slew.thrust_N >= 0.0)
    assert np.all(slew.thrust_N <= limits * (1 + 1e-9))
    # the net force, from the thrusts through the geometry, is zero at every sample
    force = slew.thrust_N @ geometry.force_map.T
    assert np.abs(force).max() <= 1e-9 * limits.sum()
    assert slew.settings["delta_v_m_s"] < 1e-12
    model, final = final_state(problem, slew, [])
    error = np.array(model.attitude_error(slew.target.q_final_BN, final[model.layout.q]))
    assert np.linalg.norm(error) < 1e-5
    # one more constraint cannot make it faster (both are local optima: 0.2 % slack)
    free = time_optimal_slew(problem, "z", math.pi, **common)
    assert slew.duration_s >= free.duration_s * (1 - 2e-3)


def test_zero_net_force_needs_thrusters(problem: Problem) -> None:
    with pytest.raises(InputShapeError, match="zero_net_force"):
        time_optimal_slew(problem, "z", math.pi, zero_net_force=True, check_vibration=False)


def test_options_object_and_keywords_give_the_same_slew(problem: Problem) -> None:
    options = OptimalSlewSettings(intervals=8, check_vibration=False, sample_s=10.0)
    by_object = time_optimal_slew(problem, "z", math.pi, options=options)
    by_keywords = time_optimal_slew(
        problem, "z", math.pi, intervals=8, check_vibration=False, sample_s=10.0
    )
    # a keyword replaces the object's field
    overridden = time_optimal_slew(problem, "z", math.pi, options=options, intervals=10)
    assert by_object.duration_s == by_keywords.duration_s
    assert by_object.settings["control_intervals"] == 8
    assert overridden.settings["control_intervals"] == 10


def test_radau_interval_is_exact_on_cubics() -> None:
    """The collocation of x' = 3 t^2 (Radau IIA, degree 3) integrates it exactly."""
    t, h = 0.7, 2.0
    points, slopes, end = radau_coefficients()
    z = (t + h * points) ** 3  # the state at the interval start and collocation points
    assert z @ slopes == pytest.approx(h * 3.0 * (t + h * points[1:]) ** 2, rel=1e-12)
    assert z @ end == pytest.approx((t + h) ** 3, rel=1e-12)
    assert len(points) == COLLOCATION_DEGREE + 1


def test_zero_vibration_shaping_keeps_bounds_and_impulse() -> None:
    knots = np.array([0.0, 10.0, 20.0])
    controls = np.array([[1.0, 0.0], [-1.0, 0.5]])
    times, amplitudes = np.array([0.0, 0.3, 0.7]), np.array([0.2, 0.5, 0.3])
    new_knots, shaped = shape(knots, controls, times, amplitudes)
    assert new_knots[-1] == pytest.approx(20.7)
    assert np.sum(shaped * np.diff(new_knots)[:, None], axis=0) == pytest.approx(
        np.sum(controls * np.diff(knots)[:, None], axis=0)
    )
    assert np.all(shaped <= controls.max(axis=0) + 1e-12)


def test_least_fuel_thrust_reproduces_torque(geometry: Geometry) -> None:
    torque = np.array([[1e-3, -0.5e-3, 2e-3], [0.0, 0.0, -1e-3], [0.0, 0.0, 0.0]])
    thrust, shortfall = least_fuel_thrust(geometry, torque)
    assert np.allclose(thrust @ geometry.torque_map.T, torque, atol=1e-12)
    assert np.all(shortfall == pytest.approx(0.0, abs=1e-12))
    # A small pure z torque (no engine at its bound) uses the longest z lever arm.
    assert thrust[1].sum() == pytest.approx(1e-3 / np.max(np.abs(geometry.torque_map[2])))


# -- bad input -----------------------------------------------------------------------------


@pytest.mark.parametrize("duration", [0.0, -5.0, 500.0])
def test_too_short_bang_bang_says_minimum(problem: Problem, geometry: Geometry, duration) -> None:
    with pytest.raises(SlewInfeasibleError, match=r"infeasible: minimum is 920\.1"):
        bang_bang_slew(problem, "z", math.pi, duration_s=duration, check_vibration=False)
    assert rigid_limit(geometry, 2) == pytest.approx(920.1, abs=0.05)


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("torque_fraction", 0.0, "torque_fraction"),
        ("residual_energy_fraction", -1.0, "residual_energy_fraction"),
        ("sample_s", math.nan, "sample_s"),
        ("intervals", 3, "intervals: must be an even number"),
        ("flexible_method", "modal", "flexible_method: one of ocp, shaper"),
    ],
)
def test_bad_slew_option_is_named(field: str, value: Any, message: str) -> None:
    with pytest.raises(InputShapeError, match=message):
        OptimalSlewSettings(**{field: value})


@pytest.mark.parametrize(
    ("written", "expected"),
    [
        ({}, {"torque_fraction": 1.0, "thrusters": False, "flexible": False}),
        (
            {"thrusters": True, "zero_net_force": True, "torque_fraction": 0.4},
            {"torque_fraction": 0.4, "thrusters": True, "zero_net_force": True},
        ),
        (
            {"flexible": True, "flexible_method": "shaper"},
            {"flexible": True, "flexible_method": "shaper"},
        ),
    ],
)
def test_settings_are_derived_from_the_request(
    written: dict[str, Any], expected: dict[str, Any]
) -> None:
    """What the request says of the model and the authority is the settings'; the
    solver's own choices are the call's, else the defaults."""
    from casadi_debris.config import slew_about

    request = slew_about("z", 90.0, method="time-optimal", **written)
    settings = OptimalSlewSettings.for_request(request, sample_s=2.0, starts=3, seed=7)
    for name, value in expected.items():
        assert getattr(settings, name) == value, name
    assert (settings.sample_s, settings.starts, settings.seed) == (2.0, 3, 7)
    assert settings.intervals == OptimalSlewSettings().intervals
    with pytest.raises(InputShapeError, match="zero_net_force applies to thruster-level"):
        OptimalSlewSettings.for_request(slew_about("z", 90.0, zero_net_force=True))


def test_unknown_keyword_and_single_axis_fuel_are_refused(problem: Problem) -> None:
    with pytest.raises(TypeError, match=r"time_optimal_slew\(\) got an unexpected keyword"):
        time_optimal_slew(problem, "z", math.pi, torque_fractoin=0.5)
    with pytest.raises(InputShapeError, match="single_axis applies to time-optimal"):
        fuel_optimal_slew(problem, "z", math.pi, duration_s=1300.0, single_axis=True)


def test_too_short_fuel_optimal_says_minimum(problem: Problem) -> None:
    with pytest.raises(SlewInfeasibleError, match="infeasible: minimum is"):
        fuel_optimal_slew(problem, "z", math.pi, duration_s=0.0)


@pytest.mark.parametrize(
    ("axis", "angle"), [("w", math.pi), ("z", 0.0), ("z", 4.0), ((0, 0, 0), 1.0)]
)
def test_bad_axis_or_angle(problem: Problem, axis: Any, angle: float) -> None:
    with pytest.raises(InputShapeError):
        bang_bang_slew(problem, axis, angle, check_vibration=False)


# -- command line --------------------------------------------------------------------------


def test_cli_bang_bang_json_and_run_folder(tmp_path: Path) -> None:
    out = tmp_path / "slew"
    result = CliRunner().invoke(
        main,
        ["slew", "--method", "bang-bang", "--duration-s", "1228", "--json", "--out", str(out)],
    )
    assert result.exit_code == 0, result.output
    summary = json.loads(result.output)
    for key in (
        "duration_s",
        "max_torque_mNm",
        "fuel_kg",
        "residual_vibration_rad",
        "eigenaxis_duration_s",
        "limits_ok",
        "solve_time_s",
        "solver_status",
    ):
        assert key in summary
    assert summary["duration_s"] == pytest.approx(1228.0)
    assert summary["limits_ok"] is True and summary["worst_axis_ratio"]["+z"] < 0.6
    assert {p.name for p in out.iterdir()} >= {"summary.json", "profile.csv", "slew.png"}
    header = (out / "profile.csv").read_text().splitlines()[0]
    assert "time_s" in header and "torque_z_mNm" in header and "yaw_deg" in header


def test_cli_infeasible_duration_is_one_line_exit_2() -> None:
    result = CliRunner().invoke(main, ["slew", "--duration-s", "100"])
    assert result.exit_code == 2
    assert "infeasible: minimum is" in result.output
    assert "Traceback" not in result.output
