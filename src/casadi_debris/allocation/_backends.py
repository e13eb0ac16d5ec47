"""QP back-ends behind one small interface, each set up once and updated per call.

Every allocation stage is a QP of fixed structure

    minimise    1/2 x' H x + c' x
    subject to  A_eq x = b_eq,   lb <= x <= ub

whose data change between calls only in ``c``, ``A_eq``, ``b_eq``, ``lb`` and
``ub``. A back-end keeps the solver's workspace between calls so that the
per-call cost is the solve itself, not the conversion of the problem:

- ``"daqp"``: DAQP's own ``daqp.Model`` (dense dual active set). Default: it
  is the fastest at this size (24 engines, 6 equalities), see
  ``benchmarks/allocation.py``.
- ``"osqp"``: OSQP's own ``osqp.OSQP`` with warm start and solution polishing
  (ADMM alone does not meet the torque to 1e-9; the polished active-set
  solution does). Kept for large sparse problems.
- any other solver that :mod:`qpsolvers` finds installed, called through
  :func:`qpsolvers.solve_problem` (the problem is converted on every call).
  ``"qpsolvers:daqp"``, ``"qpsolvers:osqp"`` force that path for a solver that
  also has a native back-end (for measurement).
"""

from __future__ import annotations

import time
import warnings
from typing import Any, Literal, NamedTuple

import numpy as np
import numpy.typing as npt

from casadi_debris.errors import AllocationError, UnknownSolverError

NATIVE_SOLVERS = ("daqp", "osqp")
QPSOLVERS_PREFIX = "qpsolvers:"

# DAQP's default primal tolerance (1e-6) lets inactive bounds be crossed by
# one part in a million of the thrust limit; 1e-10 keeps limits exact without
# costing iterations at this size.
DAQP_PRIMAL_TOLERANCE = 1e-10
OSQP_TOLERANCE = 1e-10
# OSQP's iteration cap. Measured over the benchmark's 2000 feasible and 2000
# saturating demands: feasible solves take at most 950 iterations, successful
# solves at a saturated edge 400 (median) to 7 000 (p99). The solves that run
# to the cap are edge targets a hair inside or outside the reachable set,
# which ADMM does not settle to 1e-10 at all: they go on to the next pull-in
# and then to HiGHS in the same share of demands (15 %) with a cap of 4 000,
# 10 000 or 200 000. At 10 000 (about 25 ms) the slowest saturated call took
# 74 ms instead of 0.7 s, with ten times the feasible cases' need in reserve.
OSQP_MAX_ITER = 10_000
DAQP_EQUALITY_SENSE = 5
# Settings passed through qpsolvers: full accuracy where the solver allows, and
# a time limit where it could otherwise stall.
GENERIC_SETTINGS: dict[str, dict[str, Any]] = {
    "osqp": {"eps_abs": OSQP_TOLERANCE, "eps_rel": OSQP_TOLERANCE, "polishing": True},
    "highs": {"time_limit": 1.0},
    "daqp": {"primal_tol": DAQP_PRIMAL_TOLERANCE},
}
DAQP_INFEASIBLE_FLAGS = (-1,)

QpStatus = Literal["optimal", "infeasible", "failed"]


class QpSolution(NamedTuple):
    """What a back-end returns from one solve (a named tuple: built on every solve, so cheap).

    Attributes
    ----------
    x : ndarray, shape (n,) or None
        Solution; None when no solution was found.
    status : {"optimal", "infeasible", "failed"}
    iterations : int
    solve_time_s : float
        Wall time of the back-end call (update + solve) [s].
    """

    x: npt.NDArray[np.float64] | None
    status: QpStatus
    iterations: int
    solve_time_s: float

    def optimal_x(self) -> npt.NDArray[np.float64]:
        """The solution of a solve whose status is ``"optimal"``.

        Raises
        ------
        AllocationError
            There is none: the solve was not optimal (check ``status`` first).
        """
        if self.x is None:
            raise AllocationError(f"no QP solution to read: the solve was {self.status}")
        return self.x


