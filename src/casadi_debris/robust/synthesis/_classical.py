"""Classical attitude controllers to fly beside the μ design: per-axis PD and LQG.

Both are designed on the rigid body (the full rigid inertia's diagonal, arrays included)
and use the controller file's convention (:mod:`casadi_debris.robust.plant`):
input the attitude error ``e = reference - measured`` [deg] per axis, output the torque
demand [mNm], ``u = K e``, continuous time (the closed loop samples it at its control
rate).

- **PD / PID** (per axis): ``K(s) = kp + kd s / (s / w_f + 1) + ki / s``, the derivative
  filtered at ``w_f``, gains placing the rigid loop's poles (filter left out) at
  ``(s + a w)(s^2 + 2 zeta w s + w^2)``: bandwidth ``w``, damping ``zeta``, the
  integrator's pole ``a w`` (``a = 0``: PD, no integral action, so a steady disturbance
  leaves a steady error).
- **LQG** (per axis): LQR on ``x = [angle, rate]``, ``J_i x'' = tau``, weighted by
  Bryson's rule (``Q = diag(1/angle_max^2, 0)``, ``R = 1/torque_max^2``), with a
  steady-state Kalman filter of the star-tracker angle (process noise: a torque of the
  disturbance's amplitude; measurement noise ``measurement_noise_rad``). By the
  separation principle its rigid closed-loop poles are those of the regulator and the
  filter together.

The flexible modes are not in either design: check them in closed loop (``design``'s
margins over sampled plants and corner campaigns do).
"""

from __future__ import annotations

import math
from typing import Literal

import control
import numpy as np

from casadi_debris.robust.plant import Controller
from casadi_debris.units import DEG_PER_RAD, MNM_PER_NM

ClassicalMethod = Literal["pd", "pid", "lqr"]
CLASSICAL_METHODS: tuple[ClassicalMethod, ...] = ("pd", "pid", "lqr")
DEFAULT_DAMPING = 0.7
DEFAULT_FILTER_FACTOR = 10.0
"""The derivative filter's corner over the bandwidth."""
DEFAULT_INTEGRAL_FACTOR = 0.5
"""A PID's integrator pole over the bandwidth."""
# deg -> rad at the input, N m -> mN m at the output.
_UNITS = MNM_PER_NM / DEG_PER_RAD


def pid_controller(
    inertia_kgm2: np.ndarray,
    bandwidth_rad_s: float,
    *,
    damping: float = DEFAULT_DAMPING,
    filter_factor: float = DEFAULT_FILTER_FACTOR,
    integral_factor: float = 0.0,
) -> control.StateSpace:
    """Per-axis PD, or PID, with a filtered derivative: attitude error [deg] -> torque [mNm].

    Gains per axis ``i`` place the rigid loop's poles (derivative filter left out) at
    ``(s + a w)(s^2 + 2 zeta w s + w^2)``, ``a`` the ``integral_factor``:
    ``kp = J_i w^2 (1 + 2 zeta a)``, ``kd = J_i w (2 zeta + a)``, ``ki = J_i a w^3``;
    ``a = 0`` is the PD.

    Parameters
    ----------
    inertia_kgm2 : ndarray, shape (3, 3)
        Rigid inertia; its diagonal scales each axis' gains.
    bandwidth_rad_s : float
        ``w``.
    damping : float
        ``zeta``.
    filter_factor : float
        The derivative filter's corner ``w_f = filter_factor * w``.
    integral_factor : float
        ``a``: the integrator's pole over ``w`` (0: no integral action).

    Returns
    -------
    control.StateSpace
        3 inputs, 3 outputs; a filter state per axis, and an integrator per axis for a PID.
    """
    inertia = np.diag(np.asarray(inertia_kgm2, dtype=float)) * _UNITS
    w, a = bandwidth_rad_s, integral_factor
    kp = inertia * w**2 * (1.0 + 2.0 * damping * a)
    kd = inertia * w * (2.0 * damping + a)
    corner = filter_factor * w
    # kd s / (s / wf + 1) = kd wf - kd wf^2 / (s + wf): a state x' = -wf x + e.
    pd = control.ss(
        -corner * np.eye(3), np.eye(3), np.diag(-kd * corner**2), np.diag(kp + kd * corner)
    )
    if a == 0.0:
        return pd
    integral = control.ss(
        np.zeros((3, 3)), np.eye(3), np.diag(inertia * a * w**3), np.zeros((3, 3))
    )
    return control.parallel(pd, integral)


