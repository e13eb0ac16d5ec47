"""Least-fuel allocation of a whole series of demands by reusing active sets.

The least-fuel QP of :mod:`casadi_debris.allocation._allocator`,

    minimise  eps/2 |u|^2 + w^T u   subject to  A u = b,  0 <= u <= u_max,

``w`` each engine's fuel weight (1 for every engine when they share one Isp),

is strictly convex, so its solution is a piecewise-affine function of the
target ``b`` (a multi-parametric QP): on each region the same engines sit at
zero (set L), at their limit (set U) and in between (set F). Its KKT
conditions, with multipliers lambda (equalities) and mu (bounds), are

    eps u_F + w_F + A_F^T lambda = 0,         A u = b,
    mu_L = w_L + A_L^T lambda >= 0,           mu_U = -(eps u_max_U + w_U + A_U^T lambda) >= 0,
    0 <= u_F <= u_max_F.

Engines facing each other make ``A_F`` rank deficient, so lambda is not
unique (u is). A region is therefore anchored at a solved point
``(b*, u*, lambda*)``, lambda* the multiplier with the largest least bound
multiplier (a small LP), and moved with the least-norm change:

    u_F(b) = u*_F + A_F^+ (b - b*),      lambda(b) = lambda* - eps G^+ (b - b*),  G = A_F A_F^T.

When ``A u(b) = b``, the bounds and ``mu(lambda(b)) >= 0`` hold, these u and
lambda satisfy every KKT condition: u(b) *is* the QP's unique solution, not
an approximation.

Along a simulated torque history the active set changes rarely, so a whole
series is solved by one matrix product per region: the region of the last
point is checked on the next demands (vectorised), those that pass are
taken, and the first that fails goes to the point solver, whose answer
anchors the next region. Regions seen before are tried first.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linprog

# KKT tolerances, in scaled units (thrust in units of the largest limit, cost
# 1 per unit thrust, targets of order one): far below anything that moves
# fuel or torque.
BOUND_TOLERANCE = 1e-10
MULTIPLIER_TOLERANCE = 1e-10
RESIDUAL_TOLERANCE = 1e-11
# An engine within this of a bound (scaled) counts as on it when an active set
# is read off a point solution.
ACTIVE_TOLERANCE = 1e-11
# Demands checked at once against the current region: starts small (regions
# change in bursts), doubles while every demand fits.
WINDOW_FIRST = 16
WINDOW_MAX = 4096
CACHE_SIZE = 32
# Slope of a bound multiplier along the free direction of lambda below which it is
# round-off (relative to the row's norm; slopes of a real dependence are of order one).
FLAT_SLOPE = 1e-12

LOWER, FREE, UPPER = 0, 1, 2


@dataclass(frozen=True)
class _Region:
    """One active set anchored at a solved point: ``u = u* + (b - b*) @ gain``."""

    labels: np.ndarray
    anchor: np.ndarray  # b*, (m,)
    solution: np.ndarray  # u*, (n,)
    gain: np.ndarray  # (m, n)
    multipliers: np.ndarray  # mu* on the bounds (0 on free engines), (n,)
    multiplier_gain: np.ndarray  # (m, n)


class PiecewiseAffineQp:
    """Least-fuel QP solved for many targets by active-set regions.

    Parameters
    ----------
    a_eq : ndarray, shape (m, n)
        Equality rows (scaled).
    upper : ndarray, shape (n,)
        Upper bounds (scaled), non-negative.
    proximal : float
        eps of the proximal term.
    cost : ndarray, shape (n,), optional
        Fuel weight ``w`` of each engine; default 1 each.
    """

    def __init__(
        self,
        a_eq: np.ndarray,
        upper: np.ndarray,
        proximal: float,
        cost: np.ndarray | None = None,
    ) -> None:
        self.a_eq = np.asarray(a_eq, dtype=float)
        self.upper = np.asarray(upper, dtype=float)
        self.proximal = float(proximal)
        self.cost = np.ones(len(self.upper)) if cost is None else np.asarray(cost, dtype=float)
        self._cache: OrderedDict[bytes, _Region] = OrderedDict()
        self._stacked: tuple | None = None

    def labels_of(self, u: np.ndarray) -> np.ndarray:
        """Active set read off a solution: LOWER, FREE or UPPER per engine."""
        labels = np.full(len(u), FREE, dtype=np.int8)
        labels[u >= self.upper - ACTIVE_TOLERANCE] = UPPER
        labels[u <= ACTIVE_TOLERANCE] = LOWER
        return labels

    def anchor(self, target: np.ndarray, u: np.ndarray) -> _Region | None:
        """Region of the active set of a solved point ``u`` for ``target``; None if degenerate."""
        a, eps = self.a_eq, self.proximal
        labels = self.labels_of(u)
        free, lower, at_upper = labels == FREE, labels == LOWER, labels == UPPER
        a_free = a[:, free]
        # lambda*: A_F^T lambda = -(w_F + eps u_F), maximising the least bound multiplier s.
        n_rows = len(a)
        # A failed engine (0 <= u <= 0) is fixed: its bound multiplier may take either
        # sign, so it gets no sign condition (as a free engine, but held at 0).
        fixed = self.upper <= ACTIVE_TOLERANCE
        sign = np.where(fixed, 0.0, np.where(lower, 1.0, np.where(at_upper, -1.0, 0.0)))
        bounded = ~free & ~fixed
        # mu_i = sign_i (w_i + a_i . lambda + eps u_max_i [i in U]) >= s
        mu_constant = sign * (self.cost + np.where(at_upper, eps * self.upper, 0.0))
        rhs = -(self.cost[free] + eps * u[free])
        slopes, constants = sign[bounded, None] * a[:, bounded].T, mu_constant[bounded]
        best = _one_free_direction(a_free, rhs, slopes, constants)
        if best is None:
            best = _multiplier_lp(a_free, rhs, slopes, constants)
        if best is None or best[1] < -MULTIPLIER_TOLERANCE:
            return None
        multiplier = best[0]
        # A multiplier so large that mu = c + slopes @ lambda cancels to round-off beyond
        # the tolerance cannot tell a true bound multiplier from a wrong sign: a region
        # checked with it could pass a non-optimal u (the QP's answer is unique, so that
        # would be a wrong thrust). Such a point anchors no region.
        if _cancellation(slopes, constants, multiplier) > MULTIPLIER_TOLERANCE:
            return None
        gram_pinv = np.linalg.pinv(a_free @ a_free.T) if free.any() else np.zeros((n_rows, n_rows))
        gain = np.zeros((n_rows, len(u)))
        gain[:, free] = gram_pinv @ a_free  # rows: d u_F / d b = A_F^+ = A_F^T G^+ (transposed)
        # d mu / d b: d lambda = -eps G^+ d b, d mu_i = sign_i a_i . d lambda
        multiplier_gain = (-eps * gram_pinv @ a) * sign
        multipliers = mu_constant + sign * (multiplier @ a)
        multipliers[free | fixed] = 0.0
        return _Region(labels, target.copy(), u.copy(), gain, multipliers, multiplier_gain)

    def evaluate(self, region: _Region, targets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Candidate solutions of one region and whether each is the optimum.

        Parameters
        ----------
        region : _Region
        targets : ndarray, shape (k, m)

        Returns
        -------
        u : ndarray, shape (k, n)
        optimal : ndarray of bool, shape (k,)
        """
        step = targets - region.anchor
        u = region.solution + step @ region.gain
        multipliers = region.multipliers + step @ region.multiplier_gain
        return np.clip(u, 0.0, self.upper), self._satisfies_kkt(u, multipliers, targets)

    def _satisfies_kkt(
        self, u: np.ndarray, multipliers: np.ndarray, targets: np.ndarray
    ) -> np.ndarray:
        """Rows where u and the bound multipliers meet every KKT condition (within tolerance)."""
        residual = np.abs(u @ self.a_eq.T - targets).max(axis=1)
        return (
            np.all(u >= -BOUND_TOLERANCE, axis=1)
            & np.all(u <= self.upper + BOUND_TOLERANCE, axis=1)
            & np.all(multipliers >= -MULTIPLIER_TOLERANCE, axis=1)
            & (residual <= RESIDUAL_TOLERANCE)
        )

    def solve_series(
        self, targets: np.ndarray, solve_point: Callable[[np.ndarray], np.ndarray]
    ) -> tuple[np.ndarray, int]:
        """Solutions for every row of ``targets``.

        Parameters
        ----------
        targets : ndarray, shape (k, m)
            Reachable targets (scaled).
        solve_point : callable
            ``solve_point(b) -> u``, the point solver for a target no known
            region fits.

        Returns
        -------
        u : ndarray, shape (k, n)
        point_solves : int
            How many targets went to ``solve_point``.
        """
        k = len(targets)
        solution = np.zeros((k, len(self.upper)))
        region: _Region | None = None
        point_solves = 0
        i = 0
        size = WINDOW_FIRST
        while i < k:
            if region is not None:
                window = targets[i : i + size]
                u, optimal = self.evaluate(region, window)
                run = len(window) if optimal.all() else int(np.argmin(optimal))
                solution[i : i + run] = u[:run]
                i += run
                if run == len(window):
                    size = min(2 * size, WINDOW_MAX)
                    continue
                size = WINDOW_FIRST
            # Every pass below settles targets[i]: a known region's check and the
            # window's may disagree by round-off on a target at a tolerance, and
            # leaving targets[i] to the window again would loop for ever.
            fit = self._known_fit(targets[i])
            if fit is not None:
                region, solution[i] = fit
            else:
                solution[i] = solve_point(targets[i])
                point_solves += 1
                # Anchor at the target the point solve met: a saturated solve may come
                # back pulled in by round-off, and a region must satisfy A u* = b*.
                region = self._remember(self.anchor(self.a_eq @ solution[i], solution[i]))
            i += 1
        return solution, point_solves

    def _remember(self, region: _Region | None) -> _Region | None:
        if region is not None:
            key = region.labels.tobytes()
            self._cache[key] = region
            self._cache.move_to_end(key)
            if len(self._cache) > CACHE_SIZE:
                self._cache.popitem(last=False)
            self._stacked = None
        return region

    def _known_fit(self, target: np.ndarray) -> tuple[_Region, np.ndarray] | None:
        """A region seen before whose solution is optimal for ``target``, and that solution.

        All remembered regions are checked at once (stacked arrays).
        """
        if not self._cache:
            return None
        if self._stacked is None:
            regions = list(self._cache.values())
            self._stacked = (
                regions,
                np.array([r.anchor for r in regions]),
                np.array([r.solution for r in regions]),
                np.array([r.gain for r in regions]),
                np.array([r.multipliers for r in regions]),
                np.array([r.multiplier_gain for r in regions]),
            )
        regions, anchors, solutions, gains, multipliers, multiplier_gains = self._stacked
        step = target - anchors
        u = solutions + np.einsum("rm,rmn->rn", step, gains)
        mu = multipliers + np.einsum("rm,rmn->rn", step, multiplier_gains)
        hits = np.flatnonzero(self._satisfies_kkt(u, mu, target[None, :]))
        if not len(hits):
            return None
        return regions[hits[-1]], np.clip(u[hits[-1]], 0.0, self.upper)


