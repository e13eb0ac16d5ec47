"""Demands the engines cannot meet: largest alpha, least fuel on the edge, HiGHS rescue,
least squares.

All in the scaled units of :class:`~casadi_debris.allocation._scaled_qp.ScaledQp`.
Saturation is solved lexicographically, in two QPs: ``max alpha`` over
``(u, alpha)`` (no fuel term), then the least-fuel QP at ``alpha * target``.
The second target sits on the edge of what is reachable, where round-off makes
DAQP call it infeasible for about 14 % of saturated demands; it is then pulled
in by each of ``BOUNDARY_BACKOFF`` in turn, and if that fails too HiGHS'
simplex solves both LPs (:func:`rescue`).
"""

from __future__ import annotations

import time
from typing import Any, NamedTuple

import numpy as np

from casadi_debris.allocation._backends import QpSolution
from casadi_debris.allocation._scaled_qp import ScaledQp
from casadi_debris.errors import AllocationError

# Relative pull-ins of a saturated target, tried in turn when the least-fuel
# solve calls the exact edge infeasible by round-off (measured over 3000
# random demands with up to 9 failed CubeSats: 86 % pass at 0, 10 % need a
# pull-in, 4 % go on to HiGHS). All are well inside the 1e-9 to which alpha
# is promised.
BOUNDARY_BACKOFF = (0.0, 1e-12, 1e-10)
# HiGHS' primal and dual feasibility tolerances in the rescue (tried first; then its defaults).
RESCUE_TOLERANCE = 1e-10
# A saturated target met only to below this (scaled: alpha times the target's
# largest component) is the solvers' feasibility tolerance (1e-10), not torque:
# alpha is 0 and the thrust zero. Exactly, the reachable set is a polytope
# around 0, so along any direction alpha is 0 or of the order of an engine's
# torque over the target; an alpha of 1e-25 with thrust of 1e-13 of a limit
# (seen with CubeSats failed, the demand outside what they reach) is noise.
ALPHA_RESOLUTION = 1e-10


class StageSolution(NamedTuple):
    """Scaled thrust from the saturation stages.

    Attributes
    ----------
    u : ndarray, shape (n,) or None
        Scaled thrust; None when the stage found nothing (least squares only).
    alpha : float
        Factor of the target actually met (least squares: the projection of
        the achieved torque on the demand, times any pull-in).
    iterations : int
        Summed over the QP solves.
    solve_time_s : float
        Back-end time [s].
    rescued : bool
        HiGHS gave the answer.
    verified : bool
        ``u``'s residual against ``alpha * target`` was measured within 1e-13
        (:meth:`~casadi_debris.allocation._scaled_qp.ScaledQp.polish_checked`).
    """

    u: np.ndarray | None
    alpha: float
    iterations: int
    solve_time_s: float
    rescued: bool
    verified: bool = False

    def after(self, first: QpSolution, scale: float, *, verified: bool) -> StageSolution:
        """This least-fuel stage as the end of a two-stage solve begun by ``first``: alpha
        times ``scale`` (what ``first`` found), the two stages' iterations and times summed."""
        return StageSolution(
            self.u,
            scale * self.alpha,
            first.iterations + self.iterations,
            first.solve_time_s + self.solve_time_s,
            self.rescued,
            verified,
        )


def largest_alpha(qp: ScaledQp, target: np.ndarray, free_force: bool) -> StageSolution:
    """The largest alpha in [0, 1] with ``alpha * target`` reachable, then its least-fuel thrust.

    Parameters
    ----------
    qp : ScaledQp
    target : ndarray, shape (3,) or (6,)
        Scaled target (torque, and force unless it is free), of the size of
        what the engines can reach (the max-alpha QP's proximal term leaves
        alpha exact only there).
    free_force : bool

    Returns
    -------
    StageSolution
    """
    scale_workspace = qp.workspace("scale", free_force)
    # [rows, -target]: the workspace's own copy of its rows, last column replaced.
    a_eq = qp.scale_rows[free_force]
    a_eq[:, -1] = -target
    scale_workspace.update(a_eq=a_eq)
    solution = scale_workspace.solve()
    if solution.status != "optimal":
        # The feasible set always holds u = 0, alpha = 0: a report of
        # infeasibility is round-off at a degenerate vertex (seen when
        # alpha = 0 is the only answer).
        u, alpha, t = rescue(qp, target, free_force)
        return StageSolution(u, alpha, solution.iterations, solution.solve_time_s + t, rescued=True)
    alpha = min(max(float(solution.optimal_x()[-1]), 0.0), 1.0)
    if alpha * max(map(abs, target.tolist())) <= ALPHA_RESOLUTION:
        return StageSolution(np.zeros(qp.n), 0.0, solution.iterations, solution.solve_time_s, False)
    fuel = least_fuel_on_edge(qp, alpha * target, free_force)
    return fuel.after(solution, alpha, verified=fuel.verified)


