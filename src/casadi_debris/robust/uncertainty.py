"""Sampling the uncertainty set and measuring the plants' relative error.

The paper lumps the parametric uncertainty (inertia ±17 % per axis, mass
±20 %, array angle ±180°, first bending frequency ±20 %) into one
input-multiplicative uncertainty P = P_c (I + W Δ). This module draws the
models W must cover: every corner of the parameter box plus seeded uniform
samples (the paper: 200 models, corners included), linearised from the one
CasADi model, and their relative errors E_k = P_c^-1 P_k - I on a frequency grid.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import control
import numpy as np

from casadi_debris.config import Problem
from casadi_debris.errors import SynthesisError
from casadi_debris.model import Model, Units, linearization_function, linearize
from casadi_debris.robust.margins import FrequencyResponse

N_PARAMETERS = 6


@dataclass(frozen=True, eq=False)
class UncertaintySamples:
    """Parameter sets drawn from the uncertainty box.

    Attributes
    ----------
    normalized : ndarray, shape (n, 6)
        Each parameter's position in its range, -1 .. 1 (ordered as the
        model's parameters: inertia scale x, y, z, mass, array angle, first
        bending frequency).
    parameters : ndarray, shape (n, 6)
        The model parameter vectors.
    n_corners : int
        The first ``n_corners`` rows are the box's corners.
    seed : int
    """

    normalized: np.ndarray
    parameters: np.ndarray
    n_corners: int
    seed: int


def parameters_from_normalized(
    problem: Problem, model: Model, normalized: np.ndarray
) -> np.ndarray:
    """Map positions in the uncertainty box (-1 .. 1) to model parameter vectors.

    Parameters
    ----------
    normalized : ndarray, shape (n, 6) or (6,)

    Returns
    -------
    ndarray, same shape: inertia scales 1 ± f_I, mass m (1 ± f_m), angle
    theta_0 ± range, first bending frequency omega_1 (1 ± f_w).
    """
    u = problem.uncertainty
    z = np.atleast_2d(np.asarray(normalized, dtype=float))
    nominal = model.nominal_parameters
    p = np.tile(nominal, (len(z), 1))
    p[:, 0:3] = 1.0 + u.inertia_fraction * z[:, 0:3]
    p[:, 3] = nominal[3] * (1.0 + u.mass_fraction * z[:, 3])
    p[:, 4] = nominal[4] + np.radians(u.array_angle_deg) * z[:, 4]
    p[:, 5] = nominal[5] * (1.0 + u.bending_frequency_fraction * z[:, 5])
    return p.reshape(np.shape(normalized))


def box_corners() -> np.ndarray:
    """All 2^6 corners of the normalised uncertainty box, shape (64, 6)."""
    return np.array(list(itertools.product((-1.0, 1.0), repeat=N_PARAMETERS)))


def sample_uncertainty(
    problem: Problem, model: Model, count: int | None = None, seed: int | None = None
) -> UncertaintySamples:
    """Corners of the uncertainty box first, then seeded uniform samples.

    Parameters
    ----------
    problem, model
    count : int, optional
        Total number of models (default ``problem.uncertainty.samples``);
        at least the 64 corners are always included.
    seed : int, optional
        Default ``problem.uncertainty.seed``.
    """
    count = problem.uncertainty.samples if count is None else count
    seed = problem.uncertainty.seed if seed is None else seed
    corners = box_corners()
    rng = np.random.default_rng(seed)
    extra = rng.uniform(-1.0, 1.0, size=(max(count - len(corners), 0), N_PARAMETERS))
    normalized = np.vstack([corners, extra])
    return UncertaintySamples(
        normalized=normalized,
        parameters=parameters_from_normalized(problem, model, normalized),
        n_corners=len(corners),
        seed=seed,
    )


def frequency_response(system: control.StateSpace, omega: np.ndarray) -> np.ndarray:
    """Complex response of a MIMO system on a grid, shape (n_omega, n_out, n_in)."""
    return np.moveaxis(system.frequency_response(omega).frdata, 2, 0)


def relative_errors(
    model: Model, parameters: np.ndarray, omega: np.ndarray, units: Units = "deg_mNm"
) -> np.ndarray:
    """Input-multiplicative relative errors E_k(jw) = P_c(jw)^-1 P_k(jw) - I.

    Parameters
    ----------
    model : Model
    parameters : ndarray, shape (n, 6)
    omega : ndarray, shape (n_omega,)
        Strictly positive frequencies [rad/s] (P_c is singular at 0).

    Returns
    -------
    ndarray, shape (n, n_omega, 3, 3)
    """
    if np.any(omega <= 0):
        raise SynthesisError("relative errors need strictly positive frequencies")
    function = linearization_function(model)

    def response(parameters: np.ndarray | None) -> np.ndarray:
        # Block-diagonal Schur form: O(n) per frequency (5x faster than python-control's
        # Horner/Laub evaluation here, the same to 5e-11).
        plant = linearize(model, parameters, units=units, function=function)
        return FrequencyResponse(plant)(omega)

    nominal = response(None)
    errors = np.empty((len(parameters), len(omega), 3, 3), dtype=complex)
    for k, p in enumerate(parameters):
        errors[k] = np.linalg.solve(nominal, response(p)) - np.eye(3)
    return errors


def diagonal_cover(errors: np.ndarray) -> np.ndarray:
    """Per-channel magnitudes d_i(w) with sigma_max(D^-1 E_k) <= 1 for every sample.

    With E = W Delta (W diagonal, ||Delta|| <= 1) the rows of E are what W
    must bound: start from the largest row norm per channel, then raise all
    channels together at frequencies where the row bounds alone do not
    reach sigma_max <= 1 (at most by sqrt(3)).

    Parameters
    ----------
    errors : ndarray, shape (n, n_omega, 3, 3)

    Returns
    -------
    ndarray, shape (n_omega, 3)
    """
    rows = np.linalg.norm(errors, axis=3).max(axis=0)
    rows = np.maximum(rows, 1e-12 * np.max(rows))
    scaled = errors / rows[None, :, :, None]
    excess = np.linalg.norm(scaled, ord=2, axis=(2, 3)).max(axis=0)
    return rows * excess[:, None]
