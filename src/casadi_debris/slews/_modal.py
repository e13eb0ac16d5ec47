"""Array vibration left by a piecewise-constant input, in closed form.

Linearised about rest, the flexible model is x_dot = A x + B u with
x = [theta, omega, v, eta, eta_dot] (theta = 2 q_vec, the model's own
``dynamics`` differentiated, as in :func:`casadi_debris.dynamics` but
with the CoG velocity and all nine inputs kept, so that the engines' net force
excites the arrays as well). A has the rigid eigenvalue 0 (a Jordan block:
attitude integrates rate) and one lightly damped complex pair per assembled
array mode. For each oscillatory eigenvalue lambda_k, with right and left
eigenvectors v_k, w_k (w_k^T v_k = 1), the modal coordinate xi_k = w_k^T x obeys
xi_k_dot = lambda_k xi_k + w_k^T B u exactly, whatever the rigid motion does.
An input held at u_j over an interval of length h_j therefore takes it to

    xi_k+ = exp(lambda_k h_j) xi_k + (exp(lambda_k h_j) - 1) / lambda_k  w_k^T B u_j

(the zero-order-hold discretisation of a first-order mode, Franklin, Powell &
Workman, *Digital Control*, ch. 4).

The vibration energy (:func:`casadi_debris.slews._profile.vibration_energy`) is
zero on rigid motion and non-negative, so to second order it is the quadratic
form 1/2 x_o^T H x_o of the oscillatory part alone, x_o = 2 Re sum_k v_k xi_k
over the pairs with Im lambda_k > 0 (H its Hessian at rest). The step holds for
any interval length, a symbolic one included, which is what the flexible slew
OCP needs: the bulk's interval length is its free final time.

Left out: the gyroscopic and centrifugal terms (products of rates, 1e-5 of the
torque terms at the paper's slew rates) and the attitude's effect on the
modes (none: the arrays' modal equations are written in the body frame).
The slew's check on the full nonlinear model measures what they change.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TypeVar

import casadi as ca
import numpy as np

from casadi_debris.dynamics import Model

# One kind of CasADi matrix throughout a call: numbers (DM) when marching a profile,
# symbols (SX, MX) when building a constraint. CasADi does not mix SX and MX.
Expression = TypeVar("Expression", ca.DM, ca.SX, ca.MX)
Symbolic = TypeVar("Symbolic", ca.SX, ca.MX)


@dataclass(frozen=True)
class ModalResponse:
    """The oscillatory part of the flexible model linearised at rest.

    Attributes
    ----------
    eigenvalues : ndarray, complex, shape (k,)
        One of each pair (Im > 0), rad/s.
    input_rows : ndarray, complex, shape (k, 9)
        w_k^T B: how the model input [tau (N m), tau_d, F (N)] drives xi_k.
    energy_form : ndarray, shape (2k, 2k)
        Q with E_vib = 1/2 r^T Q r (J), r = [Re xi; Im xi].
    """

    eigenvalues: np.ndarray
    input_rows: np.ndarray
    energy_form: np.ndarray

    @property
    def frequencies_rad_s(self) -> np.ndarray:
        """Natural frequencies |lambda_k|, rad/s."""
        return np.abs(self.eigenvalues)

    def step(
        self,
        real: Expression,
        imag: Expression,
        step_s: float | Expression,
        inputs: Expression | np.ndarray,
    ) -> tuple[Expression, Expression]:
        """xi (Re, Im; k x 1 each) after one interval with the input held.

        xi+ = Phi xi + (Phi - 1) / lambda  w^T B u,  Phi = exp(lambda h).

        Parameters
        ----------
        step_s
            Interval length h, s (symbolic allowed).
        inputs : shape (9,)
            Model input held on the interval (symbolic allowed).
        """
        u = ca.DM(inputs) if isinstance(inputs, np.ndarray) else inputs
        sigma, omega = ca.DM(self.eigenvalues.real), ca.DM(self.eigenvalues.imag)
        inverse = np.conj(self.eigenvalues) / np.abs(self.eigenvalues) ** 2
        decay = ca.exp(sigma * step_s)
        phi_re, phi_im = decay * ca.cos(omega * step_s), decay * ca.sin(omega * step_s)
        gain_re = (phi_re - 1.0) * ca.DM(inverse.real) - phi_im * ca.DM(inverse.imag)
        gain_im = (phi_re - 1.0) * ca.DM(inverse.imag) + phi_im * ca.DM(inverse.real)
        drive_re = ca.DM(self.input_rows.real) @ u
        drive_im = ca.DM(self.input_rows.imag) @ u
        return (
            phi_re * real - phi_im * imag + gain_re * drive_re - gain_im * drive_im,
            phi_re * imag + phi_im * real + gain_re * drive_im + gain_im * drive_re,
        )

    def final_coordinates(
        self, steps_s: np.ndarray, inputs: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Re and Im of xi(T), shape (k,) each, after the intervals, from rest.

        Parameters
        ----------
        steps_s : ndarray, shape (N,)
            Interval lengths, s.
        inputs : ndarray, shape (9, N)
            Model input held on each interval.
        """
        real = imag = ca.DM.zeros(len(self.eigenvalues))
        for step_s, u in zip(steps_s, np.asarray(inputs).T, strict=True):
            real, imag = self.step(real, imag, float(step_s), u)
        return np.array(real).ravel(), np.array(imag).ravel()

    def energy(self, real: Expression, imag: Expression) -> Expression:
        """Vibration energy (J) of the modal coordinates ``real + i imag``."""
        r = ca.vertcat(real, imag)
        return 0.5 * r.T @ ca.DM(self.energy_form) @ r