def least_fuel_on_edge(qp: ScaledQp, target: np.ndarray, free_force: bool) -> StageSolution:
    """Least-fuel thrust for a target on the edge of what is reachable.

    On the edge a solver may call the target infeasible by round-off; it
    is then pulled in by each of ``BOUNDARY_BACKOFF`` (relative) in turn;
    if every try fails, the LP is solved by HiGHS (:func:`rescue`).

    Returns
    -------
    StageSolution
        ``alpha`` is the factor applied to the target: 1 - backoff, or the
        rescue's alpha.
    """
    workspace = qp.workspace("exact", free_force)
    iterations, solve_time = 0, 0.0
    for backoff in BOUNDARY_BACKOFF:
        workspace.update(b_eq=(1.0 - backoff) * target)
        solution = workspace.solve()
        iterations += solution.iterations
        solve_time += solution.solve_time_s
        if solution.status == "optimal":
            u, verified = qp.polish_checked(
                solution.optimal_x(), (1.0 - backoff) * target, free_force
            )
            return StageSolution(u, 1.0 - backoff, iterations, solve_time, False, verified)
    u, alpha, rescue_time = rescue(qp, target, free_force)
    return StageSolution(u, alpha, iterations, solve_time + rescue_time, True)


def rescue(qp: ScaledQp, target: np.ndarray, free_force: bool) -> tuple[np.ndarray, float, float]:
    """Largest alpha, then least fuel, for ``alpha * target`` by HiGHS' simplex (rare path).

    Returns
    -------
    u : ndarray, shape (n,)
    alpha : float
    solve_time_s : float

    Raises
    ------
    AllocationError
        HiGHS found no solution either.
    """
    start = time.perf_counter()
    n = qp.n
    rows = qp.rows(free_force)
    a_eq = np.hstack([rows, -target[:, None]])
    bounds = [*zip(np.zeros(n), qp.upper, strict=True), (0.0, 1.0)]
    largest_alpha_cost = np.append(np.zeros(n), -1.0)
    best = _highs(largest_alpha_cost, a_eq, bounds, tight=True)
    if best.status != 0:
        best = _highs(largest_alpha_cost, a_eq, bounds, tight=False)
    if best.status != 0 or best.x is None:
        raise AllocationError(
            f"{qp.solver} and the HiGHS rescue found no allocation for "
            f"{(target * qp.torque_ref_Nm)[:3].tolist()} N m ({best.message})"
        )
    alpha = float(best.x[-1])
    bounds[-1] = (alpha * (1.0 - BOUNDARY_BACKOFF[-1]), 1.0)
    frugal = _highs(np.append(qp.cost, 0.0), a_eq, bounds, tight=True)
    x = frugal.x if frugal.status == 0 and frugal.x is not None else best.x
    alpha = float(np.clip(x[-1], 0.0, 1.0))
    if alpha * float(np.abs(target).max()) <= ALPHA_RESOLUTION:
        return np.zeros(n), 0.0, time.perf_counter() - start
    return x[:n], alpha, time.perf_counter() - start


def _highs(
    cost: np.ndarray, a_eq: np.ndarray, bounds: list[tuple[float, float]], *, tight: bool
) -> Any:
    """HiGHS on ``min cost x, a_eq x = 0`` within ``bounds``: the rescue's tight tolerances,
    or HiGHS' defaults."""
    from scipy.optimize import linprog  # imported when a rescue is needed, not at start-up

    zeros = np.zeros(a_eq.shape[0])
    if not tight:
        return linprog(cost, A_eq=a_eq, b_eq=zeros, bounds=bounds, method="highs", options={})
    return linprog(
        cost,
        A_eq=a_eq,
        b_eq=zeros,
        bounds=bounds,
        method="highs",
        options={
            "primal_feasibility_tolerance": RESCUE_TOLERANCE,
            "dual_feasibility_tolerance": RESCUE_TOLERANCE,
        },
    )


def least_squares(qp: ScaledQp, target: np.ndarray, free_force: bool) -> StageSolution:
    """The reachable torque closest to the target's (force kept), then its least-fuel thrust.

    Returns
    -------
    StageSolution
        ``u`` is None when the force alone cannot be met; ``alpha`` is the
        projection ``tau_a . tau / |tau|^2`` of the achieved torque on the
        demand, times any pull-in of the least-fuel solve.
    """
    workspace = qp.workspace("least_squares", free_force)
    c = -qp.torque.T @ target[:3]
    workspace.update(c=c, b_eq=target[3:])
    solution = workspace.solve()
    if solution.status != "optimal":
        return StageSolution(None, 0.0, solution.iterations, solution.solve_time_s, False)
    achieved = qp.torque @ solution.optimal_x()
    scaled_demand = target[:3]
    norm2 = float(scaled_demand @ scaled_demand)
    scale = float(achieved @ scaled_demand / norm2) if norm2 > 0 else 1.0
    settle = np.concatenate([achieved, target[3:]])
    fuel = least_fuel_on_edge(qp, settle, free_force)
    return fuel.after(solution, scale, verified=False)