def rigid_axis(inertia_kgm2: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``A, B, C`` of one rigid axis: state ``[angle, rate]``, input torque, angle measured."""
    return (
        np.array([[0.0, 1.0], [0.0, 0.0]]),
        np.array([[0.0], [1.0 / inertia_kgm2]]),
        np.array([[1.0, 0.0]]),
    )


def lqg_controller(
    inertia_kgm2: np.ndarray,
    angle_max_rad: np.ndarray,
    torque_max_Nm: np.ndarray,
    disturbance_Nm: np.ndarray,
    measurement_noise_rad: float,
) -> control.StateSpace:
    """Per-axis LQR with a steady-state Kalman filter, attitude error [deg] -> torque [mNm].

    Parameters
    ----------
    inertia_kgm2 : ndarray, shape (3, 3)
    angle_max_rad, torque_max_Nm, disturbance_Nm : ndarray, shape (3,)
        Bryson's weights per axis (the error one accepts, the torque one has) and the
        process noise's size.
    measurement_noise_rad : float
        Standard deviation of the measured angle.

    Returns
    -------
    control.StateSpace
        Six states (estimated angle and rate per axis), 3 inputs, 3 outputs.
    """
    inertia = np.diag(np.asarray(inertia_kgm2, dtype=float))
    blocks = []
    for i in range(3):
        a, b, c = rigid_axis(float(inertia[i]))
        # Only the ratios of the weights matter; posed as ratios, the Riccati solvers
        # see numbers of order one instead of 1e-10.
        angle_weight = (torque_max_Nm[i] / angle_max_rad[i]) ** 2
        gain, _, _ = control.lqr(a, b, np.diag([angle_weight, 0.0]), 1.0)
        process = (disturbance_Nm[i] / measurement_noise_rad) ** 2
        observer, _, _ = control.lqe(a, b, c, process, 1.0)
        # The measured deviation is -e: x_hat' = (A - BK - LC) x_hat - L e, u = -K x_hat.
        blocks.append(
            control.ss(a - b @ gain - observer @ c, -observer / DEG_PER_RAD, -gain * MNM_PER_NM, 0)
        )
    return control.append(*blocks)


def classical_record(
    method: ClassicalMethod,
    inertia_kgm2: np.ndarray,
    *,
    bandwidth_rad_s: float,
    angle_max_rad: np.ndarray,
    torque_max_Nm: np.ndarray,
    disturbance_Nm: np.ndarray,
    measurement_noise_rad: float,
    plant_sha256: str,
) -> Controller:
    """A PD or LQG controller as a controller file's record (no μ bookkeeping).

    The arguments are those of :func:`pid_controller` (``bandwidth_rad_s``) and
    :func:`lqg_controller` (the rest); ``plant_sha256`` binds it to its problem.
    """
    if method in ("pd", "pid"):
        integral = DEFAULT_INTEGRAL_FACTOR if method == "pid" else 0.0
        system = pid_controller(inertia_kgm2, bandwidth_rad_s, integral_factor=integral)
        details: dict[str, object] = {"method": method, "bandwidth_rad_s": bandwidth_rad_s,
                   "damping": DEFAULT_DAMPING, "filter_factor": DEFAULT_FILTER_FACTOR,
                   "integral_factor": integral}  # fmt: skip
    else:
        system = lqg_controller(
            inertia_kgm2, angle_max_rad, torque_max_Nm, disturbance_Nm, measurement_noise_rad
        )
        details = {
            "method": "lqr",
            "angle_max_deg": (np.asarray(angle_max_rad) * DEG_PER_RAD).tolist(),
            "torque_max_mNm": (np.asarray(torque_max_Nm) * MNM_PER_NM).tolist(),
            "process_noise_torque_mNm": (np.asarray(disturbance_Nm) * MNM_PER_NM).tolist(),
            "measurement_noise_arcsec": math.degrees(measurement_noise_rad) * 3600.0,
        }
    return Controller(
        reduced=system,
        full=None,
        mu_peak=None,
        mu_peak_reduced=None,
        problem_sha256=plant_sha256,
        seed=0,
        details=details,
    )
