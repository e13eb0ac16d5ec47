"""Weights of the four-block mixed-sensitivity design (paper, Section III.C) and the
uncertainty weight W fitted to the sampled relative errors (the ``ucover`` equivalent).

All in the paper's design units: attitude in deg, torque in mNm.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import control
import numpy as np
import numpy.typing as npt
from scipy.optimize import minimize

from casadi_debris.config import Problem
from casadi_debris.errors import SynthesisError

W_ORDER = 2
# Damping ratios a fitted pole or zero pair may take.
MIN_DAMPING, MAX_DAMPING = 1e-4, 1e3
# Mean log excess by which a second-order channel must beat the constant cover.
STATIC_PREFERENCE = 1e-3


@dataclass(frozen=True, eq=False)
class PerformanceWeights:
    """Dynamic weights and static scalings, each 3 x 3 diagonal.

    Attributes
    ----------
    error : control.StateSpace
        We = (s + w_cl sqrt3) / (2 s + eps w_cl sqrt3) I3: integral action up to
        the closed-loop bandwidth, sensitivity peak limited to 2 beyond.
    control_effort : control.StateSpace
        Wu = (s + w_u) / (h s + w_u) I3: unit gain to w_u, then roll-off.
    error_scaling, control_scaling, disturbance_scaling : ndarray, shape (3, 3)
        Ve [deg], Vu [mNm], Vd [mNm].
    reference_scaling : ndarray, shape (3, 3), optional
        Vr [deg]: the size of the reference the loop must follow (the input w_e is
        scaled by it). The paper uses one matrix for both, Vr = Ve (the default).
        Kept apart, because Ve then plays two parts: a looser Ve tolerates larger
        errors but also asks the loop to follow a larger reference with the same
        torque (the K S Ve block), so on a fixed controller μ can rise as Ve loosens.
        With Vr fixed, only the error rows scale by Ve^-1, and μ cannot rise.
    parameters : mapping, optional
        The parameters of We and Wu when they are not the problem's ``[weights]``
        (``closed_loop_bandwidth_rad_s``, ``epsilon``, ``control_rolloff_rad_s``,
        ``control_rolloff_high_frequency_gain``), as a controller file records them.
    """

    error: control.StateSpace
    control_effort: control.StateSpace
    error_scaling: np.ndarray
    control_scaling: np.ndarray
    disturbance_scaling: np.ndarray
    reference_scaling: np.ndarray | None = None
    parameters: Mapping[str, float] | None = None

    @property
    def reference(self) -> np.ndarray:
        """Vr [deg], shape (3, 3): :attr:`reference_scaling`, else Ve (the paper's)."""
        return self.error_scaling if self.reference_scaling is None else self.reference_scaling


def _diagonal(transfer: control.TransferFunction, gains: np.ndarray) -> control.StateSpace:
    return control.append(*[control.ss(transfer * float(g)) for g in gains])


def dynamic_weights(
    bandwidth_rad_s: float, epsilon: float, rolloff_rad_s: float, high_frequency_gain: float
) -> tuple[control.StateSpace, control.StateSpace]:
    """We and Wu, each 3 x 3 diagonal (the paper's forms).

    Parameters
    ----------
    bandwidth_rad_s : float
        w_cl of We = (s + w_cl sqrt3) / (2 s + eps w_cl sqrt3) [rad/s].
    epsilon : float
        eps of We.
    rolloff_rad_s : float
        w_u of Wu = (s + w_u) / (h s + w_u) [rad/s].
    high_frequency_gain : float
        h of Wu.

    Returns
    -------
    We, Wu : control.StateSpace
    """
    crossover = bandwidth_rad_s * math.sqrt(3.0)
    error = control.tf([1.0, crossover], [2.0, epsilon * crossover])
    effort = control.tf([1.0, rolloff_rad_s], [high_frequency_gain, rolloff_rad_s])
    return _diagonal(error, np.ones(3)), _diagonal(effort, np.ones(3))


def performance_weights(problem: Problem) -> PerformanceWeights:
    """The paper's We, Wu, Ve, Vu, Vd from the problem file."""
    w = problem.weights
    error, effort = dynamic_weights(
        w.closed_loop_bandwidth_rad_s,
        w.epsilon,
        w.control_rolloff_rad_s,
        w.control_rolloff_high_frequency_gain,
    )
    return PerformanceWeights(
        error=error,
        control_effort=effort,
        error_scaling=np.diag(w.error_scaling_deg),
        control_scaling=np.diag(w.control_scaling_mNm),
        disturbance_scaling=np.diag(w.disturbance_scaling_mNm),
    )


def recorded_performance_weights(
    problem: Problem, recorded: Mapping[str, Any]
) -> PerformanceWeights:
    """The weights a controller file records (``details["weights"]``), else the problem's.

    A design may derive its Ve, Vu and Vd rather than take ``[weights]``
    (:mod:`casadi_debris.robust.requirements`); its file records the ones it used.
    """
    weights = performance_weights(problem)
    error_weight, effort_weight = weights.error, weights.control_effort
    dynamic = ("closed_loop_bandwidth_rad_s", "epsilon", "control_rolloff_rad_s")
    if all(isinstance(recorded.get(k), int | float) for k in dynamic):
        error_weight, effort_weight = dynamic_weights(
            float(recorded["closed_loop_bandwidth_rad_s"]),
            float(recorded["epsilon"]),
            float(recorded["control_rolloff_rad_s"]),
            float(
                recorded.get(
                    "control_rolloff_high_frequency_gain",
                    problem.weights.control_rolloff_high_frequency_gain,
                )
            ),
        )
    keys = ("error_scaling_deg", "control_scaling_mNm", "disturbance_scaling_mNm")
    if not all(key in recorded for key in keys):
        return PerformanceWeights(
            error_weight,
            effort_weight,
            weights.error_scaling,
            weights.control_scaling,
            weights.disturbance_scaling,
        )
    error, control, disturbance = (np.diag(np.asarray(recorded[k], dtype=float)) for k in keys)
    reference = recorded.get("reference_scaling_deg")
    return PerformanceWeights(
        error_weight,
        effort_weight,
        error,
        control,
        disturbance,
        None if reference is None else np.diag(np.asarray(reference, dtype=float)),
    )


@dataclass(frozen=True, eq=False)
class UncertaintyWeight:
    """Fitted diagonal input-multiplicative uncertainty weight.

    Attributes
    ----------
    system : control.StateSpace
        W(s) = diag(W_1, W_2, W_3), 2 states per channel.
    coefficients : ndarray, shape (3, 5)
        Per channel [k, w_z, zeta_z, w_p, zeta_p] of
        W_i = k (s^2 + 2 zeta_z w_z s + w_z^2) / (s^2 + 2 zeta_p w_p s + w_p^2);
        all positive, so W_i is stable and minimum phase.
    margin : ndarray, shape (3,)
        min over the grid of |W_i| / d_i (>= 1: every sample is covered).
    mean_excess : ndarray, shape (3,)
        Mean of |W_i| / d_i over the grid (how conservative the fit is).
    """

    system: control.StateSpace
    coefficients: np.ndarray
    margin: np.ndarray
    mean_excess: np.ndarray


def second_order_magnitude(coefficients: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """|W(jw)| of one channel, shape (n_omega,)."""
    k, wz, zz, wp, zp = coefficients
    s = 1j * omega
    # Optimiser trial points may overflow; they are rejected by their infinite cost.
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return np.abs(k * (s**2 + 2 * zz * wz * s + wz**2) / (s**2 + 2 * zp * wp * s + wp**2))


def is_static(coefficients: np.ndarray) -> bool:
    """Whether one channel's zeros cancel its poles, so W_i is the constant k."""
    _, wz, zz, wp, zp = coefficients
    return bool(wz == wp and zz == zp)


def weight_system(coefficients: np.ndarray) -> control.StateSpace:
    """Diagonal W(s) from per-channel [k, w_z, zeta_z, w_p, zeta_p], shape (3, 5).

    A channel whose zeros equal its poles is realised as the static gain k (no states):
    a cancelling pole pair would sit in the generalised plant as an uncontrollable mode.
    """
    channels = [
        control.ss([], [], [], [[k]])
        if is_static(np.array([k, wz, zz, wp, zp]))
        else control.ss(control.tf([k, 2 * zz * wz * k, k * wz**2], [1.0, 2 * zp * wp, wp**2]))
        for k, wz, zz, wp, zp in np.asarray(coefficients, dtype=float)
    ]
    return control.append(*channels)


def _fit_channel(omega: np.ndarray, bound: np.ndarray) -> np.ndarray:
    """Tightest second-order cover of one channel, in the log-magnitude sense.

    Minimises the mean of log(|W| / d) subject to |W| >= d on the grid
    (SLSQP from several starts: the pole's frequency and damping decide which
    resonance band the weight can cover). A fit whose pole or zero frequency
    leaves the grid is discarded: outside it the fit cannot see them, and a pole
    driven towards 0 rad/s would leave the generalised plant unstabilisable.
    When the constant max(d) covers as tightly (a flat bound, as a rigid
    debris' inertia and mass errors give), the channel is that constant.
    """
    log_bound = np.log(bound)
    low, high = bound[0], bound[-1]
    peak_at = omega[np.argmax(bound)]

    def log_magnitude(theta: np.ndarray) -> np.ndarray:
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            return np.log(second_order_magnitude(np.exp(theta), omega))

    def log_excess(theta: npt.NDArray[np.float64]) -> np.ndarray:
        return log_magnitude(theta) - log_bound

    def mean_log_excess(theta: npt.NDArray[np.float64]) -> float:
        return float(np.mean(log_excess(theta)))

    frequencies = (math.log(omega[0]), math.log(omega[-1]))
    dampings = (math.log(MIN_DAMPING), math.log(MAX_DAMPING))
    lower = np.array([-np.inf, frequencies[0], dampings[0], frequencies[0], dampings[0]])
    upper = np.array([np.inf, frequencies[1], dampings[1], frequencies[1], dampings[1]])
    best: tuple[float, np.ndarray] | None = None
    for pole in (0.5 * peak_at, peak_at, 2.0 * peak_at):
        for damping in (0.01, 0.1, 0.5):
            gain = max(bound.max() * 2 * damping, high)
            zero = pole * math.sqrt(low / gain)
            start = np.log([gain, zero, 0.7, pole, damping])
            # scipy-stubs types a constraint's "fun" as scalar; SLSQP takes a vector of them.
            result = minimize(  # type: ignore[call-overload]
                mean_log_excess,
                start,
                method="SLSQP",
                constraints=[{"type": "ineq", "fun": log_excess}],
                options={"maxiter": 400, "ftol": 1e-10},
            )
            theta = result.x
            # Lift the gain until every point is covered (SLSQP stops within tolerance).
            theta[0] += max(0.0, -float(np.min(log_magnitude(theta) - log_bound)))
            cost = float(np.mean(log_magnitude(theta) - log_bound))
            inside = bool(np.all(theta >= lower) and np.all(theta <= upper))
            if inside and np.isfinite(cost) and (best is None or cost < best[0]):
                best = (cost, theta)
    static_cost = float(np.mean(log_bound.max() - log_bound))
    # A dynamic channel must beat the constant by more than the fit's noise.
    if best is None or best[0] > static_cost - STATIC_PREFERENCE:
        return np.array([bound.max(), 1.0, 1.0, 1.0, 1.0])
    return np.exp(best[1])


def fit_uncertainty_weight(omega: np.ndarray, bound: np.ndarray) -> UncertaintyWeight:
    """Fit a diagonal, stable, minimum-phase second-order W over per-channel bounds.

    Parameters
    ----------
    omega : ndarray, shape (n_omega,)
        Ascending frequencies [rad/s].
    bound : ndarray, shape (n_omega, 3)
        What |W_i(jw)| must reach, e.g.
        :func:`~casadi_debris.robust.plant.diagonal_cover` of the samples.

    Returns
    -------
    UncertaintyWeight
    """
    if bound.shape != (len(omega), 3) or not np.all(np.isfinite(bound)) or np.any(bound <= 0):
        raise SynthesisError("uncertainty bound must be positive and finite, shape (n_omega, 3)")
    coefficients = np.array([_fit_channel(omega, bound[:, i]) for i in range(3)])
    ratios = np.array(
        [second_order_magnitude(c, omega) / bound[:, i] for i, c in enumerate(coefficients)]
    )
    return UncertaintyWeight(
        system=weight_system(coefficients),
        coefficients=coefficients,
        margin=ratios.min(axis=1),
        mean_excess=ratios.mean(axis=1),
    )
