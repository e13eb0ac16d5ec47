"""Closed-loop runs with the environment torques on, checked through the numeric path.

The step evaluates the torques inside its compiled CasADi graph from the
state's quaternion; here they are recomputed from the logged attitudes with
scipy's rotations, the numeric orbit and the numeric torque functions, and the
change of the angular momentum is checked against the torques that acted.
"""

from __future__ import annotations

import dataclasses
import json
import math

import control
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from casadi_debris.config import ENVIRONMENT_TORQUES, Problem, default_controller_path, load_problem
from casadi_debris.dynamics import Model, build_model
from casadi_debris.environment import CircularOrbit, EnvironmentTorques, gravity_gradient_torque
from casadi_debris.guidance import sample_reference
from casadi_debris.robust.plant import Controller
from casadi_debris.simulation import ClosedLoopResult, LoopSettings, simulate_closed_loop

RUN_S = 120.0


def _with_torques(problem: Problem, torques: tuple[str, ...]) -> Problem:
    environment = dataclasses.replace(problem.environment, torques=torques)
    return dataclasses.replace(problem, environment=environment)


@pytest.fixture(scope="module")
def controller() -> control.StateSpace:
    return Controller.from_dict(json.loads(default_controller_path().read_text())).reduced


def _run(problem: Problem, controller: control.StateSpace, start: Rotation) -> tuple:
    model = build_model(problem)
    period = 1.0 / problem.simulation.control_rate_hz
    times = period * np.arange(round(RUN_S / period) + 1)
    reference = sample_reference(times)
    q = start.as_quat()[[3, 0, 1, 2]]
    reference = dataclasses.replace(reference, quaternion_BN=np.tile(q, (len(times), 1)))
    return model, simulate_closed_loop(model, controller, reference)


def _sine(problem: Problem, time_s: np.ndarray) -> np.ndarray:
    d = problem.disturbance
    omega = 2 * math.pi / (60.0 * d.period_min)
    phase = np.radians(d.phase_deg)
    return 1e-3 * d.amplitude_mNm * np.sin(omega * time_s[:, None] + phase)


def _attitudes(model: Model, result: ClosedLoopResult) -> Rotation:
    q = result.state[:-1, model.layout.q]
    return Rotation.from_quat(q[:, [1, 2, 3, 0]])


@pytest.fixture(scope="module")
def gravity_run(controller) -> tuple[Problem, Model, ClosedLoopResult]:
    problem = _with_torques(load_problem(), ("gravity_gradient",))
    start = Rotation.from_euler("xyz", [20.0, -35.0, 50.0], degrees=True)
    model, result = _run(problem, controller, start)
    return problem, model, result


def test_gravity_gradient_series_is_the_numeric_torque_on_the_run(gravity_run) -> None:
    problem, model, result = gravity_run
    orbit = CircularOrbit.from_problem(problem)
    t = result.time_s[:-1]
    r_body = _attitudes(model, result).inv().apply(orbit.position_m(t))
    inertia = model.geometry.inertia_total_kgm2  # the nominal parameters' rigid inertia
    expected = np.array([gravity_gradient_torque(inertia, r) for r in r_body])
    environment = result.disturbance_Nm - _sine(problem, t)
    np.testing.assert_allclose(environment, expected, rtol=1e-9, atol=1e-12)
    # At this attitude the gravity gradient is a sizeable fraction of the paper's sine.
    assert np.abs(expected).max() > 0.1e-3


def test_the_torque_acts_on_the_body(gravity_run) -> None:
    # Angular momentum about the CoG, inertial axes: its change over the run is the
    # integral of R (applied + disturbance) dt, the applied and environment torques
    # held over each period, the sine by the trapezoid rule.
    problem, model, result = gravity_run
    p = model.nominal_parameters
    h = np.array([np.asarray(model.momenta(x, p)[1]).ravel() for x in result.state])
    rotations = _attitudes(model, result)
    dt = result.control_period_s
    sine = _sine(problem, result.time_s[:-1])
    held = rotations.apply(result.torque_Nm + result.disturbance_Nm - sine) * dt
    sine_n = rotations.apply(sine)
    trapezoid = 0.5 * (sine_n[:-1] + sine_n[1:]) * dt
    change = h[-2] - h[0]
    impulse = held[:-1].sum(axis=0) + trapezoid.sum(axis=0)
    scale = np.abs(result.disturbance_Nm).max() * RUN_S
    np.testing.assert_allclose(change, impulse, atol=1e-6 * scale)
    # Without the gravity gradient's impulse the balance fails by far more.
    gravity = rotations.apply(result.disturbance_Nm - sine)[:-1].sum(axis=0) * dt
    assert np.abs(change - (impulse - gravity)).max() > 1000 * 1e-6 * scale


def test_every_torque_on_matches_the_numeric_model(controller) -> None:
    problem = _with_torques(load_problem(), ENVIRONMENT_TORQUES)
    start = Rotation.from_euler("xyz", [5.0, 10.0, -15.0], degrees=True)
    model, result = _run(problem, controller, start)
    environment = EnvironmentTorques.of(problem, model.geometry)
    t = result.time_s[:-1]
    dcm = _attitudes(model, result).as_matrix()
    inertia = model.geometry.inertia_total_kgm2
    step = 50  # every 5 s
    expected = np.array([environment.total(t[k], dcm[k], inertia) for k in range(0, len(t), step)])
    got = (result.disturbance_Nm - _sine(problem, t))[::step]
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-13)
    # The loop answered: the error stayed bounded (the step of the torques at t = 0 is a kick).
    assert result.summary().max_error_arcsec < 600.0


def test_compiled_steps_of_problems_changed_in_memory_are_told_apart(controller) -> None:
    # One file, one name: the environment and the sine decide the compiled step too.
    from casadi_debris.allocation import Allocator
    from casadi_debris.simulation import _closed_loop as closed_loop
    from casadi_debris.simulation import discretize_controller

    paper = load_problem()
    silent = dataclasses.replace(paper.disturbance, amplitude_mNm=np.zeros(3))
    variants = [
        paper,
        _with_torques(paper, ("gravity_gradient",)),
        _with_torques(paper, ENVIRONMENT_TORQUES),
        dataclasses.replace(paper, disturbance=silent),
    ]
    discrete = discretize_controller(controller, 0.1)
    keys = set()
    for problem in variants:
        model = build_model(problem)
        polytope = Allocator.from_problem(problem, model.geometry).authority_polytope()
        keys.add(closed_loop._jit_key(model, discrete, polytope, 4, 1000))
    assert len(keys) == len(variants)


@pytest.mark.slow
def test_the_compiled_step_carries_the_environment(controller) -> None:
    problem = _with_torques(load_problem(), ENVIRONMENT_TORQUES)
    model = build_model(problem)
    reference = sample_reference(0.1 * np.arange(301))
    virtual = simulate_closed_loop(model, controller, reference)
    compiled = simulate_closed_loop(model, controller, reference, settings=LoopSettings(jit=True))
    assert compiled.compiled_step
    np.testing.assert_allclose(compiled.state, virtual.state, rtol=0, atol=1e-12)
    np.testing.assert_allclose(compiled.disturbance_Nm, virtual.disturbance_Nm, atol=1e-15)
