"""Flexible and deadline-constrained time-optimal slews, checked independently: the
profile's input integrated by our own CVODES integrator on the full flexible model,
the vibration energy recomputed from the model's energy and mass matrix, and the
rigid optimum and the ZV-shaped profile as bounds."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris.cli import main
from casadi_debris.config import Problem
from casadi_debris.errors import InputShapeError, SlewInfeasibleError
from casadi_debris.plots import plot_slew
from casadi_debris.slews import fuel_optimal_slew, time_optimal_slew
from shared_results import paper_z_time_optimal
from slew_reference import every_profile_checked, final_state  # noqa: F401 (autouse)


def modal_energy(problem: Problem, model: Any, state: np.ndarray) -> float:
    """Strain plus kinetic energy of the modes relative to the rigid motion of the same
    momenta: 1/2 nu^T M nu + 1/2 sum (Omega eta)^2 - 1/2 mu^T M_rr^-1 mu."""
    lay = model.layout
    p = model.nominal_parameters
    mass = np.array(model.mass_matrix(p))
    nu = np.concatenate([state[lay.v], state[lay.omega], state[lay.eta_dot]])
    by_name = {mode.name: mode.omega_rad_s for mode in problem.arrays[0].modes}
    omegas = np.array([by_name[name] for _, name in lay.mode_labels])
    strain = 0.5 * np.sum((omegas * state[lay.eta]) ** 2)
    mu = mass[:6] @ nu
    return 0.5 * nu @ mass @ nu + strain - 0.5 * mu @ np.linalg.solve(mass[:6, :6], mu)


@pytest.fixture(scope="module")
def rigid_optimum(problem: Problem) -> Any:
    # time_optimal_slew(problem, "z", math.pi, check_vibration=False), solved once a session.
    return paper_z_time_optimal(problem)


@pytest.fixture(scope="module")
def flexible_optimum(problem: Problem) -> Any:
    return time_optimal_slew(problem, "z", math.pi, flexible=True)


def test_flexible_ocp_meets_energy_limit_and_is_not_faster_than_rigid(
    problem: Problem, rigid_optimum: Any, flexible_optimum: Any
) -> None:
    slew = flexible_optimum
    assert slew.settings["flexible_method"] == "ocp"
    limit = slew.settings["residual_energy_limit_J"]
    # the module's own CVODES check, and the OCP's closed-form prediction agrees with it
    assert slew.residual_energy_J <= limit
    assert slew.settings["predicted_residual_energy_J"] == pytest.approx(
        slew.residual_energy_J, rel=1e-3
    )
    # our integrator and our energy
    model, final = final_state(problem, slew, "all")
    assert modal_energy(problem, model, final) <= limit
    error = np.array(model.attitude_error(slew.target.q_final_BN, final[model.layout.q]))
    assert np.linalg.norm(error) < 1e-5
    # the rigid bang-bang at the limit leaves far more than the limit
    assert slew.settings["bang_bang_residual_energy_J"] > 10.0 * limit
    # a flexible slew cannot be faster than the rigid optimum, and the target holds
    assert slew.duration_s >= rigid_optimum.duration_s - 1e-3
    assert slew.duration_s <= 1.10 * slew.limit_duration_s
    # ... and the OCP is no slower than the rigid optimum through the ZV shaper
    shaped_duration = rigid_optimum.duration_s + slew.settings["shaper_length_s"]
    assert slew.duration_s <= shaped_duration + 1e-3


def test_flexible_figure_adds_the_window_panel(
    tmp_path: Path, rigid_optimum: Any, flexible_optimum: Any
) -> None:
    heights = []
    for name, slew in (("rigid", rigid_optimum), ("flexible", flexible_optimum)):
        path = plot_slew(slew, tmp_path / f"{name}.png")
        heights.append(plt.imread(path).shape[0])
    assert heights[1] / heights[0] == pytest.approx(4 / 3, rel=0.01)


@pytest.mark.slow
def test_zero_vibration_shaper_option_says_so(problem: Problem, rigid_optimum: Any) -> None:
    slew = time_optimal_slew(problem, "z", math.pi, flexible=True, flexible_method="shaper")
    assert slew.settings["flexible_method"] == "shaper"
    assert slew.duration_s == pytest.approx(
        rigid_optimum.duration_s + slew.settings["shaper_length_s"], abs=1e-6
    )
    assert slew.residual_energy_J <= slew.settings["residual_energy_limit_J"]


@pytest.mark.slow
def test_flexible_slew_about_an_axis_that_excites_no_mode(problem: Problem) -> None:
    slew = time_optimal_slew(problem, "x", math.pi / 2, flexible=True)
    assert slew.settings["flexible_method"] == "ocp"
    # The bang-bang leaves nothing to speak of about x, so the limit is the floor,
    # 1e-12 of the slew's peak kinetic energy, and the slew meets it.
    limit = slew.settings["residual_energy_limit_J"]
    assert abs(slew.settings["bang_bang_residual_energy_J"]) < limit
    assert slew.residual_energy_J <= limit
    assert slew.duration_s <= 1.10 * slew.limit_duration_s


# Torque level by default; the thruster level (the same OCP with engines) under -m slow.
@pytest.mark.parametrize("thrusters", [False, pytest.param(True, marks=pytest.mark.slow)])
def test_flexible_fuel_optimal_meets_the_limit_for_about_the_rigid_fuel(
    problem: Problem, thrusters: bool
) -> None:
    duration = 1228.0
    rigid = fuel_optimal_slew(
        problem, "z", math.pi, duration_s=duration, thrusters=thrusters, check_vibration=False
    )
    slew = fuel_optimal_slew(
        problem, "z", math.pi, duration_s=duration, thrusters=thrusters, flexible=True
    )
    assert slew.settings["flexible_method"] == "ocp"
    assert slew.duration_s == pytest.approx(duration, abs=1e-6)
    assert slew.residual_energy_J <= slew.settings["residual_energy_limit_J"]
    # Not a strict bound either way: the constraint costs fuel, the window's finer grid
    # can save some. Both are small against the slew's fuel.
    assert slew.fuel_kg == pytest.approx(rigid.fuel_kg, rel=0.01)
    model, final = final_state(problem, slew, "all")
    assert modal_energy(problem, model, final) <= slew.settings["residual_energy_limit_J"]


@pytest.mark.slow
def test_flexible_fuel_optimal_just_above_the_flexible_minimum(
    problem: Problem, flexible_optimum: Any
) -> None:
    # Here the rigid problem a shaper's length shorter has no solution; the guess must
    # come from elsewhere.
    duration = flexible_optimum.duration_s + 0.5
    slew = fuel_optimal_slew(problem, "z", math.pi, duration_s=duration, flexible=True)
    assert slew.settings["flexible_method"] == "ocp"
    assert slew.duration_s == pytest.approx(duration, abs=1e-6)
    assert slew.residual_energy_J <= slew.settings["residual_energy_limit_J"]


def test_unknown_flexible_method(problem: Problem) -> None:
    with pytest.raises(InputShapeError, match="flexible_method"):
        time_optimal_slew(problem, "z", math.pi, flexible=True, flexible_method="modal")


# Each deadline solves the same minimum-time problem before it compares: all under
# -m slow (the command's too-short deadline below runs by default).
TOO_SHORT = [pytest.param(d, marks=pytest.mark.slow) for d in (-1.0, 0.0, 500.0, 900.0)]


@pytest.mark.parametrize("duration", TOO_SHORT)
def test_time_optimal_too_short_deadline_says_minimum(
    problem: Problem, rigid_optimum: Any, duration: float
) -> None:
    expected = f"infeasible: minimum is {rigid_optimum.duration_s:.6g} s"
    with pytest.raises(SlewInfeasibleError, match=re.escape(expected)):
        time_optimal_slew(problem, "z", math.pi, duration_s=duration, check_vibration=False)


def test_time_optimal_deadline_met_returns_the_optimum(
    problem: Problem, rigid_optimum: Any
) -> None:
    slew = time_optimal_slew(problem, "z", math.pi, duration_s=1000.0, check_vibration=False)
    assert slew.duration_s == pytest.approx(rigid_optimum.duration_s, rel=1e-9)


def test_cli_time_optimal_too_short_is_one_line_exit_2() -> None:
    result = CliRunner().invoke(main, ["slew", "--method", "time-optimal", "--duration-s", "100"])
    assert result.exit_code == 2
    # The minimum named is the time-optimal slew's within the engines' torque set (917.8 s).
    minimum = float(result.output.split("infeasible: minimum is ")[1].split(" s")[0])
    assert 900.0 < minimum < 920.0
    assert result.output.count("\n") == 1 and "Traceback" not in result.output
