"""How one checked demand is solved: the exact path, tiny demands, saturation, and the
final check with its HiGHS fallback.

:class:`SolvePaths` is the half of :class:`~casadi_debris.allocation.Allocator`
that turns one demand into thrust (the other half sets up the problem, keeps
the limits and checks the input). Paths, in scaled units
(:mod:`~casadi_debris.allocation._scaled_qp`):

1. a demand of ordinary size: one least-fuel QP, polished;
2. a tiny demand (below a tenth of an engine's torque): the same, scaled up
   by a power of two and scaled back (:mod:`~casadi_debris.allocation._demand`);
3. a demand the engines cannot meet: least squares or the largest alpha
   (:mod:`~casadi_debris.allocation._saturation`).

Every answer passes one final check before it is returned (:meth:`SolvePaths._result`):
finite, and the torque (and force) within the promised tolerance of what the
mode claims. The accuracy is measured on ``B f`` in SI, or, on the common
path, read off the residual that polish has just measured on the same thrust
in scaled units (1e-13 of the target, four orders inside the promise). One
that fails is recomputed by HiGHS (:meth:`SolvePaths._fallback`); if that
fails as well, :class:`AllocationInternalError` is raised: no NaN, inf or
unlabelled wrong answer leaves the allocator.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np

from casadi_debris.allocation._demand import (
    FALLBACK_SIZE,
    SMALL_DEMAND,
    SMALL_DEMAND_LEVELS,
    stretch_exponent,
    within_tolerance,
)
from casadi_debris.allocation._results import Allocation
from casadi_debris.allocation._saturation import (
    BOUNDARY_BACKOFF,
    StageSolution,
    largest_alpha,
    least_squares,
    rescue,
)
from casadi_debris.allocation._scaled_qp import THRUST_ROUND_OFF, ScaledQp
from casadi_debris.errors import AllocationInternalError

SaturationMode = Literal["scale", "least_squares"]


class SolvePaths:
    """Solving one demand; mixed into :class:`~casadi_debris.allocation.Allocator`,
    which sets the attributes below."""

    torque_map: np.ndarray
    force_map: np.ndarray
    _uniform_exhaust: float | None  # the engines' one exhaust velocity [m/s], if one
    _mass_flow_per_N: np.ndarray  # (n,) 1 / c_i [kg/s per N]
    saturation: SaturationMode
    solver: str
    _qp: ScaledQp
    _thrust_ref_N: float
    _torque_ref: np.ndarray  # (3,) row references of the torque [N m]
    _wrench_ref: np.ndarray  # (6,) and of the force [N]
    _lever_m: float  # largest |B_ji|
    _force_per_N: float  # largest |F_ji|
    _floor_Nm: float  # subnormal resolution of B f
    _floor_N: float  # and of F f

    def _allocate(self, torque: np.ndarray, force: np.ndarray | None) -> Allocation:
        """Allocation of a checked demand; a result that fails the final check (None) is
        recomputed by HiGHS."""
        result = self._solve(torque, force)
        return result if result is not None else self._fallback(torque, force)

    def _solve(self, torque: np.ndarray, force: np.ndarray | None) -> Allocation | None:
        # The feasible case is the common one and is kept lean (about twice the
        # back-end's own time): no array is built twice, maxima of a few
        # numbers are taken in Python (numpy's reductions cost 1.5 us each at
        # this size), the result is clipped once.
        free_force = force is None
        if force is None:
            target = torque / self._torque_ref
        else:
            target = np.concatenate((torque, force)) / self._wrench_ref
        size = max(map(abs, target.tolist()))
        if size < SMALL_DEMAND:
            return self._solve_small(torque, force)
        qp = self._qp
        exact = qp.workspace("exact", free_force)
        exact.update(b_eq=target)
        solution = exact.solve()
        if solution.status == "optimal":
            u, verified = qp.polish_checked(solution.optimal_x(), target, free_force)
            # polish has clipped u already.
            return self._exact(
                u, torque, force, solution.iterations, solution.solve_time_s, verified=verified
            )
        return self._unreachable(
            target, size, 0, torque, force, solution.iterations, solution.solve_time_s
        )

    def _solve_small(self, torque: np.ndarray, force: np.ndarray | None) -> Allocation | None:
        """A demand far below one engine's torque or thrust: solved scaled up by ``2**k``.

        The solvers' tolerances are absolute, so at 1e-12 of an engine's torque
        they would call anything feasible. The demand is scaled (exactly, by a
        power of two) to each of ``SMALL_DEMAND_LEVELS`` in turn until no limit
        binds there, so that the least-fuel thrust scales back; at the last
        level the thrust is scaled back anyway (exact torque, least fuel only
        up to the limits that bind at 1e-6 of an engine's torque).
        """
        free_force = force is None
        wrench = torque if force is None else np.concatenate((torque, force))
        if not wrench.any():
            # Exactly zero: exactly zero thrust (no solve, no round-off).
            return self._exact(np.zeros(self._qp.n), torque, force, 0, 0.0)
        reference = self._torque_ref if free_force else self._wrench_ref
        qp = self._qp
        exact = qp.workspace("exact", free_force)
        iterations, solve_time = 0, 0.0
        k, target = 0, wrench / reference
        for level in SMALL_DEMAND_LEVELS:
            # Never scaled down: a demand above this level is solved at its own size.
            k = max(stretch_exponent(wrench, reference, level), 0)
            target = np.ldexp(wrench, k) / reference
            exact.update(b_eq=target)
            solution = exact.solve()
            iterations += solution.iterations
            solve_time += solution.solve_time_s
            if solution.status == "optimal":
                u = qp.polish(solution.optimal_x(), target, free_force)
                if k == 0 or level == SMALL_DEMAND_LEVELS[-1] or not self._qp.binds(u):
                    return self._exact(u, torque, force, iterations, solve_time, exponent=k)
            elif k == 0:
                break
        # Not reachable at the smallest size tried: saturate from there.
        size = float(np.abs(target).max())
        return self._unreachable(target, size, k, torque, force, iterations, solve_time)

    def _unreachable(
        self,
        target: np.ndarray,
        size: float,
        exponent: int,
        torque: np.ndarray,
        force: np.ndarray | None,
        iterations: int,
        solve_time_s: float,
    ) -> Allocation | None:
        """A demand the exact stage could not meet: least squares when asked, else the
        largest alpha (:mod:`~casadi_debris.allocation._saturation`).

        ``target`` is the scaled demand times ``2**exponent``, ``size`` its
        largest component.
        """
        free_force = force is None
        if self.saturation == "least_squares":
            fit = least_squares(self._qp, target, free_force)
            iterations += fit.iterations
            solve_time_s += fit.solve_time_s
            # A limit binding at a scaled-up size would not scale back: scale the
            # wrench instead (a direction the engines barely reach, tiny demand).
            if fit.u is not None and (exponent == 0 or not self._qp.binds(fit.u)):
                return self._result(
                    fit.u,
                    torque,
                    force,
                    fit.alpha,
                    "least_squares",
                    iterations,
                    solve_time_s,
                    fit.rescued,
                    exponent=exponent,
                )
            # The requested force alone cannot be met: fall back to scaling the wrench.
        reach = self._qp.reach[free_force]
        shrink = 1.0
        if size > reach:
            # The max-alpha QP's proximal term leaves alpha exact only for a
            # target of the size of what the engines can reach (measured: with
            # the force free, demands 1000x beyond reach lost up to 2e-4 of
            # alpha): a larger one is shrunk to the largest reachable component
            # first, which keeps every answer within alpha <= 1.
            shrink = reach / size
        edge: StageSolution = largest_alpha(self._qp, shrink * target, free_force)
        if edge.u is None:
            raise AllocationInternalError("the largest-alpha stage returned no thrust")
        return self._saturated(
            edge.u,
            edge.alpha * shrink,
            exponent,
            torque,
            force,
            iterations + edge.iterations,
            solve_time_s + edge.solve_time_s,
            edge.rescued,
            verified=edge.verified,
        )

    def _saturated(
        self,
        u: np.ndarray,
        alpha: float,
        exponent: int,
        torque: np.ndarray,
        force: np.ndarray | None,
        iterations: int,
        solve_time_s: float,
        rescued: bool,
        *,
        verified: bool = False,
    ) -> Allocation | None:
        """Result of the saturation path: thrust ``u`` makes ``alpha`` times the target,
        which is the demand times ``2**exponent``.

        A demand scaled up may turn out reachable after all (``alpha 2**exponent
        >= 1``): the thrust is then scaled back to meet it exactly. ``verified``:
        ``u``'s residual was measured (see :meth:`_result`), used as it is only.
        """
        if alpha <= 0.0:
            u = np.zeros(self._qp.n)  # whatever the solver left is round-off
        elif exponent == 0 and alpha >= 1.0:
            return self._exact(
                u / alpha, torque, force, iterations, solve_time_s, rescued, clip=True
            )
        elif exponent > 0:
            # alpha 2**exponent may overflow: compare exponents, and divide by the
            # mantissa of alpha only (u / alpha could overflow for a subnormal alpha).
            mantissa, power = math.frexp(alpha)
            if power + exponent > 0:  # alpha 2**exponent >= 1
                return self._exact(
                    u / mantissa,
                    torque,
                    force,
                    iterations,
                    solve_time_s,
                    rescued,
                    clip=True,
                    exponent=power + exponent,
                )
            # alpha 2**exponent < 1 and u already makes that fraction of the demand.
            alpha, verified = math.ldexp(alpha, exponent), False
        return self._result(
            u,
            torque,
            force,
            alpha,
            "scaled",
            iterations,
            solve_time_s,
            rescued,
            verified=verified,
        )

    def _fallback(self, torque: np.ndarray, force: np.ndarray | None) -> Allocation:
        """Both LPs by HiGHS, polished, for a demand whose first answer failed the final
        check (non-finite thrust, or a torque off the one it claims).

        Raises
        ------
        AllocationInternalError
            HiGHS' answer fails the check too.
        """
        free_force = force is None
        wrench = torque if force is None else np.concatenate((torque, force))
        reference = self._torque_ref if free_force else self._wrench_ref
        qp = self._qp
        size = float(np.abs(wrench / reference).max())
        exponent, shrink = 0, 1.0
        if size < FALLBACK_SIZE:
            exponent = stretch_exponent(wrench, reference, FALLBACK_SIZE)
        elif size > qp.reach[free_force]:
            shrink = qp.reach[free_force] / size
        target = np.ldexp(wrench, exponent) / reference * shrink
        u, alpha, solve_time_s = rescue(qp, target, free_force)
        if alpha >= 1.0 - 2.0 * BOUNDARY_BACKOFF[-1]:
            # The rescue pulls a reachable target in by its edge back-off (1e-10):
            # put it back, so that a reachable demand comes out exact.
            u, alpha = np.minimum(u / alpha, qp.upper), 1.0
        u = qp.polish(u, alpha * target, free_force)
        result = self._saturated(
            u, alpha * shrink, exponent, torque, force, 0, solve_time_s, rescued=True
        )
        if result is None:
            raise AllocationInternalError(
                f"torque_Nm = {torque.tolist()} N m, force_N = "
                f"{None if force is None else force.tolist()} N: neither {self.solver} nor "
                "HiGHS gave a finite allocation within the promised accuracy"
            )
        return result

    def _exact(
        self,
        u: np.ndarray,
        torque: np.ndarray,
        force: np.ndarray | None,
        iterations: int,
        solve_time_s: float,
        rescued: bool = False,
        *,
        clip: bool = False,
        exponent: int = 0,
        verified: bool = False,
    ) -> Allocation | None:
        """:meth:`_result` of a demand met in full (scale 1, mode ``"exact"``); ``u`` is
        taken as within its bounds unless ``clip``."""
        return self._result(
            u,
            torque,
            force,
            1.0,
            "exact",
            iterations,
            solve_time_s,
            rescued,
            clip=clip,
            exponent=exponent,
            verified=verified,
        )

    def _result(
        self,
        u: np.ndarray,
        torque: np.ndarray,
        force: np.ndarray | None,
        scale: float,
        mode: str,
        iterations: int,
        solve_time_s: float,
        rescued: bool = False,
        *,
        clip: bool = True,
        exponent: int = 0,
        verified: bool = False,
    ) -> Allocation | None:
        """Result of scaled thrust ``u`` times ``2**-exponent``, or None when it fails the
        final check: a NaN or inf, or a torque (force) off what the mode claims by more
        than the promised tolerance (:func:`~casadi_debris.allocation._demand.within_tolerance`).
        The demand is met in full (feasible) exactly when ``mode`` is ``"exact"``.

        ``clip=False`` when u is already within its bounds. ``verified`` when
        :meth:`ScaledQp.polish_checked` has just measured ``u``'s own residual
        within 1e-13 of the target: the tolerance then holds with four orders to
        spare (the conversion to N adds round-off of 1e-15 of ``l sum(f)``), and
        only finiteness is checked again, which saves 1.5 us on the common path.
        """
        if clip:
            # Solver round-off may leave u a hair outside its bounds: limits are never exceeded.
            u = np.minimum(u, self._qp.upper)
            u[u < THRUST_ROUND_OFF] = 0.0
        thrust = u * self._thrust_ref_N
        if exponent:
            thrust = np.ldexp(thrust, -exponent)
        total_N = float(np.add.reduce(thrust))  # thrust.sum(), faster
        torque_Nm = self.torque_map @ thrust
        force_N = self.force_map @ thrust
        # The sum is NaN or inf whenever any thrust is (they are never negative).
        if not math.isfinite(total_N):
            return None
        if not (verified and not exponent) and not self._meets(
            torque_Nm, force_N, torque, force, scale, mode, total_N
        ):
            return None
        return Allocation(
            thrust,
            torque_Nm,
            force_N,
            torque,
            force,
            mode == "exact",
            scale + 0.0,  # no -0.0 from a clipped alpha
            mode,
            total_N / self._uniform_exhaust
            if self._uniform_exhaust is not None
            else float(thrust @ self._mass_flow_per_N),
            f"{self.solver}+highs" if rescued else self.solver,
            iterations,
            solve_time_s,
        )

    def _meets(
        self,
        torque_Nm: np.ndarray,
        force_N: np.ndarray,
        torque: np.ndarray,
        force: np.ndarray | None,
        scale: float,
        mode: str,
        total_N: float,
    ) -> bool:
        """Whether the achieved torque and force are within the promised tolerance of what
        ``mode`` claims (``scale`` times the demand; least squares claims the force only)."""
        if mode != "least_squares" and not within_tolerance(
            torque_Nm.tolist(), torque.tolist(), scale, self._lever_m * total_N, self._floor_Nm
        ):
            return False
        return force is None or within_tolerance(
            force_N.tolist(),
            force.tolist(),
            1.0 if mode == "least_squares" else scale,  # least squares keeps the force
            self._force_per_N * total_N,
            self._floor_N,
        )
