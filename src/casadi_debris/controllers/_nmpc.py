"""Nonlinear MPC at thruster level on the toolkit's CasADi model.

Formulation
-----------
Prediction: the state of the model (:class:`~casadi_debris.dynamics.Model`) without its
star tracker, x = [q_BN, omega, v, eta, eta_dot] (no eta for the rigid prediction: the
same problem's model with no modes kept). Its derivative is the model's own ``dynamics``
Function with the star tracker held at the attitude (q_ST = q) and the input
u = [B f, d, F f], B and F the engines' torque and force maps, f their thrusts and d the
disturbance torque (zero, or the model's ``disturbance(t)`` with ``disturbance="model"``).
Each interval of length h holds f and d, and is integrated by ``integrator_steps``
classical RK4 steps: x_k+1 = Phi(x_k, f_k, d_k, h).

Multiple shooting over N intervals, the decision variables ordered stage by stage
(x_0, f_0, x_1, f_1, ..., x_N) as structure-exploiting solvers want them, scaled so
that they are of order one (:class:`NmpcScales`)::

    minimise   sum_k=0..N-1 [ w_e |e_k / s_e|^2 + w_w |(omega_k - omega_ref,k) / s_w|^2
                              + w_p sum_i rho_i f_k,i / s_f + w_r |(f_k - f_k-1) / s_f|^2
                              + w_u |f_k / s_f|^2 ]
               + w_T (w_e |e_N / s_e|^2 + w_w |(omega_N - omega_ref,N) / s_w|^2)
    subject to x_0 = x_estimate,  x_k+1 = Phi(x_k, f_k, d_k, h),
               f_min <= f_k <= f_max,  [F f_k = 0],  [e_N = 0, omega_N = omega_ref,N]

with e_k = ``model.attitude_error(q_ref,k, q_k)`` (the model's Function: the doubled
vector part of the error quaternion, short way round; its square is smooth through
180 deg), rho_i = c_max / c_i the allocator's least-fuel weight, f_-1 the thrust applied
in the last period, failed or spent engines bounded to zero. With
``objective="time"`` the interval length is h = T / N with T a decision variable, the
terminal constraint is kept and the cost is T / (N period_s) plus the thrust terms.

Solvers
-------
``solver="rti"`` (real-time iteration, Diehl et al. 2005): one SQP iteration per period
(CasADi's ``sqpmethod`` with ``max_iter=1`` and no line search), warm-started by
shifting the last solution and its multipliers one interval. Its Hessian is the
Gauss-Newton one of the least-squares cost plus a proximal term of 1e-6: positive
semidefinite by construction. (The exact Hessian with CasADi's ``regularize``
convexification shifted every eigenvalue by the stiff attitude terms and left the thrust
step at about 1e-5 of the converged one; ``eigen-clip`` failed inside CasADi.)

The QP solver is ``qpoases`` (sparse) by default, for reliability, measured on the
paper's debris, rigid prediction, 1 s period, closed loop of a 1 deg slew, the machine
shared with other jobs (load 10-15 on 2 cores: several times a quiet machine's times;
``benchmarks/nmpc.py``, ``docs/benchmarks/nmpc.json``): no failed period in any run, but
its time grows steeply with N (median 0.06 s at N = 10, 0.4-0.6 s at N = 20, 9 s at N =
40; IPOPT's full solve is faster from N = 20 on). ``qrqp`` (CasADi's own active-set
solver) is much faster on most periods (median 0.04 s at N = 20) but stalls on some (the
zero-net-force equalities with the thrusts at their zero bounds are a degenerate
vertex): about 1.3 s and a plan outside its bounds in 3 periods of 30 at N = 10 in one
loop, none in 20 periods at N = 20 in another. Dense ``qpoases`` about 1 s; ``daqp``
1-20 s and a plan outside the bounds in every period of 20 at N = 20; ``proxqp`` at its
default accuracy left the bounds; ``osqp`` through CasADi crashed the process
(``malloc(): invalid size``); ``hpipm`` needs stage-wise Hessian blocks, which the
thrust-rate term (coupling f_k and f_k-1) breaks. The real-time target (median 20 ms at
N = 20) needs a structure-exploiting QP. A plan that leaves its bounds by more than 1e-9
(scaled) is solved again from zero multipliers, then from a cold start; failing that,
the previous plan, shifted, is applied and the step is marked unsuccessful.

``solver="full"``: IPOPT (default; bounds not relaxed), fatrop (its stage structure
detected from the ordering above) or sqpmethod, to convergence, for comparison
(measured alike: IPOPT 0.2-0.4 s and 12-20 iterations per period at N = 20, fatrop
0.7-0.9 s and 26-39 iterations).
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np
import numpy.typing as npt

from casadi_debris.controllers._engines import NmpcEngines
from casadi_debris.controllers._settings import NmpcSettings
from casadi_debris.controllers._solvers import c_stdout_silenced, gauss_newton, qp_options
from casadi_debris.dynamics import Model, assembled_modes, build_model
from casadi_debris.errors import InputShapeError, ModelError

LOGGER = logging.getLogger(__name__)

# Largest h omega of one RK4 step for the fastest mode of the prediction model: well
# inside RK4's stability limit (2.78); the phase error of an oscillator is about
# (h omega)^5 / 120 = 2.6e-4 per step (3e-3 over the 12 steps of a 1 s period at the
# first bending mode), the amplitude error smaller.
RK4_STEP_OMEGA = 0.5
# Bounds of the scaled horizon T / (N period_s) of the minimum-time objective.
TIME_SCALE_BOUNDS = (1e-3, 1e3)
# Largest violation of a bound by a scaled decision variable that a solve may leave.
BOUND_TOLERANCE = 1e-9


@dataclass(frozen=True)
class NmpcScales:
    """Units of the scaled decision variables and of the cost's terms.

    Attributes
    ----------
    attitude_rad : float
        s_e = alpha T_h^2 / 2: the angle the weakest axis turns in the horizon
        T_h = N period_s at its largest acceleration alpha [rad].
    rate_rad_s : float
        s_w = alpha T_h [rad/s].
    thrust_N : float
        s_f: the largest engine limit [N].
    state : ndarray, shape (n_x,)
        Unit of each predicted state.
    """

    attitude_rad: float
    rate_rad_s: float
    thrust_N: float
    state: np.ndarray


@dataclass(frozen=True)
class NmpcReference:
    """What the NMPC follows over its horizon.

    Parameters
    ----------
    quaternion_BN : array_like, shape (4,) or (N + 1, 4)
        Reference attitude, scalar first: one (held) or one per node.
    rate_rad_s : array_like, shape (3,) or (N + 1, 3), optional
        Reference body rate [rad/s]; default zero.
    """

    quaternion_BN: npt.ArrayLike
    rate_rad_s: npt.ArrayLike | None = None


@dataclass(frozen=True)
class NmpcStep:
    """One period of the NMPC.

    Attributes
    ----------
    thrust_N : ndarray, shape (n_engines,)
        Thrust to apply over the period [N], within every engine's limits.
    torque_Nm, force_N : ndarray, shape (3,)
        B f and F f of that thrust.
    time_s : ndarray, shape (N + 1,)
        Times of the prediction's nodes [s].
    predicted_state : ndarray, shape (N + 1, n_x)
        Predicted state at each node (``NmpcController.state_names``).
    predicted_thrust_N : ndarray, shape (N, n_engines)
    status : str
        The solver's return status.
    success : bool
        The solver's own verdict (a real-time iteration is one step by design: its
        verdict is that its QP was solved).
    solve_time_s : float
        Wall time of the solver call [s].
    sqp_iterations : int
        SQP (or interior-point) iterations.
    cost : float
    """

    thrust_N: np.ndarray
    torque_Nm: np.ndarray
    force_N: np.ndarray
    time_s: np.ndarray
    predicted_state: np.ndarray
    predicted_thrust_N: np.ndarray
    status: str
    success: bool
    solve_time_s: float
    sqp_iterations: int
    cost: float

    @property
    def horizon_s(self) -> float:
        """Length of the prediction [s] (the minimum time with ``objective="time"``)."""
        return float(self.time_s[-1] - self.time_s[0])


class NmpcController:
    """Nonlinear MPC deciding every engine's thrust, on the toolkit's CasADi model.

    Parameters
    ----------
    model : Model
        The model of the body (:func:`~casadi_debris.dynamics.build_model`); with
        ``prediction="rigid"`` the same problem's model without modes is predicted,
        with ``"flexible"`` this one, with the modes it keeps.
    settings : NmpcSettings, optional
    engines : NmpcEngines, optional
        Default: the problem's engines on their first stage.
    parameters : array_like, shape (model.parameter_layout.size,), optional
        Model parameters of the prediction; default nominal.

    Example
    -------
    >>> from casadi_debris import load_problem
    >>> from casadi_debris.dynamics import build_model
    >>> controller = NmpcController(build_model(load_problem(), modes=()))
    >>> step = controller.step(0.0, controller.model.initial_state(), [1.0, 0.0, 0.0, 0.0])
    >>> step.thrust_N.shape
    (24,)
    """

    def __init__(
        self,
        model: Model,
        settings: NmpcSettings | None = None,
        *,
        engines: NmpcEngines | None = None,
        parameters: npt.ArrayLike | None = None,
    ) -> None:
        self.settings = settings if settings is not None else NmpcSettings()
        self.model = model
        if self.settings.prediction == "rigid" and model.layout.n_eta > 0:
            self.prediction_model = build_model(model.problem, modes=())
        else:
            self.prediction_model = model
        size = model.parameter_layout.size
        p = model.nominal_parameters if parameters is None else np.asarray(parameters, float)
        if p.shape != (size,) or not np.all(np.isfinite(p)):
            raise InputShapeError(f"parameters: expected {size} finite numbers, got {p.shape}")
        self.parameters = p
        self.engines = engines if engines is not None else NmpcEngines.from_model(model)
        layout = self.prediction_model.layout
        self.n_x = layout.size - 4  # the star tracker is not predicted
        self.state_names: tuple[str, ...] = tuple(layout.names()[: self.n_x])
        self.integrator_steps = self._integrator_steps()
        self.scales = self._scales()
        self._build()
        self._warm: dict[str, np.ndarray] | None = None
        self._last_thrust = np.clip(np.zeros(self.engines.n_engines), *self._bounds())

    # ------------------------------------------------------------------ set-up

    def _integrator_steps(self) -> int:
        if self.settings.integrator_steps is not None:
            return self.settings.integrator_steps
        if not self.prediction_model.layout.n_eta:
            return 1
        # The free-floating assembly's modes, not the cantilever ones: coupled to the
        # hub they sit higher (the paper's 5.6 rad/s bending pair at 5.6 and 9.0 rad/s).
        modes = assembled_modes(self.prediction_model, self.parameters)
        fastest = max(mode["omega_rad_s"] for mode in modes)
        return max(1, math.ceil(self.settings.period_s * fastest / RK4_STEP_OMEGA))

    def _bounds(self) -> tuple[np.ndarray, np.ndarray]:
        return self.engines.lower_N, self.engines.max_thrust_N

    def _scales(self) -> NmpcScales:
        engines = self.engines
        inertia = np.array(self.prediction_model.rigid_inertia(self.parameters))
        lower, upper = self._bounds()
        # Largest torque about each axis with every engine free (a scale, not a limit).
        reach = np.maximum(engines.torque_map * upper, engines.torque_map * lower).sum(axis=1)
        acceleration = float(np.min(reach / np.diag(inertia)))
        if not acceleration > 0:
            raise ModelError("the engines make no torque about some axis: no NMPC scale")
        horizon_s = self.settings.horizon_steps * self.settings.period_s
        rate = acceleration * horizon_s
        thrust = float(max(np.abs(upper).max(), np.abs(lower).max()))
        layout = self.prediction_model.layout
        state = np.ones(self.n_x)
        state[layout.omega] = rate
        mass = float(self.prediction_model.nominal.mass_kg)
        force = float(np.abs(engines.force_map).sum(axis=0).max()) * thrust * engines.n_engines
        state[layout.v] = max(force / mass * horizon_s, rate)
        if layout.n_eta:
            mass_matrix = np.array(self.prediction_model.mass_matrix(self.parameters))
            coupling = np.linalg.norm(mass_matrix[6:, 3:6], axis=1)
            deflection = np.maximum(coupling * acceleration, 1e-12)
            state[layout.eta] = deflection
            state[layout.eta_dot] = deflection * 10.0
        return NmpcScales(0.5 * acceleration * horizon_s**2, rate, thrust, state)

    def _discrete_map(self) -> ca.Function:
        """Phi(x, f, d, h): the model's dynamics held over one interval, RK4."""
        model, lay = self.prediction_model, self.prediction_model.layout
        x = ca.SX.sym("x", self.n_x)
        f = ca.SX.sym("f", self.engines.n_engines)
        d = ca.SX.sym("d", 3)
        h = ca.SX.sym("h")
        torque = ca.DM(self.engines.torque_map) @ f
        force = ca.DM(self.engines.force_map) @ f
        p = ca.DM(self.parameters)

        def rate(state: ca.SX) -> ca.SX:
            # The star tracker sits at the attitude: it is not part of the prediction.
            full = ca.vertcat(state, state[lay.q])
            return model.dynamics(full, ca.vertcat(torque, d, force), p)[: self.n_x]

        step = h / self.integrator_steps
        state = x
        for _ in range(self.integrator_steps):
            k1 = rate(state)
            k2 = rate(state + step / 2 * k1)
            k3 = rate(state + step / 2 * k2)
            k4 = rate(state + step * k3)
            state = state + step / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        return ca.Function("nmpc_interval", [x, f, d, h], [state], ["x", "f", "d", "h"], ["x_next"])

    def _build(self) -> None:
        s, sc = self.settings, self.scales
        n_steps, n_x, n_f = s.horizon_steps, self.n_x, self.engines.n_engines
        lay = self.prediction_model.layout
        phi = self._discrete_map()
        error_of = self.prediction_model.attitude_error
        x_scale = ca.DM(sc.state)
        q_ref = ca.SX.sym("q_ref", 4, n_steps + 1)
        w_ref = ca.SX.sym("w_ref", 3, n_steps + 1)
        f_prev = ca.SX.sym("f_prev", n_f)
        dist = ca.SX.sym("d", 3, n_steps)
        parameters = ca.vertcat(ca.vec(q_ref), ca.vec(w_ref), f_prev, ca.vec(dist))
        xs = [ca.SX.sym(f"x{k}", n_x) for k in range(n_steps + 1)]
        us = [ca.SX.sym(f"f{k}", n_f) for k in range(n_steps)]
        time_scale = ca.SX.sym("T") if s.objective == "time" else None
        h = s.period_s * (time_scale if time_scale is not None else 1.0)
        fuel = ca.DM(self.engines.fuel_weights)
        force_map = ca.DM(self.engines.force_map)

        def tracking(k: int, weight: float) -> list[ca.SX]:
            x = x_scale * xs[k]
            e = error_of(q_ref[:, k], x[lay.q]) / sc.attitude_rad
            w = (x[lay.omega] - w_ref[:, k]) / sc.rate_rad_s
            return [
                math.sqrt(weight * s.attitude_weight) * e,
                math.sqrt(weight * s.rate_weight) * w,
            ]

        # The cost is a sum of squares of the residuals plus a linear part: its
        # Gauss-Newton Hessian is what the SQP iterations use.
        residuals: list[ca.SX] = []
        linear: ca.SX = ca.SX(0)
        constraints: list[ca.SX] = []
        previous = f_prev / sc.thrust_N
        for k in range(n_steps):
            if s.objective == "tracking":
                residuals += tracking(k, 1.0)
            linear += s.propellant_weight * ca.dot(fuel, us[k])
            residuals.append(math.sqrt(s.thrust_rate_weight) * (us[k] - previous))
            residuals.append(math.sqrt(s.thrust_weight) * us[k])
            previous = us[k]
            # Gap first, then the stage's path constraint: the order fatrop detects.
            x_next = phi(x_scale * xs[k], sc.thrust_N * us[k], dist[:, k], h)
            constraints.append(xs[k + 1] - x_next / x_scale)
            if s.zero_net_force:
                constraints.append(force_map @ us[k])
        if s.terminal == "constraint":
            x_end = x_scale * xs[n_steps]
            constraints.append(error_of(q_ref[:, n_steps], x_end[lay.q]) / sc.attitude_rad)
            constraints.append((x_end[lay.omega] - w_ref[:, n_steps]) / sc.rate_rad_s)
        elif s.objective == "tracking":
            residuals += tracking(n_steps, s.terminal_weight)
        if time_scale is not None:
            linear += time_scale
        residual = ca.vertcat(*residuals)
        cost = ca.sumsqr(residual) + linear
        variables: list[ca.SX] = []
        for k in range(n_steps):
            variables += [xs[k], us[k]]
        variables.append(xs[n_steps])
        if time_scale is not None:
            variables.append(time_scale)
        nlp = {
            "x": ca.vertcat(*variables),
            "f": cost,
            "g": ca.vertcat(*constraints),
            "p": parameters,
        }
        self._n_stage = n_x + n_f
        self._n_g_stage = n_x + (3 if s.zero_net_force else 0)
        self._n_w = nlp["x"].numel()
        self._n_g = nlp["g"].numel()
        options = self._solver_options()
        if options.get("qpsol") is not None:
            options["hess_lag"] = gauss_newton(nlp, residual)
        if self.settings.solver == "full" and self.settings.full_solver == "fatrop":
            # Every constraint is an equality (gaps, zero force, terminal): fatrop's stage
            # structure detection needs to be told.
            options["equality"] = [True] * self._n_g
        with c_stdout_silenced():
            # qpOASES prints its licence banner from C when it is set up, whatever its
            # printLevel: nothing below the CLI prints.
            self._solver = ca.nlpsol("nmpc", *self._solver_plugin(), nlp, options)

    def _solver_plugin(self) -> tuple[str]:
        s = self.settings
        if s.solver == "rti":
            return ("sqpmethod",)
        if s.full_solver == "fatrop" and not ca.has_nlpsol("fatrop"):
            raise ModelError("full_solver: fatrop is not in this CasADi build; use ipopt")
        return (s.full_solver,)

    def _solver_options(self) -> dict[str, Any]:
        s = self.settings
        quiet: dict[str, Any] = {"print_time": False, "error_on_fail": False}
        sqp = {
            **quiet,
            "qpsol": s.qp_solver,
            "qpsol_options": self._qp_options(),
            "print_header": False,
            "print_iteration": False,
            "print_status": False,
        }
        if s.solver == "rti":
            return {**sqp, "max_iter": 1, "max_iter_ls": 0}
        if s.full_solver == "sqpmethod":
            return {**sqp, "max_iter": s.max_sqp_iterations}
        if s.full_solver == "fatrop":
            return {
                **quiet,
                "structure_detection": "auto",
                "fatrop": {"print_level": 0, "max_iter": s.max_sqp_iterations},
            }
        return {
            **quiet,
            # No relaxation of the bounds: the plan keeps every engine within its limits.
            "ipopt": {
                "print_level": 0,
                "sb": "yes",
                "max_iter": s.max_sqp_iterations,
                "tol": 1e-10,
                "bound_relax_factor": 0.0,
            },
        }

    def _qp_options(self) -> dict[str, Any]:
        """The QP solver's options; hpipm is told the stage structure."""
        options = qp_options(self.settings.qp_solver)
        if self.settings.qp_solver == "hpipm":
            n_steps = self.settings.horizon_steps
            path = 3 if self.settings.zero_net_force else 0
            terminal = 6 if self.settings.terminal == "constraint" else 0
            options.update(
                {
                    "N": n_steps,
                    "nx": [self.n_x] * (n_steps + 1),
                    "nu": [self.engines.n_engines] * n_steps + [0],
                    "ng": [path] * n_steps + [terminal],
                }
            )
        return options

    # ------------------------------------------------------------------ use

    @property
    def n_engines(self) -> int:
        return self.engines.n_engines

    def set_limits(
        self, max_thrust_N: npt.ArrayLike, min_thrust_N: npt.ArrayLike | None = None
    ) -> None:
        """New engine limits (a stage change or a failure), from the next step on.

        The solver is not rebuilt: limits are bounds of the decision variables.
        """
        self.engines = self.engines.with_limits(max_thrust_N, min_thrust_N)

    def reset(self) -> None:
        """Forget the warm start and the last applied thrust."""
        self._warm = None
        self._last_thrust = np.clip(np.zeros(self.n_engines), *self._bounds())

    def set_guess(
        self,
        state: npt.ArrayLike,
        thrust_N: npt.ArrayLike,
        horizon_s: float | None = None,
    ) -> None:
        """Start the next solve from a given trajectory instead of the shifted last one.

        Parameters
        ----------
        state : array_like, shape (N + 1, n_x)
            Predicted states (``state_names``).
        thrust_N : array_like, shape (N, n_engines)
        horizon_s : float, optional
            Horizon length, for ``objective="time"``; default ``N period_s``.
        """
        n_steps = self.settings.horizon_steps
        states = np.asarray(state, dtype=float)
        thrusts = np.asarray(thrust_N, dtype=float)
        if states.shape != (n_steps + 1, self.n_x):
            raise InputShapeError(
                f"state: expected shape {(n_steps + 1, self.n_x)}, got {states.shape}"
            )
        if thrusts.shape != (n_steps, self.n_engines):
            raise InputShapeError(
                f"thrust_N: expected shape {(n_steps, self.n_engines)}, got {thrusts.shape}"
            )
        time_scale = 1.0 if horizon_s is None else horizon_s / (n_steps * self.settings.period_s)
        self._warm = {
            "x0": self._pack(states, thrusts, time_scale),
            "lam_x0": np.zeros(self._n_w),
            "lam_g0": np.zeros(self._n_g),
        }

    def step(
        self,
        time_s: float,
        state_estimate: npt.ArrayLike,
        reference: NmpcReference | npt.ArrayLike,
        *,
        disturbance_Nm: npt.ArrayLike | None = None,
    ) -> NmpcStep:
        """Solve for the thrust of the period starting at ``time_s``.

        Parameters
        ----------
        time_s : float
            Time of the period's start [s] (the disturbance model's clock).
        state_estimate : array_like, shape (model.layout.size,) or (n_x,)
            The state of ``model`` (its star tracker ignored) or of the prediction.
        reference : NmpcReference or array_like, shape (4,)
            What to follow; a quaternion is held with zero rate.
        disturbance_Nm : array_like, shape (3,), optional
            A known disturbance torque held over the horizon, added to the model's
            with ``disturbance="model"`` [N m].

        Returns
        -------
        NmpcStep
        """
        s = self.settings
        x_init = self._prediction_state(state_estimate)
        q_ref, w_ref = self._reference(reference)
        dist = self._disturbances(float(time_s), disturbance_Nm)
        lower, upper = self._bounds()
        lbx, ubx = self._variable_bounds(x_init, lower, upper)
        warm = self._warm if self._warm is not None else self._cold_start(x_init)
        x0 = np.clip(warm["x0"], lbx, ubx)
        lbg = np.zeros(self._n_g)
        arguments = {
            "x0": x0,
            "lam_x0": warm["lam_x0"],
            "lam_g0": warm["lam_g0"],
            "lbx": lbx,
            "ubx": ubx,
            "lbg": lbg,
            "ubg": lbg,
            "p": np.concatenate([q_ref.ravel(), w_ref.ravel(), self._last_thrust, dist.ravel()]),
        }
        start = time.perf_counter()
        solution = self._solver(**arguments)
        w = np.array(solution["x"]).ravel()
        plan_ok = self._plan_within_bounds(w, lbx, ubx)
        if not plan_ok and s.solver == "rti":
            # An active-set QP warm-started from shifted multipliers can stop on a wrong
            # active set; the same linearisation started from zero multipliers is solved
            # again (measured: about one period in 40 on the paper's slew).
            for retry in (warm, self._cold_start(x_init)):
                arguments["x0"] = np.clip(retry["x0"], lbx, ubx)
                arguments["lam_x0"] = np.zeros(self._n_w)
                arguments["lam_g0"] = np.zeros(self._n_g)
                solution = self._solver(**arguments)
                w = np.array(solution["x"]).ravel()
                plan_ok = self._plan_within_bounds(w, lbx, ubx)
                if plan_ok:
                    break
                LOGGER.info("NMPC: the QP left its bounds; solved again from zero multipliers")
        solve_time = time.perf_counter() - start
        stats = self._solver.stats()
        finite = plan_ok
        if not plan_ok:
            LOGGER.warning(
                "NMPC solve (%s) left its bounds: the previous plan, shifted, is applied",
                stats.get("return_status"),
            )
            w = x0
        states, thrusts, time_scale = self._unpack(w)
        thrust = np.clip(thrusts[0], lower, upper)
        self._last_thrust = thrust
        self._warm = self._shifted(
            w,
            np.array(solution["lam_x"]).ravel() if finite else np.zeros(self._n_w),
            np.array(solution["lam_g"]).ravel() if finite else np.zeros(self._n_g),
        )
        h = s.period_s * time_scale
        status = str(stats.get("return_status", "unknown"))
        success = bool(stats.get("success", False))
        if s.solver == "rti":
            success = finite and "fail" not in status.lower() and "infeasible" not in status.lower()
        return NmpcStep(
            thrust_N=thrust,
            torque_Nm=self.engines.torque_map @ thrust,
            force_N=self.engines.force_map @ thrust,
            time_s=float(time_s) + h * np.arange(s.horizon_steps + 1),
            predicted_state=states,
            predicted_thrust_N=thrusts,
            status=status,
            success=success and finite,
            solve_time_s=solve_time,
            sqp_iterations=int(stats.get("iter_count", 0)),
            cost=float(solution["f"]),
        )

    def _plan_within_bounds(self, w: np.ndarray, lbx: np.ndarray, ubx: np.ndarray) -> bool:
        """Finite, and within the bounds to 1e-9 of the scaled variables (thrusts of
        order one): what a converged QP gives."""
        if not np.all(np.isfinite(w)):
            return False
        return bool(np.all(w >= lbx - BOUND_TOLERANCE) and np.all(w <= ubx + BOUND_TOLERANCE))

    # ------------------------------------------------------------------ packing

    def _prediction_state(self, state_estimate: npt.ArrayLike) -> np.ndarray:
        x = np.asarray(state_estimate, dtype=float)
        full = self.model.layout
        if x.shape == (self.n_x,):
            prediction = x.copy()
        elif x.shape == (full.size,):
            pred = self.prediction_model.layout
            prediction = np.zeros(self.n_x)
            prediction[pred.q] = x[full.q]
            prediction[pred.omega] = x[full.omega]
            prediction[pred.v] = x[full.v]
            if pred.n_eta:
                prediction[pred.eta] = x[full.eta]
                prediction[pred.eta_dot] = x[full.eta_dot]
        else:
            raise InputShapeError(
                f"state_estimate: expected {full.size} or {self.n_x} numbers, got shape {x.shape}"
            )
        if not np.all(np.isfinite(prediction)):
            raise InputShapeError("state_estimate: must be finite")
        lay = self.prediction_model.layout
        norm = float(np.linalg.norm(prediction[lay.q]))
        if norm == 0.0:
            raise InputShapeError("state_estimate: the quaternion must not be zero")
        prediction[lay.q] /= norm
        return prediction

    def _reference(self, reference: NmpcReference | npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        nodes = self.settings.horizon_steps + 1
        if not isinstance(reference, NmpcReference):
            reference = NmpcReference(reference)
        q = np.asarray(reference.quaternion_BN, dtype=float)
        q = np.broadcast_to(q, (nodes, 4)) if q.shape == (4,) else q
        if q.shape != (nodes, 4) or not np.all(np.isfinite(q)):
            raise InputShapeError(f"reference.quaternion_BN: expected (4,) or ({nodes}, 4) finite")
        norms = np.linalg.norm(q, axis=1, keepdims=True)
        if np.any(norms == 0):
            raise InputShapeError("reference.quaternion_BN: must not be zero")
        rate = (
            np.zeros(3) if reference.rate_rad_s is None else np.asarray(reference.rate_rad_s, float)
        )
        rate = np.broadcast_to(rate, (nodes, 3)) if rate.shape == (3,) else rate
        if rate.shape != (nodes, 3) or not np.all(np.isfinite(rate)):
            raise InputShapeError(f"reference.rate_rad_s: expected (3,) or ({nodes}, 3) finite")
        # Column-major parameters: one node's quaternion after another.
        return (q / norms), rate

    def _disturbances(self, time_s: float, disturbance_Nm: npt.ArrayLike | None) -> np.ndarray:
        s = self.settings
        held = np.zeros(3) if disturbance_Nm is None else np.asarray(disturbance_Nm, float)
        if held.shape != (3,) or not np.all(np.isfinite(held)):
            raise InputShapeError("disturbance_Nm: expected 3 finite numbers")
        dist = np.tile(held, (s.horizon_steps, 1))
        if s.disturbance == "model":
            for k in range(s.horizon_steps):
                dist[k] += np.array(self.model.disturbance(time_s + k * s.period_s)).ravel()
        return dist

    def _variable_bounds(
        self, x_init: np.ndarray, lower: np.ndarray, upper: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        n_steps = self.settings.horizon_steps
        inf_x = np.full(self.n_x, np.inf)
        lbx_stage = np.concatenate([-inf_x, lower / self.scales.thrust_N])
        ubx_stage = np.concatenate([inf_x, upper / self.scales.thrust_N])
        lbx = np.concatenate([np.tile(lbx_stage, n_steps), -inf_x])
        ubx = np.concatenate([np.tile(ubx_stage, n_steps), inf_x])
        fixed = x_init / self.scales.state
        lbx[: self.n_x] = fixed
        ubx[: self.n_x] = fixed
        if self.settings.objective == "time":
            lbx = np.append(lbx, TIME_SCALE_BOUNDS[0])
            ubx = np.append(ubx, TIME_SCALE_BOUNDS[1])
        return lbx, ubx

    def _pack(self, states: np.ndarray, thrusts: np.ndarray, time_scale: float) -> np.ndarray:
        n_steps = self.settings.horizon_steps
        scaled_x = states / self.scales.state
        scaled_f = thrusts / self.scales.thrust_N
        parts = [np.concatenate([scaled_x[k], scaled_f[k]]) for k in range(n_steps)]
        parts.append(scaled_x[n_steps])
        if self.settings.objective == "time":
            parts.append(np.array([time_scale]))
        return np.concatenate(parts)

    def _unpack(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
        n_steps, n_x = self.settings.horizon_steps, self.n_x
        body = w[: n_steps * self._n_stage].reshape(n_steps, self._n_stage)
        last = w[n_steps * self._n_stage : n_steps * self._n_stage + n_x]
        states = np.vstack([body[:, :n_x], last]) * self.scales.state
        thrusts = body[:, n_x:] * self.scales.thrust_N
        time_scale = float(w[-1]) if self.settings.objective == "time" else 1.0
        return states, thrusts, time_scale

    def _cold_start(self, x_init: np.ndarray) -> dict[str, np.ndarray]:
        n_steps = self.settings.horizon_steps
        states = np.tile(x_init, (n_steps + 1, 1))
        thrusts = np.tile(self._last_thrust, (n_steps, 1))
        return {
            "x0": self._pack(states, thrusts, 1.0),
            "lam_x0": np.zeros(self._n_w),
            "lam_g0": np.zeros(self._n_g),
        }

    def _shifted(
        self, w: np.ndarray, lam_x: np.ndarray, lam_g: np.ndarray
    ) -> dict[str, np.ndarray]:
        """The solution one interval on: drop the first stage, repeat the last."""
        if self.settings.objective == "time":
            # The minimum-time horizon shrinks by one period in real time; it is re-solved
            # from the same trajectory rather than shifted on its own grid.
            return {"x0": w, "lam_x0": lam_x, "lam_g0": lam_g}
        n_steps, stage, g_stage = self.settings.horizon_steps, self._n_stage, self._n_g_stage
        x0 = _shift(w, stage, n_steps, self.n_x)
        # The repeated last stage starts where the old horizon ended.
        end = n_steps * stage
        x0[end - stage : end - stage + self.n_x] = w[end : end + self.n_x]
        return {
            "x0": x0,
            "lam_x0": _shift(lam_x, stage, n_steps, self.n_x),
            "lam_g0": _shift(lam_g, g_stage, n_steps, self._n_g - n_steps * g_stage),
        }


def _shift(values: np.ndarray, block: int, n_blocks: int, tail: int) -> np.ndarray:
    """Blocks 1..n-1, then the last block again, then the tail (terminal part) as it was."""
    body = values[: block * n_blocks].reshape(n_blocks, block)
    shifted = np.vstack([body[1:], body[-1:]]).ravel() if n_blocks > 1 else body.ravel()
    end = values[block * n_blocks : block * n_blocks + tail]
    return np.concatenate([shifted, end])
