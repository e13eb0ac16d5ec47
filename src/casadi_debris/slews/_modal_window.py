"""The flexible slew's terminal window: the vibration left bounded in closed form.

A flexible slew (``flexible_method="ocp"``, the default) keeps the rigid
collocation for the motion and bounds the vibration left in the arrays exactly
for their linear dynamics. The horizon is a bulk of uniform intervals (free
length T_b) and a terminal window of 32 fixed intervals over W = 1.5 x the
length of the cascaded ZV shaper of all array modes (2.07 s for the paper's
arrays), where the controls are fine enough to cancel a vibration. Each
oscillatory mode's coordinate xi_k (:mod:`casadi_debris.slews._modal`: the
flexible model linearised at rest, all modes, force and torque inputs) is
stepped over every interval in closed form, xi+ = exp(lambda h) xi +
(exp(lambda h) - 1) / lambda w^T B u, with xi at every node a variable, and

    E_vib(xi(T)) <= 0.8 * max(residual_energy_fraction * E_bb, floor),

E_vib as in :func:`~casadi_debris.slews._profile.vibration_energy` (its Hessian
at rest on the modal subspace), E_bb what the eigenaxis bang-bang at the rigid
limit leaves (CVODES, full model), floor = 1e-12 x the slew's peak kinetic
energy; 0.8 is a margin for the terms the linear modes leave out (products of
rates), so that the CVODES check of the profile on the full nonlinear model,
which is what the profile reports, meets the limit (on the paper's slew the
prediction and the check agree to 1e-4). Minimise T = T_b + W. The guess is
the rigid optimum through the ZV shaper, solved first: the modes' phase at the
end turns by omega dT, so IPOPT must start at nearly the right length, and
with a small initial barrier (``mu_init`` 1e-3) so that it does not first
push every saturated control to mid-range.

Earlier transcriptions, kept out for cause: the modes as collocated states
over the whole horizon (thousands of modal periods) and CVODES shooting
stalled; an RK4 multiple-shooting window with a quasi-static hand-over took
95 s (its window controls left IPOPT with a singular reduced Hessian); the sum
of the closed-form responses over the horizon makes the constraint rows dense
in every control, and CasADi's Jacobian colouring then takes 5 s.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from casadi_debris.dynamics import Model
from casadi_debris.slews._modal import modal_response
from casadi_debris.slews._ocp_problem import SlewOcp
from casadi_debris.slews._profile import SlewProfile, simulate_open_loop, vibration_energy

WINDOW_INTERVALS = 32  # 64 gave the same optimum (2 ms shorter) at 1.5x the solve time
WINDOW_SHAPER_MULTIPLE = 1.5
ENERGY_MARGIN = 0.8
ENERGY_FLOOR = 1e-12


def window_length_s(shaper_length_s: float) -> float:
    """Length of the terminal window, s: a multiple of the cascaded ZV shaper's length."""
    return WINDOW_SHAPER_MULTIPLE * shaper_length_s


def energy_limit(ocp: SlewOcp, reference: SlewProfile, fraction: float) -> tuple[float, float]:
    """(limit, bang-bang energy), J: the vibration energy a flexible slew may leave.

    ``fraction`` of what the eigenaxis bang-bang at the rigid limit leaves (CVODES,
    full flexible model), but at least ENERGY_FLOOR times the slew's peak kinetic
    energy: a slew that excites no mode linearly (about x the bang-bang leaves
    1e-35 J) is not held to nothing, and what the nonlinear terms excite there
    (1e-18 J) is not worth constraining.

    Parameters
    ----------
    ocp : SlewOcp
        A flexible one (its ``flexible_model`` is set).
    reference : SlewProfile
        The eigenaxis bang-bang at the rigid limit.
    fraction : float
        ``residual_energy_fraction``.
    """
    model = _flexible_model(ocp)
    knots = np.array([0.0, reference.duration_s / 2.0, reference.duration_s])
    states = simulate_open_loop(
        model,
        reference.input_function,
        knots,
        model.initial_state(ocp.target.q_initial_BN),
        ocp.parameters,
    )
    energy = vibration_energy(model, states[-1], ocp.parameters)
    settings = reference.settings
    kinetic = 0.5 * settings["inertia_about_axis_kgm2"] * settings["peak_rate_rad_s"] ** 2
    return max(fraction * energy, ENERGY_FLOOR * kinetic), energy


