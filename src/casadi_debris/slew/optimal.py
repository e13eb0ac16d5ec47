"""Time- and fuel-optimal rest-to-rest slews as CasADi ``Opti`` problems.

Optimal control problem
-----------------------
States x: the rigid model's state without the star tracker (q_BN, omega, v);
the dynamics are the model's own ``dynamics`` Function (``build_model(problem,
modes=[])``, full rigid inertia), called with the sensor state equal to the
attitude (its derivative is then zero). Controls, held on each interval:

- torque level: tau in the per-axis box of the engines' authority
  (:func:`~casadi_debris.slew.maneuver.torque_limits`, times ``torque_fraction``);
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
Transcription: direct collocation on Radau IIA points of degree 3, uniform
intervals (an even count puts the single-axis switch at a node), states and
controls scaled by physical magnitudes, initial guess = the eigenaxis
bang-bang marched through the collocation equations themselves.

Flexible slews
--------------
``flexible`` (``flexible_method="ocp"``, the default) keeps the rigid
collocation for the motion and bounds the vibration left in the arrays exactly
for their linear dynamics. The horizon is a bulk of uniform intervals (free
length T_b) and a terminal window of 32 fixed intervals over W = 1.5 x the
length of the cascaded ZV shaper of all array modes (2.07 s for the paper's
arrays), where the controls are fine enough to cancel a vibration. Each
oscillatory mode's coordinate xi_k (:mod:`casadi_debris.slew.modal`: the
flexible model linearised at rest, all modes, force and torque inputs) is
stepped over every interval in closed form, xi+ = exp(lambda h) xi +
(exp(lambda h) - 1) / lambda w^T B u, with xi at every node a variable, and

    E_vib(xi(T)) <= 0.8 * max(residual_energy_fraction * E_bb, floor),

E_vib as in :func:`~casadi_debris.slew.profile.vibration_energy` (its Hessian
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

``flexible_method="shaper"`` (and the fallback when IPOPT fails on the modal
OCP, said so in ``settings["flexible_method"]``) keeps the optimal rigid
profile and passes it through the cascaded zero-vibration input shaper
(:func:`zero_vibration_shaper`); it lengthens the slew by the shaper's length
(1.38 s); fuel-optimal slews give the rigid problem that much less time.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from casadi_debris.config import Problem
from casadi_debris.errors import InputShapeError, SlewInfeasibleError
from casadi_debris.geometry import max_thrust_N
from casadi_debris.model import Model, build_model, linearize
from casadi_debris.slew.bang_bang import bang_bang_slew
from casadi_debris.slew.maneuver import (
    SlewTarget,
    check_positive,
    check_torque_fraction,
    eigenaxis_acceleration_limit,
    rigid_limit_duration,
    slew_about_axis,
    torque_limits,
)
from casadi_debris.slew.modal import modal_response
from casadi_debris.slew.profile import (
    SlewProfile,
    finish_profile,
    residual_vibration,
    sample_grid,
    simulate,
    vibration_energy,
    zoh_input_function,
)
from casadi_debris.slew.propellant import axis_fuel_rates, least_fuel_thrust

COLLOCATION_DEGREE = 3
RIGID_INTERVALS = 40
REGULARISATION = 1e-6
DEFAULT_RESIDUAL_ENERGY_FRACTION = 0.01
DEFAULT_SAMPLE_S = 1.0
WINDOW_INTERVALS = 32  # 64 gave the same optimum (2 ms shorter) at 1.5x the solve time
WINDOW_SHAPER_MULTIPLE = 1.5
ENERGY_MARGIN = 0.8
FLEXIBLE_METHODS = ("ocp", "shaper")
ACCEPTED_STATUS = ("Solve_Succeeded", "Solved_To_Acceptable_Level")
IPOPT_OPTIONS = {
    "expand": True,
    "print_time": False,
    "ipopt.print_level": 0,
    "ipopt.sb": "yes",
    "ipopt.max_iter": 1500,
    "ipopt.tol": 1e-9,
}
# The modal solve starts from the shaped rigid optimum: a small initial barrier keeps
# IPOPT from first pushing every saturated control to mid-range.
WARM_START_OPTIONS = {"ipopt.mu_init": 1e-3}
# At thruster level 24 thrusts per interval give six numbers; with the monotone barrier
# update IPOPT reaches the barrier floor while still far from the optimum and crawls
# (z slew: 133 iterations, 3.3 s; four test slews: 1.4 to 3.3 s against 0.9 to 1.3 s).
THRUSTER_OPTIONS = {"ipopt.mu_strategy": "adaptive"}
ENERGY_FLOOR = 1e-12


@dataclass(frozen=True)
class _Collocation:
    """Radau IIA collocation matrices on [0, 1] (CasADi's direct_collocation example)."""

    tau: np.ndarray  # (d + 1,) with the interval start 0 first
    derivative: np.ndarray  # C[r, j]: d/dtau of Lagrange basis r at point j
    end: np.ndarray  # D[r]: basis r at tau = 1

    @classmethod
    def radau(cls, degree: int) -> _Collocation:
        tau = np.concatenate([[0.0], ca.collocation_points(degree, "radau")])
        derivative = np.zeros((degree + 1, degree + 1))
        end = np.zeros(degree + 1)
        for r in range(degree + 1):
            basis = np.poly1d([1.0])
            for s in range(degree + 1):
                if s != r:
                    basis *= np.poly1d([1.0, -tau[s]]) / (tau[r] - tau[s])
            end[r] = basis(1.0)
            slope = np.polyder(basis)
            derivative[r] = [slope(point) for point in tau]
        return cls(tau, derivative, end)


@dataclass(frozen=True)
class _Collocated:
    """Collocation of one interval on the rigid model, states scaled by ``x_scale``.

    ``interval(xk, xc, uk, h) -> (defects (n_x x d), x_end)``, scaled states and controls.
    """

    n_x: int
    x_scale: np.ndarray
    interval: ca.Function


@dataclass(frozen=True)
class _Request:
    """What :meth:`_SlewOCP.solve` was asked for (see :func:`time_optimal_slew`)."""

    objective: str  # "time" or "fuel"
    duration_s: float | None
    intervals: int | None
    residual_energy_fraction: float
    sample_s: float
    check_vibration: bool

    @property
    def fuel(self) -> bool:
        return self.objective == "fuel"


@dataclass(frozen=True)
class _Solution:
    """What the NLP gives: control knots (s, N + 1), held controls (N x n_u, SI), IPOPT
    status, and the vibration energy its closed form predicts at the end (J; 0 if rigid)."""

    knots_s: np.ndarray
    controls: np.ndarray
    status: str
    predicted_energy_J: float


def zero_vibration_shaper(
    model: Model, parameters: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cascaded zero-vibration (ZV) input shaper for every array mode of a model.

    For a mode of natural frequency omega_n and damping zeta (poles of the
    model linearised at rest, :func:`casadi_debris.model.linearize`) the ZV
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


class _SlewOCP:
    """One slew OCP on the rigid model (module notes); ``flexible`` shapes its result."""

    def __init__(
        self,
        problem: Problem,
        target: SlewTarget,
        *,
        flexible: bool,
        thrusters: bool,
        torque_fraction: float,
        single_axis: bool,
        zero_net_force: bool = False,
    ) -> None:
        if single_axis and thrusters:
            raise InputShapeError("single_axis applies to torque-level slews only")
        if zero_net_force and not thrusters:
            raise InputShapeError(
                "zero_net_force applies to thruster-level slews (a torque-level one has no force)"
            )
        self.zero_net_force = zero_net_force
        self.problem = problem
        self.target = target
        self.flexible = flexible
        self.thrusters = thrusters
        self.single_axis = single_axis
        self.torque_fraction = torque_fraction
        self.rigid_model = build_model(problem, modes=[])
        self.flexible_model = build_model(problem, "all") if flexible else None
        if flexible and self.flexible_model.layout.n_eta == 0:
            raise InputShapeError("flexible: the problem has no array modes")
        self.geometry = self.rigid_model.geometry
        self.parameters = self.rigid_model.nominal_parameters
        self.lower, self.upper = torque_limits(self.geometry, torque_fraction)
        inertia = np.array(self.rigid_model.rigid_inertia(self.parameters))
        self.alpha_max = eigenaxis_acceleration_limit(
            inertia, target.axis_B, self.lower, self.upper
        )
        self.limit_duration_s = rigid_limit_duration(target.angle_rad, self.alpha_max)
        self.f_max = max_thrust_N(self.geometry)
        self._references: dict[float, SlewProfile] = {}

    # -- model pieces ------------------------------------------------------------------
    def _control_bounds(self, fuel: bool) -> tuple[np.ndarray, np.ndarray]:
        if self.thrusters:  # the torque fraction scales the engines' torque set
            return np.zeros_like(self.f_max), self.torque_fraction * self.f_max
        if fuel:
            return np.zeros(6), np.concatenate([self.upper, -self.lower])
        return self.lower, self.upper

    def _input_map(self, fuel: bool) -> np.ndarray:
        """G (9 x n_u): model input [tau, 0, F] = G u for this OCP's controls (linear)."""
        if self.thrusters:
            n = self.geometry.torque_map.shape[1]
            return np.vstack([self.geometry.torque_map, np.zeros((3, n)), self.geometry.force_map])
        columns = 6 if fuel else 3
        g = np.zeros((9, columns))
        g[0:3, 0:3] = np.eye(3)
        if fuel:
            g[0:3, 3:6] = -np.eye(3)
        return g

    def _collocation(self, x_scale: np.ndarray, input_map: np.ndarray) -> _Collocated:
        """Radau collocation equations of one interval on the rigid model (scaled).

        ``input_map`` (9 x n_in): the model input [tau, 0, F] of the interval's input.
        """
        model = self.rigid_model
        colloc = _Collocation.radau(COLLOCATION_DEGREE)
        n_x = model.layout.size - 4  # without the star-tracker quaternion (last)
        xk = ca.SX.sym("xk", n_x)
        xc = ca.SX.sym("xc", n_x, COLLOCATION_DEGREE)
        uk = ca.SX.sym("uk", input_map.shape[1])
        h = ca.SX.sym("h")
        x_s = ca.DM(x_scale)
        u_model = ca.DM(input_map) @ uk
        points = ca.horzcat(xk, xc)
        defects = []
        for j in range(1, COLLOCATION_DEGREE + 1):
            slope = points @ ca.DM(colloc.derivative[:, j])
            state = points[:, j] * x_s
            rate = model.dynamics(
                ca.vertcat(state, state[model.layout.q]), u_model, self.parameters
            )
            defects.append(h * rate[:n_x] / x_s - slope)
        single = ca.Function(
            "interval", [xk, xc, uk, h], [ca.horzcat(*defects), points @ ca.DM(colloc.end)]
        )
        return _Collocated(n_x, x_scale, single)

    # -- initial guess and scaling ----------------------------------------------------
    def _reference(self, duration_s: float) -> SlewProfile:
        """Eigenaxis bang-bang at ``duration_s`` (at least the rigid limit): the initial guess."""
        duration_s = max(duration_s, self.limit_duration_s)
        if duration_s not in self._references:
            self._references[duration_s] = bang_bang_slew(
                self.problem,
                target=self.target,
                duration_s=duration_s,
                check_vibration=False,
                model=self.rigid_model,
            )
        return self._references[duration_s]

    def _energy_limit(self, fraction: float) -> tuple[float, float]:
        """(limit, bang-bang energy), J: the vibration energy a flexible slew may leave.

        ``fraction`` of what the eigenaxis bang-bang at the rigid limit leaves (CVODES,
        full flexible model), but at least ENERGY_FLOOR times the slew's peak kinetic
        energy: a slew that excites no mode linearly (about x the bang-bang leaves
        1e-35 J) is not held to nothing, and what the nonlinear terms excite there
        (1e-18 J) is not worth constraining.
        """
        reference = self._reference(self.limit_duration_s)
        knots = np.array([0.0, reference.duration_s / 2.0, reference.duration_s])
        states = simulate(
            self.flexible_model,
            reference.input_function,
            knots,
            self.flexible_model.initial_state(self.target.q_initial_BN),
            self.parameters,
        )
        energy = vibration_energy(self.flexible_model, states[-1], self.parameters)
        settings = reference.settings
        kinetic = 0.5 * settings["inertia_about_axis_kgm2"] * settings["peak_rate_rad_s"] ** 2
        return max(fraction * energy, ENERGY_FLOOR * kinetic), energy

    def _state_scale(self, peak_rate_rad_s: float, duration_s: float) -> np.ndarray:
        """Magnitudes of the rigid states, from physics rather than from a guess.

        omega: the peak rate of the guess. v: what the engines' net force can give
        in the slew's duration (thruster level; the torque level has no force).
        """
        lay = self.rigid_model.layout
        scale = np.ones(lay.size - 4)
        scale[lay.omega] = peak_rate_rad_s
        if self.thrusters:
            total_mass = float(np.array(self.rigid_model.mass_matrix(self.parameters))[0, 0])
            scale[lay.v] = float(np.sum(self.f_max)) * duration_s / total_mass
        return scale

    @staticmethod
    def _march(
        colloc: _Collocated, x0: np.ndarray, controls: np.ndarray, steps_s: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Integrate the guess with the transcription itself (Newton on each interval).

        A guess that satisfies the collocation equations exactly leaves IPOPT only
        the end conditions to fix.
        """
        n, d = colloc.n_x, COLLOCATION_DEGREE
        unknown = ca.SX.sym("xc", n * d)
        given = ca.SX.sym("given", n + controls.shape[0] + 1)
        defects, end = colloc.interval(given[:n], ca.reshape(unknown, n, d), given[n:-1], given[-1])
        solver = ca.rootfinder(
            "march",
            "newton",
            ca.Function("collocation", [unknown, given], [ca.vec(defects)]),
            {"abstol": 1e-10, "max_iter": 50, "error_on_fail": False},
        )
        end_state = ca.Function("end", [unknown, given], [end])
        nodes, inner = [x0], []
        for k, step_s in enumerate(steps_s):
            parameters = np.concatenate([nodes[-1], controls[:, k], [step_s]])
            solution = solver(np.tile(nodes[-1], d), parameters)
            inner.append(np.array(solution).reshape(d, n).T)
            nodes.append(np.array(end_state(solution, parameters)).ravel())
        return np.array(nodes).T, np.hstack(inner)

    # -- the NLP -----------------------------------------------------------------------
    def solve(
        self,
        *,
        objective: str,
        duration_s: float | None,
        intervals: int | None,
        residual_energy_fraction: float,
        sample_s: float,
        check_vibration: bool,
        flexible_method: str = "ocp",
    ) -> SlewProfile:
        """Transcribe and solve.

        ``flexible_method``: ``"ocp"`` (the vibration left constrained in closed
        form, module notes) or ``"shaper"`` (the rigid optimum through a ZV shaper).
        """
        request = _Request(
            objective, duration_s, intervals, residual_energy_fraction, sample_s, check_vibration
        )
        if flexible_method not in FLEXIBLE_METHODS:
            raise InputShapeError(
                f"flexible_method: one of {', '.join(FLEXIBLE_METHODS)}, got {flexible_method!r}"
            )
        if not self.flexible or flexible_method == "shaper":
            return self._solve_rigid_or_shaped(request)
        try:
            return self._solve_modal(request)
        except SlewInfeasibleError as error:
            if "did not converge" not in str(error):
                raise
            failure = str(error)
        profile = self._solve_rigid_or_shaped(request)
        profile.settings["flexible_method"] = f"shaper (fallback: modal {failure})"
        return profile

    def _transcribe_and_solve(
        self,
        *,
        fuel: bool,
        bulk_s: float | None,
        bulk_intervals: int,
        window: tuple[int, float],
        energy_limit_J: float | None,
        guess: Callable[[np.ndarray], np.ndarray],
        guess_total_s: float,
        peak_rate_rad_s: float,
    ) -> _Solution:
        """Build the NLP on the rigid model and solve it with IPOPT.

        Parameters
        ----------
        fuel
            Minimise propellant (``bulk_s`` given) rather than time.
        bulk_s
            Length of the uniform bulk intervals together (fuel-optimal), or None
            (free: time-optimal).
        bulk_intervals
            How many bulk intervals (Radau collocation of degree 3 each).
        window
            (count, length of each in s) of the fixed intervals that end the horizon.
        energy_limit_J
            Bound on the vibration energy left at the end (closed form,
            :mod:`casadi_debris.slew.modal`), or None.
        guess, guess_total_s, peak_rate_rad_s
            Initial guess: its controls (SI, shape (n, n_u)) at given times, its
            length (s) and its peak rate (rad/s).
        """
        lower_u, upper_u = self._control_bounds(fuel)
        u_scale = np.maximum(np.maximum(np.abs(lower_u), np.abs(upper_u)), 1e-30)
        n_u = len(u_scale)
        (m, window_step_s), n = window, bulk_intervals
        x_scale = self._state_scale(peak_rate_rad_s, guess_total_s)

        opti = ca.Opti()
        bulk_guess = guess_total_s - m * window_step_s
        if bulk_s is None:
            bulk_scaled = opti.variable()
            bulk = bulk_scaled * self.limit_duration_s
            opti.subject_to(opti.bounded(0.05, bulk_scaled, 20.0))
            opti.set_initial(bulk_scaled, bulk_guess / self.limit_duration_s)
        else:
            bulk = ca.MX(bulk_s)
        steps = ca.vertcat(ca.repmat(bulk / n, n, 1), ca.DM.ones(m) * window_step_s)
        n_x = self.rigid_model.layout.size - 4
        X = opti.variable(n_x, n + m + 1)
        XC = opti.variable(n_x, (n + m) * COLLOCATION_DEGREE)
        U = opti.variable(n_u, n + m)
        drive, drive_map, to_drive = self._drive(opti, U, u_scale, fuel)
        colloc = self._collocation(x_scale, drive_map)
        defect, ends = colloc.interval.map(n + m)(X[:, :-1], XC, drive, steps.T)
        opti.subject_to(ca.vec(defect) == 0)
        opti.subject_to(ca.vec(X[:, 1:] - ends) == 0)
        opti.subject_to(
            opti.bounded(
                np.tile((lower_u / u_scale)[:, None], n + m),
                U,
                np.tile((upper_u / u_scale)[:, None], n + m),
            )
        )
        if self.single_axis:  # torque along the eigenaxis: two rows spanning its normal plane
            across = np.linalg.svd(self.target.axis_B[None, :])[2][1:]
            scaled = ca.DM(across @ np.diag(u_scale / np.max(u_scale)))
            opti.subject_to(ca.vec(scaled @ U) == 0)
        x0 = self.rigid_model.initial_state(self.target.q_initial_BN)[:n_x]
        opti.subject_to(X[:, 0] == x0 / x_scale)
        self._rest_at_target(opti, X[:, -1] * ca.DM(x_scale), peak_rate_rad_s)
        # Initial guess: its controls, marched through the transcription.
        guess_steps = np.concatenate([np.full(n, bulk_guess / n), np.full(m, window_step_s)])
        controls = guess(np.cumsum(guess_steps) - guess_steps / 2.0).T / u_scale[:, None]
        drives = to_drive @ controls
        nodes, inner = self._march(colloc, x0 / x_scale, drives, guess_steps)
        opti.set_initial(X, nodes)
        opti.set_initial(XC, inner)
        opti.set_initial(U, controls)
        if drive is not U:
            opti.set_initial(drive, drives)
        energy = ca.MX(0.0)
        if energy_limit_J is not None:
            energy = self._bound_vibration(
                opti, drive, steps, energy_limit_J, drive_map, (guess_steps, drives)
            )
        # Integrals as sums over the intervals, in units of the guess's duration.
        weights = steps / guess_total_s
        if fuel:
            cost = ca.dot(weights, (ca.DM(self._fuel_rates(u_scale)).T @ U).T)
        else:
            # The regulariser only picks one of many equally fast controls (least thrust, or
            # least squared torque); each interval counts the same, however short, so that
            # the window's controls are as well determined as the bulk's.
            effort = ca.sum1(U) / n_u if self.thrusters else ca.sum1(U**2)
            cost = ca.sum1(steps) / guess_total_s + REGULARISATION * ca.sum2(effort) / (n + m)
        opti.minimize(cost)
        options = dict(THRUSTER_OPTIONS) if self.thrusters else {}
        if energy_limit_J is not None:
            options.update(WARM_START_OPTIONS)
        value, status = _solve_with_ipopt(opti, options)
        return _Solution(
            knots_s=np.concatenate([[0.0], np.cumsum(np.array(value(steps)).ravel())]),
            # IPOPT meets bounds to 1e-8 of their size (bound_relax_factor): clip back.
            controls=np.clip(np.array(value(U)).reshape(n_u, n + m).T * u_scale, lower_u, upper_u),
            status=status,
            predicted_energy_J=float(value(energy)),
        )

    def _drive(
        self, opti: ca.Opti, controls: ca.MX, u_scale: np.ndarray, fuel: bool
    ) -> tuple[ca.MX, np.ndarray, np.ndarray]:
        """What the dynamics see of the (scaled) controls: (drive, its 9 x n_d model-input
        map, the n_d x n_u map from controls to drive).

        Torque level: the controls themselves. Thruster level: the 24 thrusts act on the
        motion and on the modes only through six numbers, the torque and the force (three
        with ``zero_net_force``, which holds the force at zero), so
        those are variables of their own (scaled by sum_i |B_ki| f_max,i, at most twice
        what the engines give about each axis) with six linear equations per interval;
        every collocation and modal row then depends on six variables instead of 24, and
        the KKT matrix stays sparse.
        """
        input_map = self._input_map(fuel) * u_scale
        if not self.thrusters:
            return controls, input_map, np.eye(len(u_scale))
        torque_rows, force_rows = [0, 1, 2], [6, 7, 8]  # of the model input
        acting = torque_rows if self.zero_net_force else torque_rows + force_rows
        if self.zero_net_force:
            force = input_map[force_rows]
            force = force / np.maximum(np.sum(np.abs(force), axis=1), 1e-30)[:, None]
            opti.subject_to(ca.vec(ca.DM(force) @ controls) == 0)
        effect = input_map[acting]
        drive_scale = np.maximum(np.sum(np.abs(effect), axis=1), 1e-30)
        drive_map = np.zeros((9, len(acting)))
        drive_map[acting, np.arange(len(acting))] = drive_scale
        to_drive = effect / drive_scale[:, None]
        drive = opti.variable(len(acting), controls.shape[1])
        opti.subject_to(ca.vec(drive - ca.DM(to_drive) @ controls) == 0)
        return drive, drive_map, to_drive

    def _bound_vibration(
        self,
        opti: ca.Opti,
        drive: ca.MX,
        steps: ca.MX,
        energy_limit_J: float,
        input_map: np.ndarray,
        guess: tuple[np.ndarray, np.ndarray],
    ) -> ca.MX:
        """Bound the vibration energy left at the end by ``energy_limit_J``; return it.

        The modes' coordinates xi at every node are variables, stepped interval by
        interval in closed form (:class:`~casadi_debris.slew.modal.ModalResponse`).
        A sum over the horizon instead makes the constraint rows dense in every
        control, and CasADi's Jacobian colouring then takes seconds.

        Parameters
        ----------
        drive : MX, shape (n_d, N)
            What drives the model on each interval (scaled, :meth:`_drive`);
            ``input_map`` (9 x n_d) gives the model input of one.
        steps : MX, shape (N, 1)
            Interval lengths, s.
        guess : (steps_s, drive)
            The initial guess, marched to start xi and to scale it.
        """
        response = modal_response(self.flexible_model, self.parameters)
        k = len(response.eigenvalues)
        xi, h, u = ca.SX.sym("xi", 2 * k), ca.SX.sym("h"), ca.SX.sym("u", input_map.shape[1])

        def step(coordinates: ca.SX) -> ca.SX:
            return ca.vertcat(
                *response.step(coordinates[:k], coordinates[k:], h, ca.DM(input_map) @ u)
            )

        march = ca.Function("modal_step", [xi, h, u], [step(xi)])
        path = [np.zeros(2 * k)]
        for step_s, control in zip(guess[0], guess[1].T, strict=True):
            path.append(np.array(march(path[-1], step_s, control)).ravel())
        path = np.array(path).T
        # xi's size: the largest of the guess, at least what alone holds half the limit.
        floor = np.sqrt(energy_limit_J / np.diag(response.energy_form))
        scale = np.maximum(np.max(np.abs(path), axis=1), floor)
        scaled = ca.Function("scaled_modal_step", [xi, h, u], [step(xi * scale) / scale])
        count = path.shape[1] - 1
        XI = opti.variable(2 * k, count + 1)
        opti.subject_to(XI[:, 0] == 0)
        opti.subject_to(ca.vec(XI[:, 1:] - scaled.map(count)(XI[:, :-1], steps.T, drive)) == 0)
        opti.set_initial(XI, path / scale[:, None])
        final = XI[:, -1] * ca.DM(scale)
        energy = response.energy(final[:k], final[k:])
        opti.subject_to(energy / energy_limit_J <= 1.0)
        return energy

    def _solve_rigid(
        self, fuel: bool, duration_s: float | None, intervals: int | None
    ) -> tuple[_Solution, float]:
        """The rigid OCP from the eigenaxis bang-bang; its solution and the guess's peak rate."""
        reference = self._reference(duration_s if fuel else self.limit_duration_s)
        peak_rate = float(np.max(np.linalg.norm(reference.rate_rad_s, axis=1)))
        solution = self._transcribe_and_solve(
            fuel=fuel,
            bulk_s=duration_s if fuel else None,
            bulk_intervals=intervals or RIGID_INTERVALS,
            window=(0, 0.0),
            energy_limit_J=None,
            guess=lambda times: self._control_guess(reference, times, fuel),
            guess_total_s=duration_s if fuel else reference.duration_s,
            peak_rate_rad_s=peak_rate,
        )
        return solution, peak_rate

    def _solve_modal(self, request: _Request) -> SlewProfile:
        """Rigid bulk and fine window, the vibration left bounded in closed form (module notes)."""
        fuel, duration_s = request.fuel, request.duration_s
        shaper_times, shaper_amplitudes, _ = zero_vibration_shaper(
            self.flexible_model, self.parameters
        )
        shaper_length = float(shaper_times[-1])
        reference_started = time.perf_counter()
        energy_limit, reference_energy = self._energy_limit(request.residual_energy_fraction)
        reference_time = time.perf_counter() - reference_started
        started = time.perf_counter()
        window_s = WINDOW_SHAPER_MULTIPLE * shaper_length
        # Guess: the rigid optimum through the ZV shaper. Its length must be nearly right:
        # the modes' phase at the end turns by omega dT, 36 rad per second of change.
        rigid_length = None
        if fuel:
            rigid_length = duration_s - shaper_length
            if rigid_length < self.limit_duration_s:
                # Within a shaper's length of the minimum the rigid problem may have no
                # solution: ask it for no less than 1.001 x its own minimum.
                fastest, _ = self._solve_rigid(False, None, request.intervals)
                rigid_length = max(rigid_length, 1.001 * float(fastest.knots_s[-1]))
        rigid, peak_rate = self._solve_rigid(fuel, rigid_length, request.intervals)
        knots, controls = shape(rigid.knots_s, rigid.controls, shaper_times, shaper_amplitudes)
        if fuel:  # squeezed into the duration if it came out longer
            knots = knots * min(1.0, duration_s / float(knots[-1]))
        solution = self._transcribe_and_solve(
            fuel=fuel,
            bulk_s=duration_s - window_s if fuel else None,
            bulk_intervals=request.intervals or RIGID_INTERVALS,
            window=(WINDOW_INTERVALS, window_s / WINDOW_INTERVALS),
            energy_limit_J=ENERGY_MARGIN * energy_limit,
            guess=lambda times: held(knots, controls, times),
            guess_total_s=float(knots[-1]),
            peak_rate_rad_s=peak_rate,
        )
        settings = {
            "flexible_method": "ocp",
            "window_s": window_s,
            "window_intervals": WINDOW_INTERVALS,
            "rigid_duration_s": float(rigid.knots_s[-1]),
            "predicted_residual_energy_J": solution.predicted_energy_J,
            "residual_energy_limit_J": energy_limit,
            "bang_bang_residual_energy_J": reference_energy,
            "reference_energy_time_s": reference_time,
            "shaper_length_s": shaper_length,
        }
        return self._profile(
            request,
            solution,
            solve_time=time.perf_counter() - started,
            extra_settings=settings,
        )

    def _solve_rigid_or_shaped(self, request: _Request) -> SlewProfile:
        """The rigid OCP; when ``flexible``, its result through the ZV shaper."""
        started = time.perf_counter()
        fuel, duration_s = request.fuel, request.duration_s
        if self.flexible:
            shaper_times, shaper_amplitudes, shaped_frequencies = zero_vibration_shaper(
                self.flexible_model, self.parameters
            )
            if fuel:  # the shaper stretches the rigid profile by its length
                duration_s = duration_s - float(shaper_times[-1])
        solution, _ = self._solve_rigid(fuel, duration_s, request.intervals)
        solve_time = time.perf_counter() - started
        knots, controls = solution.knots_s, solution.controls
        settings = {}
        if self.flexible:
            rigid_duration = float(knots[-1])
            knots, controls = shape(knots, controls, shaper_times, shaper_amplitudes)
            energy_limit, _ = self._energy_limit(request.residual_energy_fraction)
            settings = {
                "flexible_method": "shaper",
                "rigid_duration_s": rigid_duration,
                "shaped_frequencies_rad_s": shaped_frequencies,
                "shaper_length_s": float(shaper_times[-1]),
                "residual_energy_limit_J": energy_limit,
            }
        return self._profile(
            request,
            dataclasses.replace(solution, knots_s=knots, controls=controls),
            solve_time=solve_time,
            extra_settings=settings,
        )

    def _fuel_rates(self, u_scale: np.ndarray) -> np.ndarray:
        """Propellant weight of each (scaled) control in the fuel objective, largest 1."""
        if self.thrusters:
            return u_scale / np.max(u_scale) / len(u_scale)  # sum f_i / (n f_max)
        plus, minus = axis_fuel_rates(self.geometry)
        rates = np.concatenate([plus, minus]) * u_scale
        return rates / np.max(rates)

    def _rest_at_target(self, opti: ca.Opti, final: ca.MX, peak_rate: float) -> None:
        """End on the target attitude with no angular momentum (``final``: rigid state).

        Three attitude equations, not four: the dynamics keep |q| = 1, so
        q(T) = q_f would be (nearly) rank deficient.
        """
        model = self.rigid_model
        final_q = final[model.layout.q]
        opti.subject_to(model.attitude_error(self.target.q_final_BN, final_q) == 0)
        inertia = np.array(model.rigid_inertia(self.parameters))
        momentum_scale = float(self.target.axis_B @ inertia @ self.target.axis_B) * peak_rate
        _, angular = model.momenta(ca.vertcat(final, final_q), self.parameters)
        opti.subject_to(angular / momentum_scale == 0)

    def _control_guess(self, reference: SlewProfile, times_s: np.ndarray, fuel: bool) -> np.ndarray:
        """Controls of the torque-level ``reference`` at ``times_s`` in this OCP's form,
        shape (n, n_u)."""
        inputs = np.array(reference.input_function.map(len(times_s))(times_s)).T
        torque = np.clip(inputs[:, :3], self.lower, self.upper)
        if self.thrusters:
            return least_fuel_thrust(self.geometry, torque)[0]
        if fuel:
            return np.hstack([np.maximum(torque, 0.0), np.maximum(-torque, 0.0)])
        return torque

    def _profile(
        self, request: _Request, solution: _Solution, *, solve_time: float, extra_settings: dict
    ) -> SlewProfile:
        """The solution as a profile, integrated on the flexible model if there is one."""
        knots, controls = solution.knots_s, solution.controls
        model = self.flexible_model if self.flexible else self.rigid_model
        lay = model.layout
        total = float(knots[-1])
        if self.thrusters:
            torque = controls @ self.geometry.torque_map.T
            force = controls @ self.geometry.force_map.T
        else:
            torque = controls[:, 0:3] - controls[:, 3:6] if request.fuel else controls
            force = None
        input_function = zoh_input_function(knots, torque, force)
        grid = sample_grid(total, request.sample_s, knots)
        states = simulate(
            model,
            input_function,
            grid,
            model.initial_state(self.target.q_initial_BN),
            self.parameters,
        )
        inputs = np.array(input_function.map(len(grid))(grid)).T
        accelerations = np.array(
            [
                np.array(model.dynamics(x, u, self.parameters)).ravel()[lay.omega]
                for x, u in zip(states, inputs, strict=True)
            ]
        )
        final_error = np.array(
            model.attitude_error(self.target.q_final_BN, states[-1, lay.q])
        ).ravel()
        settings = {
            "torque_fraction": self.torque_fraction,
            "control_intervals": len(knots) - 1,
            "collocation_degree": COLLOCATION_DEGREE,
            "final_attitude_error_rad": float(np.linalg.norm(final_error)),
            "final_rate_rad_s": float(np.linalg.norm(states[-1, lay.omega])),
            "single_axis": self.single_axis,
        }
        settings.update(extra_settings)
        if self.thrusters:
            settings["delta_v_m_s"] = float(np.linalg.norm(states[-1, lay.v]))
        return finish_profile(
            problem=self.problem,
            geometry=self.geometry,
            method=f"{request.objective}-optimal",
            target=self.target,
            flexible=self.flexible,
            thrusters=self.thrusters,
            time_s=grid,
            quaternion_BN=states[:, lay.q],
            rate_rad_s=states[:, lay.omega],
            acceleration_rad_s2=accelerations,
            input_function=input_function,
            knots_s=knots,
            interval_thrust_N=controls if self.thrusters else None,
            duration_s=total,
            limit_duration_s=self.limit_duration_s,
            solve_time_s=solve_time,
            solver_status=solution.status,
            settings=settings,
            check_vibration=request.check_vibration,
            flexible_model=self.flexible_model,
        )


def time_optimal_slew(
    problem: Problem,
    axis: str | Sequence[float] = "z",
    angle_rad: float = math.pi,
    *,
    target: SlewTarget | None = None,
    flexible: bool = False,
    thrusters: bool = False,
    zero_net_force: bool = False,
    torque_fraction: float = 1.0,
    single_axis: bool = False,
    intervals: int | None = None,
    residual_energy_fraction: float = DEFAULT_RESIDUAL_ENERGY_FRACTION,
    sample_s: float = DEFAULT_SAMPLE_S,
    check_vibration: bool = True,
    duration_s: float | None = None,
    flexible_method: str = "ocp",
) -> SlewProfile:
    """Minimum-time rest-to-rest slew (free final time, nonlinear attitude dynamics).

    Parameters
    ----------
    problem : Problem
    axis, angle_rad
        Eigenaxis and angle in (0, pi] (ignored when ``target`` is given).
    target : SlewTarget, optional
        Any rest-to-rest attitude pair.
    flexible : bool
        Keep the array modes: the vibration energy left at the end is constrained to
        0.8 x max(``residual_energy_fraction`` x the rigid-limit bang-bang's, 1e-12 x
        the slew's peak kinetic energy) (module notes).
    thrusters : bool
        Thrust per engine as the decision variable (0 <= f <= torque_fraction f_max).
    zero_net_force : bool
        Thruster level: the engines' net force is zero at every instant, as the
        closed loop's allocator keeps it, so the closed loop can fly the profile.
    torque_fraction : float
        Share of the torque authority usable in (0, 1]: of each per-axis limit at
        torque level, of each engine's thrust at thruster level.
    single_axis : bool
        Restrict the torque to the eigenaxis (the single-degree-of-freedom slew).
    intervals : int, optional
        Collocation intervals (even; default 40); a flexible slew adds its 32 window
        intervals.
    residual_energy_fraction : float
        Flexible only: the reported limit on the vibration energy left, as a fraction of
        what the bang-bang at the rigid limit leaves.
    sample_s : float
        Output sample spacing (the control knots are added).
    check_vibration : bool
        Integrate the result on the full flexible model for the residual vibration.
    duration_s : float, optional
        A deadline (s): the slew must not take longer. Checked after the solve.
    flexible_method : {"ocp", "shaper"}
        Flexible only: ``"ocp"`` solves with the modal states (falling back to the
        shaper, and saying so in ``settings["flexible_method"]``, if IPOPT fails);
        ``"shaper"`` passes the rigid optimum through a zero-vibration shaper.

    Returns
    -------
    SlewProfile

    Raises
    ------
    SlewInfeasibleError
        ``"infeasible: minimum is X s"`` when ``duration_s`` is shorter than the
        time-optimal slew; or IPOPT did not converge.

    Examples
    --------
    >>> from casadi_debris import load_problem
    >>> slew = time_optimal_slew(load_problem(), "z", math.pi, check_vibration=False)
    >>> round(slew.duration_s)
    903
    """
    _check_common(torque_fraction, residual_energy_fraction, sample_s, intervals)
    if duration_s is not None and not math.isfinite(duration_s):
        raise InputShapeError(f"duration_s: must be finite, got {duration_s}")
    goal = slew_about_axis(axis, angle_rad) if target is None else target
    ocp = _SlewOCP(
        problem,
        goal,
        flexible=flexible,
        thrusters=thrusters,
        torque_fraction=torque_fraction,
        single_axis=single_axis,
        zero_net_force=zero_net_force,
    )
    fastest = ocp.solve(
        objective="time",
        duration_s=None,
        intervals=intervals,
        residual_energy_fraction=residual_energy_fraction,
        sample_s=sample_s,
        check_vibration=check_vibration and duration_s is None,
        flexible_method=flexible_method,
    )
    if duration_s is None:
        return fastest
    if duration_s < fastest.duration_s:
        raise SlewInfeasibleError(f"infeasible: minimum is {fastest.duration_s:.6g} s")
    if not check_vibration:
        return fastest
    # The deadline is met: now the (long) check on the flexible model.
    vibration, energy = residual_vibration(
        problem,
        goal,
        fastest.input_function,
        fastest.time_s,
        fastest.duration_s,
        ocp.flexible_model,
    )
    return dataclasses.replace(fastest, residual_vibration_rad=vibration, residual_energy_J=energy)


def fuel_optimal_slew(
    problem: Problem,
    axis: str | Sequence[float] = "z",
    angle_rad: float = math.pi,
    *,
    duration_s: float,
    target: SlewTarget | None = None,
    flexible: bool = False,
    thrusters: bool = False,
    zero_net_force: bool = False,
    torque_fraction: float = 1.0,
    intervals: int | None = None,
    residual_energy_fraction: float = DEFAULT_RESIDUAL_ENERGY_FRACTION,
    sample_s: float = DEFAULT_SAMPLE_S,
    check_vibration: bool = True,
    flexible_method: str = "ocp",
) -> SlewProfile:
    """Least-propellant rest-to-rest slew of a given duration.

    Parameters are those of :func:`time_optimal_slew`, plus ``duration_s`` (s).
    Durations below the rigid eigenaxis limit are checked against the
    time-optimal slew first.

    Raises
    ------
    SlewInfeasibleError
        ``"infeasible: minimum is X s"`` when ``duration_s`` is shorter than the
        time-optimal slew; or IPOPT did not converge.
    """
    _check_common(torque_fraction, residual_energy_fraction, sample_s, intervals)
    if not math.isfinite(duration_s):
        raise InputShapeError(f"duration_s: must be finite, got {duration_s}")
    goal = slew_about_axis(axis, angle_rad) if target is None else target
    ocp = _SlewOCP(
        problem,
        goal,
        flexible=flexible,
        thrusters=thrusters,
        torque_fraction=torque_fraction,
        single_axis=False,
        zero_net_force=zero_net_force,
    )
    if duration_s < ocp.limit_duration_s:
        # Three free axes can beat the eigenaxis limit (Bilimoria & Wie 1993): ask the OCP.
        fastest = ocp.solve(
            objective="time",
            duration_s=None,
            intervals=intervals,
            residual_energy_fraction=residual_energy_fraction,
            sample_s=sample_s,
            check_vibration=False,
            flexible_method=flexible_method,
        )
        if duration_s < fastest.duration_s:
            raise SlewInfeasibleError(f"infeasible: minimum is {fastest.duration_s:.6g} s")
    return ocp.solve(
        objective="fuel",
        duration_s=duration_s,
        intervals=intervals,
        residual_energy_fraction=residual_energy_fraction,
        sample_s=sample_s,
        check_vibration=check_vibration,
        flexible_method=flexible_method,
    )


def _check_common(
    torque_fraction: float, energy_fraction: float, sample_s: float, intervals: int | None
) -> None:
    check_torque_fraction(torque_fraction)
    check_positive("residual_energy_fraction", energy_fraction)
    check_positive("sample_s", sample_s)
    if intervals is not None and (intervals < 2 or intervals % 2):
        raise InputShapeError(f"intervals: must be an even number >= 2, got {intervals}")


def _solve_with_ipopt(opti: ca.Opti, options: dict[str, Any]) -> tuple[Any, str]:
    """Solve with IPOPT: the solution's ``value`` function and the return status.

    ``options`` are added to ``IPOPT_OPTIONS``.

    Raises
    ------
    SlewInfeasibleError
        IPOPT ended in a status not in ``ACCEPTED_STATUS``.
    """
    opti.solver("ipopt", {**IPOPT_OPTIONS, **options})
    try:
        solution = opti.solve()
        status = solution.stats()["return_status"]
        value = solution.value
    except RuntimeError:
        status = opti.stats().get("return_status", "failed")
        value = opti.debug.value
    if status not in ACCEPTED_STATUS:
        raise SlewInfeasibleError(f"optimal slew did not converge (ipopt: {status})")
    return value, status
