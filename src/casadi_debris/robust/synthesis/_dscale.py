"""Fitting the D-scales of a D-K iteration with stable, minimum-phase transfer functions.

Each block but the last (whose scale is normalised to 1) gets a scalar
d_b(w); only |d_b(jw)| matters (a phase is a unitary factor). A plain
least-squares fit of the pointwise optimal d(w) stalls the iteration: d is
ill-defined where mu is far below its peak, and spans decades across the
grid. So the fit has two stages, both from one fixed start, with no choice
among local optima that a rounding-level change of the data could flip:

1. per block, a Gauss-Newton (trust-region) fit of log|D_b| to log d_b
   weighted by (mu / mu_peak)^4, starting from coincident pole/zero pairs
   log-spaced over the grid (|D_b| = constant, where the residual's gradient
   pulls each pair apart in the direction the data asks for);
2. a joint refinement of all blocks' D_b(s) = g prod (s + z_i) / (s + p_i)
   minimising the mean over frequency of log(sigma_max(D M D^-1) / mu), the
   loss of the fitted scaling against the optimal one, with its peak kept at
   or below the current mu peak; kept only if it lowers that loss.

Poles and zeros stay within the frequency grid, where the Riccati solves
remain well conditioned.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import control
import numpy as np
from scipy.optimize import least_squares, minimize

PEAK_PENALTY = 50.0
SHAPE_WEIGHT_POWER = 4
GAIN_MARGIN = 30.0  # log-gain bound beyond the data's range


def _log_magnitude(theta: np.ndarray, log_omega: np.ndarray, order: int) -> np.ndarray:
    """log|g prod (jw + z) / (jw + p)| for theta = (log g, log z, log p), shape (n_omega,)."""
    w2 = np.exp(2.0 * log_omega)[:, None]
    zeros2, poles2 = np.exp(2.0 * theta[1 : 1 + order]), np.exp(2.0 * theta[1 + order :])
    return theta[0] + 0.5 * np.sum(np.log(w2 + zeros2) - np.log(w2 + poles2), axis=1)


def _log_magnitude_jacobian(theta: np.ndarray, log_omega: np.ndarray, order: int) -> np.ndarray:
    w2 = np.exp(2.0 * log_omega)[:, None]
    zeros2, poles2 = np.exp(2.0 * theta[1 : 1 + order]), np.exp(2.0 * theta[1 + order :])
    return np.hstack(
        [np.ones((len(log_omega), 1)), zeros2 / (w2 + zeros2), -poles2 / (w2 + poles2)]
    )


def scaled_peaks(responses: np.ndarray, sizes: Sequence[int], magnitudes: np.ndarray) -> np.ndarray:
    """sigma_max of D M D^-1 per frequency, shape (n_omega,).

    Parameters
    ----------
    responses : ndarray, shape (n_omega, n, n)
    sizes : sequence of int
        Block sizes (sum n).
    magnitudes : ndarray, shape (n_omega, n_blocks - 1)
        |d_b(jw)| of every block but the last (whose scale is 1).
    """
    d = np.repeat(np.hstack([magnitudes, np.ones((len(magnitudes), 1))]), np.asarray(sizes), axis=1)
    return np.linalg.svd(d[:, :, None] * responses / d[:, None, :], compute_uv=False)[:, 0]


def _fit_block(
    log_omega: np.ndarray, log_d: np.ndarray, weight: np.ndarray, order: int
) -> np.ndarray:
    """Weighted log-magnitude fit of one block's scale: theta = (log g, log z, log p)."""
    low, high = float(log_omega[0]), float(log_omega[-1])
    centres = np.linspace(low, high, order + 2)[1:-1]
    gain = float(np.average(log_d, weights=weight))
    theta = np.concatenate([[gain], centres, centres])
    lower = np.concatenate([[float(np.min(log_d)) - GAIN_MARGIN], np.full(2 * order, low)])
    upper = np.concatenate([[float(np.max(log_d)) + GAIN_MARGIN], np.full(2 * order, high)])
    root = np.sqrt(weight)

    def residual(t: np.ndarray) -> np.ndarray:
        return root * (_log_magnitude(t, log_omega, order) - log_d)

    def jacobian(t: np.ndarray) -> np.ndarray:
        return root[:, None] * _log_magnitude_jacobian(t, log_omega, order)

    fit = least_squares(
        residual,
        theta,
        jac=jacobian,
        bounds=(lower, upper),
        method="trf",
        x_scale="jac",
    )
    return np.asarray(fit.x)