@dataclass(frozen=True)
class VibrationBound:
    """The end condition E_vib(xi(T)) <= ``limit_J`` on the modes' closed-form steps.

    Attributes
    ----------
    model : Model
        The flexible model (all modes).
    parameters : ndarray
        Its parameters.
    limit_J : float
        Bound on the vibration energy left at the end, J.
    """

    model: Model
    parameters: np.ndarray
    limit_J: float

    @classmethod
    def of(cls, ocp: SlewOcp, limit_J: float) -> VibrationBound:
        """The bound on a flexible OCP's modes."""
        return cls(_flexible_model(ocp), ocp.parameters, limit_J)

    def constrain(
        self,
        opti: ca.Opti,
        drive: ca.MX,
        steps: ca.MX,
        input_map: np.ndarray,
        guess: tuple[np.ndarray, np.ndarray],
    ) -> ca.MX:
        """Add the modes' steps and the bound to ``opti``; return the energy left (J).

        The modes' coordinates xi at every node are variables, stepped interval by
        interval in closed form (:class:`~casadi_debris.slews._modal.ModalResponse`).
        A sum over the horizon instead makes the constraint rows dense in every
        control, and CasADi's Jacobian colouring then takes seconds.

        Parameters
        ----------
        opti : casadi.Opti
        drive : MX, shape (n_d, N)
            What drives the model on each interval (scaled); ``input_map``
            (shape (9, n_d)) gives the model input of one.
        steps : MX, shape (N, 1)
            Interval lengths, s.
        guess : (steps_s, drive)
            The initial guess (shapes (N,) and (n_d, N)), marched to start xi and to
            scale it.
        """
        response = modal_response(self.model, self.parameters)
        k = len(response.eigenvalues)
        xi, h, u = ca.SX.sym("xi", 2 * k), ca.SX.sym("h"), ca.SX.sym("u", input_map.shape[1])

        def step(coordinates: ca.SX) -> ca.SX:
            return ca.vertcat(
                *response.step(coordinates[:k], coordinates[k:], h, ca.DM(input_map) @ u)
            )

        march = ca.Function("modal_step", [xi, h, u], [step(xi)])
        nodes = [np.zeros(2 * k)]
        for step_s, control in zip(guess[0], guess[1].T, strict=True):
            nodes.append(np.array(march(nodes[-1], step_s, control)).ravel())
        path = np.array(nodes).T  # (2k, N + 1)
        # xi's size: the largest of the guess, at least what alone holds half the limit.
        floor = np.sqrt(self.limit_J / np.diag(response.energy_form))
        scale = np.maximum(np.max(np.abs(path), axis=1), floor)
        scaled = ca.Function("scaled_modal_step", [xi, h, u], [step(xi * scale) / scale])
        count = path.shape[1] - 1
        XI = opti.variable(2 * k, count + 1)
        opti.subject_to(XI[:, 0] == 0)
        opti.subject_to(ca.vec(XI[:, 1:] - scaled.map(count)(XI[:, :-1], steps.T, drive)) == 0)
        opti.set_initial(XI, path / scale[:, None])
        final = XI[:, -1] * ca.DM(scale)
        energy = response.energy(final[:k], final[k:])
        opti.subject_to(energy / self.limit_J <= 1.0)
        return energy


def _flexible_model(ocp: SlewOcp) -> Model:
    if ocp.flexible_model is None:
        raise ValueError("the modal window needs a flexible slew OCP (options.flexible)")
    return ocp.flexible_model
