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
from casadi_debris.dynamics import (
    INERTIA_SCALE_NAMES,
    Model,
    ParameterLayout,
    Units,
    linearization_function,
    linearize,
)
from casadi_debris.errors import SynthesisError
from casadi_debris.robust.plant._response import FrequencyResponse


@dataclass(frozen=True, eq=False)
class UncertaintySamples:
    """Parameter sets drawn from the uncertainty box.

    Attributes
    ----------
    normalized : ndarray, shape (n, n_parameters)
        Each parameter's position in its range, -1 .. 1, ordered as the model's
        parameters (``model.parameter_names``).
    parameters : ndarray, shape (n, n_parameters)
        The model parameter vectors.
    n_corners : int
        The first ``n_corners`` rows are the box's corners.
    seed : int
    """

    normalized: np.ndarray
    parameters: np.ndarray
    n_corners: int
    seed: int


def half_ranges(problem: Problem, layout: ParameterLayout) -> dict[str, tuple[str, float]]:
    """How far each parameter of ``layout`` ranges: name -> (kind, half-range).

    ``"relative"``: nominal (1 + h z); ``"absolute"``: nominal + h z, for z in
    -1 .. 1 (h in the parameter's unit, radians for the angle).
    """
    u = problem.uncertainty
    ranges = {name: ("relative", u.inertia_fraction) for name in INERTIA_SCALE_NAMES}
    ranges["mass_kg"] = ("relative", u.mass_fraction)
    for name in layout.angle_names:
        ranges[name] = ("absolute", np.radians(u.array_angle_deg))
    ranges["bending_frequency_scale"] = ("relative", u.bending_frequency_fraction)
    return {name: ranges[name] for name in layout.names}


def parameters_from_normalized(model: Model, normalized: np.ndarray) -> np.ndarray:
    """Map positions in the uncertainty box (-1 .. 1) to model parameter vectors.

    Parameters
    ----------
    model : Model
        Its layout and nominal values; the box is ``model.problem``'s uncertainty.
    normalized : ndarray, shape (n, n_parameters) or (n_parameters,)
        Ordered as ``model.parameter_names``.

    Returns
    -------
    ndarray, same shape: inertia scales 1 ± f_I, mass m (1 ± f_m), angle
    theta_0 ± range, first bending frequency factor 1 ± f_w.
    """
    problem = model.problem
    layout = model.parameter_layout
    z = np.atleast_2d(np.asarray(normalized, dtype=float))
    if z.shape[-1] != layout.size:
        raise SynthesisError(
            f"normalized parameters: expected {layout.size} per row "
            f"({', '.join(layout.names)}), got shape {np.shape(normalized)}"
        )
    nominal = model.nominal_parameters
    p = np.tile(nominal, (len(z), 1))
    for index, (kind, half) in enumerate(half_ranges(problem, layout).values()):
        if kind == "relative":
            p[:, index] = nominal[index] * (1.0 + half * z[:, index])
        else:
            p[:, index] = nominal[index] + half * z[:, index]
    return p.reshape(np.shape(normalized))


def normalized_from_parameters(model: Model, parameters: np.ndarray) -> np.ndarray:
    """Positions in the uncertainty box of model parameter vectors (inverse of
    :func:`parameters_from_normalized`; outside -1 .. 1 for parameters outside the box).

    Parameters
    ----------
    parameters : ndarray, shape (n, n_parameters) or (n_parameters,)

    Returns
    -------
    ndarray, same shape
    """
    problem = model.problem
    layout = model.parameter_layout
    p = np.atleast_2d(np.asarray(parameters, dtype=float))
    nominal = model.nominal_parameters
    z = np.zeros_like(p)
    for index, (kind, half) in enumerate(half_ranges(problem, layout).values()):
        if kind == "relative":
            z[:, index] = (p[:, index] / nominal[index] - 1.0) / half if half else 0.0
        else:
            z[:, index] = (p[:, index] - nominal[index]) / half if half else 0.0
    return z.reshape(np.shape(parameters))


FULL_CIRCLE_DEG = 180.0


def corner_angles(problem: Problem, count: int | None = None) -> np.ndarray:
    """Normalised array-angle positions of the corner set, shape (count,).

    ``count`` defaults to ``montecarlo.corner_array_angles``. With a +-180 deg
    range the two extremes are one attitude of the arrays, so the angles are
    spaced by 360 deg / count; for a smaller range they run from one extreme
    to the other, both included.
    """
    count = problem.montecarlo.corner_array_angles if count is None else count
    if problem.uncertainty.array_angle_deg >= FULL_CIRCLE_DEG:
        return -1.0 + 2.0 * np.arange(count) / count
    return np.linspace(-1.0, 1.0, count) if count > 1 else np.zeros(1)


def box_corners(n_parameters: int) -> np.ndarray:
    """All 2^n corners of the normalised uncertainty box, shape (2^n, n)."""
    return np.array(list(itertools.product((-1.0, 1.0), repeat=n_parameters)))


def sample_uncertainty(
    model: Model, count: int | None = None, seed: int | None = None
) -> UncertaintySamples:
    """Corners of the uncertainty box first, then seeded uniform samples.

    Parameters
    ----------
    model : Model
        Its layout sets the parameters; the box is ``model.problem``'s uncertainty.
    count : int, optional
        Total number of models (default ``problem.uncertainty.samples``);
        at least the box's corners are always included.
    seed : int, optional
        Default ``problem.uncertainty.seed``.
    """
    problem = model.problem
    count = problem.uncertainty.samples if count is None else count
    seed = problem.uncertainty.seed if seed is None else seed
    n_parameters = model.parameter_layout.size
    corners = box_corners(n_parameters)
    rng = np.random.default_rng(seed)
    extra = rng.uniform(-1.0, 1.0, size=(max(count - len(corners), 0), n_parameters))
    normalized = np.vstack([corners, extra])
    return UncertaintySamples(
        normalized=normalized,
        parameters=parameters_from_normalized(model, normalized),
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
