"""How the NMPC controller computes: horizon, period, prediction model, weights, solver.

Every weight is dimensionless: it multiplies a term normalised by the scales of
:class:`~casadi_debris.controllers.NmpcScales` (derived from the body and its
engines when the controller is built), so that one set of defaults suits a
1 kg m^2 test body and the paper's 668 kg debris alike.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from casadi_debris.errors import InputShapeError

PredictionKind = Literal["rigid", "flexible"]
SolverKind = Literal["rti", "full"]
TerminalKind = Literal["cost", "constraint"]
ObjectiveKind = Literal["tracking", "time"]
DisturbanceKind = Literal["none", "model"]

PREDICTIONS: tuple[str, ...] = ("rigid", "flexible")
SOLVERS: tuple[str, ...] = ("rti", "full")
TERMINALS: tuple[str, ...] = ("cost", "constraint")
OBJECTIVES: tuple[str, ...] = ("tracking", "time")
DISTURBANCES: tuple[str, ...] = ("none", "model")
# QP solvers of CasADi's ``conic`` that the real-time iteration can use, and the full solves.
QP_SOLVERS: tuple[str, ...] = ("qrqp", "osqp", "daqp", "hpipm", "qpoases", "proxqp")
FULL_SOLVERS: tuple[str, ...] = ("ipopt", "fatrop", "sqpmethod")


@dataclass(frozen=True)
class NmpcSettings:
    """Settings of :class:`~casadi_debris.controllers.NmpcController`.

    Parameters
    ----------
    horizon_steps : int
        Shooting intervals N of the prediction (>= 1).
    period_s : float
        Length of each interval and the control period [s] (> 0).
    prediction : {"rigid", "flexible"}
        ``"rigid"``: the same problem's model with no modal states (the arrays as rigid
        bodies); ``"flexible"``: the model given, with the modes it keeps.
    integrator_steps : int or None
        RK4 steps per interval; ``None``: enough that every step is at most
        ``0.5 / omega_max`` long, omega_max the fastest mode of the free-floating
        assembly the prediction model describes (1 step for a rigid one).
    attitude_weight, rate_weight : float
        Weight of |e / attitude_scale|^2 and |(omega - omega_ref) / rate_scale|^2 at
        each node (>= 0).
    propellant_weight : float
        Weight of sum_i (f_i / thrust_scale) (c_max / c_i): the propellant flow, Isp
        weighted as the allocator's least-fuel cost (>= 0). Engines that can push both
        ways (``min_thrust_N < 0``) are not charged.
    thrust_rate_weight : float
        Weight of |(f_k - f_k-1) / thrust_scale|^2, f_-1 the thrust applied last (>= 0).
    thrust_weight : float
        Weight of |f_k / thrust_scale|^2 (>= 0): a small one regularises the QPs.
    terminal : {"cost", "constraint"}
        ``"cost"``: ``terminal_weight`` times the attitude and rate terms at node N;
        ``"constraint"``: e_N = 0 and omega_N = omega_ref,N.
    terminal_weight : float
    zero_net_force : bool
        Add F f_k = 0 at every interval (translation left alone).
    objective : {"tracking", "time"}
        ``"tracking"``: the quadratic cost over the fixed horizon ``N period_s``;
        ``"time"``: the shortest horizon T (intervals of T / N) reaching the reference at
        rest (terminal constraint), plus the other terms as a tie-break.
    solver : {"rti", "full"}
        ``"rti"``: one SQP iteration per period, warm-started by shifting;
        ``"full"``: ``full_solver`` to convergence.
    qp_solver : str
        QP solver of the SQP iterations, one of ``QP_SOLVERS``.
    full_solver : str
        ``"ipopt"``, ``"fatrop"`` or ``"sqpmethod"`` (with ``qp_solver``) to convergence.
    max_sqp_iterations : int
        Iteration limit of the full solve.
    disturbance : {"none", "model"}
        ``"model"``: the model's own disturbance torque d(t) is predicted.
    """

    horizon_steps: int = 20
    period_s: float = 1.0
    prediction: PredictionKind = "rigid"
    integrator_steps: int | None = None
    attitude_weight: float = 1.0
    rate_weight: float = 0.1
    propellant_weight: float = 1e-3
    thrust_rate_weight: float = 1e-3
    thrust_weight: float = 1e-4
    terminal: TerminalKind = "cost"
    terminal_weight: float = 10.0
    zero_net_force: bool = True
    objective: ObjectiveKind = "tracking"
    solver: SolverKind = "rti"
    qp_solver: str = "qpoases"
    full_solver: str = "ipopt"
    max_sqp_iterations: int = 100
    disturbance: DisturbanceKind = "none"

    def __post_init__(self) -> None:
        _check_int("horizon_steps", self.horizon_steps, 1)
        _check_int("max_sqp_iterations", self.max_sqp_iterations, 1)
        if self.integrator_steps is not None:
            _check_int("integrator_steps", self.integrator_steps, 1)
        if not (isinstance(self.period_s, int | float) and math.isfinite(self.period_s)):
            raise InputShapeError(f"period_s: expected a finite number, got {self.period_s!r}")
        if self.period_s <= 0:
            raise InputShapeError(f"period_s: must be > 0, got {self.period_s}")
        for name in (
            "attitude_weight",
            "rate_weight",
            "propellant_weight",
            "thrust_rate_weight",
            "thrust_weight",
            "terminal_weight",
        ):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and math.isfinite(value) and value >= 0):
                raise InputShapeError(f"{name}: expected a finite number >= 0, got {value!r}")
        _check_choice("prediction", self.prediction, PREDICTIONS)
        _check_choice("terminal", self.terminal, TERMINALS)
        _check_choice("objective", self.objective, OBJECTIVES)
        _check_choice("solver", self.solver, SOLVERS)
        _check_choice("qp_solver", self.qp_solver, QP_SOLVERS)
        _check_choice("full_solver", self.full_solver, FULL_SOLVERS)
        _check_choice("disturbance", self.disturbance, DISTURBANCES)
        if self.objective == "time" and self.terminal != "constraint":
            raise InputShapeError(
                'objective: "time" needs terminal = "constraint" (the horizon ends at the '
                "reference)"
            )


def _check_int(name: str, value: object, smallest: int) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or value < smallest:
        raise InputShapeError(f"{name}: expected an integer >= {smallest}, got {value!r}")


def _check_choice(name: str, value: object, choices: tuple[str, ...]) -> None:
    if value not in choices:
        raise InputShapeError(f"{name}: expected one of {', '.join(choices)}, got {value!r}")