def _cancellation(slopes: np.ndarray, constants: np.ndarray, multiplier: np.ndarray) -> float:
    """Round-off bound of the bound multipliers ``constants + slopes @ multiplier``: a few
    units in the last place of the largest term summed."""
    if not len(constants):
        return 0.0
    terms = np.abs(constants) + np.abs(slopes) @ np.abs(multiplier)
    return float(8.0 * np.finfo(float).eps * terms.max())


def _multiplier_lp(
    a_free: np.ndarray, rhs: np.ndarray, slopes: np.ndarray, constants: np.ndarray
) -> tuple[np.ndarray, float] | None:
    """lambda with ``A_F^T lambda = rhs`` maximising ``s = min(1, min_i mu_i)``,
    ``mu = constants + slopes @ lambda``, by an LP; (lambda, s), None if infeasible."""
    n_rows = a_free.shape[0]
    free = a_free.shape[1] > 0
    result = linprog(
        np.append(np.zeros(n_rows), -1.0),
        A_ub=np.hstack([-slopes, np.ones((len(slopes), 1))]),
        b_ub=constants,
        A_eq=np.hstack([a_free.T, np.zeros((a_free.shape[1], 1))]) if free else None,
        b_eq=rhs if free else None,
        bounds=[(None, None)] * n_rows + [(None, 1.0)],
        method="highs",
    )
    if result.status != 0 or result.x is None:
        return None
    return result.x[:n_rows], float(result.x[-1])