def _small_angle_state(model: Model, z: ca.SX) -> ca.SX:
    """Full model state from [theta, omega, v, eta, eta_dot]."""
    half = z[0:3] / 2.0
    q = ca.vertcat(ca.sqrt(1.0 - ca.dot(half, half)), half)
    return ca.vertcat(q, z[3 : model.layout.size - 5], q)


def vibration_energy_expression(model: Model, state: Symbolic, parameters: np.ndarray) -> Symbolic:
    """Symbolic :func:`~casadi_debris.slews._profile.vibration_energy` of a full state (J)."""
    lay = model.layout
    mass = np.array(model.mass_matrix(parameters))
    nu = ca.vertcat(state[lay.v], state[lay.omega], state[lay.eta_dot])
    momenta = ca.DM(mass[:6]) @ nu
    rigid = 0.5 * momenta.T @ ca.DM(np.linalg.inv(mass[:6, :6])) @ momenta
    return model.energy(state, parameters) - rigid


def modal_response(model: Model, parameters: np.ndarray) -> ModalResponse:
    """Linearise ``model`` (with array modes) at rest and split off its oscillatory part.

    Raises
    ------
    ValueError
        The model has no array modes, or its modes are not distinct.
    """
    lay = model.layout
    n_z = lay.size - 5  # the two quaternions become one theta
    z = ca.SX.sym("z", n_z)
    u = ca.SX.sym("u", 9)
    x = _small_angle_state(model, z)
    xdot = model.dynamics(x, u, parameters)
    zdot = ca.vertcat(2.0 * xdot[lay.q][1:4], xdot[4 : lay.size - 4])
    energy = vibration_energy_expression(model, x, parameters)
    linear = ca.Function(
        "modal_linearisation",
        [z, u],
        [ca.jacobian(zdot, z), ca.jacobian(zdot, u), ca.hessian(energy, z)[0]],
    )
    a, b, hessian = (np.array(m) for m in linear(np.zeros(n_z), np.zeros(9)))
    eigenvalues, right = np.linalg.eig(a)
    oscillatory = np.flatnonzero(eigenvalues.imag > 1e-9 * np.max(np.abs(eigenvalues)))
    if len(oscillatory) == 0:
        raise ValueError("the model has no oscillatory array modes")
    if len(oscillatory) != lay.n_eta:
        raise ValueError(f"{len(oscillatory)} oscillatory eigenvalues for {lay.n_eta} modes")
    values = eigenvalues[oscillatory]
    gaps = np.abs(values[:, None] - values[None, :]) + np.diag(np.full(len(values), np.inf))
    if np.min(gaps) < 1e-6 * np.min(np.abs(values)):
        raise ValueError("the array modes are not distinct (repeated eigenvalues)")
    left_values, left = np.linalg.eig(a.T)
    rows, columns = [], []
    for index in oscillatory:
        lam = eigenvalues[index]
        match = int(np.argmin(np.abs(left_values - lam)))
        if abs(left_values[match] - lam) > 1e-8 * abs(lam):
            raise ValueError(f"eigenvalue {lam} has no matching left eigenvector")
        w, v = left[:, match], right[:, index]
        w = w / (w @ v)  # w^T v = 1 (no conjugate: biorthogonal, not Hermitian)
        rows.append(w @ b)
        columns.append(v)
    vectors = np.array(columns).T  # (n_z, k)
    # x_o = 2 Re(V xi) = [2 Re V, -2 Im V] [Re xi; Im xi]
    projection = np.hstack([2.0 * vectors.real, -2.0 * vectors.imag])
    return ModalResponse(
        eigenvalues=eigenvalues[oscillatory],
        input_rows=np.array(rows),
        energy_form=projection.T @ hessian @ projection,
    )
