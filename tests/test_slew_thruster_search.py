"""Multi-start thruster-level time-optimal slews against independent bounds and integration."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import linprog

from casadi_debris.config import Problem
from casadi_debris.geometry import Geometry, max_thrust_N
from casadi_debris.model import build_model
from casadi_debris.slew import RigidBody, time_optimal_slew
from slew_reference import every_profile_checked, final_state  # noqa: F401 (autouse)


def engine_torque_extents(geometry: Geometry) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) of each torque component over 0 <= f <= f_max, by LPs of our own.

    The engines' torque set lies inside this box (its bounding box), so the rigid
    time-optimal slew in this box is a lower bound of the thruster-level one.
    """
    torque_map = geometry.torque_map
    bounds = list(zip(np.zeros(torque_map.shape[1]), max_thrust_N(geometry), strict=True))
    upper = [-linprog(-row, bounds=bounds, method="highs").fun for row in torque_map]
    lower = [linprog(row, bounds=bounds, method="highs").fun for row in torque_map]
    return np.array(lower), np.array(upper)


@pytest.mark.slow
def test_paper_thruster_slew_multistart(problem: Problem, geometry: Geometry) -> None:
    slew = time_optimal_slew(problem, "z", math.pi, thrusters=True, check_vibration=False)
    settings = slew.settings
    assert settings["starts"] == 4
    assert settings["agreement_fraction"] == 1.0
    assert settings["best_start"] in settings["start_durations_s"]
    assert slew.duration_s == pytest.approx(min(settings["start_durations_s"].values()))
    # not faster than the rigid optimum in the engines' bounding box
    lower, upper = engine_torque_extents(geometry)
    rigid = build_model(problem, modes=[])
    inertia = np.array(rigid.rigid_inertia(rigid.nominal_parameters))
    box = time_optimal_slew(
        RigidBody(inertia_kgm2=inertia, torque_max_Nm=upper, torque_min_Nm=lower),
        axis="z",
        angle_rad=math.pi,
    )
    assert slew.duration_s >= box.duration_s * (1 - 1e-6)
    # within the engines' bounds, and it gets there: our own integration
    limits = max_thrust_N(geometry)
    assert np.all(slew.thrust_N >= -1e-12)
    assert np.all(slew.thrust_N <= limits * (1 + 1e-9))
    model, final = final_state(problem, slew, [])
    error = np.array(model.attitude_error(slew.target.q_final_BN, final[model.layout.q]))
    assert np.linalg.norm(error) < 1e-5
    assert np.linalg.norm(final[model.layout.omega]) < 1e-7


def test_zero_net_force_starts_hold_the_net_force_at_zero(problem: Problem) -> None:
    """Every start of a zero-net-force search lies on F f = 0 within the bounds (a
    perturbed start off that plane kept IPOPT busy for minutes), and its torque is that
    of the thrust it perturbs, within what the engines can give at zero net force."""
    from casadi_debris.slew import SlewOptions, slew_about_axis
    from casadi_debris.slew.global_slew import GlobalSlew
    from casadi_debris.slew.initial_guess import BangBangReferences, bang_bang_guess
    from casadi_debris.slew.ocp_problem import SlewOcp
    from casadi_debris.slew.thruster_search import thruster_starts

    options = SlewOptions(thrusters=True, zero_net_force=True, check_vibration=False)
    ocp = SlewOcp(problem, slew_about_axis("z", math.pi), options)
    reference = BangBangReferences(ocp).at(ocp.limit_duration_s)
    eigenaxis = bang_bang_guess(ocp, reference, False, reference.duration_s)
    # a box optimum of four held corners (outside the engines' torque set)
    corners = np.array([[1, 1, 1], [1, -1, 1], [-1, 1, -1], [-1, -1, -1]]) * ocp.upper
    box = GlobalSlew(np.linspace(0.0, 900.0, 5), corners, "test", 900.0, {})
    starts = thruster_starts(ocp, eigenaxis, box, 4, seed=3)
    assert [start.label.split()[0] for start in starts] == [
        "eigenaxis",
        "torque-box",
        "perturbed",
        "perturbed",
    ]
    unit = float(ocp.f_max.max())
    for start in starts:
        force = start.thrust_N @ ocp.geometry.force_map.T
        assert np.abs(force).max() <= 1e-9 * unit, start.label
        assert np.all(start.thrust_N >= 0.0) and np.all(start.thrust_N <= ocp.f_max)
