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
``flexible`` (``flexible_method="ocp"``, the default) solves the OCP with the
array modes as states where they matter: a rigid bulk (the collocation above,
free length T_b) followed by a terminal window of fixed length W (1.5 x the
length of the cascaded ZV shaper of all array modes, 2.07 s for the paper's
arrays) on the full flexible model (``build_model(problem, "all")``, 22
states), multiple shooting with piecewise-constant controls on 64 intervals,
each integrated by RK4 substeps with h * omega_max <= 0.4. The window starts
from the bulk's rigid state with the modes at the quasi-static deflection of
the last bulk control (eta = S u, S from the model's modal equation at rest,
eta_dot = 0) and ends with the attitude error and the angular momentum zero and

    E_vib(x(T)) <= 0.8 * residual_energy_fraction * E_bb,

E_vib as in :func:`~casadi_debris.slew.profile.vibration_energy`, E_bb what the
eigenaxis bang-bang at the rigid limit leaves; 0.8 is a margin for the RK4
window and the hand-over, so that the CVODES check of the whole horizon on the
full model (which is what the profile reports) meets the limit. Minimise
T = T_b + W. The hand-over is exact for the rigid states; for the modes it
assumes the transients excited during the bulk have decayed (damping
exp(-zeta omega t): the lowest assembled mode, 5.8 rad/s at zeta 0.0052, loses
a factor 2 in amplitude per 23 s bulk interval, e^-13 over half the slew); the
CVODES check catches it if not. Modal coordinates are scaled by their
quasi-static deflection under the largest acceleration (~1e-5 to 1e-4).
Collocating the modes over the whole horizon (thousands of modal periods),
and collocation windows, stalled in IPOPT; CVODES shooting intervals of 23 s
run out of steps in the sensitivities.

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
from collections.abc import Sequence
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
from casadi_debris.slew.profile import (
    SlewProfile,
    finish_profile,
    input_vector,
    residual_vibration,
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
WINDOW_INTERVALS = 64
WINDOW_SHAPER_MULTIPLE = 1.5
WINDOW_STEP_PHASE = 0.4
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


@dataclass
class _Phase:
    """One stretch of the horizon on one model: uniform intervals, scaled states.

    ``interval(xk, xc, uk, h) -> (defects (n x d), x_end)`` works on scaled states
    and controls; ``variables`` are filled in when the NLP is built.
    """

    model: Model
    n_x: int
    x_scale: np.ndarray
    intervals: int
    interval: ca.Function
    X: ca.MX | None = None
    XC: ca.MX | None = None
    U: ca.MX | None = None

    def full_state(self, x: ca.SX | ca.MX) -> ca.SX | ca.MX:
        """Reduced state with the star tracker appended at the true attitude."""
        return ca.vertcat(x, x[self.model.layout.q])


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
    shaped = np.zeros((len(middles), controls.shape[1]))
    for t, a in zip(times_s, amplitudes, strict=True):
        index = np.searchsorted(knots_s, middles - t, side="right") - 1
        inside = (index >= 0) & (index < len(controls))
        shaped[inside] += a * controls[index[inside]]
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
    ) -> None:
        if single_axis and thrusters:
            raise InputShapeError("single_axis applies to torque-level slews only")
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

    # -- model pieces ------------------------------------------------------------------
    def _torque_force(self, control: ca.SX, fuel: bool) -> tuple[ca.SX, ca.SX]:
        if self.thrusters:
            return (
                ca.DM(self.geometry.torque_map) @ control,
                ca.DM(self.geometry.force_map) @ control,
            )
        torque = control[0:3] - control[3:6] if fuel else control
        return torque, ca.SX.zeros(3)

    def _control_bounds(self, fuel: bool) -> tuple[np.ndarray, np.ndarray]:
        if self.thrusters:
            return np.zeros_like(self.f_max), self.f_max
        if fuel:
            return np.zeros(6), np.concatenate([self.upper, -self.lower])
        return self.lower, self.upper

    def _phase(
        self, model: Model, x_scale: np.ndarray, u_scale: np.ndarray, intervals: int, fuel: bool
    ) -> _Phase:
        """Radau collocation equations of one interval on ``model`` (scaled), mapped."""
        colloc = _Collocation.radau(COLLOCATION_DEGREE)
        n_x = model.layout.size - 4  # without the star-tracker quaternion (last)
        xk = ca.SX.sym("xk", n_x)
        xc = ca.SX.sym("xc", n_x, COLLOCATION_DEGREE)
        uk = ca.SX.sym("uk", len(u_scale))
        h = ca.SX.sym("h")
        x_s = ca.DM(x_scale)
        torque, force = self._torque_force(uk * ca.DM(u_scale), fuel)
        u_model = input_vector(torque, force)
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
        return _Phase(model, n_x, x_scale, intervals, single)

    # -- initial guess and scaling ----------------------------------------------------
    def _reference(self, duration_s: float) -> SlewProfile:
        """Eigenaxis bang-bang at ``duration_s`` (at least the rigid limit): the initial guess."""
        return bang_bang_slew(
            self.problem,
            target=self.target,
            duration_s=max(duration_s, self.limit_duration_s),
            check_vibration=False,
            model=self.rigid_model,
        )

    def _bang_bang_energy(self) -> float:
        """Vibration energy (J) the bang-bang at the rigid limit leaves in the arrays."""
        reference = self._reference(self.limit_duration_s)
        knots = np.array([0.0, reference.duration_s / 2.0, reference.duration_s])
        states = simulate(
            self.flexible_model,
            reference.input_function,
            knots,
            self.flexible_model.initial_state(self.target.q_initial_BN),
            self.parameters,
        )
        return vibration_energy(self.flexible_model, states[-1], self.parameters)

    def _state_scale(self, model: Model, peak_rate_rad_s: float, duration_s: float) -> np.ndarray:
        """Magnitudes of the states, from physics rather than from a guess.

        omega: the peak rate of the guess. eta_k: the quasi-static deflection under
        the largest acceleration, |H_r,k| alpha_max / Omega_k^2 (H_r,k the rotational
        participation, from the model's mass matrix); eta_dot_k: Omega_k times
        that. v: the translation the modes' momentum P_t^T eta_dot gives the
        reference point, or what the engines' net force can give in T.
        """
        lay = model.layout
        scale = np.ones(lay.size - 4)
        scale[lay.omega] = peak_rate_rad_s
        mass = np.array(model.mass_matrix(self.parameters))
        total_mass = float(mass[0, 0])
        velocity = 0.0
        if lay.n_eta:
            omegas = {mode.name: mode.omega_rad_s for mode in self.problem.arrays.modes}
            frequency = np.array([omegas[name] for _, name in lay.mode_labels])
            translational, rotational = mass[6:, 0:3], mass[6:, 3:6]
            deflection = np.linalg.norm(rotational, axis=1) * self.alpha_max / frequency**2
            scale[lay.eta] = deflection
            scale[lay.eta_dot] = frequency * deflection
            velocity = (
                float(np.linalg.norm(translational.T @ (frequency * deflection))) / total_mass
            )
        if self.thrusters:
            velocity = max(velocity, float(np.sum(self.f_max)) * duration_s / total_mass)
        scale[lay.v] = velocity if velocity > 0.0 else 1.0
        return scale

    @staticmethod
    def _march(
        phase: _Phase, x0: np.ndarray, controls: np.ndarray, step_s: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """Integrate the guess with the transcription itself (Newton on each interval).

        A guess that satisfies the collocation equations exactly leaves IPOPT only
        the end conditions to fix.
        """
        n, d = phase.n_x, COLLOCATION_DEGREE
        unknown = ca.SX.sym("xc", n * d)
        given = ca.SX.sym("given", n + controls.shape[0] + 1)
        defects, end = phase.interval(given[:n], ca.reshape(unknown, n, d), given[n:-1], given[-1])
        solver = ca.rootfinder(
            "march",
            "newton",
            ca.Function("collocation", [unknown, given], [ca.vec(defects)]),
            {"abstol": 1e-10, "max_iter": 50, "error_on_fail": False},
        )
        end_state = ca.Function("end", [unknown, given], [end])
        nodes, inner = [x0], []
        for k in range(controls.shape[1]):
            parameters = np.concatenate([nodes[-1], controls[:, k], [step_s]])
            solution = solver(np.tile(nodes[-1], d), parameters)
            inner.append(np.array(solution).reshape(d, n).T)
            nodes.append(np.array(end_state(solution, parameters)).ravel())
        return np.array(nodes).T, np.hstack(inner)

    # -- flexible terminal window -----------------------------------------------------
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

    def _quasi_static_map(self) -> np.ndarray:
        """S (n_eta x 9): modal deflection at rest under a constant input u, eta = S u.

        From the model's own modal equation at rest: eta_ddot = A eta + B u = 0.
        """
        model = self.flexible_model
        lay = model.layout
        x = ca.SX.sym("x", lay.size)
        u = ca.SX.sym("u", 9)
        acceleration = model.dynamics(x, u, self.parameters)[lay.eta_dot]
        jacobians = ca.Function(
            "modal_jacobians", [x, u], [ca.jacobian(acceleration, x), ca.jacobian(acceleration, u)]
        )
        a_x, b_u = (np.array(m) for m in jacobians(model.initial_state(), np.zeros(9)))
        return -np.linalg.solve(a_x[:, lay.eta], b_u)

    def _vibration_energy_expression(self, state: ca.MX) -> ca.MX:
        """Symbolic :func:`~casadi_debris.slew.profile.vibration_energy` of a reduced state."""
        model = self.flexible_model
        lay = model.layout
        mass = np.array(model.mass_matrix(self.parameters))
        nu = ca.vertcat(state[lay.v], state[lay.omega], state[lay.eta_dot])
        momenta = ca.DM(mass[:6]) @ nu
        rigid = 0.5 * momenta.T @ ca.DM(np.linalg.inv(mass[:6, :6])) @ momenta
        full = ca.vertcat(state, state[lay.q])
        return model.energy(full, self.parameters) - rigid

    def _window_step(
        self, x_scale: np.ndarray, u_scale: np.ndarray, fuel: bool, step_s: float, substeps: int
    ) -> ca.Function:
        """One window interval on the full flexible model: RK4 substeps, scaled states."""
        model = self.flexible_model
        n_x = model.layout.size - 4
        x = ca.SX.sym("x", n_x)
        u = ca.SX.sym("u", len(u_scale))
        u_model = ca.DM(self._input_map(fuel)) @ (u * ca.DM(u_scale))
        x_s = ca.DM(x_scale)

        def rate(z: ca.SX) -> ca.SX:
            state = z * x_s
            full = ca.vertcat(state, state[model.layout.q])
            return model.dynamics(full, u_model, self.parameters)[:n_x] / x_s

        h = step_s / substeps
        z = x
        for _ in range(substeps):
            k1 = rate(z)
            k2 = rate(z + 0.5 * h * k1)
            k3 = rate(z + 0.5 * h * k2)
            k4 = rate(z + h * k3)
            z = z + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
        return ca.Function("window_step", [x, u], [z])

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
        warm_start: SlewProfile | None = None,
        flexible_method: str = "ocp",
    ) -> SlewProfile:
        """Transcribe and solve; ``warm_start`` (e.g. the rigid solution) replaces the bang-bang.

        ``flexible_method``: ``"ocp"`` (modal states in a terminal window, module
        notes) or ``"shaper"`` (the rigid optimum through a ZV shaper).
        """
        options = {
            "objective": objective,
            "duration_s": duration_s,
            "intervals": intervals,
            "residual_energy_fraction": residual_energy_fraction,
            "sample_s": sample_s,
            "check_vibration": check_vibration,
            "warm_start": warm_start,
        }
        if flexible_method not in FLEXIBLE_METHODS:
            raise InputShapeError(
                f"flexible_method: one of {', '.join(FLEXIBLE_METHODS)}, got {flexible_method!r}"
            )
        if not self.flexible or flexible_method == "shaper":
            return self._solve_rigid_or_shaped(**options)
        try:
            return self._solve_modal(**options)
        except SlewInfeasibleError as error:
            if "did not converge" not in str(error):
                raise
            failure = str(error)
        profile = self._solve_rigid_or_shaped(**options)
        profile.settings["flexible_method"] = f"shaper (fallback: modal {failure})"
        return profile

    def _solve_modal(
        self,
        *,
        objective: str,
        duration_s: float | None,
        intervals: int | None,
        residual_energy_fraction: float,
        sample_s: float,
        check_vibration: bool,
        warm_start: SlewProfile | None,
    ) -> SlewProfile:
        """Rigid collocation bulk + flexible multiple-shooting window (module notes)."""
        fuel = objective == "fuel"
        model = self.flexible_model
        lay = model.layout
        shaper_times, shaper_amplitudes, _ = zero_vibration_shaper(model, self.parameters)
        reference_started = time.perf_counter()
        reference_energy = self._bang_bang_energy()
        reference_time = time.perf_counter() - reference_started
        started = time.perf_counter()
        window_s, step_s, substeps = self._window_grid(float(shaper_times[-1]))
        m = WINDOW_INTERVALS
        reference = self._reference(duration_s if fuel else self.limit_duration_s)
        if warm_start is not None:
            reference = warm_start
        shaper_length = float(shaper_times[-1])
        guess_total = duration_s if fuel else reference.duration_s + shaper_length
        peak_rate = float(np.max(np.linalg.norm(reference.rate_rad_s, axis=1)))
        lower_u, upper_u = self._control_bounds(fuel)
        u_scale = np.maximum(np.maximum(np.abs(lower_u), np.abs(upper_u)), 1e-30)
        n_u = len(u_scale)
        n = intervals or RIGID_INTERVALS
        d = COLLOCATION_DEGREE
        rigid_scale = self._state_scale(self.rigid_model, peak_rate, guess_total)
        flexible_scale = self._state_scale(model, peak_rate, guess_total)
        rigid = self._phase(self.rigid_model, rigid_scale, u_scale, n, fuel)
        step = self._window_step(flexible_scale, u_scale, fuel, step_s, substeps)
        n_r, n_f = rigid.n_x, lay.size - 4

        opti = ca.Opti()
        if fuel:
            bulk = ca.MX(duration_s - window_s)
            if duration_s - window_s <= 0.0:
                raise SlewInfeasibleError(f"infeasible: minimum is {window_s:.6g} s")
        else:
            bulk_scaled = opti.variable()
            bulk = bulk_scaled * self.limit_duration_s
            opti.subject_to(opti.bounded(0.05, bulk_scaled, 20.0))
            opti.set_initial(bulk_scaled, (guess_total - window_s) / self.limit_duration_s)
        X = opti.variable(n_r, n + 1)
        XC = opti.variable(n_r, n * d)
        U = opti.variable(n_u, n)
        defect, ends = rigid.interval.map(n)(X[:, :-1], XC, U, ca.repmat(bulk / n, 1, n))
        opti.subject_to(ca.vec(defect) == 0)
        opti.subject_to(ca.vec(X[:, 1:] - ends) == 0)
        XW = opti.variable(n_f, m + 1)
        UW = opti.variable(n_u, m)
        opti.subject_to(ca.vec(XW[:, 1:] - step.map(m)(XW[:, :-1], UW)) == 0)
        for controls, count in ((U, n), (UW, m)):
            opti.subject_to(
                opti.bounded(
                    np.tile((lower_u / u_scale)[:, None], count),
                    controls,
                    np.tile((upper_u / u_scale)[:, None], count),
                )
            )
        x0 = self.rigid_model.initial_state(self.target.q_initial_BN)[:n_r]
        opti.subject_to(X[:, 0] == x0 / rigid_scale)
        # Hand-over: rigid states continue; the modes start at the quasi-static deflection
        # of the last bulk control (the transients of the bulk have decayed, module notes).
        qs_map = self._quasi_static_map() @ self._input_map(fuel) @ np.diag(u_scale)
        eta = np.arange(lay.size)[lay.eta]
        eta_dot = np.arange(lay.size)[lay.eta_dot]
        opti.subject_to(XW[:n_r, 0] * ca.DM(flexible_scale[:n_r] / rigid_scale) - X[:, -1] == 0)
        opti.subject_to(XW[eta, 0] - ca.DM(qs_map / flexible_scale[eta, None]) @ U[:, -1] == 0)
        opti.subject_to(XW[eta_dot, 0] == 0)
        final = XW[:, -1] * ca.DM(flexible_scale)
        self._rest_at_target(opti, model, final[lay.q], ca.vertcat(final, final[lay.q]), peak_rate)
        energy = self._vibration_energy_expression(final)
        # The window is RK4 and the hand-over quasi-static: keep a margin for the CVODES check.
        opti.subject_to(energy / reference_energy <= ENERGY_MARGIN * residual_energy_fraction)

        total = bulk + window_s
        bulk_weight = bulk / guess_total / n
        window_weight = step_s / guess_total
        if fuel:
            rates = self._fuel_rates(u_scale)
            cost = bulk_weight * ca.sum2(ca.DM(rates).T @ U) + window_weight * ca.sum2(
                ca.DM(rates).T @ UW
            )
        else:
            cost = total / guess_total + REGULARISATION * (
                bulk_weight * ca.sumsqr(U) + window_weight * ca.sumsqr(UW)
            )
        opti.minimize(cost)

        # Initial guess: the reference on the bulk, its ZV-shaped end in the window.
        bulk_guess = guess_total - window_s
        times = (np.arange(n) + 0.5) * bulk_guess / n
        controls = self._control_guess(reference, times, fuel).T / u_scale[:, None]
        nodes, inner = self._march(rigid, x0 / rigid_scale, controls, bulk_guess / n)
        window_times = bulk_guess + (np.arange(m) + 0.5) * step_s
        window_controls = (
            sum(
                a * self._control_guess(reference, window_times - t, fuel)
                for t, a in zip(shaper_times, shaper_amplitudes, strict=True)
            ).T
            / u_scale[:, None]
        )
        start = np.zeros(n_f)
        start[:n_r] = nodes[:, -1] * rigid_scale / flexible_scale[:n_r]
        start[eta] = qs_map @ controls[:, -1] / flexible_scale[eta]
        window_nodes = [start]
        for k in range(m):
            window_nodes.append(np.array(step(window_nodes[-1], window_controls[:, k])).ravel())
        opti.set_initial(X, nodes)
        opti.set_initial(XC, inner)
        opti.set_initial(U, controls)
        opti.set_initial(XW, np.array(window_nodes).T)
        opti.set_initial(UW, window_controls)
        value, status = _solve_with_ipopt(opti)
        solve_time = time.perf_counter() - started
        bulk_s = float(value(bulk))
        knots = np.concatenate(
            [np.linspace(0.0, bulk_s, n + 1), bulk_s + np.arange(1, m + 1) * step_s]
        )
        controls = (
            np.vstack(
                [
                    np.array(value(U)).reshape(n_u, n).T,
                    np.array(value(UW)).reshape(n_u, m).T,
                ]
            )
            * u_scale
        )
        settings = {
            "flexible_method": "ocp",
            "window_s": window_s,
            "window_intervals": m,
            "window_rk4_substeps": substeps,
            "predicted_residual_energy_J": float(value(energy)),
            "residual_energy_limit_J": residual_energy_fraction * reference_energy,
            "bang_bang_residual_energy_J": reference_energy,
            "reference_energy_time_s": reference_time,
            "shaper_length_s": shaper_length,
        }
        return self._profile(
            objective=objective,
            knots=knots,
            controls=controls,
            extra_settings=settings,
            fuel=fuel,
            solve_time=solve_time,
            status=status,
            sample_s=sample_s,
            check_vibration=check_vibration,
        )

    def _window_grid(self, shaper_length_s: float) -> tuple[float, float, int]:
        """Window length, interval and RK4 substeps (h omega_max <= WINDOW_STEP_PHASE)."""
        window_s = WINDOW_SHAPER_MULTIPLE * shaper_length_s
        step_s = window_s / WINDOW_INTERVALS
        highest = max(mode.omega_rad_s for mode in self.problem.arrays.modes)
        poles = np.linalg.eigvals(linearize(self.flexible_model, self.parameters).A)
        highest = max(highest, float(np.max(np.abs(poles))))
        substeps = max(1, math.ceil(step_s * highest / WINDOW_STEP_PHASE))
        return window_s, step_s, substeps

    def _solve_rigid_or_shaped(
        self,
        *,
        objective: str,
        duration_s: float | None,
        intervals: int | None,
        residual_energy_fraction: float,
        sample_s: float,
        check_vibration: bool,
        warm_start: SlewProfile | None = None,
    ) -> SlewProfile:
        """The rigid OCP; when ``flexible``, its result through the ZV shaper."""
        started = time.perf_counter()
        fuel = objective == "fuel"
        shaper_times, shaper_amplitudes, shaped_frequencies = (
            zero_vibration_shaper(self.flexible_model, self.parameters)
            if self.flexible
            else (np.zeros(1), np.ones(1), np.zeros(0))
        )
        if fuel:  # the shaper stretches the rigid profile by its length
            duration_s = duration_s - float(shaper_times[-1])
        reference = self._reference(duration_s if fuel else self.limit_duration_s)
        if warm_start is not None:
            reference = warm_start
        guess_total = duration_s if fuel else reference.duration_s
        peak_rate = float(np.max(np.linalg.norm(reference.rate_rad_s, axis=1)))
        lower_u, upper_u = self._control_bounds(fuel)
        u_scale = np.maximum(np.maximum(np.abs(lower_u), np.abs(upper_u)), 1e-30)
        n_u = len(u_scale)
        rigid_scale = self._state_scale(self.rigid_model, peak_rate, guess_total)
        phases = [
            self._phase(self.rigid_model, rigid_scale, u_scale, intervals or RIGID_INTERVALS, fuel)
        ]
        opti = ca.Opti()
        if fuel:
            bulk = ca.MX(duration_s)
        else:
            bulk_scaled = opti.variable()
            bulk = bulk_scaled * self.limit_duration_s
            opti.subject_to(opti.bounded(0.05, bulk_scaled, 20.0))
            opti.set_initial(bulk_scaled, guess_total / self.limit_duration_s)
        lengths = [bulk]
        d = COLLOCATION_DEGREE
        for phase, length in zip(phases, lengths, strict=False):
            n = phase.intervals
            phase.X = opti.variable(phase.n_x, n + 1)
            phase.XC = opti.variable(phase.n_x, n * d)
            phase.U = opti.variable(n_u, n)
            defect, ends = phase.interval.map(n)(
                phase.X[:, :-1], phase.XC, phase.U, ca.repmat(length / n, 1, n)
            )
            opti.subject_to(ca.vec(defect) == 0)
            opti.subject_to(ca.vec(phase.X[:, 1:] - ends) == 0)
            opti.subject_to(
                opti.bounded(
                    np.tile((lower_u / u_scale)[:, None], n),
                    phase.U,
                    np.tile((upper_u / u_scale)[:, None], n),
                )
            )
            if self.single_axis:  # torque along the eigenaxis: two rows spanning its normal plane
                across = np.linalg.svd(self.target.axis_B[None, :])[2][1:]
                scaled = ca.DM(across @ np.diag(u_scale / np.max(u_scale)))
                opti.subject_to(ca.vec(scaled @ phase.U) == 0)
        rigid = phases[0]
        x0 = self.rigid_model.initial_state(self.target.q_initial_BN)[: rigid.n_x]
        opti.subject_to(rigid.X[:, 0] == x0 / rigid_scale)

        last = phases[-1]
        lay = last.model.layout
        final = last.X[:, -1] * ca.DM(last.x_scale)
        final_full = last.full_state(final)
        self._rest_at_target(opti, last.model, final[lay.q], final_full, peak_rate)
        # Objective: integrals as sums over both phases, in units of the guess's duration.
        total_scaled = bulk / guess_total
        cost = 0
        for phase, length in zip(phases, lengths, strict=False):
            weight = length / guess_total / phase.intervals
            if fuel:
                rates = self._fuel_rates(u_scale)
                cost += weight * ca.sum2(ca.DM(rates).T @ phase.U)
            elif self.thrusters:
                cost += REGULARISATION * weight * ca.sum2(ca.sum1(phase.U)) / n_u
            else:
                cost += REGULARISATION * weight * ca.sumsqr(phase.U)
        opti.minimize(cost if fuel else total_scaled + cost)

        # Initial guess: the reference's controls, marched through the transcription.
        bulk_guess = guess_total
        times = (np.arange(rigid.intervals) + 0.5) * bulk_guess / rigid.intervals
        controls = self._control_guess(reference, times, fuel).T / u_scale[:, None]
        nodes, inner = self._march(rigid, x0 / rigid_scale, controls, bulk_guess / rigid.intervals)
        opti.set_initial(rigid.X, nodes)
        opti.set_initial(rigid.XC, inner)
        opti.set_initial(rigid.U, controls)
        value, status = _solve_with_ipopt(opti)
        solve_time = time.perf_counter() - started
        bulk_s = float(value(bulk))
        knots = [np.linspace(0.0, bulk_s, rigid.intervals + 1)]
        controls = [np.array(value(rigid.U)).reshape(n_u, rigid.intervals).T]
        knots, controls = np.concatenate(knots), np.vstack(controls) * u_scale
        settings = {}
        if self.flexible:
            rigid_duration = float(knots[-1])
            knots, controls = shape(knots, controls, shaper_times, shaper_amplitudes)
            reference_energy = self._bang_bang_energy()
            settings = {
                "flexible_method": "shaper",
                "rigid_duration_s": rigid_duration,
                "shaped_frequencies_rad_s": shaped_frequencies,
                "shaper_length_s": float(shaper_times[-1]),
                "residual_energy_limit_J": residual_energy_fraction * reference_energy,
            }
        return self._profile(
            objective=objective,
            knots=knots,
            controls=controls,
            extra_settings=settings,
            fuel=fuel,
            solve_time=solve_time,
            status=status,
            sample_s=sample_s,
            check_vibration=check_vibration,
        )

    def _fuel_rates(self, u_scale: np.ndarray) -> np.ndarray:
        """Propellant weight of each (scaled) control in the fuel objective, largest 1."""
        if self.thrusters:
            return np.ones(len(u_scale)) / len(u_scale)
        plus, minus = axis_fuel_rates(self.geometry)
        rates = np.concatenate([plus, minus]) * u_scale
        return rates / np.max(rates)

    def _rest_at_target(
        self,
        opti: ca.Opti,
        model: Model,
        final_q: ca.MX,
        final_full: ca.MX,
        peak_rate: float,
    ) -> None:
        """End on the target attitude with no angular momentum.

        Three attitude equations, not four: the dynamics keep |q| = 1, so
        q(T) = q_f would be (nearly) rank deficient.
        """
        opti.subject_to(model.attitude_error(self.target.q_final_BN, final_q) == 0)
        inertia = np.array(self.rigid_model.rigid_inertia(self.parameters))
        momentum_scale = float(self.target.axis_B @ inertia @ self.target.axis_B) * peak_rate
        _, angular = model.momenta(final_full, self.parameters)
        opti.subject_to(angular / momentum_scale == 0)

    def _control_guess(self, reference: SlewProfile, times_s: np.ndarray, fuel: bool) -> np.ndarray:
        """Controls of ``reference`` at ``times_s`` in this OCP's form, shape (n, n_u)."""
        if self.thrusters and reference.thrusters:
            held = np.searchsorted(reference.time_s, times_s, side="right") - 1
            return reference.thrust_N[np.clip(held, 0, len(reference.time_s) - 1)]
        inputs = np.array(reference.input_function.map(len(times_s))(times_s)).T
        torque = np.clip(inputs[:, :3], self.lower, self.upper)
        if self.thrusters:
            return least_fuel_thrust(self.geometry, torque)[0]
        if fuel:
            return np.hstack([np.maximum(torque, 0.0), np.maximum(-torque, 0.0)])
        return torque

    def _profile(
        self,
        *,
        objective: str,
        knots: np.ndarray,
        controls: np.ndarray,
        fuel: bool,
        solve_time: float,
        status: str,
        sample_s: float,
        check_vibration: bool,
        extra_settings: dict,
    ) -> SlewProfile:
        model = self.flexible_model if self.flexible else self.rigid_model
        lay = model.layout
        total = float(knots[-1])
        if self.thrusters:
            torque = controls @ self.geometry.torque_map.T
            force = controls @ self.geometry.force_map.T
        else:
            torque = controls[:, 0:3] - controls[:, 3:6] if fuel else controls
            force = None
        input_function = zoh_input_function(knots, torque, force)
        grid = np.unique(np.concatenate([np.arange(0.0, total, sample_s), knots]))
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
            method=f"{objective}-optimal",
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
            solver_status=status,
            settings=settings,
            check_vibration=check_vibration,
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
        ``residual_energy_fraction`` times the rigid-limit bang-bang's (module notes).
    thrusters : bool
        Thrust per engine as the decision variable (0 <= f <= f_max).
    torque_fraction : float
        Share of the per-axis torque authority usable (torque level) in (0, 1].
    single_axis : bool
        Restrict the torque to the eigenaxis (the single-degree-of-freedom slew).
    intervals : int, optional
        Collocation intervals (even; default 40).
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


def _solve_with_ipopt(opti: ca.Opti) -> tuple[Any, str]:
    """Solve with IPOPT: the solution's ``value`` function and the return status.

    Raises
    ------
    SlewInfeasibleError
        IPOPT ended in a status not in ``ACCEPTED_STATUS``.
    """
    opti.solver("ipopt", IPOPT_OPTIONS)
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