class QpData(NamedTuple):
    """The data of one QP: minimise ``1/2 x' h x + c' x`` subject to ``a_eq x = b_eq``,
    ``lb <= x <= ub``.

    Attributes
    ----------
    h : ndarray, shape (n, n)
        Positive definite Hessian.
    c : ndarray, shape (n,)
    a_eq : ndarray, shape (m, n)
    b_eq : ndarray, shape (m,)
    lb, ub : ndarray, shape (n,)
    """

    h: np.ndarray
    c: np.ndarray
    a_eq: np.ndarray
    b_eq: np.ndarray
    lb: np.ndarray
    ub: np.ndarray


class QpBackend:
    """A QP workspace of fixed structure: what every back-end shares.

    The equality targets and the simple bounds are kept as the one pair of
    lower/upper vectors the solver takes (``lower = upper = b_eq`` on the
    equality rows), updated in place; a back-end hands the changed data to
    its solver in :meth:`_load` and solves in :meth:`solve`.
    """

    name: str

    def __init__(self, data: QpData, *, equalities_first: bool) -> None:
        b_eq, lb, ub = data.b_eq, data.lb, data.ub
        m, n = len(b_eq), len(lb)
        self._rows = slice(0, m) if equalities_first else slice(n, n + m)
        self._box = slice(m, m + n) if equalities_first else slice(0, n)
        self._lower = np.empty(m + n)
        self._upper = np.empty(m + n)
        self._lower[self._rows] = b_eq
        self._upper[self._rows] = b_eq
        self._lower[self._box] = lb
        self._upper[self._box] = ub

    def update(
        self,
        *,
        c: np.ndarray | None = None,
        a_eq: np.ndarray | None = None,
        b_eq: np.ndarray | None = None,
        lb: np.ndarray | None = None,
        ub: np.ndarray | None = None,
    ) -> None:
        """Replace some of the problem data (same shapes as at set-up)."""
        if b_eq is not None:
            self._lower[self._rows] = b_eq
            self._upper[self._rows] = b_eq
        if lb is not None:
            self._lower[self._box] = lb
        if ub is not None:
            self._upper[self._box] = ub
        self._load(c, a_eq, bounds=b_eq is not None or lb is not None or ub is not None)

    def _load(self, c: np.ndarray | None, a_eq: np.ndarray | None, *, bounds: bool) -> None:
        """Hand the new cost and rows (those given) and, when ``bounds``, the bound vectors
        to the solver."""
        raise NotImplementedError

    def solve(self) -> QpSolution:
        """Solve the current problem, warm-started from the last solution where possible."""
        raise NotImplementedError


def available_solvers() -> tuple[str, ...]:
    """Names accepted by :func:`make_backend`: native back-ends, then the rest of qpsolvers.

    Returns
    -------
    tuple of str
        e.g. ``("daqp", "osqp", "qpsolvers:daqp", "qpsolvers:osqp", "quadprog")``.
    """
    import qpsolvers

    installed = tuple(qpsolvers.available_solvers)
    native = tuple(name for name in NATIVE_SOLVERS if name in installed)
    forced = tuple(QPSOLVERS_PREFIX + name for name in native)
    others = tuple(sorted(name for name in installed if name not in NATIVE_SOLVERS))
    return native + forced + others


def make_backend(name: str, data: QpData) -> QpBackend:
    """Set up a QP workspace on the named back-end.

    Parameters
    ----------
    name : str
        One of :func:`available_solvers`.
    data : QpData
        The problem at set-up; later calls change its data, never its shapes.

    Raises
    ------
    UnknownSolverError
        ``name`` is not installed; the message lists what is.
    """
    names = available_solvers()
    if name not in names:
        raise UnknownSolverError(
            f"unknown QP solver {name!r}; installed: {', '.join(names)} "
            "(others: pip install qpsolvers[<solver>])"
        )
    if name == "daqp":
        return DaqpBackend(data)
    if name == "osqp":
        return OsqpBackend(data)
    return QpsolversBackend(name.removeprefix(QPSOLVERS_PREFIX), data)


