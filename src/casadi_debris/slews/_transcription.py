"""Direct collocation of the slew OCP and its solution with IPOPT.

The statement (:class:`~casadi_debris.slews._ocp_problem.SlewOcp`) is
transcribed by direct collocation on Radau IIA points of degree 3
(coefficients from ``casadi.collocation_coeff``) over a horizon of uniform
bulk intervals (an even count puts the single-axis switch at a node; their
total length free for a time-optimal slew) followed, for a flexible slew, by
the fixed intervals of the terminal window
(:mod:`casadi_debris.slews._modal_window`). States and controls are scaled by
physical magnitudes; the initial guess
(:mod:`casadi_debris.slews._initial_guess`) is marched through the collocation
equations themselves, so that IPOPT starts with only the end conditions to fix.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, TypeAlias

import casadi as ca
import numpy as np

from casadi_debris.dynamics import Model
from casadi_debris.errors import SlewNotConvergedError
from casadi_debris.parallel import keep_ctrl_c
from casadi_debris.slews._initial_guess import InitialGuess
from casadi_debris.slews._modal_window import VibrationBound
from casadi_debris.slews._ocp_problem import FORCE_ROWS, N_MODEL_INPUTS, TORQUE_ROWS, SlewOcp

COLLOCATION_DEGREE = 3
RIGID_INTERVALS = 40
REGULARISATION = 1e-6
ACCEPTED_STATUS = ("Solve_Succeeded", "Solved_To_Acceptable_Level")
# The values CasADi's solver options take here (its own option type also allows nesting).
SolverOptions: TypeAlias = Mapping[str, bool | int | float | str]
IPOPT_OPTIONS: SolverOptions = {
    "expand": True,
    "print_time": False,
    "ipopt.print_level": 0,
    "ipopt.sb": "yes",
    "ipopt.max_iter": 1500,
    "ipopt.tol": 1e-9,
}
# The modal solve starts from the shaped rigid optimum: a small initial barrier keeps
# IPOPT from first pushing every saturated control to mid-range.
WARM_START_OPTIONS: SolverOptions = {"ipopt.mu_init": 1e-3}
# At thruster level 24 thrusts per interval give six numbers; with the monotone barrier
# update IPOPT reaches the barrier floor while still far from the optimum and crawls
# (z slew: 133 iterations, 3.3 s; four test slews: 1.4 to 3.3 s against 0.9 to 1.3 s).
THRUSTER_OPTIONS: SolverOptions = {"ipopt.mu_strategy": "adaptive"}


@dataclass(frozen=True)
class Horizon:
    """The transcription's intervals: a uniform bulk, then a fixed terminal window.

    Attributes
    ----------
    bulk_s : float or None
        Total length of the bulk intervals, s; None: free (time-optimal).
    bulk_intervals : int
        How many bulk intervals.
    window_intervals : int
        How many window intervals (0: none, a rigid slew).
    window_step_s : float
        Length of each window interval, s.
    """

    bulk_s: float | None
    bulk_intervals: int
    window_intervals: int = 0
    window_step_s: float = 0.0

    @property
    def count(self) -> int:
        """All intervals."""
        return self.bulk_intervals + self.window_intervals

    def guess_steps(self, total_s: float) -> np.ndarray:
        """Interval lengths (s, shape (count,)) of a guess ``total_s`` seconds long."""
        n, m = self.bulk_intervals, self.window_intervals
        bulk = total_s - m * self.window_step_s
        return np.concatenate([np.full(n, bulk / n), np.full(m, self.window_step_s)])


@dataclass(frozen=True)
class NlpSolution:
    """What the NLP gives.

    Attributes
    ----------
    knots_s : ndarray, shape (N + 1,)
        Interval bounds, s, from 0.
    controls : ndarray, shape (N, n_u)
        The control held on each interval, SI, within its bounds.
    status : str
        IPOPT's return status.
    predicted_energy_J : float
        The vibration energy its closed form predicts at the end (J; 0 if rigid).
    """

    knots_s: np.ndarray
    controls: np.ndarray
    status: str
    predicted_energy_J: float


def radau_coefficients() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Radau IIA collocation on [0, 1] of degree ``COLLOCATION_DEGREE`` (d).

    A polynomial Pi through (0, x_0) and the collocation points (tau_j, x_cj)
    has, with Z = [x_0, x_c1 .. x_cd] (one row per state), the slopes
    dPi/dtau (tau_j) = Z C and the end value Pi(1) = Z D; over an interval of
    length h, dPi/dt = Z C / h (``casadi.collocation_coeff``). The last Radau point
    is the interval's end, so D = [0, .., 0, 1] exactly.

    Returns
    -------
    points : ndarray, shape (d + 1,)
        0, then the collocation points tau_1 .. tau_d (tau_d = 1).
    C : ndarray, shape (d + 1, d)
    D : ndarray, shape (d + 1,)
    """
    tau = ca.collocation_points(COLLOCATION_DEGREE, "radau")
    C, D, _ = ca.collocation_coeff(tau)
    return np.concatenate([[0.0], tau]), np.array(C), np.array(D).ravel()


