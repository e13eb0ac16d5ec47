"""Our own integration of a slew profile, independent of the slew module's check."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import casadi as ca
import numpy as np
import pytest

from casadi_debris.config import Problem
from casadi_debris.dynamics import Model, build_model


def final_state(problem: Problem, slew: Any, modes: str | list) -> tuple[Model, np.ndarray]:
    """The model (``build_model(problem, modes)``) and its state at the end of the slew,
    driven by the slew's input from rest by CVODES, restarting at every sample so that
    it never steps across a switch."""
    model = build_model(problem, modes)
    x = ca.SX.sym("x", model.layout.size)
    t = ca.SX.sym("t")
    ode = model.dynamics(x, slew.input_function(t), model.nominal_parameters)
    integrator = ca.integrator(
        "slew_check",
        "cvodes",
        {"x": x, "t": t, "ode": ode},
        0.0,
        np.asarray(slew.time_s),
        {"abstol": 1e-13, "reltol": 1e-11, "max_num_steps": 500000},
    )
    start = model.initial_state(slew.target.q_initial_BN)
    return model, np.array(integrator(x0=start)["xf"])[:, -1]


# -- limits, computed here apart from casadi_debris.slews ----------------------------------

RATIO_SLACK = 1e-6


def _polytope(problem: Problem, zero_net_force: bool) -> Any:
    """The engines' torque set as facets (the allocator's own construction, not the slew
    check's LP)."""
    from casadi_debris.allocation import authority_polytope
    from casadi_debris.geometry import build_geometry, max_thrust_N

    geometry = build_geometry(problem)
    return geometry, authority_polytope(
        geometry.torque_map,
        geometry.force_map,
        max_thrust_N(geometry),
        free_force=not zero_net_force,
    )


def torque_set_gauge(polytope: Any, torque_Nm: np.ndarray) -> np.ndarray:
    """max_i n_i . tau / b_i over the facets: <= 1 exactly when tau is in the set, (n,)."""
    reach = np.atleast_2d(torque_Nm) @ polytope.normals.T
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(
            polytope.offsets > 0, reach / polytope.offsets, np.where(reach > 1e-15, np.inf, 0.0)
        )
    return np.maximum(ratio.max(axis=1), 0.0)


def independent_limits(problem: Problem, slew: Any) -> dict[str, Any]:
    """The slew's torque and thrust against the engines, computed here: the torque-set
    gauge from the allocator's facets (the test), the per-axis ratio from the facets'
    reach (information: a torque of the set may exceed a pure-axis reach on one
    component), thrust bounds, B f and F f from the geometry. Torque-level profiles at
    zero net force (the closed loop's allocator), thruster-level ones with their own
    rule."""
    zero_net_force = bool(slew.settings["zero_net_force"]) if slew.thrusters else True
    geometry, polytope = _polytope(problem, zero_net_force)
    torque = np.asarray(slew.torque_Nm)
    gauge = float(np.max(torque_set_gauge(polytope, torque)))
    reach = polytope.axis_reach()  # +x, -x, +y, -y, +z, -z
    per_axis = 0.0
    for index in range(3):
        plus, minus = np.maximum(torque[:, index], 0.0), np.maximum(-torque[:, index], 0.0)
        per_axis = max(per_axis, float(np.max(plus)) / reach[2 * index])
        per_axis = max(per_axis, float(np.max(minus)) / reach[2 * index + 1])
    ok = gauge <= 1.0 + RATIO_SLACK
    figures: dict[str, Any] = {"gauge": gauge, "per_axis": per_axis}
    if slew.thrusters:
        from casadi_debris.geometry import max_thrust_N

        thrust, limits = np.asarray(slew.thrust_N), max_thrust_N(geometry)
        unit = float(limits.max())
        lever = float(np.abs(geometry.torque_map).max())
        residual = float(np.abs(thrust @ geometry.torque_map.T - torque).max())
        force = float(np.abs(thrust @ geometry.force_map.T).max())
        ok = ok and bool(np.all(thrust >= -RATIO_SLACK * unit))
        ok = ok and bool(np.all(thrust <= limits * (1 + RATIO_SLACK)))
        ok = ok and residual <= RATIO_SLACK * unit * lever
        if zero_net_force:
            ok = ok and force <= RATIO_SLACK * unit
        figures.update({"torque_residual_Nm": residual, "net_force_N": force})
    figures["ok"] = ok
    return figures


