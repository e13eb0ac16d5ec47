"""The NMPC controller checked against computations made here: the unconstrained LQ
solution of the same cost (a Riccati recursion on the linearised rigid body), the
Bilimoria-Wie time-optimal slew (literature, and the toolkit's own slew OCP), and a
closed loop of this test's own (the model's Function integrated by CVODES between
periods) in which every applied thrust is checked against its engine's limits."""

from __future__ import annotations

import dataclasses
import math

import casadi as ca
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm, solve_discrete_are

from casadi_debris import load_problem
from casadi_debris.controllers import (
    NmpcController,
    NmpcEngines,
    NmpcReference,
    NmpcSettings,
)
from casadi_debris.dynamics import (
    Model,
    assembled_modes,
    attitude_error,
    axis_angle_quaternion,
    build_model,
)
from casadi_debris.errors import InputShapeError
from casadi_debris.slews import RigidBody, time_optimal_slew

# Bilimoria & Wie, "Time-optimal three-axis reorientation of a rigid spacecraft",
# J. Guidance 16(3), 1993: J = I, |u_i| <= 1, rest to rest 180 deg about a principal axis.
BENCHMARK_S = 3.2431
EIGENAXIS_S = 2.0 * math.sqrt(math.pi)


@pytest.fixture(scope="module")
def rigid_model() -> Model:
    """The paper's debris without arrays: a rigid body with the paper's engines."""
    return build_model(load_problem("rigid_no_arrays"))


def unit_body() -> tuple[Model, np.ndarray]:
    """A model of the toolkit whose rigid inertia is the identity, and its parameters.

    The hub inertia is chosen so that hub plus CubeSats make 400 I about the CoG; the
    model's inertia factors of 1/400 then give J = I.
    """
    problem = load_problem("rigid_no_arrays")
    model = build_model(problem)
    others = np.array(model.rigid_inertia(model.nominal_parameters)) - problem.hub.inertia_kgm2
    hub = dataclasses.replace(problem.hub, inertia_kgm2=400.0 * np.eye(3) - others)
    unit = build_model(dataclasses.replace(problem, hub=hub))
    scale = 1.0 / 400.0
    p = unit.parameters(inertia_scale_x=scale, inertia_scale_y=scale, inertia_scale_z=scale)
    np.testing.assert_allclose(np.array(unit.rigid_inertia(p)), np.eye(3), atol=1e-14)
    return unit, p


def torque_box(limit_Nm: float) -> NmpcEngines:
    """Three two-way 'engines', one per axis, of 1 N m per unit: the box |u_i| <= limit."""
    return NmpcEngines(
        torque_map=np.eye(3),
        force_map=np.zeros((3, 3)),
        max_thrust_N=np.full(3, limit_Nm),
        min_thrust_N=np.full(3, -limit_Nm),
    )


# -- settings and inputs ------------------------------------------------------------------


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("horizon_steps", 0),
        ("period_s", -1.0),
        ("period_s", math.nan),
        ("attitude_weight", -1.0),
        ("prediction", "elastic"),
        ("qp_solver", "gurobi"),
        ("solver", "fast"),
    ],
)
def test_settings_name_the_bad_field(field: str, value: object) -> None:
    with pytest.raises(InputShapeError, match=field):
        NmpcSettings(**{field: value})  # type: ignore[arg-type]


def test_time_objective_needs_the_terminal_constraint() -> None:
    with pytest.raises(InputShapeError, match="terminal"):
        NmpcSettings(objective="time")


def test_state_of_the_wrong_size_is_refused(rigid_model: Model) -> None:
    controller = NmpcController(rigid_model, NmpcSettings(horizon_steps=3))
    with pytest.raises(InputShapeError, match="state_estimate"):
        controller.step(0.0, np.zeros(5), [1.0, 0.0, 0.0, 0.0])
    with pytest.raises(InputShapeError, match="quaternion_BN"):
        controller.step(0.0, rigid_model.initial_state(), [0.0, 0.0, 0.0, 0.0])
    with pytest.raises(InputShapeError, match="rate_rad_s"):
        reference = NmpcReference([1.0, 0.0, 0.0, 0.0], rate_rad_s=np.zeros((2, 3)))
        controller.step(0.0, rigid_model.initial_state(), reference)


