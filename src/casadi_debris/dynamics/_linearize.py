"""Linearisation of the compiled model about rest, by CasADi Jacobians.

The quaternions are replaced by minimal small-angle coordinates theta = 2 q_vec
(q = [sqrt(1 - |theta/2|^2), theta/2]); the model's own ``dynamics`` Function is
evaluated on that map and differentiated, so the linear plant comes from the
same equations as the simulation. The CoG velocity v is left out: at rest
nothing depends on it (its coupling terms are products with zero momenta), so
dropping it is exact.

States: theta (3), omega (3), eta, eta_dot, and with ``sensor=True`` the star
tracker's theta_ST (3). Inputs: control torque (3), optionally disturbance
torque (3). Outputs: attitude angles [Phi, Theta, Psi] (the star tracker's
with ``sensor=True``).
"""

from __future__ import annotations

import math
from typing import Literal

import casadi as ca
import control
import numpy as np
import numpy.typing as npt

from casadi_debris.dynamics._compiled import Model
from casadi_debris.errors import InputShapeError, ModelError

Units = Literal["SI", "deg_mNm"]
UNITS: tuple[Units, ...] = ("SI", "deg_mNm")
AXES = ("x", "y", "z")


def _small_angle_quaternion(theta: ca.SX) -> ca.SX:
    half = theta / 2.0
    return ca.vertcat(ca.sqrt(1.0 - ca.dot(half, half)), half)


def linearization_function(
    model: Model, sensor: bool = False, disturbance_input: bool = False
) -> ca.Function:
    """``Function('linearization', [p], [A, B])`` about rest at identity attitude.

    Build once and call per parameter set when linearising many samples.
    """
    lay = model.layout
    n_eta = lay.n_eta
    n_z = 6 + 2 * n_eta + (3 if sensor else 0)
    z = ca.SX.sym("z", n_z)
    n_u = 6 if disturbance_input else 3
    w = ca.SX.sym("w", n_u)
    p = ca.SX.sym("p", len(model.nominal_parameters))

    theta = z[0:3]
    theta_st = z[6 + 2 * n_eta : 9 + 2 * n_eta] if sensor else theta
    x = ca.vertcat(
        _small_angle_quaternion(theta),
        z[3:6],
        ca.SX.zeros(3),
        z[6 : 6 + 2 * n_eta],
        _small_angle_quaternion(theta_st),
    )
    u = ca.vertcat(w, ca.SX.zeros(9 - n_u))
    xdot = model.dynamics(x, u, p)
    zdot = ca.vertcat(2.0 * xdot[lay.q][1:4], xdot[lay.omega], xdot[lay.eta], xdot[lay.eta_dot])
    if sensor:
        zdot = ca.vertcat(zdot, 2.0 * xdot[lay.q_st][1:4])
    at_rest = ca.SX.zeros(n_z + n_u)
    a = ca.substitute(ca.jacobian(zdot, z), ca.vertcat(z, w), at_rest)
    b = ca.substitute(ca.jacobian(zdot, w), ca.vertcat(z, w), at_rest)
    return ca.Function("linearization", [p], [a, b], ["p"], ["A", "B"])


def state_names(model: Model, sensor: bool = False) -> list[str]:
    """Names of the linear plant's states."""
    modal = [f"array{a}_{m}" for a, m in model.layout.mode_labels]
    names = [f"theta_{a}" for a in AXES] + [f"omega_{a}" for a in AXES]
    names += [f"eta_{n}" for n in modal] + [f"eta_dot_{n}" for n in modal]
    if sensor:
        names += [f"theta_st_{a}" for a in AXES]
    return names


