"""The allocation QPs in scaled units: one warm-started workspace per stage, set up once.

Units: thrust ``u = f / f_ref`` in units of the largest limit, torque rows in
units of the largest lever arm times that limit, force rows likewise (see
:mod:`casadi_debris.allocation._allocator`), so every number handed to a
solver is of order one.

Stages, each a QP of fixed structure whose data change only in ``b_eq``,
``a_eq`` or ``c`` between calls, and in ``ub`` when the limits change:

- ``"exact"``: least fuel, ``min eps/2 |u|^2 + w'u`` s.t. ``A u = b``, ``0 <= u <= u_max``,
  ``w`` each engine's mass flow per unit thrust relative to the best (1 for one Isp);
- ``"scale"``: largest alpha, ``min eps/2 |(u, alpha)|^2 - alpha`` s.t.
  ``A u - alpha b = 0``, ``0 <= u <= u_max``, ``0 <= alpha <= 1``;
- ``"least_squares"``: ``min 1/2 |B u - tau|^2`` (plus a tiny proximal term)
  s.t. ``F u = phi`` unless the force is free.

``A`` is the torque rows, with the force rows below them unless the force is free.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
import numpy.typing as npt

from casadi_debris.allocation._backends import QpBackend, QpData, make_backend

# Proximal weight of the least-fuel QP, in scaled thrust units against a fuel
# weight of 1 per engine: far below the reduced costs of the LP (order one),
# so the least-fuel optimum is exact (see the allocator's module docstring).
EXACT_PROXIMAL = 1e-3
# Max-alpha stage: alpha has weight 1, proximal eps << 1. It carries no fuel
# term: with the force free, a little more alpha can cost a lot of fuel, so no
# fixed fuel weight is small enough for every demand (measured: 2e-4 of alpha
# lost with 1e-3); the least-fuel solve that follows does the fuel.
SCALE_PROXIMAL = 1e-6
LEAST_SQUARES_PROXIMAL = 1e-9
# Thrust below this fraction of the largest limit is solver round-off: set to 0.
THRUST_ROUND_OFF = 1e-12
# Equality residual (relative to the target) above which a solution is polished.
POLISH_TOLERANCE = 1e-13
# An engine within this fraction of its limit counts as on it (a stretched small
# demand is scaled back only when no limit binds).
LIMIT_ACTIVE_RTOL = 1e-9

# The QP workspaces: least fuel for the exact target, largest alpha, least squares.
Stage = Literal["exact", "scale", "least_squares"]


class ScaledQp:
    """The allocation stages of one allocator, in scaled units.

    Parameters
    ----------
    scaled_torque : ndarray, shape (3, n)
        Torque rows ``B f_ref / tau_ref``.
    scaled_force : ndarray, shape (3, n)
        Force rows ``F f_ref / phi_ref``.
    upper : ndarray, shape (n,)
        Scaled thrust limits ``f_max / f_ref``.
    solver : str
        QP back-end name (see :func:`~casadi_debris.allocation.available_solvers`).
    torque_ref_Nm : float
        ``tau_ref``, only to state a target in N m in an error message.
    cost : ndarray, shape (n,), optional
        Fuel weight ``w`` of each engine, ``c_max / c_i`` (at least 1); default 1 each.
    """

    def __init__(
        self,
        scaled_torque: np.ndarray,
        scaled_force: np.ndarray,
        upper: np.ndarray,
        solver: str,
        torque_ref_Nm: float,
        cost: np.ndarray | None = None,
    ) -> None:
        self.torque = scaled_torque
        self.cost = np.ones(scaled_torque.shape[1]) if cost is None else np.asarray(cost, float)
        self.force = scaled_force
        self.wrench = np.vstack([scaled_torque, scaled_force])
        self.solver = solver
        self.torque_ref_Nm = torque_ref_Nm
        # Equality rows of the max-alpha stage, [rows, -target], keyed by free_force.
        self.scale_rows = {
            free: np.hstack([self.rows(free), np.zeros((len(self.rows(free)), 1))])
            for free in (False, True)
        }
        self._workspaces: dict[tuple[Stage, bool], QpBackend] = {}
        self.set_upper(upper)

    @property
    def n(self) -> int:
        """Number of engines."""
        return self.torque.shape[1]

    def binds(self, u: np.ndarray) -> npt.NDArray[np.bool_] | np.bool_:
        """Whether an engine that can fire is on its limit; per row for ``u`` of shape (k, n)."""
        return (u >= self.on_limit).any(axis=-1)

    def rows(self, free_force: bool) -> np.ndarray:
        """Scaled equality rows: torque, and force unless it is free."""
        return self.torque if free_force else self.wrench

    def set_upper(self, upper: np.ndarray) -> None:
        """New scaled limits, handed to every workspace set up so far."""
        self.upper = upper
        self.reach = self._reachable_size()
        # Thrust at or above which an engine that can fire counts as on its limit.
        self.on_limit = np.where(upper > 0.0, upper * (1.0 - LIMIT_ACTIVE_RTOL), np.inf)
        for (stage, _), workspace in self._workspaces.items():
            workspace.update(ub=self._stage_upper(stage))

    def _reachable_size(self) -> dict[bool, float]:
        """Bound on every component of a reachable scaled target: ``max_j sum_i |A_ji| u_max_i``.

        Keyed by ``free_force`` (the rows differ).
        """
        return {free: float((np.abs(self.rows(free)) @ self.upper).max()) for free in (False, True)}

    def _stage_upper(self, stage: Stage) -> np.ndarray:
        return np.append(self.upper, 1.0) if stage == "scale" else self.upper

    def workspace(self, stage: Stage, free_force: bool) -> QpBackend:
        """The workspace of ``stage`` (``"exact"``, ``"scale"``, ``"least_squares"``), set up
        on first use."""
        key = (stage, free_force)
        workspace = self._workspaces.get(key)
        if workspace is not None:
            return workspace
        n = self.n
        rows = self.torque if free_force else np.vstack([self.torque, self.force])
        if stage == "exact":
            data = QpData(
                EXACT_PROXIMAL * np.eye(n),
                self.cost,
                rows,
                np.zeros(len(rows)),
                np.zeros(n),
                self.upper,
            )
        elif stage == "scale":
            data = QpData(
                SCALE_PROXIMAL * np.eye(n + 1),
                np.append(np.zeros(n), -1.0),
                np.hstack([rows, np.zeros((len(rows), 1))]),
                np.zeros(len(rows)),
                np.zeros(n + 1),
                np.append(self.upper, 1.0),
            )
        else:
            torque = self.torque
            force_rows = np.zeros((0, n)) if free_force else self.force
            data = QpData(
                torque.T @ torque + LEAST_SQUARES_PROXIMAL * np.eye(n),
                np.zeros(n),
                force_rows,
                np.zeros(len(force_rows)),
                np.zeros(n),
                self.upper,
            )
        workspace = make_backend(self.solver, data)
        self._workspaces[key] = workspace
        return workspace

    def polish(self, u: np.ndarray, target: np.ndarray, free_force: bool) -> np.ndarray:
        """Remove the solver's residual on the equalities by moving the engines off their bounds.

        A warm-started active-set solve can leave thrusts of 1e-13 of the
        limit that should be zero, and a residual of that size; against a
        small demand that is a large relative error. One least-squares step
        on the free engines (the solver's own active set) removes it.
        """
        return self.polish_checked(u, target, free_force)[0]

    def polish_checked(
        self, u: np.ndarray, target: np.ndarray, free_force: bool
    ) -> tuple[np.ndarray, bool]:
        """:meth:`polish`, and whether the returned ``u`` was seen to meet the target to
        ``POLISH_TOLERANCE`` (relative to its largest component).

        True only when the residual of the returned ``u`` itself was measured
        (no step taken): the allocator then needs no second check of its
        accuracy. ``max`` may pass over a NaN in the residual, so a caller must
        still check that ``u`` is finite (the allocator checks every answer's sum).
        """
        rows = self.torque if free_force else self.wrench
        u = np.minimum(u, self.upper)
        u[u < THRUST_ROUND_OFF] = 0.0
        residual = target - rows @ u
        # Largest entries by Python's max over a handful of floats: cheaper than numpy's.
        tolerance = POLISH_TOLERANCE * max(map(abs, target.tolist()))
        if max(map(abs, residual.tolist())) <= tolerance:
            return u, True
        free = (u > 0.0) & (u < self.upper)
        if not free.any():
            return u, False
        active = rows[:, free]
        try:
            # Minimum-norm step through the (at most 6 x 6) Gram matrix: a tenth of lstsq's cost.
            step = active.T @ np.linalg.solve(active @ active.T, residual)
        except np.linalg.LinAlgError:
            step = np.linalg.lstsq(active, residual, rcond=None)[0]
        polished = u.copy()
        polished[free] = np.clip(u[free] + step, 0.0, self.upper[free])
        if float(np.abs(target - rows @ polished).max()) > float(np.abs(residual).max()):
            # A rank-deficient Gram matrix gave a poor step: take the least-squares one.
            step = np.linalg.lstsq(active, residual, rcond=None)[0]
            polished[free] = np.clip(u[free] + step, 0.0, self.upper[free])
        return polished, False
