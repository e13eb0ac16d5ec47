"""Thruster-level allocation: torque (and force) demand -> thrust of every CubeSat engine.

Problem
-------
With ``B`` the torque map (3 x n) [N m / N], ``F`` the force map (3 x n),
``f_max`` the thrust limit of each engine's active stage (0 for a failed or
spent CubeSat), a demand ``tau`` [N m] and a net force ``phi`` [N] (zero
unless given; left free on request):

1. **exact, least fuel** -- if the demand can be met,

       minimise sum(f)   subject to  B f = tau,  F f = phi,  0 <= f <= f_max.

   Every engine has the same Isp, so sum(f) is the mass flow times Isp g0.
2. **saturation, direction kept** (default when 1 is infeasible) -- the
   largest ``alpha`` in [0, 1] with ``B f = alpha tau, F f = alpha phi``, then
   problem 1 at ``alpha tau, alpha phi`` (least fuel among the maximisers).
   The whole requested wrench is scaled, so a zero net force stays zero.
3. **least squares** (option) -- the achievable torque closest to ``tau``
   (with ``F f = phi`` kept exactly), then problem 1 at that torque.

Every stage is solved as a QP: the LPs get a small proximal term
``eps/2 |u|^2`` on the scaled thrust ``u = f / f_ref``. For an LP there is a
threshold below which such a term does not move the optimum (exact
regularisation, Mangasarian & Meyer 1979): it only picks the least-norm point
of the optimal face, which also makes the answer unique and continuous in the
demand.

Saturation is solved lexicographically, in two QPs: ``max alpha`` over
``(u, alpha)`` (no fuel term), then the least-fuel QP of 1 at
``alpha tau, alpha phi``. One weighted QP ``max alpha - delta sum(u)`` was
tried and rejected: with the force free, a little more alpha can cost much
fuel, so no fixed ``delta`` is small enough for every demand (it lost 2e-4
of alpha on a random demand). The second target sits on the edge of what is
reachable, where round-off makes DAQP call it infeasible for about 14 % of
saturated demands; it is then pulled in by 1e-12, then 1e-10 (relative).
If that fails too (about 4 % with several failed CubeSats, fewer without),
or if the first stage fails (a degenerate vertex where alpha = 0 is the only
answer), HiGHS' simplex solves both LPs instead and the result's ``solver``
says so (``"daqp+highs"``). The common case, a feasible demand, costs one
solve.

Scaling: thrust in units of the largest limit, torque rows in units of the
largest lever arm times that limit, force rows likewise, so all QP data are
of order one whatever the problem's units.

Failed or spent engines keep their column with an upper bound of zero: the
solver workspaces are set up once and only their bounds change.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from casadi_debris.allocation.authority import AuthorityPolytope, authority_polytope
from casadi_debris.allocation.backends import QpBackend, make_backend
from casadi_debris.allocation.propulsion import PropulsionState
from casadi_debris.allocation.series import PiecewiseAffineQp
from casadi_debris.config import AXIS_NAMES, SIGNED_AXES, Problem
from casadi_debris.errors import AllocationError, InputShapeError
from casadi_debris.geometry import Geometry, build_geometry

SaturationMode = Literal["scale", "least_squares"]
SATURATION_MODES: tuple[str, ...] = ("scale", "least_squares")
DEFAULT_SOLVER = "daqp"

# Proximal weight of the least-fuel QP, in scaled thrust units against a fuel
# weight of 1 per engine: far below the reduced costs of the LP (order one),
# so the least-fuel optimum is exact (see the module docstring).
EXACT_PROXIMAL = 1e-3
# Max-alpha stage: alpha has weight 1, proximal eps << 1. It carries no fuel
# term: with the force free, a little more alpha can cost a lot of fuel, so no
# fixed fuel weight is small enough for every demand (measured: 2e-4 of alpha
# lost with 1e-3); the least-fuel solve that follows does the fuel.
SCALE_PROXIMAL = 1e-6
# Relative pull-ins of a saturated target, tried in turn when the least-fuel
# solve calls the exact edge infeasible by round-off (measured over 3000
# random demands with up to 9 failed CubeSats: 86 % pass at 0, 10 % need a
# pull-in, 4 % go on to HiGHS). All are well inside the 1e-9 to which alpha
# is promised.
BOUNDARY_BACKOFF = (0.0, 1e-12, 1e-10)
# Thrust below this fraction of the largest limit is solver round-off: set to 0.
THRUST_ROUND_OFF = 1e-12
# Demands smaller than this (scaled: fraction of one engine's full torque or
# thrust) are solved stretched to this size and scaled back; no limit binds
# there in a direction the engines can reach with margin.
SMALL_DEMAND = 1e-2
# An engine within this fraction of its limit counts as on it (a stretched small
# demand is scaled back only when no limit binds).
LIMIT_ACTIVE_RTOL = 1e-9
# Equality residual (relative to the target) above which a solution is polished.
POLISH_TOLERANCE = 1e-13
# Relative pull-in of a saturated demand in :meth:`Allocator.allocate_series`,
# so that the target lies strictly inside the reachable set (alpha is promised
# to 1e-9).
SERIES_BACKOFF = 1e-10
RESCUE_OPTIONS = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}
LEAST_SQUARES_PROXIMAL = 1e-9


class NoEngineError(AllocationError):
    """Every CubeSat has failed or is spent: no torque can be made."""


@dataclass(frozen=True, eq=False)
class AllocationResult:
    """Thrust of every engine for one demand.

    Attributes
    ----------
    thrust_N : ndarray, shape (n_engines,)
        Within ``0 <= f <= f_max`` always.
    torque_Nm : ndarray, shape (3,)
        Achieved torque ``B f``.
    force_N : ndarray, shape (3,)
        Achieved net force ``F f``.
    demand_torque_Nm : ndarray, shape (3,)
    demand_force_N : ndarray, shape (3,) or None
        None when the force was left free.
    feasible : bool
        The demand was met exactly.
    scale : float
        alpha of the direction-preserving saturation (1 when feasible); in
        least-squares mode the projection of the achieved torque on the demand,
        ``tau_a . tau / |tau|^2``.
    mode : str
        ``"exact"``, ``"scaled"``, ``"least_squares"`` or ``"pseudo_inverse"``.
    fuel_rate_kg_s : float
        Propellant mass flow ``sum(f) / (Isp g0)`` [kg/s].
    solver : str
    iterations : int
        Summed over the QP solves of this call.
    solve_time_s : float
        Wall time spent in the back-end (update + solve) [s].
    """

    thrust_N: np.ndarray
    torque_Nm: np.ndarray
    force_N: np.ndarray
    demand_torque_Nm: np.ndarray
    demand_force_N: np.ndarray | None
    feasible: bool
    scale: float
    mode: str
    fuel_rate_kg_s: float
    solver: str
    iterations: int
    solve_time_s: float


@dataclass(frozen=True, eq=False)
class BatchAllocation:
    """Allocations of many demands (rows).

    Attributes
    ----------
    thrust_N : ndarray, shape (k, n_engines)
    torque_Nm, force_N : ndarray, shape (k, 3)
    feasible : ndarray of bool, shape (k,)
    scale : ndarray, shape (k,)
    fuel_rate_kg_s : ndarray, shape (k,)
    iterations : ndarray of int, shape (k,)
    solve_time_s : ndarray, shape (k,)
        Back-end time per demand [s].
    wall_time_s : float
        Whole batch, Python included [s].
    """

    thrust_N: np.ndarray
    torque_Nm: np.ndarray
    force_N: np.ndarray
    feasible: np.ndarray
    scale: np.ndarray
    fuel_rate_kg_s: np.ndarray
    iterations: np.ndarray
    solve_time_s: np.ndarray
    wall_time_s: float


@dataclass(frozen=True, eq=False)
class SeriesAllocation:
    """Allocation of a history of demands (rows), see :meth:`Allocator.allocate_series`.

    Attributes
    ----------
    thrust_N : ndarray, shape (k, n_engines)
    torque_Nm, force_N : ndarray, shape (k, 3)
        Achieved torque ``B f`` and net force ``F f``.
    scale : ndarray, shape (k,)
        alpha of the direction-keeping saturation (1 when the demand is met).
    fuel_rate_kg_s : ndarray, shape (k,)
    point_solves : int
        Demands that needed a QP solve; the others reused an active set.
    wall_time_s : float
    """

    thrust_N: np.ndarray
    torque_Nm: np.ndarray
    force_N: np.ndarray
    scale: np.ndarray
    fuel_rate_kg_s: np.ndarray
    point_solves: int
    wall_time_s: float


def _as_vector3(value: Any, name: str) -> np.ndarray:
    array = np.asarray(value, dtype=float)
    if array.shape != (3,):
        raise InputShapeError(f"{name} must have shape (3,), got {array.shape}")
    x, y, z = array.tolist()  # three scalar checks: a tenth of np.isfinite's cost
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)):
        raise InputShapeError(f"{name} must be finite, got {array.tolist()}")
    return array


class Allocator:
    """Least-fuel thrust allocation over every engine, set up once, solved per demand.

    Parameters
    ----------
    torque_map : ndarray, shape (3, n)
        Torque about the CoG per newton of each engine [N m / N].
    force_map : ndarray, shape (3, n)
        Force on the body per newton of each engine [N / N].
    max_thrust_N : ndarray, shape (n,)
        Thrust limit of each engine's active stage [N]; 0 removes an engine.
    exhaust_velocity_m_s : float
        Isp g0 of the engines [m/s], for the fuel rate.
    solver : str
        QP back-end, one of :func:`~casadi_debris.allocation.available_solvers`.
    saturation : {"scale", "least_squares"}
        What to do with a demand that cannot be met.

    Raises
    ------
    InputShapeError
        Maps or limits of the wrong shape, or non-finite.
    UnknownSolverError
        ``solver`` not installed (the message lists what is).
    NoEngineError
        Every limit is zero.

    Example
    -------
    >>> from casadi_debris import load_problem
    >>> allocator = Allocator.from_problem(load_problem())
    >>> result = allocator.allocate([1e-3, 0.0, 0.0])
    >>> bool(result.feasible), round(float(result.torque_Nm[0]), 12)
    (True, 0.001)
    """

    def __init__(
        self,
        torque_map: np.ndarray,
        force_map: np.ndarray,
        max_thrust_N: np.ndarray,
        *,
        exhaust_velocity_m_s: float,
        solver: str = DEFAULT_SOLVER,
        saturation: SaturationMode = "scale",
        geometry: Geometry | None = None,
    ) -> None:
        torque_map = np.array(torque_map, dtype=float)
        force_map = np.array(force_map, dtype=float)
        if torque_map.ndim != 2 or torque_map.shape[0] != 3 or torque_map.shape[1] == 0:
            raise InputShapeError(f"torque_map must have shape (3, n), got {torque_map.shape}")
        n = torque_map.shape[1]
        if force_map.shape != (3, n):
            raise InputShapeError(f"force_map must have shape (3, {n}), got {force_map.shape}")
        if not (np.isfinite(torque_map).all() and np.isfinite(force_map).all()):
            raise InputShapeError("torque_map and force_map must be finite")
        if saturation not in SATURATION_MODES:
            raise AllocationError(
                f"unknown saturation mode {saturation!r}; one of {', '.join(SATURATION_MODES)}"
            )
        if not np.isfinite(exhaust_velocity_m_s) or exhaust_velocity_m_s <= 0:
            raise AllocationError(
                f"exhaust_velocity_m_s must be positive, got {exhaust_velocity_m_s}"
            )
        self.torque_map = torque_map
        self.force_map = force_map
        self.exhaust_velocity_m_s = float(exhaust_velocity_m_s)
        self.saturation = saturation
        self.geometry = geometry
        limits = self._checked_limits(max_thrust_N)
        self._thrust_ref_N = float(limits.max())
        self._torque_ref_Nm = float(np.abs(torque_map).max()) * self._thrust_ref_N
        self._force_ref_N = float(np.abs(force_map).max()) * self._thrust_ref_N
        if self._torque_ref_Nm <= 0:
            raise AllocationError("torque_map is all zeros: no engine makes a torque")
        self._scaled_torque = torque_map * (self._thrust_ref_N / self._torque_ref_Nm)
        self._scaled_force = force_map * (self._thrust_ref_N / self._force_ref_N)
        self._scaled_wrench = np.vstack([self._scaled_torque, self._scaled_force])
        # Per-row references: target = wrench / reference, bit for bit the
        # division by the scalar references.
        self._wrench_ref = np.array([self._torque_ref_Nm] * 3 + [self._force_ref_N] * 3)
        self._torque_ref = self._wrench_ref[:3].copy()
        # Equality rows of the max-alpha stage, [rows, -target], keyed by free_force.
        self._scale_rows = {
            free: np.hstack([self._rows(free), np.zeros((len(self._rows(free)), 1))])
            for free in (False, True)
        }
        self._max_thrust_N = limits
        self._upper = limits / self._thrust_ref_N
        self._reach = self._reachable_size()
        self._workspaces: dict[tuple[str, bool], QpBackend] = {}
        self._polytopes: dict[bool, AuthorityPolytope] = {}
        self._series_qps: dict[bool, PiecewiseAffineQp] = {}
        self.solver = solver
        # Set up the default workspace now: an unknown solver fails at construction.
        self._workspace("exact", False)

    @classmethod
    def from_problem(
        cls,
        problem: Problem,
        geometry: Geometry | None = None,
        *,
        state: PropulsionState | None = None,
        solver: str = DEFAULT_SOLVER,
        saturation: SaturationMode = "scale",
    ) -> Allocator:
        """Build from a problem's geometry and engines.

        Parameters
        ----------
        problem : Problem
        geometry : Geometry, optional
            Built from ``problem`` when omitted.
        state : PropulsionState, optional
            Active stages and failures; default all CubeSats on their first stage.
        solver : str
        saturation : {"scale", "least_squares"}
        """
        geometry = geometry or build_geometry(problem)
        limits = (
            state.max_thrust_N()
            if state is not None
            else np.array([m.max_thrust_N for m in geometry.cubesats])
        )
        return cls(
            geometry.torque_map,
            geometry.force_map,
            limits,
            exhaust_velocity_m_s=problem.engine.isp_s * problem.constants.standard_gravity_m_s2,
            solver=solver,
            saturation=saturation,
            geometry=geometry,
        )

    # ------------------------------------------------------------------ limits

    @property
    def n_engines(self) -> int:
        """Number of engines (CubeSats)."""
        return self.torque_map.shape[1]

    @property
    def max_thrust_N(self) -> np.ndarray:
        """Current thrust limit per engine, shape (n,) [N] (read-only copy)."""
        return self._max_thrust_N.copy()

    def _checked_limits(self, max_thrust_N: Any) -> np.ndarray:
        limits = np.array(max_thrust_N, dtype=float)
        n = self.torque_map.shape[1]
        if limits.shape != (n,):
            raise InputShapeError(f"max_thrust_N must have shape ({n},), got {limits.shape}")
        if not np.isfinite(limits).all() or np.any(limits < 0):
            raise InputShapeError("max_thrust_N must be finite and non-negative")
        if not np.any(limits > 0):
            raise NoEngineError("every CubeSat has failed or is spent: no engine can fire")
        return limits

    def set_max_thrust(self, max_thrust_N: np.ndarray) -> None:
        """Change the engines' limits (stage change, failure); workspaces keep their set-up.

        Parameters
        ----------
        max_thrust_N : ndarray, shape (n,)
            New limit per engine [N]; 0 removes it.

        Raises
        ------
        NoEngineError
            Every limit is zero.
        """
        limits = self._checked_limits(max_thrust_N)
        if np.array_equal(limits, self._max_thrust_N):
            return  # unchanged: keep the cached polytope and active-set regions
        self._max_thrust_N = limits
        self._upper = limits / self._thrust_ref_N
        self._reach = self._reachable_size()
        self._polytopes.clear()
        self._series_qps.clear()
        for (stage, _), workspace in self._workspaces.items():
            workspace.update(ub=self._stage_upper(stage))

    def set_failed(self, failed: Any) -> None:
        """Remove CubeSats by index (the others keep their current limits).

        Parameters
        ----------
        failed : iterable of int
            0-based CubeSat indices.
        """
        limits = self._max_thrust_N.copy()
        for index in failed:
            if not 0 <= int(index) < self.n_engines:
                raise AllocationError(
                    f"failed CubeSat {index} out of range 0..{self.n_engines - 1}"
                )
            limits[int(index)] = 0.0
        self.set_max_thrust(limits)

    def update_from_state(self, state: PropulsionState) -> None:
        """Take the limits of each CubeSat's active stage (0 when failed or spent)."""
        self.set_max_thrust(state.max_thrust_N())

    def _reachable_size(self) -> dict[bool, float]:
        """Bound on every component of a reachable scaled target: ``max_j sum_i |A_ji| u_max_i``.

        Keyed by ``free_force`` (the rows differ).
        """
        return {
            free: float((np.abs(self._rows(free)) @ self._upper).max()) for free in (False, True)
        }

    def _stage_upper(self, stage: str) -> np.ndarray:
        return np.append(self._upper, 1.0) if stage == "scale" else self._upper

    # ------------------------------------------------------------------ workspaces

    def _workspace(self, stage: str, free_force: bool) -> QpBackend:
        key = (stage, free_force)
        workspace = self._workspaces.get(key)
        if workspace is not None:
            return workspace
        n = self.n_engines
        rows = (
            self._scaled_torque
            if free_force
            else np.vstack([self._scaled_torque, self._scaled_force])
        )
        if stage == "exact":
            workspace = make_backend(
                self.solver,
                EXACT_PROXIMAL * np.eye(n),
                np.ones(n),
                rows,
                np.zeros(len(rows)),
                np.zeros(n),
                self._upper,
            )
        elif stage == "scale":
            a_eq = np.hstack([rows, np.zeros((len(rows), 1))])
            workspace = make_backend(
                self.solver,
                SCALE_PROXIMAL * np.eye(n + 1),
                np.append(np.zeros(n), -1.0),
                a_eq,
                np.zeros(len(rows)),
                np.zeros(n + 1),
                np.append(self._upper, 1.0),
            )
        else:
            torque = self._scaled_torque
            force_rows = np.zeros((0, n)) if free_force else self._scaled_force
            workspace = make_backend(
                self.solver,
                torque.T @ torque + LEAST_SQUARES_PROXIMAL * np.eye(n),
                np.zeros(n),
                force_rows,
                np.zeros(len(force_rows)),
                np.zeros(n),
                self._upper,
            )
        self._workspaces[key] = workspace
        return workspace

    # ------------------------------------------------------------------ allocation

    def allocate(
        self, torque_Nm: Any, force_N: Any = None, *, free_force: bool = False
    ) -> AllocationResult:
        """Thrust of every engine for one torque (and force) demand.

        Parameters
        ----------
        torque_Nm : array_like, shape (3,)
            Demanded torque about the CoG, body frame [N m].
        force_N : array_like, shape (3,), optional
            Demanded net force [N]; default zero.
        free_force : bool
            Leave the net force free (cannot be combined with ``force_N``).

        Returns
        -------
        AllocationResult

        Raises
        ------
        InputShapeError
            Demand of the wrong shape or not finite.
        AllocationError
            ``force_N`` with ``free_force``, or the back-end failed.
        """
        torque = _as_vector3(torque_Nm, "torque_Nm")
        if force_N is None:
            force = None if free_force else np.zeros(3)
        else:
            if free_force:
                raise AllocationError("give either force_N or free_force, not both")
            force = _as_vector3(force_N, "force_N")
        return self._allocate(torque, force)

    def _allocate(self, torque: np.ndarray, force: np.ndarray | None) -> AllocationResult:
        # The feasible case is the common one and is kept lean (about twice the
        # back-end's own time): no array is built twice, maxima of a few
        # numbers are taken in Python (numpy's reductions cost 1.5 us each at
        # this size), the result is clipped once.
        free_force = force is None
        if free_force:
            target = torque / self._torque_ref
        else:
            target = np.concatenate((torque, force)) / self._wrench_ref
        size = max(map(abs, target.tolist()))
        if size == 0.0:
            return self._result(np.zeros(self.n_engines), torque, force, True, 1.0, "exact", 0, 0.0)
        exact = self._workspace("exact", free_force)
        # A demand far below one engine's torque is solved stretched to
        # SMALL_DEMAND and scaled back: the solvers' tolerances are absolute, so
        # at 1e-12 of an engine's torque they would call anything feasible.
        stretch = SMALL_DEMAND / size if size < SMALL_DEMAND else 1.0
        target_stretched = stretch * target if stretch != 1.0 else target
        exact.update(b_eq=target_stretched)
        solution = exact.solve()
        iterations = solution.iterations
        solve_time = solution.solve_time_s
        if solution.status == "optimal" and stretch != 1.0:
            u = self._polish(solution.x, target_stretched, free_force)
            if not np.any((self._upper > 0.0) & (u >= self._upper * (1.0 - LIMIT_ACTIVE_RTOL))):
                return self._result(
                    u / stretch, torque, force, True, 1.0, "exact", iterations, solve_time
                )
            # A limit binds at the stretched size (few engines left), so the least-fuel
            # answer does not scale back: solve at the demand's own size instead.
            stretch, target_stretched = 1.0, target
            exact.update(b_eq=target)
            solution = exact.solve()
            iterations += solution.iterations
            solve_time += solution.solve_time_s
        if solution.status == "optimal":
            u = self._polish(solution.x, target_stretched, free_force)
            # _polish has clipped u already.
            return self._result(
                u, torque, force, True, 1.0, "exact", iterations, solve_time, clip=False
            )

        if self.saturation == "least_squares":
            u, iterations_ls, time_ls = self._least_squares(target, free_force)
            iterations += iterations_ls
            solve_time += time_ls
            if u is not None:
                achieved = self._scaled_torque @ u
                scaled_demand = target[:3]
                norm2 = float(scaled_demand @ scaled_demand)
                scale = float(achieved @ scaled_demand / norm2) if norm2 > 0 else 1.0
                settle = np.concatenate([achieved, target[3:]])
                u, shrink, it, t, rescued = self._least_fuel(settle, free_force)
                return self._result(
                    u,
                    torque,
                    force,
                    False,
                    scale * shrink,
                    "least_squares",
                    iterations + it,
                    solve_time + t,
                    rescued,
                )
            # The requested force alone cannot be met: fall back to scaling the wrench.

        if size > self._reach[free_force]:
            # The max-alpha QP's proximal term leaves alpha exact only for a
            # target of the size of what the engines can reach (measured: with
            # the force free, demands 1000x beyond reach lost up to 2e-4 of
            # alpha): a larger one is shrunk to the largest reachable component
            # first, which keeps every answer within alpha <= 1.
            stretch = self._reach[free_force] / size
        target = stretch * target
        scale_workspace = self._workspace("scale", free_force)
        # [rows, -target]: the workspace's own copy of its rows, last column replaced.
        a_eq = self._scale_rows[free_force]
        a_eq[:, -1] = -target
        scale_workspace.update(a_eq=a_eq)
        solution = scale_workspace.solve()
        iterations += solution.iterations
        solve_time += solution.solve_time_s
        if solution.status != "optimal":
            # The feasible set always holds u = 0, alpha = 0: a report of
            # infeasibility is round-off at a degenerate vertex (seen when
            # alpha = 0 is the only answer).
            u, alpha, t = self._rescue(target, free_force)
            return self._saturated(
                u, alpha * stretch, torque, force, iterations, solve_time + t, True
            )
        alpha = min(max(float(solution.x[-1]), 0.0), 1.0)
        u, shrink, it, t, rescued = self._least_fuel(alpha * target, free_force)
        return self._saturated(
            u, alpha * shrink * stretch, torque, force, iterations + it, solve_time + t, rescued
        )

    def _saturated(
        self,
        u: np.ndarray,
        alpha: float,
        torque: np.ndarray,
        force: np.ndarray | None,
        iterations: int,
        solve_time_s: float,
        rescued: bool,
    ) -> AllocationResult:
        """Result of the saturation path; ``alpha`` is relative to the demand as given.

        A stretched small demand may turn out reachable after all (alpha >= 1):
        the thrust is then scaled back to meet it exactly.
        """
        if alpha <= 0.0:
            u = np.zeros(self.n_engines)  # whatever the solver left is round-off
        elif alpha >= 1.0:
            return self._result(
                u / alpha, torque, force, True, 1.0, "exact", iterations, solve_time_s, rescued
            )
        return self._result(
            u, torque, force, False, alpha, "scaled", iterations, solve_time_s, rescued
        )

    def _polish(self, u: np.ndarray, target: np.ndarray, free_force: bool) -> np.ndarray:
        """Remove the solver's residual on the equalities by moving the engines off their bounds.

        A warm-started active-set solve can leave thrusts of 1e-13 of the
        limit that should be zero, and a residual of that size; against a
        small demand that is a large relative error. One least-squares step
        on the free engines (the solver's own active set) removes it.
        """
        rows = self._scaled_torque if free_force else self._scaled_wrench
        u = np.minimum(u, self._upper)
        u[u < THRUST_ROUND_OFF] = 0.0
        residual = target - rows @ u
        # Largest entries by Python's max over a handful of floats: cheaper than numpy's.
        tolerance = POLISH_TOLERANCE * max(map(abs, target.tolist()))
        if max(map(abs, residual.tolist())) <= tolerance:
            return u
        free = (u > 0.0) & (u < self._upper)
        if not free.any():
            return u
        active = rows[:, free]
        try:
            # Minimum-norm step through the (at most 6 x 6) Gram matrix: a tenth of lstsq's cost.
            step = active.T @ np.linalg.solve(active @ active.T, residual)
        except np.linalg.LinAlgError:
            step = np.linalg.lstsq(active, residual, rcond=None)[0]
        polished = u.copy()
        polished[free] = np.clip(u[free] + step, 0.0, self._upper[free])
        if float(np.abs(target - rows @ polished).max()) > float(np.abs(residual).max()):
            # A rank-deficient Gram matrix gave a poor step: take the least-squares one.
            step = np.linalg.lstsq(active, residual, rcond=None)[0]
            polished[free] = np.clip(u[free] + step, 0.0, self._upper[free])
        return polished

    def _rows(self, free_force: bool) -> np.ndarray:
        """Scaled equality rows: torque, and force unless it is free."""
        return self._scaled_torque if free_force else self._scaled_wrench

    def _least_fuel(
        self, target: np.ndarray, free_force: bool
    ) -> tuple[np.ndarray, float, int, float, bool]:
        """Least-fuel thrust for a target on the edge of what is reachable.

        On the edge a solver may call the target infeasible by round-off; it
        is then pulled in by each of ``BOUNDARY_BACKOFF`` (relative) in turn;
        if every try fails, the LP is solved by HiGHS (:meth:`_rescue`).

        Returns
        -------
        u : ndarray, shape (n,)
        shrink : float
            Factor applied to the target: 1 - backoff, or the rescue's alpha.
        iterations : int
        solve_time_s : float
        rescued : bool
            HiGHS gave the answer.
        """
        workspace = self._workspace("exact", free_force)
        iterations, solve_time = 0, 0.0
        for backoff in BOUNDARY_BACKOFF:
            workspace.update(b_eq=(1.0 - backoff) * target)
            solution = workspace.solve()
            iterations += solution.iterations
            solve_time += solution.solve_time_s
            if solution.status == "optimal":
                u = self._polish(solution.x, (1.0 - backoff) * target, free_force)
                return u, 1.0 - backoff, iterations, solve_time, False
        u, alpha, rescue_time = self._rescue(target, free_force)
        return u, alpha, iterations, solve_time + rescue_time, True

    def _rescue(self, target: np.ndarray, free_force: bool) -> tuple[np.ndarray, float, float]:
        """Largest alpha, then least fuel, for ``alpha * target`` by HiGHS' simplex (rare path).

        Returns
        -------
        u : ndarray, shape (n,)
        alpha : float
        solve_time_s : float
        """
        from scipy.optimize import linprog

        start = time.perf_counter()
        n = self.n_engines
        rows = self._rows(free_force)
        a_eq = np.hstack([rows, -target[:, None]])
        bounds = [*zip(np.zeros(n), self._upper, strict=True), (0.0, 1.0)]
        zeros = np.zeros(len(rows))
        best = None
        for options in (RESCUE_OPTIONS, {}):
            best = linprog(
                np.append(np.zeros(n), -1.0),
                A_eq=a_eq,
                b_eq=zeros,
                bounds=bounds,
                method="highs",
                options=options,
            )
            if best.status == 0:
                break
        if best is None or best.status != 0:
            raise AllocationError(
                f"{self.solver} and the HiGHS rescue found no allocation for "
                f"{(target * self._torque_ref_Nm)[:3].tolist()} N m ({best.message})"
            )
        alpha = float(best.x[-1])
        bounds[-1] = (alpha * (1.0 - BOUNDARY_BACKOFF[-1]), 1.0)
        frugal = linprog(
            np.append(np.ones(n), 0.0),
            A_eq=a_eq,
            b_eq=zeros,
            bounds=bounds,
            method="highs",
            options=RESCUE_OPTIONS,
        )
        x = frugal.x if frugal.status == 0 else best.x
        return x[:n], float(np.clip(x[-1], 0.0, 1.0)), time.perf_counter() - start

    def _least_squares(
        self, target: np.ndarray, free_force: bool
    ) -> tuple[np.ndarray | None, int, float]:
        workspace = self._workspace("least_squares", free_force)
        c = -self._scaled_torque.T @ target[:3]
        workspace.update(c=c, b_eq=target[3:])
        solution = workspace.solve()
        x = solution.x if solution.status == "optimal" else None
        return x, solution.iterations, solution.solve_time_s

    def _result(
        self,
        u: np.ndarray,
        torque: np.ndarray,
        force: np.ndarray | None,
        feasible: bool,
        scale: float,
        mode: str,
        iterations: int,
        solve_time_s: float,
        rescued: bool = False,
        *,
        clip: bool = True,
    ) -> AllocationResult:
        """Result of scaled thrust ``u``; ``clip=False`` when u is already within its bounds."""
        if clip:
            # Solver round-off may leave u a hair outside its bounds: limits are never exceeded.
            u = np.minimum(u, self._upper)
            u[u < THRUST_ROUND_OFF] = 0.0
        thrust = u * self._thrust_ref_N
        return AllocationResult(
            thrust,
            self.torque_map @ thrust,
            self.force_map @ thrust,
            torque,
            force,
            feasible,
            scale + 0.0,  # no -0.0 from a clipped alpha
            mode,
            float(np.add.reduce(thrust)) / self.exhaust_velocity_m_s,  # thrust.sum(), faster
            f"{self.solver}+highs" if rescued else self.solver,
            iterations,
            solve_time_s,
        )

    def allocate_batch(
        self, torques_Nm: Any, forces_N: Any = None, *, free_force: bool = False
    ) -> BatchAllocation:
        """Allocate many demands in a row (warm-started workspaces).

        Parameters
        ----------
        torques_Nm : array_like, shape (k, 3)
        forces_N : array_like, shape (k, 3), optional
            Default zero net force.
        free_force : bool

        Returns
        -------
        BatchAllocation
        """
        start = time.perf_counter()
        torques = np.asarray(torques_Nm, dtype=float)
        if torques.ndim != 2 or torques.shape[1] != 3:
            raise InputShapeError(f"torques_Nm must have shape (k, 3), got {torques.shape}")
        if forces_N is not None:
            if free_force:
                raise AllocationError("give either forces_N or free_force, not both")
            forces = np.asarray(forces_N, dtype=float)
            if forces.shape != torques.shape:
                raise InputShapeError(
                    f"forces_N must have the shape {torques.shape} of torques_Nm, "
                    f"got {forces.shape}"
                )
        else:
            forces = None if free_force else np.zeros_like(torques)
        if not np.isfinite(torques).all() or (forces is not None and not np.isfinite(forces).all()):
            raise InputShapeError("torques_Nm and forces_N must be finite")
        results = [
            self._allocate(torques[i], None if forces is None else forces[i])
            for i in range(len(torques))
        ]
        k, n = len(results), self.n_engines
        return BatchAllocation(
            thrust_N=np.array([r.thrust_N for r in results]).reshape(k, n),
            torque_Nm=np.array([r.torque_Nm for r in results]).reshape(k, 3),
            force_N=np.array([r.force_N for r in results]).reshape(k, 3),
            feasible=np.array([r.feasible for r in results], dtype=bool),
            scale=np.array([r.scale for r in results]),
            fuel_rate_kg_s=np.array([r.fuel_rate_kg_s for r in results]),
            iterations=np.array([r.iterations for r in results], dtype=int),
            solve_time_s=np.array([r.solve_time_s for r in results]),
            wall_time_s=time.perf_counter() - start,
        )

    def authority_polytope(self, *, free_force: bool = False) -> AuthorityPolytope:
        """Facets of the reachable torques with the current limits (cached until they change)."""
        polytope = self._polytopes.get(free_force)
        if polytope is None:
            polytope = authority_polytope(
                self.torque_map, self.force_map, self._max_thrust_N, free_force=free_force
            )
            self._polytopes[free_force] = polytope
        return polytope

    def allocate_series(self, torques_Nm: Any, *, free_force: bool = False) -> SeriesAllocation:
        """Allocate a history of torque demands at zero (or free) net force.

        The same answers as :meth:`allocate` in ``"scale"`` saturation, computed
        for a whole series at once: alpha from the facets of
        :meth:`authority_polytope`, then the least-fuel thrust from the
        piecewise-affine solution of the QP (:mod:`~casadi_debris.allocation.series`),
        which needs a QP solve only where the active set changes.

        Parameters
        ----------
        torques_Nm : array_like, shape (k, 3)
            Torque demands [N m], e.g. one per control step.
        free_force : bool
            Leave the net force free instead of zero.

        Returns
        -------
        SeriesAllocation
        """
        start = time.perf_counter()
        torques = np.asarray(torques_Nm, dtype=float)
        if torques.ndim != 2 or torques.shape[1] != 3:
            raise InputShapeError(f"torques_Nm must have shape (k, 3), got {torques.shape}")
        if not np.isfinite(torques).all():
            raise InputShapeError("torques_Nm must be finite")
        scale = self.authority_polytope(free_force=free_force).scale(torques)
        shrink = np.where(scale < 1.0, scale * (1.0 - SERIES_BACKOFF), 1.0)
        targets = torques * shrink[:, None] / self._torque_ref_Nm
        rows = self._rows(free_force)
        if not free_force:
            targets = np.hstack([targets, np.zeros_like(targets)])
        qp = self._series_qps.get(free_force)
        if qp is None:
            qp = PiecewiseAffineQp(rows, self._upper, EXACT_PROXIMAL)
            self._series_qps[free_force] = qp

        def solve_point(target: np.ndarray) -> np.ndarray:
            torque = target[:3] * self._torque_ref_Nm
            result = self._allocate(torque, None if free_force else np.zeros(3))
            return result.thrust_N / self._thrust_ref_N

        u, point_solves = qp.solve_series(targets, solve_point)
        u = np.where(u < THRUST_ROUND_OFF, 0.0, np.minimum(u, self._upper))
        thrust = u * self._thrust_ref_N
        return SeriesAllocation(
            thrust_N=thrust,
            torque_Nm=thrust @ self.torque_map.T,
            force_N=thrust @ self.force_map.T,
            scale=scale,
            fuel_rate_kg_s=thrust.sum(axis=1) / self.exhaust_velocity_m_s,
            point_solves=point_solves,
            wall_time_s=time.perf_counter() - start,
        )

    def torque_authority(self, *, free_force: bool = False) -> dict[str, float]:
        """Largest pure torque about each signed body axis with the current limits.

        Found by allocating a demand far beyond reach along each axis and
        reading the saturated torque (direction-preserving mode).

        Returns
        -------
        dict
            ``{"+x": tau [N m], "-x": ..., ...}``.
        """
        beyond_reach = 10.0 * self._torque_ref_Nm * self.n_engines
        authority = {}
        saturation, self.saturation = self.saturation, "scale"
        try:
            for name in SIGNED_AXES:
                demand = np.zeros(3)
                axis = AXIS_NAMES.index(name[1])
                demand[axis] = beyond_reach if name[0] == "+" else -beyond_reach
                result = self._allocate(demand, None if free_force else np.zeros(3))
                authority[name] = abs(float(result.torque_Nm[axis]))
        finally:
            self.saturation = saturation
        return authority