def _one_free_direction(
    a_free: np.ndarray, rhs: np.ndarray, slopes: np.ndarray, constants: np.ndarray
) -> tuple[np.ndarray, float] | None:
    """:func:`_multiplier_lp` in closed form when ``A_F^T lambda = rhs`` leaves lambda one
    free direction (engines facing each other make ``A_F`` lose one rank): None otherwise.

    On ``lambda = lambda_0 + t v`` every bound multiplier is a line ``c_i + d_i t``, and
    their minimum is concave and piecewise linear in t: its largest value lies where a
    rising line meets a falling one, or, with lines of one sign only, where the lowest
    reaches the cap of 1. Every such t is tried and the best kept.
    """
    if a_free.shape[1] == 0:
        return None
    left, singular, _ = np.linalg.svd(a_free)
    rank = int(np.sum(singular > singular[0] * 1e-12)) if len(singular) else 0
    if a_free.shape[0] - rank != 1:
        return None
    base = left[:, :rank] @ ((left[:, :rank].T @ a_free @ rhs) / singular[:rank] ** 2)
    if np.abs(a_free.T @ base - rhs).max() > RESIDUAL_TOLERANCE * max(1.0, np.abs(rhs).max()):
        return None  # inconsistent to round-off: the LP says what it makes of it
    direction = left[:, rank]
    c = constants + slopes @ base
    d = slopes @ direction
    # A line flat to round-off (the engine's column orthogonal to the free direction, as
    # for a failed engine's partner) is flat: read as rising or falling, its 1e-17 slope
    # sends t to 1e16 and every multiplier to round-off.
    d[np.abs(d) <= FLAT_SLOPE * np.linalg.norm(slopes, axis=1)] = 0.0
    rising, falling = d > 0, d < 0
    candidates = [np.zeros(1)]
    if rising.any() and falling.any():
        cross = (c[falling][None, :] - c[rising][:, None]) / (
            d[rising][:, None] - d[falling][None, :]
        )
        candidates.append(cross.ravel())
    else:
        # Lines of one sign: the least rises (or falls) until the flat lines or the cap
        # hold it; the nearest t that reaches that level keeps lambda as small as it can be.
        level = min(1.0, float(np.min(c[d == 0.0], initial=1.0)))
        if rising.any():
            candidates.append(np.array([np.max((level - c[rising]) / d[rising], initial=0.0)]))
        elif falling.any():
            candidates.append(np.array([np.min((level - c[falling]) / d[falling], initial=0.0)]))
    t = np.concatenate(candidates)
    least = np.minimum(1.0, (c[None, :] + t[:, None] * d[None, :]).min(axis=1, initial=np.inf))
    best = int(np.argmax(least))
    return base + t[best] * direction, float(least[best])