def linearize(
    model: Model,
    parameters: npt.ArrayLike | None = None,
    *,
    sensor: bool = False,
    disturbance_input: bool = False,
    units: Units = "SI",
    function: ca.Function | None = None,
) -> control.StateSpace:
    """Linear attitude plant of the model at rest.

    Parameters
    ----------
    model : Model
        From :func:`build_model`; ``build_model(problem, modes="first")`` gives
        the paper's truncated plant (10 states without the sensor).
    parameters : sequence of float, shape (6,), optional
        Ordered as ``model.parameter_names``; default nominal.
    sensor : bool
        Include the star-tracker low pass (3 states); outputs become its angles.
    disturbance_input : bool
        Add the disturbance torque as three more inputs.
    units : {"SI", "deg_mNm"}
        "SI": torque in N m, angles in rad. "deg_mNm": torque in mNm, angles in
        deg (the paper's design units).
    function : casadi.Function, optional
        A :func:`linearization_function` of the same model and options, to
        reuse across many parameter sets.

    Returns
    -------
    control.StateSpace
        Inputs ``tau_x, tau_y, tau_z`` (+ ``tau_d_*``), outputs ``phi, theta,
        psi``, states named as :func:`state_names`.
    """
    if units not in UNITS:
        raise ModelError(f"units must be one of {UNITS}, got {units!r}")
    p = model.nominal_parameters if parameters is None else np.asarray(parameters, dtype=float)
    if p.shape != model.nominal_parameters.shape or not np.all(np.isfinite(p)):
        raise InputShapeError(
            f"parameters: expected {len(model.nominal_parameters)} finite numbers "
            f"({', '.join(model.parameter_names)}), got {p!r}"
        )
    fn = function or linearization_function(model, sensor, disturbance_input)
    a, b = (np.array(m) for m in fn(p))
    n_states = a.shape[0]
    output_offset = 6 + 2 * model.layout.n_eta if sensor else 0
    c = np.zeros((3, n_states))
    c[:, output_offset : output_offset + 3] = np.eye(3)
    if units == "deg_mNm":
        b = b * 1e-3
        c = c * (180.0 / math.pi)
    inputs = [f"tau_{a}" for a in AXES] + (
        [f"tau_d_{a}" for a in AXES] if disturbance_input else []
    )
    return control.ss(
        a,
        b,
        c,
        np.zeros((3, b.shape[1])),
        inputs=inputs,
        outputs=["phi", "theta", "psi"],
        states=state_names(model, sensor),
        name="combined_body",
    )


def flexible_frequencies(plant: control.StateSpace) -> np.ndarray:
    """Natural frequencies [rad/s] of the plant's oscillatory poles, ascending, one per pair."""
    poles = np.linalg.eigvals(plant.A)
    oscillatory = poles[poles.imag > 1e-9]
    return np.sort(np.abs(oscillatory))


def assembled_modes(model: Model, parameters: npt.ArrayLike | None = None) -> list[dict]:
    """Flexible modes of the free-floating assembly, from the linear plant's eigenvectors.

    Parameters
    ----------
    model : Model
    parameters : sequence of float, optional
        Default nominal.

    Returns
    -------
    list of dict
        Ascending in frequency, one per oscillatory pole pair, with
        ``omega_rad_s`` (undamped natural frequency), ``zeta``,
        ``dominant_mode`` (name of the cantilever mode carrying most of the
        eigenvector's modal part), ``array_share`` (fraction of the modal part
        on each array) and ``in_phase`` (both arrays deflect the same way;
        None when one array carries it alone).
    """
    plant = linearize(model, parameters)
    poles, vectors = np.linalg.eig(plant.A)
    lay = model.layout
    eta = slice(6, 6 + lay.n_eta)
    modes = []
    for index in np.flatnonzero(poles.imag > 1e-9):
        pole, shape = poles[index], vectors[eta, index]
        weight = np.abs(shape) ** 2
        by_mode: dict[str, float] = {}
        for (_, name), w in zip(lay.mode_labels, weight, strict=True):
            by_mode[name] = by_mode.get(name, 0.0) + w
        dominant = max(by_mode, key=by_mode.__getitem__)
        arrays = sorted({a for a, _ in lay.mode_labels})
        share = [
            float(sum(w for (a, _), w in zip(lay.mode_labels, weight, strict=True) if a == k))
            / float(weight.sum())
            for k in arrays
        ]
        pair = [shape[i] for i, (_, name) in enumerate(lay.mode_labels) if name == dominant]
        in_phase = None
        if len(pair) == 2 and min(share) > 0.1:
            in_phase = bool((pair[0] * np.conj(pair[1])).real > 0)
        modes.append(
            {
                "omega_rad_s": float(abs(pole)),
                "zeta": float(-pole.real / abs(pole)),
                "dominant_mode": dominant,
                "array_share": share,
                "in_phase": in_phase,
            }
        )
    return sorted(modes, key=lambda m: m["omega_rad_s"])