class DaqpBackend(QpBackend):
    """DAQP workspace (``daqp.Model``): set up once, bounds and data updated in place."""

    name = "daqp"

    def __init__(self, data: QpData) -> None:
        import daqp

        # DAQP takes simple bounds first, then the rows of A, in one pair of vectors.
        super().__init__(data, equalities_first=False)
        h, c, a_eq, b_eq, _, _ = data
        n = len(c)
        self._a = np.ascontiguousarray(a_eq, dtype=float)
        # The same minimiser with a Hessian of unit size: with H = eps I (eps = 1e-3)
        # DAQP leaves equality residuals of about 1e-12 of the target at
        # primal_tol 1e-10, with unit H about 1e-16 in as many iterations
        # (measured over 400 demands), so the polish step is rarely needed.
        self._objective_scale = float(np.abs(h).max())
        self._c = np.array(c, dtype=float) / self._objective_scale
        sense = np.zeros(n + len(b_eq), dtype=np.int32)
        sense[n:] = DAQP_EQUALITY_SENSE
        self._model = daqp.Model()
        flag, _ = self._model.setup(
            np.array(h, dtype=float) / self._objective_scale,
            self._c,
            self._a,
            self._upper,
            self._lower,
            sense,
        )
        if flag < 0:
            raise AllocationError(f"DAQP could not set up the allocation QP (exit flag {flag})")
        self._model.settings = {"primal_tol": DAQP_PRIMAL_TOLERANCE}

    def _load(self, c: np.ndarray | None, a_eq: np.ndarray | None, *, bounds: bool) -> None:
        if bounds and c is None and a_eq is None:
            # The hot path, one target per demand: only the equality rows change.
            self._model.update(bupper=self._upper, blower=self._lower)
            return
        if c is not None:
            self._c[:] = c
            self._c /= self._objective_scale
        if a_eq is not None:
            self._a[:] = a_eq
        self._model.update(
            f=self._c if c is not None else None,
            A=self._a if a_eq is not None else None,
            bupper=self._upper if bounds else None,
            blower=self._lower if bounds else None,
        )

    def solve(self) -> QpSolution:
        start = time.perf_counter()
        x, _, flag, info = self._model.solve()
        elapsed = time.perf_counter() - start
        if flag > 0:
            # x is a fresh array owned by the caller (DAQP allocates it per solve).
            return QpSolution(x, "optimal", info["iterations"], elapsed)
        status: QpStatus = "infeasible" if flag in DAQP_INFEASIBLE_FLAGS else "failed"
        return QpSolution(None, status, int(info["iterations"]), elapsed)


class OsqpBackend(QpBackend):
    """OSQP workspace (``osqp.OSQP``), warm-started, polished, tight tolerances."""

    name = "osqp"

    def __init__(self, data: QpData) -> None:
        import osqp
        from scipy import sparse

        h, c, a_eq, b_eq, _, _ = data
        n = len(c)
        self._n = n
        self._m = len(b_eq)
        # A_eq (dense, zeros kept so later updates only change values) over the
        # identity of the bounds, built column by column in CSC order: column j
        # stores A_eq[:, j] then the 1 of bound j.
        m = len(b_eq)
        self._indptr = np.arange(0, (m + 1) * n + 1, m + 1)
        indices = np.empty((n, m + 1), dtype=np.int64)
        indices[:, :m] = np.arange(m)
        indices[:, m] = m + np.arange(n)
        self._indices = indices.ravel()
        a_full = sparse.csc_matrix(
            (self._stacked_values(a_eq), self._indices, self._indptr), shape=(m + n, n)
        )
        super().__init__(data, equalities_first=True)
        self._solver = osqp.OSQP()
        self._solver.setup(
            sparse.triu(sparse.csc_matrix(h), format="csc"),
            np.array(c, dtype=float),
            a_full,
            self._lower,
            self._upper,
            verbose=False,
            eps_abs=OSQP_TOLERANCE,
            eps_rel=OSQP_TOLERANCE,
            eps_prim_inf=1e-9,
            eps_dual_inf=1e-9,
            max_iter=OSQP_MAX_ITER,
            polishing=True,
            polish_refine_iter=10,
            warm_starting=True,
        )
        self._warm = (np.zeros(n), np.zeros(m + n))
        self._status_optimal = osqp.SolverStatus.OSQP_SOLVED
        self._status_infeasible = (
            osqp.SolverStatus.OSQP_PRIMAL_INFEASIBLE,
            osqp.SolverStatus.OSQP_PRIMAL_INFEASIBLE_INACCURATE,
        )

    def _load(self, c: np.ndarray | None, a_eq: np.ndarray | None, *, bounds: bool) -> None:
        kwargs: dict[str, np.ndarray] = {}
        if bounds:
            kwargs["l"] = self._lower
            kwargs["u"] = self._upper
        if c is not None:
            kwargs["q"] = np.array(c, dtype=float)
        if a_eq is not None:
            kwargs["Ax"] = self._stacked_values(a_eq)
        self._solver.update(**kwargs)

    def _stacked_values(self, a_eq: np.ndarray) -> np.ndarray:
        values = np.ones((self._n, self._m + 1))
        values[:, : self._m] = np.asarray(a_eq, dtype=float).T
        return values.ravel()

    def solve(self) -> QpSolution:
        start = time.perf_counter()
        result = self._solver.solve(raise_error=False)
        elapsed = time.perf_counter() - start
        status_value = result.info.status_val
        status: QpStatus
        if status_value == self._status_optimal:
            status = "optimal"
        elif status_value in self._status_infeasible:
            status = "infeasible"
        else:
            status = "failed"
        if status == "optimal":
            x = np.array(result.x)
            self._warm = (x.copy(), np.array(result.y))
        else:
            x = None
            # The iterates of an infeasible or unfinished solve are a poor start
            # for the next problem (measured: 142 550 iterations for a
            # saturated target after an infeasibility certificate, 3 325 from
            # the last solution): start again from the last solution found.
            self._solver.warm_start(x=self._warm[0], y=self._warm[1])
        return QpSolution(x, status, int(result.info.iter), elapsed)


