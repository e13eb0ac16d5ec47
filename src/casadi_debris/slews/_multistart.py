"""Multi-start direct collocation of the rigid time-optimal slew.

A time-optimal slew has several local optima, and the eigenaxis bang-bang is
a stationary point of the NLP on symmetric bodies (its off-axis torques have a
zero gradient there): IPOPT started from it alone stays there (Bilimoria & Wie
1993: with J = I and |u_i| <= 1 the eigenaxis 180 deg slew takes 2 sqrt(pi) =
3.545, the time-optimal one 3.243). This module solves the same NLP from
several seeded starts and sorts what they find:

- the eigenaxis bang-bang, and the box-corner bang-bang of the same signs;
- eigenaxis bang-bangs about tilted axes (the rate profile rotated by 15 to 60
  deg about a random perpendicular axis), which break the symmetry;
- nutating ones: the eigenaxis bang-bang plus a random perpendicular torque
  that reverses at the quarter or half times;
- the eigenaxis bang-bang plus random noise on every interval.

The NLP is the scaled rigid body (:func:`~casadi_debris.slews._rigid_body.scaled_rigid_ode`:
time in units of the eigenaxis limit, torques in units of each axis' bound),
transcribed by Radau collocation of degree 3 on uniform intervals of free
total length (the coefficients of :func:`~casadi_debris.slews._transcription.radau_coefficients`),
the end conditions the attitude error and the rate. It is built once per
process and re-solved from each start; starts run in parallel processes
(:func:`~casadi_debris.parallel.parallel_map`) when more than one worker is
asked for. Each start is recorded with its label; the generator's seed is the
caller's.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol, TypeVar

import casadi as ca
import numpy as np

from casadi_debris.dynamics import quaternion_product
from casadi_debris.errors import SlewInfeasibleError
from casadi_debris.parallel import ItemFailure, keep_ctrl_c, parallel_map
from casadi_debris.slews._rigid_body import N_RIGID_STATE, RigidBody, scaled_rigid_ode
from casadi_debris.slews._transcription import (
    ACCEPTED_STATUS,
    COLLOCATION_DEGREE,
    IntervalCollocation,
    SolverOptions,
    radau_coefficients,
)


class Labelled(Protocol):
    """A start: its label names it in the logs and the outcomes."""

    @property
    def label(self) -> str: ...


StartT = TypeVar("StartT", bound=Labelled)
OutcomeT = TypeVar("OutcomeT")

# Durations within this relative distance are one optimum: the same local optimum
# reached from two starts agrees to the solver tolerance (1e-8); distinct optima of the
# benchmarks differ by 1e-3 and more.
AGREEMENT_TOLERANCE = 1e-5
# Picks one of many equally fast controls (singular arcs); far below the tolerance.
REGULARISATION = 1e-8
START_OPTIONS: SolverOptions = {
    "expand": True,
    "print_time": False,
    "ipopt.print_level": 0,
    "ipopt.sb": "yes",
    "ipopt.max_iter": 600,
    "ipopt.tol": 1e-10,
}
DURATION_BOUNDS = (0.05, 20.0)  # scaled: the slew lasts 0.05 to 20 eigenaxis limits
TILT_DEG = (15.0, 60.0)
NOISE = 0.3
KINDS = ("tilted", "nutating", "perturbed")
# Half turns about the body axes: each maps the torque box onto itself (when its bounds
# are symmetric) and commutes with a diagonal inertia.
HALF_TURNS = {"x": (1.0, -1.0, -1.0), "y": (-1.0, 1.0, -1.0), "z": (-1.0, -1.0, 1.0)}


@dataclass(frozen=True)
class RigidSlew:
    """A rest-to-rest slew of a rigid body, everything the NLP needs (picklable).

    Attributes
    ----------
    body : RigidBody
    q_initial_BN, q_final_BN : ndarray, shape (4,)
        Start and end attitude, scalar first.
    axis_B : ndarray, shape (3,)
        The eigenaxis.
    angle_rad : float
        The eigenaxis angle, in (0, pi].
    time_scale_s : float
        T_s, the eigenaxis limit, s: the unit of the scaled time.
    alpha_max_rad_s2 : float
        The eigenaxis acceleration limit, rad/s^2.
    intervals : int
        Collocation intervals.
    """

    body: RigidBody
    q_initial_BN: np.ndarray
    q_final_BN: np.ndarray
    axis_B: np.ndarray
    angle_rad: float
    time_scale_s: float
    alpha_max_rad_s2: float
    intervals: int

    @property
    def lower(self) -> np.ndarray:
        """Scaled torque bounds, lower, shape (3,)."""
        return self.body.lower_Nm / self.body.torque_scale_Nm

    @property
    def upper(self) -> np.ndarray:
        """Scaled torque bounds, upper, shape (3,)."""
        return self.body.upper_Nm / self.body.torque_scale_Nm

    def eigenaxis_torque(self, axis: np.ndarray | None = None) -> np.ndarray:
        """Scaled torque J a alpha of the largest eigenaxis acceleration about ``axis``
        (default the slew's), gyroscopic term left out, shape (3,)."""
        e = self.axis_B if axis is None else axis
        moment = self.body.inertia_kgm2 @ e
        scale = self.body.torque_scale_Nm
        bound = np.where(moment >= 0.0, self.body.upper_Nm, -self.body.lower_Nm)
        bound = np.minimum(bound, np.where(moment >= 0.0, -self.body.lower_Nm, self.body.upper_Nm))
        used = np.abs(moment) > 1e-12 * np.max(np.abs(moment))
        alpha = float(np.min(bound[used] / np.abs(moment[used])))
        return alpha * moment / scale

    def terminal_error(self, final: ca.SX) -> ca.SX:
        """Vector part of q_f^-1 (x) q(T) and the scaled rate (6); zero at the target."""
        conjugate = np.concatenate([self.q_final_BN[:1], -self.q_final_BN[1:]])
        error = quaternion_product(ca.SX(conjugate), final[0:4])
        return ca.vertcat(error[1:4], final[4:7])


@dataclass(frozen=True)
class Start:
    """One initial guess.

    Attributes
    ----------
    label : str
        What it is (``"eigenaxis"``, ``"tilted 3"``, ...).
    controls : ndarray, shape (intervals, 3)
        Scaled torque held on each interval, within the bounds.
    duration : float
        Scaled length.
    """

    label: str
    controls: np.ndarray
    duration: float


@dataclass(frozen=True)
class StartOutcome:
    """Where IPOPT went from one start.

    Attributes
    ----------
    label : str
        The start's label.
    status : str
        IPOPT's return status (or the error, if the solve raised).
    duration : float
        Scaled length found (nan unless converged).
    controls : ndarray, shape (intervals, 3)
        Scaled torque of the solution.
    """

    label: str
    status: str
    duration: float
    controls: np.ndarray

    @property
    def converged(self) -> bool:
        """IPOPT succeeded."""
        return self.status in ACCEPTED_STATUS


@dataclass(frozen=True)
class MultiStartResult:
    """Every start's outcome, sorted into optima.

    Attributes
    ----------
    outcomes : tuple of StartOutcome
        In the order of the starts.
    optima : tuple of float
        The distinct scaled durations found, shortest first.
    seed : int
        The seed of the random starts.
    """

    outcomes: tuple[StartOutcome, ...]
    optima: tuple[float, ...]
    seed: int

    @property
    def best(self) -> StartOutcome:
        """The converged outcome of least duration."""
        converged = [o for o in self.outcomes if o.converged]
        if not converged:
            statuses = sorted({o.status for o in self.outcomes})
            raise SlewInfeasibleError(
                f"optimal slew did not converge from any of {len(self.outcomes)} starts "
                f"(ipopt: {', '.join(statuses)})"
            )
        return min(converged, key=lambda o: o.duration)

    @property
    def agreeing(self) -> int:
        """How many starts found the best duration (within ``AGREEMENT_TOLERANCE``)."""
        best = self.best.duration
        return sum(
            1
            for o in self.outcomes
            if o.converged and abs(o.duration - best) <= AGREEMENT_TOLERANCE * best
        )


def distinct(durations: list[float]) -> tuple[float, ...]:
    """The durations with those within ``AGREEMENT_TOLERANCE`` of a shorter one removed."""
    kept: list[float] = []
    for value in sorted(durations):
        if not kept or value - kept[-1] > AGREEMENT_TOLERANCE * kept[-1]:
            kept.append(value)
    return tuple(kept)


def bang_bang(
    torque: np.ndarray, count: int, pattern: tuple[float, ...] = (1.0, -1.0)
) -> np.ndarray:
    """``torque`` (shape (3,)) times the signs of ``pattern`` over equal parts of ``count``
    intervals, shape (count, 3)."""
    parts = np.minimum((np.arange(count) + 0.5) / count * len(pattern), len(pattern) - 1)
    return np.array(pattern)[parts.astype(int)][:, None] * torque[None, :]


def make_starts(slew: RigidSlew, count: int, seed: int) -> list[Start]:
    """``count`` starts (module notes): the eigenaxis and box-corner bang-bangs, then tilted,
    nutating and perturbed ones in turn, drawn from ``numpy.random.default_rng(seed)``."""
    n = slew.intervals
    rng = np.random.default_rng(seed)
    eigen = slew.eigenaxis_torque()
    clip = functools.partial(np.clip, a_min=slew.lower, a_max=slew.upper)
    starts = [Start("eigenaxis", clip(bang_bang(eigen, n)), 1.0)]
    corner = np.where(eigen >= 0.0, slew.upper, slew.lower) * (np.abs(eigen) > 1e-9)
    starts.append(Start("box corner", clip(bang_bang(corner, n)), 0.95))
    for index in range(count - len(starts)):
        kind = KINDS[index % len(KINDS)]
        across = _perpendicular(slew.axis_B, rng)
        if kind == "tilted":
            tilt = math.radians(rng.uniform(*TILT_DEG))
            axis = math.cos(tilt) * slew.axis_B + math.sin(tilt) * across
            controls = bang_bang(slew.eigenaxis_torque(axis), n)
        elif kind == "nutating":
            pattern = (1.0, -1.0, -1.0, 1.0) if rng.random() < 0.5 else (1.0, -1.0)
            side = rng.uniform(0.3, 1.0) * bang_bang(slew.eigenaxis_torque(across), n, pattern)
            controls = bang_bang(eigen, n) + side
        else:
            controls = bang_bang(eigen, n) + rng.normal(0.0, NOISE, (n, 3))
        starts.append(Start(f"{kind} {index + 1}", clip(controls), rng.uniform(0.85, 1.0)))
    return starts[:count]


def _perpendicular(axis: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """A random unit vector perpendicular to ``axis``."""
    basis = np.linalg.svd(axis[None, :])[2][1:]
    angle = rng.uniform(0.0, 2.0 * math.pi)
    return math.cos(angle) * basis[0] + math.sin(angle) * basis[1]


class CollocationNlp:
    """The scaled rigid slew's collocation NLP, built once and solved from any start.

    Decision vector: [T, X (7 x (N + 1)), XC (7 x 3N), U (3 x N)], column-major.

    Parameters
    ----------
    slew : RigidSlew
    """

    def __init__(self, slew: RigidSlew) -> None:
        self.slew = slew
        n, d, nx = slew.intervals, COLLOCATION_DEGREE, N_RIGID_STATE
        self.collocation = _interval_collocation(slew)
        duration = ca.SX.sym("T")
        X = ca.SX.sym("X", nx, n + 1)
        XC = ca.SX.sym("XC", nx, n * d)
        U = ca.SX.sym("U", 3, n)
        steps = ca.repmat(duration / n, 1, n)
        defects, ends = self.collocation.interval.map(n)(X[:, :-1], XC, U, steps)
        constraints = ca.vertcat(
            ca.vec(defects), ca.vec(X[:, 1:] - ends), slew.terminal_error(X[:, -1])
        )
        variables = ca.vertcat(duration, ca.vec(X), ca.vec(XC), ca.vec(U))
        cost = duration + REGULARISATION * ca.sumsqr(U) / n
        self.sizes = (1, nx * (n + 1), nx * n * d, 3 * n)
        self.solver = ca.nlpsol(
            "rigid_slew", "ipopt", {"x": variables, "f": cost, "g": constraints}, START_OPTIONS
        )
        self.n_constraints = constraints.shape[0]
        self.lbx, self.ubx = self._bounds()

    def _bounds(self) -> tuple[np.ndarray, np.ndarray]:
        slew, n = self.slew, self.slew.intervals
        _, n_x, n_xc, _ = self.sizes
        x0 = np.concatenate([slew.q_initial_BN, np.zeros(3)])
        lower = np.concatenate(
            [[DURATION_BOUNDS[0]], np.full(n_x + n_xc, -np.inf), np.tile(slew.lower, n)]
        )
        upper = np.concatenate(
            [[DURATION_BOUNDS[1]], np.full(n_x + n_xc, np.inf), np.tile(slew.upper, n)]
        )
        lower[1 : 1 + N_RIGID_STATE] = x0  # rest at the start
        upper[1 : 1 + N_RIGID_STATE] = x0
        return lower, upper

    def solve(self, start: Start) -> StartOutcome:
        """Solve from ``start``: its controls marched through the collocation equations."""
        slew, n = self.slew, self.slew.intervals
        x0 = np.concatenate([slew.q_initial_BN, np.zeros(3)])
        steps = np.full(n, start.duration / n)
        nodes, inner = self.collocation.march(x0, start.controls.T, steps)
        guess = np.concatenate(
            [[start.duration], nodes.T.ravel(), inner.T.ravel(), start.controls.ravel()]
        )
        zeros = np.zeros(self.n_constraints)
        with keep_ctrl_c():
            result = self.solver(x0=guess, lbx=self.lbx, ubx=self.ubx, lbg=zeros, ubg=zeros)
        status = str(self.solver.stats()["return_status"])
        solution = np.array(result["x"]).ravel()
        controls = solution[-3 * n :].reshape(n, 3)
        converged = status in ACCEPTED_STATUS
        duration = float(solution[0]) if converged else math.nan
        return StartOutcome(
            start.label, status, duration, np.clip(controls, slew.lower, slew.upper)
        )


def _interval_collocation(slew: RigidSlew) -> IntervalCollocation:
    """Radau collocation of the scaled rigid body on one interval (unscaled states)."""
    ode = scaled_rigid_ode(slew.body, slew.time_scale_s)
    nx, d = N_RIGID_STATE, COLLOCATION_DEGREE
    _, C, D = (ca.DM(matrix) for matrix in radau_coefficients())
    xk, xc = ca.SX.sym("xk", nx), ca.SX.sym("xc", nx, d)
    uk, h = ca.SX.sym("uk", 3), ca.SX.sym("h")
    points = ca.horzcat(xk, xc)
    defects = [h * ode(xc[:, j], uk) - points @ C[:, j] for j in range(d)]
    interval = ca.Function("interval", [xk, xc, uk, h], [ca.horzcat(*defects), points @ D])
    return IntervalCollocation(nx, np.ones(nx), interval)


def _nlp_of(slew: RigidSlew) -> CollocationNlp:
    """A worker's context: the NLP, built once per process."""
    return CollocationNlp(slew)


def _solve_start(nlp: CollocationNlp, start: Start) -> StartOutcome:
    return nlp.solve(start)


def solve_each(
    solve: Callable[[Any, StartT], OutcomeT],
    starts: Sequence[StartT],
    context: Callable[[], Any],
    workers: int,
    failed: Callable[[StartT, str], OutcomeT],
) -> list[OutcomeT]:
    """``solve(context, start)`` for every start in ``workers`` processes, in the starts'
    order; a start that raises becomes ``failed(start, "<error type>: <message>")``.

    Each start has a ``label`` (its id in the logs); ``context()`` builds what a worker
    shares between its starts (the NLP), once per worker.
    """
    outcomes: list[OutcomeT | None] = [None] * len(starts)
    with parallel_map(
        solve, starts, context, workers=workers, item_id=lambda start: start.label
    ) as results:
        for result in results:
            if isinstance(result, ItemFailure):
                outcome = failed(result.item, f"{result.error_type}: {result.message}")
            else:
                outcome = result.value
            outcomes[result.index] = outcome
    return [o for o in outcomes if o is not None]


def run_starts(slew: RigidSlew, starts: list[Start], seed: int, workers: int) -> MultiStartResult:
    """Solve the NLP from every start, in ``workers`` processes; failures are outcomes too.

    Parameters
    ----------
    slew : RigidSlew
    starts : list of Start
    seed : int
        The seed the random starts were drawn with (recorded).
    workers : int
        Processes (1: this one, in turn).
    """
    outcomes = solve_each(
        _solve_start,
        starts,
        functools.partial(_nlp_of, slew),
        workers,
        lambda start, error: StartOutcome(start.label, error, math.nan, start.controls),
    )
    done = tuple(outcomes)
    return MultiStartResult(done, distinct([o.duration for o in done if o.converged]), seed)


def symmetric_images(slew: RigidSlew, outcome: StartOutcome) -> list[Start]:
    """Starts that are images of a solution under the slew's (near) symmetries.

    A half turn R about a body axis maps a solution u(t) to R u(t), a solution of the
    slew about R e: the same slew when R e = e, or when R e = -e and the angle is pi (a
    half turn either way is the same attitude). On a body with small products of
    inertia, or a slightly uneven box, these map a local optimum near another one, often
    the better (the paper's x slew: 1185.6 s to 1183.4 s, turning the other way round).
    """
    half_turn = math.isclose(slew.angle_rad, math.pi, rel_tol=0.0, abs_tol=1e-12)
    images = []
    for name, half in HALF_TURNS.items():
        signs = np.array(half)
        mapped = signs * slew.axis_B
        if np.allclose(mapped, slew.axis_B, atol=1e-12) or (
            half_turn and np.allclose(mapped, -slew.axis_B, atol=1e-12)
        ):
            controls = np.clip(outcome.controls * signs, slew.lower, slew.upper)
            images.append(Start(f"half turn {name} of {outcome.label}", controls, outcome.duration))
    return images
