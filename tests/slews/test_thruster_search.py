"""Multi-start thruster-level time-optimal slews against independent bounds and integration."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import linprog

from casadi_debris.config import Problem
from casadi_debris.dynamics import build_model
from casadi_debris.geometry import Geometry, max_thrust_N
from casadi_debris.slews import RigidBody, time_optimal_slew
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
