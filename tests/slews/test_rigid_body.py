"""A plain rigid body for the slew functions: its checks, and what it refuses."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from casadi_debris.errors import InputShapeError
from casadi_debris.slews import (
    OptimalSlewSettings,
    RigidBody,
    fuel_optimal_slew,
    scaled_rigid_ode,
    time_optimal_slew,
)


def test_defaults_and_conversion() -> None:
    body = RigidBody(inertia_kgm2=[[2, 0, 0], [0, 3, 0], [0, 0, 4]], torque_max_Nm=(1, 2, 3))
    assert isinstance(body.inertia_kgm2, np.ndarray)
    assert body.lower_Nm.tolist() == [-1.0, -2.0, -3.0]
    uneven = RigidBody(np.eye(3), (1, 1, 1), torque_min_Nm=(-2, -0.5, -1))
    assert uneven.torque_scale_Nm.tolist() == [2.0, 1.0, 1.0]
    assert uneven.scaled(0.5).upper_Nm.tolist() == [0.5, 0.5, 0.5]


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"inertia_kgm2": np.eye(2)}, "inertia_kgm2: expected shape"),
        (
            {"inertia_kgm2": [[1, 0, 0], [0, 1, 0], [0, 0, math.nan]]},
            "inertia_kgm2: must be finite",
        ),
        ({"inertia_kgm2": [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]}, "inertia_kgm2: must be symmetric"),
        ({"inertia_kgm2": -np.eye(3)}, "inertia_kgm2: must be positive definite"),
        ({"inertia_kgm2": np.diag([1.0, 1.0, 3.0])}, "inertia_kgm2: principal moments violate"),
        ({"inertia_kgm2": "abc"}, "inertia_kgm2: expected numbers"),
        ({"torque_max_Nm": (1, 1)}, "torque_max_Nm: expected shape"),
        ({"torque_max_Nm": (1, 0, 1)}, "torque_max_Nm: every bound must be > 0"),
        ({"torque_max_Nm": (1, math.inf, 1)}, "torque_max_Nm: must be finite"),
        ({"torque_min_Nm": (-1, 1, -1)}, "torque_min_Nm: every bound must be < 0"),
    ],
)
def test_bad_fields_are_named(fields: dict[str, Any], message: str) -> None:
    arguments = {"inertia_kgm2": np.eye(3), "torque_max_Nm": (1, 1, 1), **fields}
    with pytest.raises(InputShapeError, match=message):
        RigidBody(**arguments)


def test_scaled_equations_are_euler_s() -> None:
    inertia = np.array([[3.0, 0.2, 0.1], [0.2, 2.0, -0.3], [0.1, -0.3, 2.5]])
    body = RigidBody(inertia, (1.0, 2.0, 0.5))
    scale = 7.0
    ode = scaled_rigid_ode(body, scale)
    q = np.array([0.5, 0.5, -0.5, 0.5])
    omega = np.array([0.1, -0.2, 0.3])
    torque = np.array([0.3, -1.0, 0.25])
    derivative = np.array(ode(np.concatenate([q, omega * scale]), torque / [1, 2, 0.5])).ravel()
    euler = np.linalg.solve(inertia, torque - np.cross(omega, inertia @ omega))
    assert derivative[4:] / scale**2 == pytest.approx(euler, rel=1e-12)
    # q_dot = 1/2 q (x) [0, omega], the scaled time tau = t / scale
    q0, qv = q[0], q[1:]
    q_dot = 0.5 * np.concatenate([[-qv @ omega], q0 * omega + np.cross(qv, omega)])
    assert derivative[:4] / scale == pytest.approx(q_dot, rel=1e-12)


@pytest.mark.parametrize("name", ["flexible", "thrusters", "single_axis"])
def test_options_that_need_a_problem_are_refused(name: str) -> None:
    body = RigidBody(np.eye(3), (1, 1, 1))
    with pytest.raises(InputShapeError, match=f"{name}: applies to the slew of a Problem"):
        time_optimal_slew(body, "z", math.pi, **{name: True})


def test_fuel_optimal_needs_a_problem() -> None:
    with pytest.raises(InputShapeError, match="needs a Problem"):
        fuel_optimal_slew(RigidBody(np.eye(3), (1, 1, 1)), "z", math.pi, duration_s=4.0)


@pytest.mark.parametrize(
    ("field", "value"), [("starts", 0), ("seed", -1), ("workers", 0), ("starts", 2.5)]
)
def test_bad_search_options_are_named(field: str, value: Any) -> None:
    with pytest.raises(InputShapeError, match=f"{field}: must be an integer"):
        OptimalSlewSettings(**{field: value})