class QpsolversBackend(QpBackend):
    """Any solver qpsolvers knows, through :func:`qpsolvers.solve_problem` (converted per call)."""

    def __init__(self, solver: str, data: QpData) -> None:
        super().__init__(data, equalities_first=True)
        h, c, a_eq, _, _, _ = data
        self.name = QPSOLVERS_PREFIX + solver if solver in NATIVE_SOLVERS else solver
        self._solver = solver
        self._h = np.array(h, dtype=float)
        self._c = np.array(c, dtype=float)
        self._a = np.array(a_eq, dtype=float)
        self._last: np.ndarray | None = None

    def _load(self, c: np.ndarray | None, a_eq: np.ndarray | None, *, bounds: bool) -> None:
        if c is not None:
            self._c[:] = c
        if a_eq is not None:
            self._a[...] = a_eq

    def solve(self) -> QpSolution:
        import qpsolvers

        # Same minimiser with a Hessian of unit size: HiGHS' QP solver stalls on
        # a Hessian as small as the proximal terms used here.
        objective_scale = float(np.abs(self._h).max())
        problem = qpsolvers.Problem(
            self._h / objective_scale,
            self._c / objective_scale,
            A=self._a,
            b=self._lower[self._rows],
            lb=self._lower[self._box],
            ub=self._upper[self._box],
        )
        settings = GENERIC_SETTINGS.get(self._solver, {})
        start = time.perf_counter()
        with warnings.catch_warnings():
            # qpsolvers warns on dense-to-sparse conversion and on every
            # infeasible status; the status is handled below.
            warnings.simplefilter("ignore")
            solution = qpsolvers.solve_problem(
                problem, self._solver, initvals=self._last, **settings
            )
        elapsed = time.perf_counter() - start
        found = bool(solution.found) and solution.x is not None
        self._last = solution.x if found else None
        status: QpStatus = "optimal" if found else "infeasible"
        iterations = _iterations(solution.extras)
        return QpSolution(np.array(solution.x) if found else None, status, iterations, elapsed)


def _iterations(extras: object) -> int:
    """Iteration count from a qpsolvers solution's solver-specific extras, when it gives one."""
    if isinstance(extras, dict):
        for key in ("iterations", "iter", "iters"):
            if key in extras:
                return int(extras[key])
        info = extras.get("info")
        if isinstance(info, dict) and "iterations" in info:
            return int(info["iterations"])
    info = getattr(extras, "info", None)
    return int(getattr(info, "iter", 0) or 0)
