"""The compiled nonlinear model: conservation laws, an independent rigid-body integration,
and the named Functions."""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from casadi_debris.dynamics import INPUT_NAMES, build_model
from casadi_debris.errors import InputShapeError, ModelError


def _integrate(model, x0, p, times, u=None):
    """CasADi CVODES over a whole time grid, inputs held constant.

    Adams rather than BDF: BDF's numerical damping of the array modes would show
    up as a slow energy drift (1e-6 in 200 s) that is the integrator's, not the model's.
    """
    lay = model.layout
    x = ca.MX.sym("x", lay.size)
    params = ca.MX.sym("params", 9 + len(p))
    ode = model.dynamics(x, params[:9], params[9:])
    integrator = ca.integrator(
        "plant",
        "cvodes",
        {"x": x, "p": params, "ode": ode},
        0.0,
        times,
        {
            "abstol": 1e-12,
            "reltol": 1e-12,
            "max_num_steps": 200000,
            "linear_multistep_method": "adams",
            "nonlinear_solver_iteration": "functional",
        },
    )
    inputs = np.zeros(9) if u is None else np.asarray(u)
    return np.array(integrator(x0=x0, p=np.concatenate([inputs, p]))["xf"])


def test_function_names_and_shapes(model):
    assert model.dynamics.name_in() == ["x", "u", "p"]
    assert model.dynamics.name_out() == ["xdot"]
    assert model.dynamics.size1_in(1) == len(INPUT_NAMES) == 9
    assert model.dynamics.size1_in(2) == len(model.parameter_names) == 6
    assert model.layout.size == 14 + 2 * 6
    assert len(model.layout.names()) == model.layout.size


def test_energy_and_momentum_conserved_without_damping(undamped_problem):
    model = build_model(undamped_problem)
    lay = model.layout
    p = model.parameters(array_angle_offset_rad=0.7)
    x0 = model.initial_state(quaternion=[0.9, 0.1, -0.3, 0.2], rate_rad_s=[0.02, -0.03, 0.01])
    # Deflect the arrays; at rest in eta_dot and v, so the linear momentum is zero.
    x0[lay.eta] = [0.02, -0.01, 0.005, -0.015, 0.01, 0.002]
    times = np.linspace(0.0, 200.0, 21)
    states = _integrate(model, x0, p, times)
    energy = np.array([float(model.energy(states[:, k], p)) for k in range(len(times))])
    momentum = np.array(
        [np.array(model.momenta(states[:, k], p)[1]).ravel() for k in range(len(times))]
    )
    linear = np.array(
        [np.array(model.momenta(states[:, k], p)[0]).ravel() for k in range(len(times))]
    )
    assert np.max(np.abs(energy / energy[0] - 1)) < 1e-7
    assert np.max(np.linalg.norm(momentum - momentum[0], axis=1)) < 1e-7 * np.linalg.norm(
        momentum[0]
    )
    assert np.max(np.abs(linear)) < 1e-10
    np.testing.assert_allclose(np.linalg.norm(states[lay.q], axis=0), 1.0, atol=1e-9)
    # the arrays really vibrate and exchange energy with the hub
    assert np.ptp(states[lay.eta][0]) > 0.01


def _euler_rigid(inertia, q0, w0, times):
    """Independent rigid-body reference: Euler's equations and quaternion kinematics."""
    inverse = np.linalg.inv(inertia)

    def rhs(_, y):
        q, w = y[:4], y[4:]
        q_dot = 0.5 * np.array(
            [
                -q[1] * w[0] - q[2] * w[1] - q[3] * w[2],
                q[0] * w[0] + q[2] * w[2] - q[3] * w[1],
                q[0] * w[1] - q[1] * w[2] + q[3] * w[0],
                q[0] * w[2] + q[1] * w[1] - q[2] * w[0],
            ]
        )
        w_dot = inverse @ (-np.cross(w, inertia @ w))
        return np.concatenate([q_dot, w_dot])

    sol = solve_ivp(
        rhs,
        (times[0], times[-1]),
        np.concatenate([q0, w0]),
        t_eval=times,
        method="DOP853",
        rtol=1e-12,
        atol=1e-13,
    )
    return sol.y


def test_rigid_model_matches_euler_equations(problem):
    rigid = build_model(problem, modes=[])
    p = rigid.nominal_parameters
    q0 = np.array([1.0, 0.0, 0.0, 0.0])
    w0 = np.array([0.05, -0.02, 0.04])
    times = np.linspace(0.0, 300.0, 31)
    states = _integrate(rigid, rigid.initial_state(q0, w0), p, times)
    reference = _euler_rigid(np.array(rigid.rigid_inertia(p)), q0, w0, times)
    np.testing.assert_allclose(states[rigid.layout.q], reference[:4], atol=1e-8)
    np.testing.assert_allclose(states[rigid.layout.omega], reference[4:], atol=1e-10)


