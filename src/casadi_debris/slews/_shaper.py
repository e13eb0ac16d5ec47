"""Zero-vibration input shaping of a piecewise-constant control.

``flexible_method="shaper"`` (and the fallback when IPOPT fails on the modal
OCP, said so in ``settings["flexible_method"]``) keeps the optimal rigid
profile and passes it through the cascaded zero-vibration input shaper
(:func:`zero_vibration_shaper`); it lengthens the slew by the shaper's length
(1.38 s for the paper's arrays); fuel-optimal slews give the rigid problem that
much less time. The modal OCP (:mod:`casadi_debris.slews._modal_window`) starts
from the shaped rigid optimum too.
"""

from __future__ import annotations

import math

import numpy as np

from casadi_debris.dynamics import Model, linearize


def zero_vibration_shaper(
    model: Model, parameters: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cascaded zero-vibration (ZV) input shaper for every array mode of a model.

    For a mode of natural frequency omega_n and damping zeta (poles of the
    model linearised at rest, :func:`casadi_debris.dynamics`) the ZV
    shaper (Singer & Seering, J. Dyn. Sys. Meas. Control 112, 1990) is two
    impulses

        A_1 = 1 / (1 + K) at t = 0,   A_2 = K / (1 + K) at t = pi / omega_d,
        K = exp(-zeta pi / sqrt(1 - zeta^2)),  omega_d = omega_n sqrt(1 - zeta^2);

    a linear mode driven by the shaped input is left at rest after the last
    impulse. Cascading one shaper per mode (convolving the impulse trains)
    cancels them all; the amplitudes are positive and sum to one, so a shaped
    torque or thrust stays within its bounds and keeps its integral.

    Returns
    -------
    times_s, amplitudes : ndarray, shape (2**m,)
        Impulse times (ascending, from 0) and amplitudes.
    frequencies_rad_s : ndarray, shape (m,)
        The natural frequencies shaped.
    """
    poles = np.linalg.eigvals(linearize(model, parameters).A)
    oscillatory = poles[poles.imag > 1e-9]
    times, amplitudes = np.zeros(1), np.ones(1)
    for pole in oscillatory:
        natural = abs(pole)
        zeta = -pole.real / natural
        k = math.exp(-zeta * math.pi / math.sqrt(1.0 - zeta**2))
        delay = math.pi / pole.imag
        times = np.concatenate([times, times + delay])
        amplitudes = np.concatenate([amplitudes / (1 + k), amplitudes * k / (1 + k)])
    order = np.argsort(times)
    return times[order], amplitudes[order], np.sort(np.abs(oscillatory))


def held(knots_s: np.ndarray, controls: np.ndarray, times_s: np.ndarray) -> np.ndarray:
    """Piecewise-constant control at ``times_s``: ``controls[k]`` on [knots[k], knots[k + 1]).

    Zero before the first knot and from the last one on; shape (len(times_s), n_u).
    """
    index = np.searchsorted(knots_s, times_s, side="right") - 1
    inside = (index >= 0) & (index < len(controls))
    values = np.zeros((len(times_s), controls.shape[1]))
    values[inside] = controls[index[inside]]
    return values


def shape(
    knots_s: np.ndarray, controls: np.ndarray, times_s: np.ndarray, amplitudes: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Convolve a piecewise-constant control with an impulse train.

    ``u_shaped(t) = sum_i A_i u(t - t_i)`` with u held at ``controls[k]`` on
    [knots[k], knots[k + 1]) and zero outside. Returns the new knots and the
    control on each new interval (breaks closer than 1 microsecond merged).
    """
    knots = np.unique(np.concatenate([knots_s + t for t in times_s]))
    knots = knots[np.concatenate([[True], np.diff(knots) > 1e-6])]
    middles = 0.5 * (knots[:-1] + knots[1:])
    shaped = sum(
        a * held(knots_s, controls, middles - t) for t, a in zip(times_s, amplitudes, strict=True)
    )
    return knots, shaped
