"""Attitude estimation: a multiplicative extended Kalman filter (MEKF), symbolic.

The filter of Lefferts, Markley and Shuster (1982), as written in Crassidis and
Junkins, *Optimal Estimation of Dynamic Systems* (2nd ed., Table 7.1), at the
control rate. Its state is the attitude estimate q (scalar first, B to N), the
gyro-bias estimate b [rad/s] and the 6 x 6 covariance P of the error state
``dx = [dtheta, db]`` with ``q = q_hat (x) [1, dtheta / 2]``.

Each control period, with the gyro reading ``w~`` and (when ``valid``) the
star tracker's quaternion ``q_m``:

1. update: ``r = 2 vec(q_hat^-1 (x) q_m)`` (short way round),
   ``K = P H^T (H P H^T + R)^-1`` with ``H = [I 0]``, ``R = sigma_st^2 I``;
   ``dx = K r``; ``q_hat <- q_hat (x) [1, dtheta / 2]`` normalised,
   ``b <- b + db``; ``P <- (I - K H) P (I - K H)^T + K R K^T`` (Joseph form);
2. propagate over h with ``w = w~ - b`` held: ``q_hat <- q_hat (x) exp(w h / 2)``;
   ``P <- Phi P Phi^T + Q`` with ``Phi = [[I - [w x] h, -I h], [0, I]]`` and
   Farrenkopf's ``Q = [[sv^2 h + su^2 h^3 / 3, -su^2 h^2 / 2], [., su^2 h]]``
   (``sv`` the angle random walk [rad/sqrt(s)], ``su`` the rate random walk
   [rad/s/sqrt(s)]).

The controller reads the updated attitude of step 1. The noise variances come
in as inputs (one compiled step for every noise level).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from casadi_debris.dynamics import attitude_error_vector, quaternion_product

STATE_SIZE = 4 + 3 + 36
# Keeps |w| > 0 in the quaternion exponential without changing any rate that matters.
_RATE_FLOOR_SQ = 1e-40


@dataclass(frozen=True)
class MekfState:
    """Slices of the filter's state vector (size :data:`STATE_SIZE`)."""

    QUATERNION = slice(0, 4)
    BIAS = slice(4, 7)
    COVARIANCE = slice(7, 43)


def initial_filter_state(
    quaternion: np.ndarray, attitude_sigma_rad: float, bias_sigma_rad_s: float
) -> np.ndarray:
    """Filter state at t = 0: the given attitude, zero bias, diagonal covariance, shape (43,)."""
    covariance = np.diag([attitude_sigma_rad**2] * 3 + [bias_sigma_rad_s**2] * 3)
    return np.concatenate([quaternion, np.zeros(3), covariance.ravel(order="F")])


def rotate_by_vector(q: ca.SX, rotation_rad: ca.SX) -> ca.SX:
    """``q (x) exp(rotation / 2)``: q turned by the rotation vector (body axes), exact."""
    angle = ca.sqrt(ca.sumsqr(rotation_rad) + _RATE_FLOOR_SQ)
    half = ca.vertcat(ca.cos(angle / 2), ca.sin(angle / 2) / angle * rotation_rad)
    return quaternion_product(q, half)


def mekf_step() -> ca.Function:
    """``mekf(s, w_m, q_m, valid, noise, h) -> (s_next, q_post)``.

    Inputs: s the filter state (43); ``w_m`` the gyro reading [rad/s] (3);
    ``q_m`` the star tracker's quaternion (4); ``valid`` 1 when it is a new
    reading, else 0; ``noise`` = [sigma_st^2 (rad^2), sv^2 (rad^2/s),
    su^2 (rad^2/s^3)]; h the period [s]. Outputs: the prior state of the next
    period and the updated attitude of this one.
    """
    s = ca.SX.sym("s", STATE_SIZE)
    w_m = ca.SX.sym("w_m", 3)
    q_m = ca.SX.sym("q_m", 4)
    valid = ca.SX.sym("valid")
    noise = ca.SX.sym("noise", 3)
    h = ca.SX.sym("h")
    q, b = s[MekfState.QUATERNION], s[MekfState.BIAS]
    p = ca.reshape(s[MekfState.COVARIANCE], 6, 6)
    r_var, v_var, u_var = noise[0], noise[1], noise[2]

    # Update.
    residual = attitude_error_vector(q, q_m)
    innovation = p[0:3, 0:3] + r_var * ca.SX.eye(3)
    gain = p[:, 0:3] @ ca.inv(innovation)
    correction = valid * (gain @ residual)
    q_post = q + 0.5 * quaternion_product(q, ca.vertcat(0, correction[0:3]))
    q_post = q_post / ca.norm_2(q_post)
    b_post = b + correction[3:6]
    h_matrix = ca.horzcat(ca.SX.eye(3), ca.SX.zeros(3, 3))
    joseph = ca.SX.eye(6) - gain @ h_matrix
    p_updated = joseph @ p @ joseph.T + r_var * (gain @ gain.T)
    p_post = ca.if_else(valid > 0.5, p_updated, p)

    # Propagation.
    rate = w_m - b_post
    q_next = rotate_by_vector(q_post, rate * h)
    phi = ca.vertcat(
        ca.horzcat(ca.SX.eye(3) - ca.skew(rate) * h, -h * ca.SX.eye(3)),
        ca.horzcat(ca.SX.zeros(3, 3), ca.SX.eye(3)),
    )
    q11 = (v_var * h + u_var * h**3 / 3) * ca.SX.eye(3)
    q12 = -u_var * h**2 / 2 * ca.SX.eye(3)
    q22 = u_var * h * ca.SX.eye(3)
    process = ca.vertcat(ca.horzcat(q11, q12), ca.horzcat(q12, q22))
    p_next = phi @ p_post @ phi.T + process
    p_next = 0.5 * (p_next + p_next.T)
    s_next = ca.vertcat(q_next, b_post, ca.vec(p_next))
    return ca.Function(
        "mekf",
        [s, w_m, q_m, valid, noise, h],
        [s_next, q_post],
        ["s", "w_m", "q_m", "valid", "noise", "h"],
        ["s_next", "q_post"],
    )