def test_debris_without_arrays_is_a_rigid_body(tmp_path):
    from casadi_debris import load_problem
    from casadi_debris.config import default_problem_path
    from casadi_debris.geometry import build_geometry

    child = tmp_path / "rigid.toml"
    child.write_text(f'extends = "{default_problem_path()}"\nname = "rigid"\narrays = []\n')
    problem = load_problem(child)
    rigid = build_model(problem)  # every mode of every array: there are none
    assert rigid.layout.n_eta == 0
    assert rigid.parameter_names == (
        "inertia_scale_x",
        "inertia_scale_y",
        "inertia_scale_z",
        "mass_kg",
    )
    # Reference inertia from the geometry's part-by-part sum, not from the model.
    inertia = build_geometry(problem).inertia_total_kgm2
    q0, w0 = (
        np.array([0.9, 0.1, -0.3, 0.3]) / np.linalg.norm([0.9, 0.1, -0.3, 0.3]),
        np.array([0.03, 0.05, -0.04]),
    )
    times = np.linspace(0.0, 400.0, 41)
    states = _integrate(rigid, rigid.initial_state(q0, w0), rigid.nominal_parameters, times)
    reference = _euler_rigid(inertia, q0, w0, times)
    np.testing.assert_allclose(states[rigid.layout.q], reference[:4], atol=1e-8)
    np.testing.assert_allclose(states[rigid.layout.omega], reference[4:], atol=1e-10)


def test_torque_and_force_enter_as_newton_euler(model):
    """At rest, the instantaneous response to a torque is the inverse of the Schur complement."""
    p = model.nominal_parameters
    x0 = model.initial_state()
    torque = np.array([1e-3, -2e-3, 0.5e-3])
    xdot = np.array(model.dynamics(x0, np.concatenate([torque, np.zeros(6)]), p)).ravel()
    mass_matrix = np.array(model.mass_matrix(p))
    accel = np.linalg.solve(mass_matrix, np.concatenate([np.zeros(3), torque, np.zeros(6)]))
    np.testing.assert_allclose(xdot[model.layout.omega], accel[3:6], rtol=1e-10)
    np.testing.assert_allclose(xdot[model.layout.eta_dot], accel[6:], rtol=1e-10, atol=1e-16)
    # The disturbance input adds to the control torque.
    xdot_d = np.array(model.dynamics(x0, np.concatenate([np.zeros(3), torque, np.zeros(3)]), p))
    np.testing.assert_allclose(xdot_d.ravel(), xdot, rtol=1e-12)


def test_inertia_scale_scales_the_hub_cubesats_diagonal(model, geometry):
    base = np.array(model.rigid_inertia(model.nominal_parameters))
    scaled = np.array(model.rigid_inertia(model.parameters(inertia_scale_y=1.17)))
    hub_cubesats = geometry.inertia_hub_cubesats_kgm2
    assert scaled[1, 1] - base[1, 1] == pytest.approx(0.17 * hub_cubesats[1, 1], rel=1e-12)
    assert scaled[0, 0] == pytest.approx(base[0, 0], rel=1e-14)


def test_disturbance_is_the_problem_sine(model, problem):
    period_s = problem.disturbance.period_min * 60.0
    np.testing.assert_allclose(np.array(model.disturbance(period_s / 4)).ravel(), [0.7e-3] * 3)
    np.testing.assert_allclose(np.array(model.disturbance(period_s / 2)).ravel(), 0.0, atol=1e-18)


def test_attitude_error_small_angle_and_short_way(model):
    angle = 1e-3
    q = np.array([math.cos(angle / 2), math.sin(angle / 2), 0.0, 0.0])
    identity = np.array([1.0, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(
        np.array(model.attitude_error(identity, q)).ravel(), [angle, 0, 0], rtol=1e-6
    )
    np.testing.assert_allclose(
        np.array(model.attitude_error(identity, -q)).ravel(), [angle, 0, 0], rtol=1e-6
    )
    # 180 deg about z: doubled vector part has magnitude 2, about z, well defined
    half_turn = np.array([0.0, 0.0, 0.0, 1.0])
    np.testing.assert_allclose(
        np.array(model.attitude_error(identity, half_turn)).ravel(), [0, 0, 2]
    )


def test_bad_parameters_and_states_named(model):
    with pytest.raises(ModelError, match="unknown parameter 'inertia_x'"):
        model.parameters(inertia_x=1.0)
    with pytest.raises(InputShapeError, match="quaternion"):
        model.initial_state(quaternion=[1.0, 0.0, 0.0])
    with pytest.raises(InputShapeError, match="rate_rad_s"):
        model.initial_state(rate_rad_s=[0.0, math.nan, 0.0])
    with pytest.raises(ModelError, match="unknown modes"):
        build_model(model.problem, modes=["bending7"])