def fit_d_scales(
    omega: np.ndarray,
    responses: np.ndarray,
    mu: np.ndarray,
    scales: np.ndarray,
    sizes: Sequence[int],
    order: int,
) -> list[control.StateSpace]:
    """Stable minimum-phase SISO D_b(s) of the given order for every block but the last.

    Parameters
    ----------
    omega : ndarray, shape (n_omega,)
        Frequency grid [rad/s], increasing.
    responses : ndarray, shape (n_omega, n, n)
        Closed-loop response of the current iterate.
    mu : ndarray, shape (n_omega,)
        Its mu upper bound.
    scales : ndarray, shape (n_omega, n_blocks)
        Pointwise optimal d of each block (the last one's = 1), as
        :func:`casadi_debris.robust.mu.mu_upper_bound` returns them.
    sizes : sequence of int
        Block sizes (sum n), in the order of ``scales``.
    order : int
        Number of pole/zero pairs of each D_b (0: constants).

    Returns
    -------
    list of control.StateSpace
        D_b(s) for the first ``n_blocks - 1`` blocks, biproper, stable and
        minimum phase.
    """
    peak = float(np.max(mu))
    log_omega = np.log(omega)
    weight = (mu / peak) ** SHAPE_WEIGHT_POWER
    log_scales = np.log(scales[:, :-1])
    n_fit = log_scales.shape[1]
    thetas = [_fit_block(log_omega, log_scales[:, b], weight, order) for b in range(n_fit)]
    low, high = float(log_omega[0]), float(log_omega[-1])
    bounds = []
    for b in range(n_fit):
        bounds.append(
            (
                float(np.min(log_scales[:, b])) - GAIN_MARGIN,
                float(np.max(log_scales[:, b])) + GAIN_MARGIN,
            )
        )
        bounds += [(low, high)] * (2 * order)

    def cost(flat: np.ndarray) -> tuple[float, np.ndarray]:
        return _refinement_cost(flat, log_omega, responses, mu, sizes, order)

    start = np.concatenate(thetas)
    refined = minimize(cost, start, jac=True, method="L-BFGS-B", bounds=bounds).x
    flat = refined if cost(refined)[0] <= cost(start)[0] else start
    return [_transfer(t, order) for t in flat.reshape(n_fit, 1 + 2 * order)]


def _refinement_cost(
    flat: np.ndarray,
    log_omega: np.ndarray,
    responses: np.ndarray,
    mu: np.ndarray,
    sizes: Sequence[int],
    order: int,
) -> tuple[float, np.ndarray]:
    """Mean log loss of the fitted scaling plus the peak penalty, and its gradient.

    d log sigma_max(D M D^-1) / d log d_b = |u_b|^2 - |v_b|^2 (u, v the singular
    vectors, restricted to block b's channels): scaling block b by e^t multiplies
    its rows by e^t and its columns by e^-t.
    """
    parts = flat.reshape(-1, 1 + 2 * order)
    log_d = np.stack([_log_magnitude(t, log_omega, order) for t in parts], axis=1)
    d = np.repeat(np.hstack([np.exp(log_d), np.ones((len(log_d), 1))]), np.asarray(sizes), axis=1)
    u, sigma, vh = np.linalg.svd(d[:, :, None] * responses / d[:, None, :])
    peaks = sigma[:, 0]
    edges = np.cumsum([0, *sizes])
    u2, v2 = np.abs(u[:, :, 0]) ** 2, np.abs(vh[:, 0, :]) ** 2
    sensitivity = np.stack(
        [
            u2[:, a:b].sum(axis=1) - v2[:, a:b].sum(axis=1)
            for a, b in itertools.pairwise(edges[:-1])
        ],
        axis=1,
    )  # d log sigma / d log d_b, shape (n_omega, n_fit)
    peak = float(np.max(mu))
    top = int(np.argmax(peaks))
    excess = math.log(float(peaks[top]) / peak)
    value = float(np.mean(np.log(peaks / mu))) + PEAK_PENALTY * max(0.0, excess)
    weights = np.full(len(peaks), 1.0 / len(peaks))
    gradient = []
    for b, theta in enumerate(parts):
        jac = _log_magnitude_jacobian(theta, log_omega, order)
        grad = (weights * sensitivity[:, b]) @ jac
        if excess > 0:
            grad = grad + PEAK_PENALTY * sensitivity[top, b] * jac[top]
        gradient.append(grad)
    return value, np.concatenate(gradient)


def _transfer(theta: np.ndarray, order: int) -> control.StateSpace:
    """g prod (s + z_i) / (s + p_i) as a cascade of first-order sections.

    A cascade keeps every entry of the realisation of the size of a pole or a
    zero; the companion form of the product spans the polynomial coefficients
    (decades apart for roots spread over the grid) and spoils the Riccati
    solves of the K step.
    """
    system = control.ss([], [], [], [[math.exp(theta[0])]])
    for z, p in zip(np.exp(theta[1 : 1 + order]), np.exp(theta[1 + order :]), strict=True):
        system = control.ss([[-p]], [[1.0]], [[z - p]], [[1.0]]) * system
    return system


def inverse(system: control.StateSpace) -> control.StateSpace:
    """Inverse of a biproper square system (D invertible).

    Parameters
    ----------
    system : control.StateSpace

    Returns
    -------
    control.StateSpace
    """
    d_inv = np.linalg.inv(system.D)
    return control.ss(
        system.A - system.B @ d_inv @ system.C, system.B @ d_inv, -d_inv @ system.C, d_inv
    )