# -- (b) the first move is the LQ solution when no constraint is active ----------------------


def lq_problem(
    inertia: np.ndarray, controller: NmpcController
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A_d, B_d, Q, R of the NMPC's cost on the rigid body linearised at rest
    (e_dot = omega, J omega_dot = tau), discretised exactly (zero-order hold)."""
    s, sc = controller.settings, controller.scales
    a = np.zeros((6, 6))
    a[:3, 3:] = np.eye(3)
    b = np.vstack([np.zeros((3, 3)), np.linalg.inv(inertia)])
    augmented = expm(np.block([[a, b], [np.zeros((3, 9))]]) * s.period_s)
    q = np.diag(
        [s.attitude_weight / sc.attitude_rad**2] * 3 + [s.rate_weight / sc.rate_rad_s**2] * 3
    )
    r = s.thrust_weight / sc.thrust_N**2 * np.eye(3)
    return augmented[:6, :6], augmented[:6, 6:], q, r


def riccati(
    ad: np.ndarray, bd: np.ndarray, q: np.ndarray, r: np.ndarray, terminal: np.ndarray, steps: int
) -> tuple[np.ndarray, np.ndarray]:
    """First gain and cost-to-go of the finite-horizon LQ problem, by the backward
    Riccati recursion."""
    p, gain = terminal, np.zeros((bd.shape[1], ad.shape[0]))
    for _ in range(steps):
        gain = np.linalg.solve(r + bd.T @ p @ bd, bd.T @ p @ ad)
        p = q + ad.T @ p @ (ad - bd @ gain)
    return gain, p


def lq_first_move(
    inertia: np.ndarray, controller: NmpcController, error0: np.ndarray, rate0: np.ndarray
) -> np.ndarray:
    """First torque of the finite-horizon LQ problem with the NMPC's cost."""
    s = controller.settings
    ad, bd, q, r = lq_problem(inertia, controller)
    gain, _ = riccati(ad, bd, q, r, s.terminal_weight * q, s.horizon_steps)
    return -gain @ np.concatenate([error0, rate0])


@pytest.mark.parametrize("solver", ["full", "rti"])
def test_first_move_is_the_unconstrained_lq_solution(rigid_model: Model, solver: str) -> None:
    settings = NmpcSettings(
        horizon_steps=10,
        period_s=2.0,
        propellant_weight=0.0,
        thrust_rate_weight=0.0,
        thrust_weight=1e-2,
        rate_weight=0.3,
        zero_net_force=False,
        solver=solver,  # type: ignore[arg-type]
    )
    controller = NmpcController(rigid_model, settings, engines=torque_box(1.0))
    inertia = np.array(rigid_model.rigid_inertia(rigid_model.nominal_parameters))
    error0 = np.array([3.0, -2.0, 1.5]) * 1e-6
    rate0 = np.array([-1.0, 2.0, 0.5]) * 1e-8
    quaternion = np.concatenate([[math.sqrt(1.0 - np.sum((error0 / 2) ** 2))], error0 / 2])
    state = rigid_model.initial_state(quaternion=quaternion, rate_rad_s=rate0)
    step = controller.step(0.0, state, [1.0, 0.0, 0.0, 0.0])
    expected = lq_first_move(inertia, controller, error0, rate0)
    # The box is far away: no constraint is active.
    assert np.abs(expected).max() < 1e-2
    # The nonlinear terms are of the order of the error (1e-6) relative to the move.
    np.testing.assert_allclose(
        step.thrust_N, expected, rtol=1e-4, atol=1e-4 * np.abs(expected).max()
    )


def test_the_riccati_recursion_here_converges_to_scipys_dare(rigid_model: Model) -> None:
    """The reference of the test above, checked: run long, the recursion gives the
    cost-to-go and gain of scipy's discrete algebraic Riccati solver."""
    controller = NmpcController(
        rigid_model,
        NmpcSettings(horizon_steps=10, period_s=2.0, thrust_weight=1e-2, zero_net_force=False),
        engines=torque_box(1.0),
    )
    inertia = np.array(rigid_model.rigid_inertia(rigid_model.nominal_parameters))
    ad, bd, q, r = lq_problem(inertia, controller)
    gain, p = riccati(ad, bd, q, r, q, 5000)
    p_are = solve_discrete_are(ad, bd, q, r)
    np.testing.assert_allclose(p, p_are, rtol=1e-8, atol=1e-8 * np.abs(p_are).max())
    gain_are = np.linalg.solve(r + bd.T @ p_are @ bd, bd.T @ p_are @ ad)
    np.testing.assert_allclose(gain, gain_are, rtol=1e-8, atol=1e-8 * np.abs(gain_are).max())


# -- (a) minimum time on the Bilimoria-Wie body --------------------------------------------


def tilted_guess(n_steps: int, duration_s: float, tilt_rad: float) -> tuple[np.ndarray, np.ndarray]:
    """States along a 180 deg turn about z with a tilt about x that comes and goes: a start
    off the eigenaxis path (a stationary point that a local solver started on stays at)."""
    fraction = np.linspace(0.0, 1.0, n_steps + 1)
    q_turn = axis_angle_quaternion([0.0, 0.0, 1.0], math.pi * fraction)
    q_tilt = axis_angle_quaternion([1.0, 0.0, 0.0], tilt_rad * np.sin(math.pi * fraction))
    q0, qv = q_turn[:, :1], q_turn[:, 1:]
    t0, tv = q_tilt[:, :1], q_tilt[:, 1:]
    quaternion = np.hstack(
        [q0 * t0 - np.sum(qv * tv, axis=1, keepdims=True), q0 * tv + t0 * qv + np.cross(qv, tv)]
    )
    rate = np.zeros((n_steps + 1, 3))
    rate[:, 2] = math.pi / duration_s * np.pi / 2 * np.sin(math.pi * fraction)
    states = np.hstack([quaternion, rate, np.zeros((n_steps + 1, 3))])
    return states, np.zeros((n_steps, 3))


def euler_rates(state: np.ndarray, torque: np.ndarray) -> np.ndarray:
    """d/dt [q, omega] of the body J = I (omega x J omega = 0), written here."""
    q, omega = state[:4], state[4:]
    q_dot = 0.5 * np.concatenate([[-q[1:] @ omega], q[0] * omega + np.cross(q[1:], omega)])
    return np.concatenate([q_dot, torque])


@pytest.mark.slow
def test_minimum_time_reproduces_bilimoria_wie() -> None:
    model, p = unit_body()
    n_steps = 80
    settings = NmpcSettings(
        horizon_steps=n_steps,
        period_s=EIGENAXIS_S / n_steps,
        objective="time",
        terminal="constraint",
        propellant_weight=0.0,
        thrust_rate_weight=0.0,
        thrust_weight=0.0,
        zero_net_force=False,
        solver="full",
        max_sqp_iterations=3000,
    )
    controller = NmpcController(model, settings, engines=torque_box(1.0), parameters=p)
    target = axis_angle_quaternion([0.0, 0.0, 1.0], math.pi)
    best = None
    for tilt in (0.3, -0.3, 0.6):
        states, thrusts = tilted_guess(n_steps, EIGENAXIS_S, tilt)
        controller.set_guess(states, thrusts, horizon_s=EIGENAXIS_S)
        step = controller.step(0.0, model.initial_state(), target)
        if step.success and (best is None or step.horizon_s < best.horizon_s):
            best = step
    assert best is not None
    # Literature value and the toolkit's own (independent: collocation, multi-start,
    # switch times refined) time-optimal slew.
    assert abs(best.horizon_s - BENCHMARK_S) <= 0.01 * BENCHMARK_S
    body = RigidBody(inertia_kgm2=np.eye(3), torque_max_Nm=(1.0, 1.0, 1.0))
    reference = time_optimal_slew(body, axis=(0, 0, 1), angle_rad=math.pi, workers=1)
    assert abs(best.horizon_s - reference.duration_s) <= 0.01 * reference.duration_s
    assert best.horizon_s < EIGENAXIS_S - 0.2  # not the eigenaxis slew
    # The predicted thrusts flown by scipy on equations written here end at the target.
    assert np.abs(best.predicted_thrust_N).max() <= 1.0 + 1e-9
    state = np.concatenate([[1.0, 0.0, 0.0, 0.0], np.zeros(3)])
    h = best.horizon_s / n_steps
    for torque in best.predicted_thrust_N:
        state = solve_ivp(
            lambda _, x, u=torque: euler_rates(x, u), (0, h), state, rtol=1e-11, atol=1e-12
        ).y[:, -1]
    assert np.linalg.norm(attitude_error(target, state[:4] / np.linalg.norm(state[:4]))) < 1e-5
    assert np.linalg.norm(state[4:]) < 1e-5


# -- (c) a closed loop of this test's own ----------------------------------------------------


def plant_step(model: Model, period_s: float) -> ca.Function:
    """The model's dynamics, thrust and disturbance held over one period, by CVODES."""
    x = ca.MX.sym("x", model.layout.size)
    u = ca.MX.sym("u", 9)
    ode = model.dynamics(x, u, ca.DM(model.nominal_parameters))
    options = {"abstol": 1e-12, "reltol": 1e-10}
    return ca.integrator("plant", "cvodes", {"x": x, "p": u, "ode": ode}, 0.0, period_s, options)


def fly(
    controller: NmpcController,
    plant: Model,
    x0: np.ndarray,
    target: np.ndarray,
    periods: int,
) -> tuple[list, np.ndarray]:
    """Closed loop: the true state is the estimate; thrust held over each period."""
    period = controller.settings.period_s
    integrate = plant_step(plant, period)
    engines = controller.engines
    x = x0.copy()
    steps, errors = [], []
    for k in range(periods):
        time_s = k * period
        step = controller.step(time_s, x, target)
        steps.append(step)
        disturbance = np.array(plant.disturbance(time_s)).ravel()
        u = np.concatenate(
            [engines.torque_map @ step.thrust_N, disturbance, engines.force_map @ step.thrust_N]
        )
        x = np.array(integrate(x0=x, p=u)["xf"]).ravel()
        errors.append(np.linalg.norm(attitude_error(target, x[plant.layout.q])))
    return steps, np.array(errors)


def check_engines(steps: list, engines: NmpcEngines, failed: list[int]) -> None:
    """Every applied thrust within its limits, failed engines at zero, no net force."""
    limit = engines.max_thrust_N
    for step in steps:
        assert np.all(step.thrust_N >= 0.0)
        assert np.all(step.thrust_N <= limit)
        assert np.all(step.thrust_N[failed] == 0.0)
        assert np.abs(step.force_N).max() <= 1e-9 * limit.max()
        # The solver's own plan (before the applied move is clipped) meets them too.
        assert step.predicted_thrust_N.min() >= -1e-9 * limit.max()
        assert np.all(step.predicted_thrust_N <= limit + 1e-9 * limit.max())


def test_closed_loop_small_slew_with_failed_engines() -> None:
    """The paper's debris (every array mode in the plant), rigid prediction, RTI: a 0.3
    deg slew about z with two CubeSats failed."""
    plant = build_model(load_problem())
    settings = NmpcSettings(horizon_steps=15, period_s=2.0)
    controller = NmpcController(plant, settings)
    failed = [2, 9]
    limits = controller.engines.max_thrust_N.copy()
    limits[failed] = 0.0
    controller.set_limits(limits)
    target = axis_angle_quaternion([0.0, 0.0, 1.0], math.radians(0.3))
    steps, errors = fly(controller, plant, plant.initial_state(), target, periods=40)
    check_engines(steps, controller.engines, failed)
    assert all(step.success for step in steps)
    # Converging: from 0.3 deg to within the paper's 60 arcsec pointing requirement.
    assert errors[-1] < math.radians(60.0 / 3600.0)
    assert errors[-10:].max() < 0.05 * errors[0]


def test_nothing_is_printed(rigid_model: Model, capfd: pytest.CaptureFixture[str]) -> None:
    """qpOASES prints a licence banner from C when set up; the controller silences it."""
    controller = NmpcController(rigid_model, NmpcSettings(horizon_steps=3))
    controller.step(0.0, rigid_model.initial_state(), [1.0, 0.0, 0.0, 0.0])
    out, err = capfd.readouterr()
    assert out == ""
    assert err == ""


def test_flexible_prediction_follows_the_model_with_its_modes() -> None:
    """The flexible prediction's first interval against CVODES on the model's Function,
    from a state with the arrays deflected and the body turning."""
    model = build_model(load_problem(), modes="first")
    # A full solve: its plan meets the nonlinear gaps (one RTI step meets their
    # linearisation only).
    settings = NmpcSettings(horizon_steps=4, period_s=1.0, prediction="flexible", solver="full")
    controller = NmpcController(model, settings)
    assert controller.n_x == 10 + 2 * model.layout.n_eta
    # Enough RK4 steps for the fastest mode of the assembly: h omega <= 0.5.
    fastest = max(mode["omega_rad_s"] for mode in assembled_modes(model))
    steps = controller.integrator_steps
    assert steps == math.ceil(fastest * 1.0 / 0.5)
    # RK4 on an oscillator: phase error (h omega)^5 / 120 per step, amplitude error
    # (h omega)^6 / 144; their sum over the interval bounds the relative error.
    h_omega = fastest / steps
    tolerance = steps * (h_omega**5 / 120 + h_omega**6 / 144)
    x0 = model.initial_state(rate_rad_s=[1e-4, -2e-4, 3e-4])
    x0[model.layout.eta] = 1e-4
    x0[model.layout.eta_dot] = -2e-4
    step = controller.step(0.0, x0, axis_angle_quaternion([0.0, 0.0, 1.0], 0.01))
    assert step.success
    u = np.concatenate(
        [
            controller.engines.torque_map @ step.predicted_thrust_N[0],
            np.zeros(3),
            controller.engines.force_map @ step.predicted_thrust_N[0],
        ]
    )
    x_cvodes = np.array(plant_step(model, 1.0)(x0=x0, p=u)["xf"]).ravel()
    predicted = step.predicted_state[1]
    layout = model.layout
    for part in (layout.q, layout.omega, layout.eta, layout.eta_dot):
        scale = np.abs(x_cvodes[part]).max()
        np.testing.assert_allclose(predicted[part], x_cvodes[part], atol=tolerance * scale)


@pytest.mark.slow
def test_closed_loop_slew_with_a_failure_during_the_run() -> None:
    """A 2 deg slew about z, predicted disturbance, CubeSat 5 lost at 80 s: its engine
    at zero from then on, every limit kept, the error back within 60 arcsec."""
    plant = build_model(load_problem())
    settings = NmpcSettings(horizon_steps=10, period_s=2.0, disturbance="model")
    controller = NmpcController(plant, settings)
    period = settings.period_s
    integrate = plant_step(plant, period)
    target = axis_angle_quaternion([0.0, 0.0, 1.0], math.radians(2.0))
    engines = controller.engines
    x = plant.initial_state()
    before, after, errors = [], [], []
    for k in range(150):
        if k == 40:
            limits = controller.engines.max_thrust_N.copy()
            limits[4] = 0.0
            controller.set_limits(limits)
        step = controller.step(k * period, x, target)
        (before if k < 40 else after).append(step)
        u = np.concatenate(
            [
                engines.torque_map @ step.thrust_N,
                np.array(plant.disturbance(k * period)).ravel(),
                engines.force_map @ step.thrust_N,
            ]
        )
        x = np.array(integrate(x0=x, p=u)["xf"]).ravel()
        errors.append(np.linalg.norm(attitude_error(target, x[plant.layout.q])))
    check_engines(before, engines, [])
    check_engines(after, controller.engines, [4])
    assert all(step.success for step in before + after)
    assert max(errors[-20:]) < math.radians(60.0 / 3600.0)