@dataclass(frozen=True)
class IntervalCollocation:
    """Radau collocation of one interval on the rigid model, states scaled by ``x_scale``.

    Attributes
    ----------
    n_x : int
        Size of the state.
    x_scale : ndarray, shape (n_x,)
        SI state = scaled state * x_scale.
    interval : casadi.Function
        ``interval(xk, xc, uk, h) -> (defects, x_end)``: scaled start state (n_x),
        collocation states (n_x x d), input (n_in) and length (s) to the collocation
        defects (n_x x d) and the end state (n_x).
    """

    n_x: int
    x_scale: np.ndarray
    interval: ca.Function

    @classmethod
    def radau(
        cls, model: Model, parameters: np.ndarray, x_scale: np.ndarray, input_map: np.ndarray
    ) -> IntervalCollocation:
        """The collocation equations of ``model`` (rigid) on one interval.

        With Z = [x_0, x_c1 .. x_cd], ``casadi.collocation_coeff`` gives C
        ((d + 1) x d) and D (d + 1) such that the interpolating polynomial's slopes
        at the collocation points are Z C / h and its end is Z D.

        Parameters
        ----------
        input_map : ndarray, shape (9, n_in)
            The model input [tau, 0, F] of the interval's input.
        """
        n_x = len(x_scale)
        _, C, D = (ca.DM(matrix) for matrix in radau_coefficients())
        xk = ca.SX.sym("xk", n_x)
        xc = ca.SX.sym("xc", n_x, COLLOCATION_DEGREE)
        uk = ca.SX.sym("uk", input_map.shape[1])
        h = ca.SX.sym("h")
        x_s = ca.DM(x_scale)
        u_model = ca.DM(input_map) @ uk
        points = ca.horzcat(xk, xc)
        defects = []
        for j in range(COLLOCATION_DEGREE):
            state = xc[:, j] * x_s
            # The tracker's quaternion follows the attitude: its derivative is then zero.
            rate = model.dynamics(ca.vertcat(state, state[model.layout.q]), u_model, parameters)
            defects.append(h * rate[:n_x] / x_s - points @ C[:, j])
        single = ca.Function("interval", [xk, xc, uk, h], [ca.horzcat(*defects), points @ D])
        return cls(n_x, x_scale, single)

    def march(
        self, x0: np.ndarray, controls: np.ndarray, steps_s: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Integrate a guess with the transcription itself (Newton on each interval).

        A guess that satisfies the collocation equations exactly leaves IPOPT only
        the end conditions to fix.

        Parameters
        ----------
        x0 : ndarray, shape (n_x,)
            Scaled start state.
        controls : ndarray, shape (n_in, N)
            The input of each interval.
        steps_s : ndarray, shape (N,)
            Interval lengths, s.

        Returns
        -------
        nodes : ndarray, shape (n_x, N + 1)
        inner : ndarray, shape (n_x, N d)
            Scaled states at the interval bounds and at the collocation points.
        """
        n, d = self.n_x, COLLOCATION_DEGREE
        unknown = ca.SX.sym("xc", n * d)
        given = ca.SX.sym("given", n + controls.shape[0] + 1)
        defects, end = self.interval(given[:n], ca.reshape(unknown, n, d), given[n:-1], given[-1])
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


@dataclass(frozen=True)
class _Drive:
    """What the dynamics see of the (scaled) controls.

    Attributes
    ----------
    variable : MX, shape (n_d, N)
        The controls themselves, or variables equal to a linear map of them.
    model_map : ndarray, shape (9, n_d)
        The model input of one column of ``variable``.
    from_controls : ndarray, shape (n_d, n_u)
        ``variable = from_controls @ controls``.
    """

    variable: ca.MX
    model_map: np.ndarray
    from_controls: np.ndarray


def transcribe_and_solve(
    ocp: SlewOcp,
    *,
    fuel: bool,
    horizon: Horizon,
    guess: InitialGuess,
    vibration: VibrationBound | None = None,
) -> NlpSolution:
    """Transcribe the OCP by Radau collocation and solve it with IPOPT.

    Parameters
    ----------
    ocp : SlewOcp
    fuel : bool
        Minimise propellant (``horizon.bulk_s`` given) rather than time.
    horizon : Horizon
    guess : InitialGuess
    vibration : VibrationBound, optional
        Bound on the vibration energy left at the end (flexible slews).

    Raises
    ------
    SlewNotConvergedError
        IPOPT did not converge.
    """
    nlp = _RadauNlp(ocp, fuel, horizon, guess)
    guess_steps, drives = nlp.start()
    energy = ca.MX(0.0)
    if vibration is not None:
        energy = vibration.constrain(
            nlp.opti, nlp.drive.variable, nlp.steps, nlp.drive.model_map, (guess_steps, drives)
        )
    nlp.opti.minimize(nlp.cost())
    options = dict(THRUSTER_OPTIONS) if ocp.thrusters else {}
    if vibration is not None:
        options.update(WARM_START_OPTIONS)
    value, status = solve_with_ipopt(nlp.opti, options)
    return NlpSolution(
        knots_s=np.concatenate([[0.0], np.cumsum(np.array(value(nlp.steps)).ravel())]),
        controls=nlp.controls_of(value),
        status=status,
        predicted_energy_J=float(value(energy)),
    )


class _RadauNlp:
    """The NLP of one transcription: variables, collocation and end constraints, guess."""

    def __init__(self, ocp: SlewOcp, fuel: bool, horizon: Horizon, guess: InitialGuess) -> None:
        self.ocp, self.fuel, self.horizon, self.guess = ocp, fuel, horizon, guess
        self.lower_u, self.upper_u = ocp.control_bounds(fuel)
        self.u_scale = np.maximum(np.maximum(np.abs(self.lower_u), np.abs(self.upper_u)), 1e-30)
        self.x_scale = ocp.state_scale(guess.peak_rate_rad_s, guess.total_s)
        self.opti = ca.Opti()
        self.steps = self._steps()
        count = horizon.count
        self.X = self.opti.variable(ocp.n_x, count + 1)
        self.XC = self.opti.variable(ocp.n_x, count * COLLOCATION_DEGREE)
        self.U = self.opti.variable(len(self.u_scale), count)
        self.drive = self._drive()
        self.collocation = IntervalCollocation.radau(
            ocp.rigid_model, ocp.parameters, self.x_scale, self.drive.model_map
        )
        self._constrain()

    def _steps(self) -> ca.MX:
        """Interval lengths, s, shape (count, 1); the bulk's a variable when free."""
        horizon, opti = self.horizon, self.opti
        n = horizon.bulk_intervals
        if horizon.bulk_s is None:
            limit_s = self.ocp.limit_duration_s
            bulk_scaled = opti.variable()
            bulk = bulk_scaled * limit_s
            opti.subject_to(opti.bounded(0.05, bulk_scaled, 20.0))
            bulk_guess = self.guess.total_s - horizon.window_intervals * horizon.window_step_s
            opti.set_initial(bulk_scaled, bulk_guess / limit_s)
        else:
            bulk = ca.MX(horizon.bulk_s)
        window = ca.DM.ones(horizon.window_intervals) * horizon.window_step_s
        return ca.vertcat(ca.repmat(bulk / n, n, 1), window)

    def _drive(self) -> _Drive:
        """What the dynamics see of the controls.

        Torque level: the controls themselves. Thruster level: the 24 thrusts act on
        the motion and on the modes only through six numbers, the torque and the force
        (three with ``zero_net_force``, which holds the force at zero), so those are
        variables of their own (scaled by sum_i |B_ki| f_max,i, at most twice what the
        engines give about each axis) with six linear equations per interval; every
        collocation and modal row then depends on six variables instead of 24, and the
        KKT matrix stays sparse.
        """
        input_map = self.ocp.input_map(self.fuel) * self.u_scale
        controls = self.U
        if not self.ocp.thrusters:
            return _Drive(controls, input_map, np.eye(len(self.u_scale)))
        zero_net_force = self.ocp.options.zero_net_force
        acting = TORQUE_ROWS if zero_net_force else TORQUE_ROWS + FORCE_ROWS
        if zero_net_force:
            force = input_map[FORCE_ROWS]
            force = force / np.maximum(np.sum(np.abs(force), axis=1), 1e-30)[:, None]
            self.opti.subject_to(ca.vec(ca.DM(force) @ controls) == 0)
        effect = input_map[acting]
        drive_scale = np.maximum(np.sum(np.abs(effect), axis=1), 1e-30)
        drive_map = np.zeros((N_MODEL_INPUTS, len(acting)))
        drive_map[acting, np.arange(len(acting))] = drive_scale
        to_drive = effect / drive_scale[:, None]
        drive = self.opti.variable(len(acting), controls.shape[1])
        self.opti.subject_to(ca.vec(drive - ca.DM(to_drive) @ controls) == 0)
        return _Drive(drive, drive_map, to_drive)

    def _constrain(self) -> None:
        """Collocation, continuity, control bounds, path and end conditions."""
        opti, count, u_scale = self.opti, self.horizon.count, self.u_scale
        interval = self.collocation.interval.map(count)
        defect, ends = interval(self.X[:, :-1], self.XC, self.drive.variable, self.steps.T)
        opti.subject_to(ca.vec(defect) == 0)
        opti.subject_to(ca.vec(self.X[:, 1:] - ends) == 0)
        opti.subject_to(
            opti.bounded(
                np.tile((self.lower_u / u_scale)[:, None], count),
                self.U,
                np.tile((self.upper_u / u_scale)[:, None], count),
            )
        )
        self._within_torque_set()
        across = self.ocp.eigenaxis_normal()
        if across is not None:  # torque along the eigenaxis
            scaled = ca.DM(across @ np.diag(u_scale / np.max(u_scale)))
            opti.subject_to(ca.vec(scaled @ self.U) == 0)
        opti.subject_to(self.X[:, 0] == self.ocp.initial_state() / self.x_scale)
        final = self.X[:, -1] * ca.DM(self.x_scale)
        for residual in self.ocp.terminal_residuals(final, self.guess.peak_rate_rad_s):
            opti.subject_to(residual == 0)

    def _within_torque_set(self) -> None:
        """Torque level: every interval's torque in the engines' torque set, each facet's
        row scaled to a right-hand side of one (a facet through the origin by its normal's
        reach instead)."""
        facets = self.ocp.torque_set()
        if facets is None:
            return
        normals, offsets = facets
        rows = normals @ (self.ocp.input_map(self.fuel)[TORQUE_ROWS] * self.u_scale)
        reach = np.max(np.abs(rows), axis=1)
        scale = np.maximum(offsets, 1e-9 * np.max(reach) + 1e-300)
        bound = np.tile((offsets / scale)[:, None], self.horizon.count)
        self.opti.subject_to(ca.vec(ca.DM(rows / scale[:, None]) @ self.U) <= bound.ravel("F"))

    def start(self) -> tuple[np.ndarray, np.ndarray]:
        """Set the initial guess: its controls, marched through the transcription.

        Returns
        -------
        steps_s : ndarray, shape (count,)
        drives : ndarray, shape (n_d, count)
            The guess's interval lengths and (scaled) drive.
        """
        steps_s = self.horizon.guess_steps(self.guess.total_s)
        middles = np.cumsum(steps_s) - steps_s / 2.0
        controls = self.guess.controls(middles).T / self.u_scale[:, None]
        drives = self.drive.from_controls @ controls
        x0 = self.ocp.initial_state() / self.x_scale
        nodes, inner = self.collocation.march(x0, drives, steps_s)
        self.opti.set_initial(self.X, nodes)
        self.opti.set_initial(self.XC, inner)
        self.opti.set_initial(self.U, controls)
        if self.drive.variable is not self.U:
            self.opti.set_initial(self.drive.variable, drives)
        return steps_s, drives

    def cost(self) -> ca.MX:
        """The objective, integrals as sums over the intervals in units of the guess's
        length."""
        U, steps, total_s = self.U, self.steps, self.guess.total_s
        if self.fuel:
            rates = ca.DM(self.ocp.fuel_rates(self.u_scale))
            return ca.dot(steps / total_s, (rates.T @ U).T)
        # The regulariser only picks one of many equally fast controls (least thrust, or
        # least squared torque); each interval counts the same, however short, so that
        # the window's controls are as well determined as the bulk's.
        effort = ca.sum1(U) / U.shape[0] if self.ocp.thrusters else ca.sum1(U**2)
        return ca.sum1(steps) / total_s + REGULARISATION * ca.sum2(effort) / self.horizon.count

    def controls_of(self, value: Any) -> np.ndarray:
        """The solution's controls, SI, shape (count, n_u), clipped to their bounds.

        IPOPT meets bounds to 1e-8 of their size (``bound_relax_factor``): clip back.
        """
        count, n_u = self.horizon.count, len(self.u_scale)
        scaled = np.array(value(self.U)).reshape(n_u, count).T
        return np.clip(scaled * self.u_scale, self.lower_u, self.upper_u)


def solve_with_ipopt(opti: ca.Opti, options: SolverOptions) -> tuple[Any, str]:
    """Solve with IPOPT: the solution's ``value`` function and the return status.

    ``options`` are added to ``IPOPT_OPTIONS``.

    Raises
    ------
    SlewNotConvergedError
        IPOPT ended in a status not in ``ACCEPTED_STATUS``.
    """
    opti.solver("ipopt", {**IPOPT_OPTIONS, **options})
    try:
        with keep_ctrl_c():
            solution = opti.solve()
        status = solution.stats()["return_status"]
        value = solution.value
    except RuntimeError:
        status = opti.stats().get("return_status", "failed")
        value = opti.debug.value
    if status not in ACCEPTED_STATUS:
        raise SlewNotConvergedError(f"optimal slew did not converge (ipopt: {status})")
    return value, status
