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
from casadi_debris.slews import RigidBody, bang_bang_slew, time_optimal_slew
from slew_reference import (  # noqa: F401 (every_profile_checked: autouse)
    _polytope,
    assert_checked,
    every_profile_checked,
    torque_set_gauge,
)

DIAGONAL = (1.0, 1.0, 1.0)


def _use(problem: Problem, torque_Nm: np.ndarray) -> np.ndarray:
    """Share of the authority each torque needs: per signed axis and in the torque set."""
    _, polytope = _polytope(problem, zero_net_force=True)
    reach = polytope.axis_reach()
    torque = np.atleast_2d(torque_Nm)
    per_axis = np.max(
        np.column_stack(
            [
                np.maximum(s * torque[:, i], 0.0) / reach[2 * i + k]
                for i in range(3)
                for k, s in enumerate((1.0, -1.0))
            ]
        ),
        axis=1,
    )
    return np.maximum(per_axis, torque_set_gauge(polytope, torque))


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
    assert max(figures["gauge"], figures["per_axis"]) == pytest.approx(1.0, abs=2e-3)
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
    assert max(figures["gauge"], figures["per_axis"]) <= fraction * (1 + 1e-6)
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


def test_torque_level_time_optimal_keeps_to_the_engines_torque_set(problem: Problem) -> None:
    """The per-axis box's corners need about 1.5 times the engines' torque set at zero net
    force (its time-optimal slew is 903.0 s): the torque-level time-optimal slew keeps to
    the set instead, as the independent check computes it, and is slower than the box's."""
    slew = time_optimal_slew(problem, "z", math.pi, check_vibration=False, starts=1, workers=1)
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
