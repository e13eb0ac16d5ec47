"""Thruster-level allocation: torque (and force) demand -> thrust of every CubeSat engine.

Problem
-------
With ``B`` the torque map (3 x n) [N m / N], ``F`` the force map (3 x n),
``f_max`` the thrust limit of each engine's active stage (0 for a failed or
spent CubeSat), a demand ``tau`` [N m] and a net force ``phi`` [N] (zero
unless given; left free on request):

1. **exact, least fuel** -- if the demand can be met,

       minimise sum(f_i / c_i)   subject to  B f = tau,  F f = phi,  0 <= f <= f_max,

   the propellant mass flow, ``c_i = Isp_i g0`` each engine's exhaust
   velocity. With one Isp for every engine this is the least total thrust.
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
of order one whatever the problem's units. The fuel weight of engine ``i`` is
``c_max / c_i`` (1 for the engines of highest Isp, more for the others):
proportional to its mass flow per newton, and never below the weight of 1
against which the proximal term is sized.

Failed or spent engines keep their column with an upper bound of zero: the
solver workspaces are set up once and only their bounds change.

Modules: the QP stages in scaled units (:mod:`~casadi_debris.allocation._scaled_qp`),
the saturation path and its HiGHS rescue (:mod:`~casadi_debris.allocation._saturation`),
demand checks (:mod:`~casadi_debris.allocation._demand`), result types
(:mod:`~casadi_debris.allocation._results`), batches and series
(:mod:`~casadi_debris.allocation._batch`); this one holds the :class:`Allocator`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from casadi_debris.allocation import _batch as batch
from casadi_debris.allocation._authority import AuthorityPolytope, authority_polytope
from casadi_debris.allocation._demand import ABSURD_FACTOR, SMALLEST_SUBNORMAL, as_vector3
from casadi_debris.allocation._paths import SaturationMode, SolvePaths
from casadi_debris.allocation._propulsion import PropulsionState
from casadi_debris.allocation._results import Allocation, BatchAllocation, SeriesAllocation
from casadi_debris.allocation._scaled_qp import ScaledQp
from casadi_debris.allocation._series import PiecewiseAffineQp
from casadi_debris.config import AXIS_NAMES, SIGNED_AXES, Problem
from casadi_debris.errors import AllocationError, InputShapeError, NoEngineError
from casadi_debris.geometry import Authority, Geometry, build_geometry, max_thrust_N

__all__ = ["DEFAULT_SOLVER", "SATURATION_MODES", "Allocator", "NoEngineError"]

SATURATION_MODES: tuple[SaturationMode, ...] = ("scale", "least_squares")
DEFAULT_SOLVER = "daqp"


class Allocator(SolvePaths):
    """Least-fuel thrust allocation over every engine, set up once, solved per demand.

    Parameters
    ----------
    torque_map : ndarray, shape (3, n)
        Torque about the CoG per newton of each engine [N m / N].
    force_map : ndarray, shape (3, n)
        Force on the body per newton of each engine [N / N].
    max_thrust_N : ndarray, shape (n,)
        Thrust limit of each engine's active stage [N]; 0 removes an engine.
    exhaust_velocity_m_s : float or array_like, shape (n,)
        Isp g0 of the engines [m/s], one for all or one per engine: the
        least-fuel objective weights each engine's thrust by its inverse.
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
        exhaust_velocity_m_s: float | npt.ArrayLike,
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
        exhaust = _exhaust_velocities(exhaust_velocity_m_s, n)
        self.torque_map = torque_map
        self.force_map = force_map
        self.exhaust_velocity_m_s = exhaust
        # One Isp: the fuel rate stays sum(f) / c, bit for bit the single-Isp formula.
        self._uniform_exhaust = float(exhaust[0]) if np.all(exhaust == exhaust[0]) else None
        self._mass_flow_per_N = 1.0 / exhaust
        self.saturation = saturation
        self.geometry = geometry
        limits = self._checked_limits(max_thrust_N)
        self._thrust_ref_N = float(limits.max())
        self._torque_ref_Nm = float(np.abs(torque_map).max()) * self._thrust_ref_N
        self._force_ref_N = float(np.abs(force_map).max()) * self._thrust_ref_N
        if self._torque_ref_Nm <= 0:
            raise AllocationError("torque_map is all zeros: no engine makes a torque")
        # Per-row references: target = wrench / reference, bit for bit the
        # division by the scalar references.
        self._wrench_ref = np.array([self._torque_ref_Nm] * 3 + [self._force_ref_N] * 3)
        self._torque_ref = self._wrench_ref[:3].copy()
        self._max_thrust_N = limits
        self._set_demand_bounds(limits)
        # Final check of every answer (see allocate): largest torque and force per
        # newton of any engine, and the subnormal resolution of B f and F f.
        self._lever_m = float(np.abs(torque_map).max())
        self._force_per_N = float(np.abs(force_map).max())
        self._floor_Nm = n * (self._lever_m + 2.0) * SMALLEST_SUBNORMAL
        self._floor_N = n * (self._force_per_N + 2.0) * SMALLEST_SUBNORMAL
        self._qp = ScaledQp(
            torque_map * (self._thrust_ref_N / self._torque_ref_Nm),
            force_map * (self._thrust_ref_N / self._force_ref_N),
            limits / self._thrust_ref_N,
            solver,
            self._torque_ref_Nm,
            # Mass flow per unit thrust relative to the best engine: exactly 1 for one Isp.
            float(exhaust.max()) / exhaust,
        )
        self.solver = solver
        self._polytopes: dict[bool, AuthorityPolytope] = {}
        self._series_qps: dict[bool, PiecewiseAffineQp] = {}
        # Set up the default workspace now: an unknown solver fails at construction.
        self._qp.workspace("exact", False)

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
        limits = state.max_thrust_N() if state is not None else max_thrust_N(geometry)
        g0 = problem.constants.standard_gravity_m_s2
        return cls(
            geometry.torque_map,
            geometry.force_map,
            limits,
            exhaust_velocity_m_s=np.array([engine.isp_s * g0 for engine in problem.engines]),
            solver=solver,
            saturation=saturation,
            geometry=geometry,
        )

    # ------------------------------------------------------------------ limits

    @property
    def n_engines(self) -> int:
        """Number of engines (columns of the maps)."""
        return self.torque_map.shape[1]

    def fuel_rate_kg_s(self, thrust_N: npt.ArrayLike) -> Any:
        """Propellant mass flow ``sum_i f_i / c_i`` of a thrust or of each row of a series.

        Parameters
        ----------
        thrust_N : array_like, shape (n,) or (k, n)
            Thrust per engine [N].

        Returns
        -------
        float or ndarray, shape (k,)
            [kg/s].
        """
        thrust = np.asarray(thrust_N, dtype=float)
        if self._uniform_exhaust is None:
            rate = thrust @ self._mass_flow_per_N
        elif thrust.ndim > 1:
            rate = thrust @ np.ones(thrust.shape[-1]) / self._uniform_exhaust
        else:
            rate = np.add.reduce(thrust) / self._uniform_exhaust
        return float(rate) if thrust.ndim == 1 else rate

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
        self._set_demand_bounds(limits)
        self._qp.set_upper(limits / self._thrust_ref_N)
        self._polytopes.clear()
        self._series_qps.clear()

    def _set_demand_bounds(self, limits: np.ndarray) -> None:
        """Largest demand component accepted: ABSURD_FACTOR times the largest that any
        thrust within ``limits`` makes (see :mod:`~casadi_debris.allocation._demand`)."""
        self._torque_bound_Nm = ABSURD_FACTOR * float((np.abs(self.torque_map) @ limits).max())
        self._force_bound_N = ABSURD_FACTOR * float((np.abs(self.force_map) @ limits).max())

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

    # ------------------------------------------------------------------ allocation

    def allocate(
        self, torque_Nm: Any, force_N: Any = None, *, free_force: bool = False
    ) -> Allocation:
        """Thrust of every engine for one torque (and force) demand.

        The answer is exact (``feasible``, mode ``"exact"``) only when the
        achieved torque ``B f`` (and force ``F f``) meets the demand to the
        promised accuracy,

            |B f - tau|_inf <= 1e-9 max(|tau|_inf, l sum(f)) + n (l + 2) 2**-1074 N m,

        ``l`` the largest lever arm [m] and ``n`` the number of engines (the last
        term, 4e-322 N m for the paper's 24 CubeSats, is the resolution of
        subnormal floats: below 1e-9 of any demand above about 1e-300 N m, the
        whole of a demand of 5e-324 N m); the same bound holds for ``alpha tau``
        when saturated, and for the force with ``F``.
        This holds for every demand from the smallest subnormal up (tiny ones are
        solved scaled up by a power of two, see
        :mod:`~casadi_debris.allocation._demand`); a demand of exactly zero gets
        exactly zero thrust. No NaN or inf is ever returned: an answer of the
        back-end that fails these checks is recomputed by HiGHS, and if that
        fails too an :class:`~casadi_debris.allocation._paths.AllocationInternalError` is raised.

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
        Allocation

        Raises
        ------
        DemandError
            A demand of the wrong shape, not finite, or with a component beyond
            1e6 times the largest that any thrust within the limits makes; an
            :class:`~casadi_debris.errors.AllocationError` naming the argument.
        AllocationError
            ``force_N`` with ``free_force``.
        AllocationInternalError
            Neither the back-end nor HiGHS found an answer that passes the checks
            (a bug: please report it).
        """
        torque = as_vector3(torque_Nm, "torque_Nm", self._torque_bound_Nm, "N m")
        if force_N is None:
            force = None if free_force else np.zeros(3)
        else:
            if free_force:
                raise AllocationError("give either force_N or free_force, not both")
            force = as_vector3(force_N, "force_N", self._force_bound_N, "N")
        # self._allocate, inlined: this is the hot path.
        result = self._solve(torque, force)
        return result if result is not None else self._fallback(torque, force)

    # ------------------------------------------------------------------ many demands

    def allocate_batch(
        self, torques_Nm: Any, forces_N: Any = None, *, free_force: bool = False
    ) -> BatchAllocation:
        """Allocate many demands in a row (warm-started workspaces), each as :meth:`allocate`.

        Parameters
        ----------
        torques_Nm : array_like, shape (k, 3)
            Torque demands [N m].
        forces_N : array_like, shape (k, 3), optional
            Net force demands [N]; default zero.
        free_force : bool

        Returns
        -------
        BatchAllocation

        Raises
        ------
        DemandError
            A row of the wrong shape, not finite or absurd (the message names the row).
        """
        return batch.allocate_batch(self, torques_Nm, forces_N, free_force)

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
        piecewise-affine solution of the QP (:mod:`~casadi_debris.allocation._series`),
        which needs a QP solve only where the active set changes. Tiny demands
        are scaled up by a power of two as in :meth:`allocate`; every row passes
        the same final check (finite, torque within the promised tolerance of
        ``scale`` times the demand) or is recomputed by :meth:`allocate`.

        Parameters
        ----------
        torques_Nm : array_like, shape (k, 3)
            Torque demands [N m], e.g. one per control step.
        free_force : bool
            Leave the net force free instead of zero.

        Returns
        -------
        SeriesAllocation

        Raises
        ------
        DemandError
            A row not finite or absurd (the message names the row).
        """
        return batch.allocate_series(self, torques_Nm, free_force)

    def torque_authority(self, *, free_force: bool = False) -> Authority:
        """Largest pure torque about each signed body axis with the current limits.

        Found by allocating a demand far beyond reach along each axis and
        reading the saturated torque (direction-preserving mode).

        Returns
        -------
        Authority
            At zero net force unless ``free_force``.
        """
        beyond_reach = 10.0 * self._torque_ref_Nm * self.n_engines
        authority: dict[str, float] = {}
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
        return Authority(np.array([authority[name] for name in SIGNED_AXES]), not free_force)


def _exhaust_velocities(exhaust_velocity_m_s: float | npt.ArrayLike, n: int) -> np.ndarray:
    """One exhaust velocity per engine [m/s], shape (n,), finite and positive."""
    exhaust = np.array(exhaust_velocity_m_s, dtype=float)
    if exhaust.ndim == 0:
        exhaust = np.full(n, float(exhaust))
    if exhaust.shape != (n,):
        raise InputShapeError(
            f"exhaust_velocity_m_s must be a number or one per engine ({n}), "
            f"got shape {exhaust.shape}"
        )
    if not np.all(np.isfinite(exhaust)) or np.any(exhaust <= 0):
        raise AllocationError(f"exhaust_velocity_m_s must be positive, got {exhaust}")
    return exhaust