def dynamics_residual(problem: Problem, slew: Any) -> float:
    """max |J alpha + omega x J omega - tau| over the profile, over max |tau| (rigid profiles:
    the hub's equation of motion, J the model's full rigid inertia)."""
    model = build_model(problem, [])
    inertia = np.array(model.rigid_inertia(model.nominal_parameters))
    omega, alpha = np.asarray(slew.rate_rad_s), np.asarray(slew.acceleration_rad_s2)
    need = alpha @ inertia.T + np.cross(omega, omega @ inertia.T)
    torque = np.asarray(slew.torque_Nm)
    return float(np.abs(need - torque).max() / max(float(np.abs(torque).max()), 1e-300))


def assert_checked(problem: Problem, slew: Any) -> dict[str, Any]:
    """The slew's own limit check agrees with the one computed here, and a rigid profile
    obeys the body's equation J alpha + omega x J omega = tau; the figures here returned."""
    figures = independent_limits(problem, slew)
    check = slew.limits
    assert check.limits_ok == figures["ok"], (check, figures)
    assert check.worst_torque_set_ratio == pytest.approx(figures["gauge"], rel=1e-6, abs=1e-9)
    assert max(check.worst_axis_ratio.values()) == pytest.approx(
        figures["per_axis"], rel=1e-6, abs=1e-9
    )
    if not slew.flexible:
        assert dynamics_residual(problem, slew) < 1e-6
    return figures


def _box_checked(body: Any, slew: Any) -> None:
    """A rigid body's slew: its torque within the body's box, as its check says, and
    J alpha + omega x J omega = tau."""
    torque = np.asarray(slew.torque_Nm)
    inside = bool(
        np.all(torque <= body.upper_Nm * (1 + RATIO_SLACK) + 1e-300)
        and np.all(torque >= body.lower_Nm * (1 + RATIO_SLACK) - 1e-300)
    )
    assert slew.limits.limits_ok == inside
    omega, alpha = np.asarray(slew.rate_rad_s), np.asarray(slew.acceleration_rad_s2)
    inertia = np.asarray(body.inertia_kgm2)
    need = alpha @ inertia.T + np.cross(omega, omega @ inertia.T)
    assert np.abs(need - torque).max() <= 1e-6 * np.abs(torque).max()


def check_every_profile(monkeypatch: Any) -> None:
    """Patch the slew module so that every profile it builds (through ``finish_profile``
    or, for a rigid body, ``rigid_body_profile``) is checked here as soon as it is made:
    :func:`assert_checked` for a problem's, the box for a rigid body's. For a
    module-scoped autouse fixture, so that module-scoped slews are checked too."""
    from casadi_debris.config import Problem as ProblemType
    from casadi_debris.dynamics import Model
    from casadi_debris.slews import _bang_bang as bang_bang
    from casadi_debris.slews import _ocp_solution as ocp_solution
    from casadi_debris.slews import _optimal as optimal
    from casadi_debris.slews import finish_profile, rigid_body_profile

    def finish(**keywords: Any) -> Any:
        slew = finish_profile(**keywords)
        given = keywords["problem"]  # a problem, or its flexible model
        problem = given.problem if isinstance(given, Model) else given
        assert isinstance(problem, ProblemType)
        assert_checked(problem, slew)
        return slew

    def rigid(body: Any, *arguments: Any, **keywords: Any) -> Any:
        slew = rigid_body_profile(body, *arguments, **keywords)
        _box_checked(body, slew)
        return slew

    monkeypatch.setattr(bang_bang, "finish_profile", finish)
    monkeypatch.setattr(ocp_solution, "finish_profile", finish)
    monkeypatch.setattr(optimal, "rigid_body_profile", rigid)


@pytest.fixture(scope="module", autouse=True)
def every_profile_checked() -> Iterator[None]:
    """Every slew profile a test module makes is checked (:func:`check_every_profile`):
    autouse in each module that imports it."""
    with pytest.MonkeyPatch.context() as patch:
        check_every_profile(patch)
        yield
