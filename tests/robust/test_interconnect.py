"""The generalised plant closes into the paper's four-block problem."""

from __future__ import annotations

import control
import numpy as np
import pytest

from casadi_debris.dynamics import build_model, linearize
from casadi_debris.robust.plant import frequency_response, generalized_plant, performance_weights


@pytest.fixture(scope="module")
def setup(problem):
    model = build_model(problem, modes="first")
    plant = linearize(model, sensor=True, units="deg_mNm")
    weight = control.append(*[control.ss(control.tf([0.3, 0.6], [1.0, 2.0]))] * 3)
    weights = performance_weights(problem)
    # a simple stabilising PD-like controller with roll-off, per axis
    controller = control.append(
        *[control.ss(control.tf([k * 20.0, k * 0.4], [1.0, 2.0])) for k in (300.0, 200.0, 150.0)]
    )
    return plant, weight, weights, controller


def test_shape_and_names(setup):
    plant, weight, weights, _ = setup
    p = generalized_plant(plant, weight, weights)
    assert p.system.ninputs == 12 and p.system.noutputs == 12
    assert p.system.input_labels[:3] == ["w_delta[0]", "w_delta[1]", "w_delta[2]"]
    assert p.system.output_labels[-3:] == ["e[0]", "e[1]", "e[2]"]
    assert p.blocks == (3, 6)


def test_closed_loop_is_the_four_block_problem(setup):
    plant, weight, weights, controller = setup
    p = generalized_plant(plant, weight, weights)
    closed = p.system.lft(controller, 3, 3)
    omega = np.array([0.003, 0.05, 0.4, 3.0])
    m = frequency_response(closed, omega)
    g = frequency_response(plant, omega)
    k = frequency_response(controller, omega)
    w_resp = frequency_response(weight, omega)
    we = frequency_response(weights.error, omega)
    wu = frequency_response(weights.control_effort, omega)
    ve, vu, vd = weights.error_scaling, weights.control_scaling, weights.disturbance_scaling
    eye = np.eye(3)
    for i in range(len(omega)):
        s = np.linalg.inv(eye + g[i] @ k[i])  # output sensitivity, u = K e, e = r - y
        si = np.linalg.inv(eye + k[i] @ g[i])  # input sensitivity
        left = np.block(
            [[we[i] @ np.linalg.inv(ve), 0 * eye], [0 * eye, wu[i] @ np.linalg.inv(vu)]]
        )
        four = np.block([[s, -s @ g[i]], [k[i] @ s, -k[i] @ s @ g[i]]])
        right = np.block([[ve, 0 * eye], [0 * eye, vd]])
        # State-space and matrix evaluations of a stiff loop agree to ~1e-6 of its size.
        expected = left @ four @ right
        tol = 1e-5 * np.linalg.norm(expected, 2)
        np.testing.assert_allclose(m[i, 3:, 3:], expected, rtol=0, atol=tol)
        # uncertainty channel: z_delta <- w_delta is -T_i W (input complementary sensitivity)
        expected = -(eye - si) @ w_resp[i]
        np.testing.assert_allclose(
            m[i, :3, :3], expected, rtol=0, atol=1e-5 * np.linalg.norm(expected, 2)
        )
