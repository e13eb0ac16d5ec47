"""The slew OCP as a statement: dynamics, bounds, end conditions and objective.

States x: the rigid model's state without the star tracker (q_BN, omega, v);
the dynamics are the model's own ``dynamics`` Function (``build_model(problem,
modes=[])``, full rigid inertia), called with the sensor state equal to the
attitude (its derivative is then zero). Controls, held on each interval:

- torque level: tau in the per-axis box of the engines' authority
  (:func:`~casadi_debris.slews._maneuver.torque_limits`, times ``torque_fraction``)
  and in the engines' torque set at zero net force, {tau : N tau <= b} times
  ``torque_fraction`` (:meth:`SlewOcp.torque_set`): the box's corners lie outside
  that set (the allocator cannot give them), so the box alone is not enough;
- thruster level: the thrust of every engine, 0 <= f_i <= f_max,i; the model
  receives tau = B f and F = B_F f (geometry torque and force maps), so the
  profile is realisable by construction.

Problems (Betts, *Practical Methods for Optimal Control*, 2nd ed., ch. 4):

    time-optimal:  min T   s.t. x(0) = rest at q_i, e(q_f, q(T)) = 0, h(T) = 0
    fuel-optimal:  min sum_i int f_i dt (thruster level), or
                   min int sum_i c_i+ tau_i+ + c_i- tau_i- dt (torque level,
                   tau = tau+ - tau-, c the least thrust per unit torque about
                   each signed axis), T given,

e the model's attitude error (three equations; q(T) = q_f would be four,
nearly rank deficient) and h the angular momentum (``model.momenta``).

This module states the problem and nothing about how it is solved: the direct
collocation is :mod:`casadi_debris.slews._transcription`, the flexible terminal
window :mod:`casadi_debris.slews._modal_window`.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from casadi_debris.allocation import authority_polytope
from casadi_debris.config import Problem
from casadi_debris.dynamics import build_model
from casadi_debris.errors import InputShapeError
from casadi_debris.geometry import max_thrust_N
from casadi_debris.slews._maneuver import (
    SlewTarget,
    eigenaxis_acceleration_limit,
    rigid_limit_duration,
    torque_limits,
)
from casadi_debris.slews._options import OptimalSlewSettings
from casadi_debris.slews._propellant import axis_fuel_rates, fuel_weights

# Rows of the model input [tau (3), tau_d (3), F (3)] the controls act on.
TORQUE_ROWS = [0, 1, 2]
FORCE_ROWS = [6, 7, 8]
N_MODEL_INPUTS = 9


class SlewOcp:
    """One rest-to-rest slew OCP on the rigid model, stated apart from its transcription.

    Parameters
    ----------
    problem : Problem
    target : SlewTarget
    options : OptimalSlewSettings

    Attributes
    ----------
    rigid_model, flexible_model : Model
        The model the OCP is stated on (no array modes) and, when
        ``options.flexible``, the one with all modes (else None).
    parameters : ndarray
        The models' nominal parameters.
    inertia : ndarray, shape (3, 3)
        The full rigid inertia at the nominal parameters, kg m^2.
    lower, upper : ndarray, shape (3,)
        Per-axis torque box, N m.
    alpha_max : float
        Eigenaxis acceleration limit, rad/s^2.
    limit_duration_s : float
        Rigid eigenaxis limit 2 sqrt(theta / alpha_max), s.
    f_max : ndarray, shape (n_engines,)
        Each engine's largest thrust, N.

    Raises
    ------
    InputShapeError
        ``options.flexible`` on a problem without array modes.
    """

    def __init__(self, problem: Problem, target: SlewTarget, options: OptimalSlewSettings) -> None:
        self.problem = problem
        self.target = target
        self.options = options
        self.rigid_model = build_model(problem, modes=[])
        self.flexible_model = build_model(problem, "all") if options.flexible else None
        if self.flexible_model is not None and self.flexible_model.layout.n_eta == 0:
            raise InputShapeError("flexible: the problem has no array modes")
        self.geometry = self.rigid_model.geometry
        self.parameters = self.rigid_model.nominal_parameters
        self.lower, self.upper = torque_limits(self.geometry, options.torque_fraction)
        self.inertia = np.array(self.rigid_model.rigid_inertia(self.parameters))
        self.alpha_max = eigenaxis_acceleration_limit(
            self.inertia, target.axis_B, self.lower, self.upper
        )
        self.limit_duration_s = rigid_limit_duration(target.angle_rad, self.alpha_max)
        self.f_max = max_thrust_N(self.geometry)

    @property
    def thrusters(self) -> bool:
        """Thrust per engine is the control (else the torque)."""
        return self.options.thrusters

    @property
    def n_x(self) -> int:
        """Size of the OCP's state: the rigid model's without the star-tracker quaternion."""
        return self.rigid_model.layout.size - 4

    def initial_state(self) -> np.ndarray:
        """Rest at the initial attitude, shape (n_x,)."""
        return self.rigid_model.initial_state(self.target.q_initial_BN)[: self.n_x]

    def control_bounds(self, fuel: bool) -> tuple[np.ndarray, np.ndarray]:
        """(lower, upper) of the controls, SI, shape (n_u,) each.

        Torque level, fuel-optimal: tau+ and tau- apart (six controls, both >= 0), so
        that the propellant is linear in them.
        """
        if self.thrusters:  # the torque fraction scales the engines' torque set
            return np.zeros_like(self.f_max), self.options.torque_fraction * self.f_max
        if fuel:
            return np.zeros(6), np.concatenate([self.upper, -self.lower])
        return self.lower, self.upper

    def torque_set(self) -> tuple[np.ndarray, np.ndarray] | None:
        """The torques the closed loop's allocator can give, ``{tau : N tau <= b}``:
        ``(N, b)``, shapes (m, 3) and (m,) N m, at zero net force and times
        ``torque_fraction``; None at thruster level (tau = B f lies in it by construction).
        """
        if self.thrusters:
            return None
        polytope = authority_polytope(self.geometry.torque_map, self.geometry.force_map, self.f_max)
        return np.asarray(polytope.normals), self.options.torque_fraction * polytope.offsets

    def input_map(self, fuel: bool) -> np.ndarray:
        """G, shape (9, n_u): the model input [tau, 0, F] = G u of this OCP's controls."""
        if self.thrusters:
            n = self.geometry.torque_map.shape[1]
            return np.vstack([self.geometry.torque_map, np.zeros((3, n)), self.geometry.force_map])
        columns = 6 if fuel else 3
        g = np.zeros((N_MODEL_INPUTS, columns))
        g[0:3, 0:3] = np.eye(3)
        if fuel:
            g[0:3, 3:6] = -np.eye(3)
        return g

    def model_inputs(
        self, controls: np.ndarray, fuel: bool
    ) -> tuple[np.ndarray, np.ndarray | None]:
        """Torque (N m, shape (n, 3)) and force (N, or None at torque level) of controls
        (SI, shape (n, n_u))."""
        if self.thrusters:
            return controls @ self.geometry.torque_map.T, controls @ self.geometry.force_map.T
        return (controls[:, 0:3] - controls[:, 3:6] if fuel else controls), None

    def fuel_rates(self, u_scale: np.ndarray) -> np.ndarray:
        """Propellant weight of each (scaled) control in the fuel objective, largest 1;
        engines of different Isp weigh by their mass flow per newton.

        Parameters
        ----------
        u_scale : ndarray, shape (n_u,)
            The controls' scale, SI.
        """
        weights = fuel_weights(self.problem)  # c_max / c_i; None for one Isp
        if self.thrusters:
            if weights is None:
                return u_scale / np.max(u_scale) / len(u_scale)  # sum f_i / (n f_max)
            rates = weights * u_scale
            return rates / np.max(rates) / len(u_scale)
        plus, minus = axis_fuel_rates(self.geometry, weights)
        rates = np.concatenate([plus, minus]) * u_scale
        return rates / np.max(rates)

    def state_scale(self, peak_rate_rad_s: float, duration_s: float) -> np.ndarray:
        """Magnitudes of the states, shape (n_x,), from physics rather than from a guess.

        omega: the peak rate of the guess (rad/s). v: what the engines' net force can
        give in the slew's duration (m/s; thruster level, the torque level has no force).
        """
        lay = self.rigid_model.layout
        scale = np.ones(self.n_x)
        scale[lay.omega] = peak_rate_rad_s
        if self.thrusters:
            total_mass = float(np.array(self.rigid_model.mass_matrix(self.parameters))[0, 0])
            scale[lay.v] = float(np.sum(self.f_max)) * duration_s / total_mass
        return scale

    def eigenaxis_normal(self) -> np.ndarray | None:
        """Single-axis slews: two rows spanning the plane normal to the eigenaxis, shape
        (2, 3), along which the torque must be zero; else None."""
        if not self.options.single_axis:
            return None
        return np.linalg.svd(self.target.axis_B[None, :])[2][1:]

    def terminal_residuals(self, final: ca.MX, peak_rate_rad_s: float) -> list[ca.MX]:
        """What must be zero at the end: the attitude error (3, rad) and the angular
        momentum (3), scaled by the slew's peak momentum about its axis.

        Three attitude equations, not four: the dynamics keep |q| = 1, so
        q(T) = q_f would be (nearly) rank deficient.

        Parameters
        ----------
        final : MX, shape (n_x,)
            The state at the end, SI.
        peak_rate_rad_s : float
            The guess's peak rate, for the momentum's scale.
        """
        model = self.rigid_model
        final_q = final[model.layout.q]
        inertia = np.array(model.rigid_inertia(self.parameters))
        momentum_scale = float(self.target.axis_B @ inertia @ self.target.axis_B) * peak_rate_rad_s
        _, angular = model.momenta(ca.vertcat(final, final_q), self.parameters)
        return [model.attitude_error(self.target.q_final_BN, final_q), angular / momentum_scale]
