"""Fitting the D-scale of a D-K iteration with a stable, minimum-phase transfer function.

For the {uncertainty (3 x 3), performance} structure the scaling is one
scalar d(w) on the uncertainty channels, and only |d(jw)| matters (a phase is
a unitary factor). A plain least-squares fit of the pointwise optimal d(w)
stalls the iteration: d is ill-defined where mu is far below its peak, and
spans decades across the grid. So the fit has two stages: a least-squares fit
of log|D| to log d weighted by (mu / mu_peak)^4, from interleaved pole/zero
starts, then a refinement of D(s) = g prod (s + z_i) / (s + p_i) minimising
the mean over frequency of log(sigma_max(D M D^-1) / mu), the loss of the
fitted scaling against the optimal one, with its peak kept at or below the
current mu peak. Poles and zeros stay in [1e-4, 100] rad/s, where the
Riccati solves remain well conditioned.
"""

from __future__ import annotations

import math

import control
import numpy as np
from scipy.optimize import minimize

ROOT_BOUNDS = (1e-4, 100.0)
PEAK_PENALTY = 50.0
SHAPE_WEIGHT_POWER = 4


def _magnitude(theta: np.ndarray, omega: np.ndarray, order: int) -> np.ndarray:
    gain = math.exp(theta[0])
    zeros, poles = np.exp(theta[1 : 1 + order]), np.exp(theta[1 + order :])
    s = 1j * omega[:, None]
    return gain * np.prod(np.abs((s + zeros) / (s + poles)), axis=1)


def scaled_peaks(responses: np.ndarray, n_delta: int, magnitude: np.ndarray) -> np.ndarray:
    """sigma_max of diag(d I, I) M diag(d^-1 I, I) per frequency, shape (n_omega,)."""
    scaled = responses.copy()
    scaled[:, :n_delta, n_delta:] *= magnitude[:, None, None]
    scaled[:, n_delta:, :n_delta] /= magnitude[:, None, None]
    return np.linalg.svd(scaled, compute_uv=False)[:, 0]


def fit_d_scale(
    omega: np.ndarray,
    responses: np.ndarray,
    mu: np.ndarray,
    optimal_scale: np.ndarray,
    n_delta: int,
    order: int,
) -> control.StateSpace:
    """Stable minimum-phase SISO D(s) of the given order for the uncertainty channels.

    Parameters
    ----------
    omega : ndarray, shape (n_omega,)
    responses : ndarray, shape (n_omega, n, n)
        Closed-loop response of the current iterate.
    mu : ndarray, shape (n_omega,)
        Its mu upper bound.
    optimal_scale : ndarray, shape (n_omega,)
        Pointwise optimal d of the uncertainty block (performance block's = 1),
        as :func:`casadi_debris.robust.mu.mu_upper_bound` returns it.
    n_delta : int
        Size of the uncertainty block (its channels come first).
    order : int
        Number of pole/zero pairs (0: a constant).

    Returns
    -------
    control.StateSpace
        D(s), biproper, stable and minimum phase.
    """
    peak = float(np.max(mu))
    log_low, log_high = (math.log(b) for b in ROOT_BOUNDS)
    log_d = np.log(optimal_scale)
    bounds = [(float(np.min(log_d)) - 30, float(np.max(log_d)) + 30)]
    bounds += [(log_low, log_high)] * (2 * order)
    weight = (mu / peak) ** SHAPE_WEIGHT_POWER

    def shape_error(theta: np.ndarray) -> float:
        return float(np.sum(weight * (np.log(_magnitude(theta, omega, order)) - log_d) ** 2))

    def cost(theta: np.ndarray) -> float:
        peaks = scaled_peaks(responses, n_delta, _magnitude(theta, omega, order))
        loss = float(np.mean(np.log(peaks / mu)))
        return loss + PEAK_PENALTY * max(0.0, math.log(float(np.max(peaks)) / peak))

    span = np.log(omega[[0, -1]])
    centres = np.linspace(span[0], span[1], order + 2)[1:-1]
    gap = (span[1] - span[0]) / (2 * order + 2) if order else 0.0
    starts = []
    for direction in (1.0, -1.0):  # |D| falling (zeros above poles) or rising
        poles = np.clip(centres, log_low, log_high)
        zeros = np.clip(centres + direction * gap, log_low, log_high)
        theta = np.concatenate([[0.0], zeros, poles])
        theta[0] = float(
            np.average(log_d - np.log(_magnitude(theta, omega, order)), weights=weight)
        )
        starts.append(minimize(shape_error, theta, method="L-BFGS-B", bounds=bounds).x)
    theta = min(starts, key=cost)
    refined = minimize(cost, theta, method="L-BFGS-B", bounds=bounds).x
    if cost(refined) <= cost(theta):
        theta = refined

    gain = math.exp(theta[0])
    transfer = control.tf([gain], [1.0])
    for z, p in zip(np.exp(theta[1 : 1 + order]), np.exp(theta[1 + order :]), strict=True):
        transfer = transfer * control.tf([1.0, z], [1.0, p])
    return control.ss(transfer)


def inverse(system: control.StateSpace) -> control.StateSpace:
    """Inverse of a biproper square system (D invertible)."""
    d_inv = np.linalg.inv(system.D)
    return control.ss(
        system.A - system.B @ d_inv @ system.C, system.B @ d_inv, -d_inv @ system.C, d_inv
    )
