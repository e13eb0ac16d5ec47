"""PD and LQG attitude controllers against their closed-form closed loops."""

from __future__ import annotations

import math

import control
import numpy as np
import pytest
from scipy.linalg import solve_continuous_are

from casadi_debris.robust.synthesis import lqg_controller, pid_controller, rigid_axis

INERTIA = np.diag([677.3, 450.8, 291.0])
DEG_PER_RAD = 180.0 / math.pi


def _rigid_plant(axis: int) -> control.TransferFunction:
    """Torque [mNm] -> attitude [deg] of one rigid axis."""
    return control.tf([DEG_PER_RAD * 1e-3], [INERTIA[axis, axis], 0.0, 0.0])


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_pd_closes_the_rigid_loop_on_its_analytic_polynomial(axis: int) -> None:
    w, zeta, factor = 0.028, 0.7, 10.0
    controller = pid_controller(INERTIA, w, damping=zeta, filter_factor=factor)
    loop = _rigid_plant(axis) * control.ss2tf(controller[axis, axis])
    poles = np.sort_complex(control.poles(control.feedback(loop, 1)))
    wf = factor * w
    # s^2 (s + wf) + w^2 (s + wf) + 2 zeta w wf s = 0
    expected = np.sort_complex(np.roots([1.0, wf, w**2 + 2 * zeta * w * wf, w**2 * wf]))
    np.testing.assert_allclose(poles, expected, rtol=1e-6)
    # Diagonal: no axis drives another.
    assert controller.nstates == 3
    gain = control.dcgain(controller)
    assert np.count_nonzero(np.abs(gain - np.diag(np.diag(gain))) > 0) == 0


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_pid_closes_the_rigid_loop_on_its_analytic_polynomial(axis: int) -> None:
    w, zeta, factor, a = 0.028, 0.7, 10.0, 0.5
    controller = pid_controller(INERTIA, w, damping=zeta, filter_factor=factor, integral_factor=a)
    loop = _rigid_plant(axis) * control.ss2tf(controller[axis, axis])
    poles = np.sort_complex(control.poles(control.feedback(loop, 1)))
    kp, kd, ki, wf = w**2 * (1 + 2 * zeta * a), w * (2 * zeta + a), a * w**3, factor * w
    # s^3 (s + wf) + kp s (s + wf) + kd wf s^2 + ki (s + wf) = 0
    expected = np.roots([1.0, wf, kp + kd * wf, kp * wf + ki, ki * wf])
    np.testing.assert_allclose(poles, np.sort_complex(expected), rtol=1e-6)
    # Without the filter the poles are the ones placed: (s + a w)(s^2 + 2 zeta w s + w^2).
    far = pid_controller(INERTIA, w, damping=zeta, filter_factor=1e3, integral_factor=a)
    loop = control.ss(_rigid_plant(axis)) * control.minreal(far[axis, axis], verbose=False)
    poles = np.linalg.eigvals(control.feedback(loop, 1).A)
    slow = np.sort_complex(poles[np.abs(poles) < 10 * w])  # all but the filter's far pole
    placed = np.sort_complex(np.roots(np.polymul([1.0, a * w], [1.0, 2 * zeta * w, w**2])))
    np.testing.assert_allclose(slow, placed, rtol=1e-2)


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_lqg_poles_are_the_regulators_and_the_filters(axis: int) -> None:
    """Separation: the closed loop's poles are eig(A - BK) and eig(A - LC), with K and L
    from scipy's Riccati solver on Bryson's unscaled weights."""
    angle = np.radians([0.6, 0.6, 0.6])
    torque = np.array([4.6e-3, 2.0e-3, 4.3e-3])
    disturbance = np.array([0.7e-3, 0.7e-3, 0.7e-3])
    noise = math.radians(5.0 / 3600.0)
    controller = lqg_controller(INERTIA, angle, torque, disturbance, noise)
    loop = _rigid_plant(axis) * control.ss2tf(controller[axis, axis])
    poles = np.sort_complex(control.poles(control.feedback(loop, 1)))
    a, b, c = rigid_axis(INERTIA[axis, axis])
    q, r = np.diag([1.0 / angle[axis] ** 2, 0.0]), np.array([[1.0 / torque[axis] ** 2]])
    gain = np.linalg.solve(r, b.T @ solve_continuous_are(a, b, q, r))
    w, v = b @ b.T * disturbance[axis] ** 2, np.array([[noise**2]])
    observer = solve_continuous_are(a.T, c.T, w, v) @ c.T / noise**2
    expected = np.sort_complex(
        np.concatenate([np.linalg.eigvals(a - b @ gain), np.linalg.eigvals(a - observer @ c)])
    )
    np.testing.assert_allclose(poles, expected, rtol=1e-6)
    assert np.all(poles.real < 0)
