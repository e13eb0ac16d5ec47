"""What a burn asks for, and the quantities it is flown by: its thrust axis, its thrust,
and the LVLH offset that holds the axis along its direction.

The direction is one of the orbit's LVLH frame (o1 along track, o2 against the orbit
normal, o3 to nadir; :mod:`~casadi_debris.guidance._targets`): prograde o1,
retrograde -o1, normal -o2, anti-normal o2.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from scipy.optimize import linprog
from scipy.spatial.transform import Rotation

from casadi_debris.allocation import Allocator, PropulsionState
from casadi_debris.config import (
    BURN_DIRECTIONS,
    SIGNED_AXES,
    BurnDirection,
    BurnRequest,
    Problem,
    axis_unit_vector,
)
from casadi_debris.environment import CircularOrbit
from casadi_debris.errors import CasadiDebrisError, SimulationError
from casadi_debris.guidance._targets import body_rates, frame_attitude, lvlh_matrices

if TYPE_CHECKING:
    from casadi_debris.geometry import Geometry
    from casadi_debris.guidance._reference import Reference
    from casadi_debris.slews import LimitCheck

# In LVLH components (o1 along track, o2 against the orbit normal, o3 to nadir).
_LVLH_DIRECTION = {
    "prograde": (1.0, 0.0, 0.0),
    "retrograde": (-1.0, 0.0, 0.0),
    "normal": (0.0, -1.0, 0.0),
    "antinormal": (0.0, 1.0, 0.0),
}


@dataclass(frozen=True, eq=False)
class BurnPlan:
    """A burn as flown: its request with the axis resolved to a unit vector and the firing
    time set (:func:`plan_burn`).

    Attributes
    ----------
    direction : {"prograde", "retrograde", "normal", "antinormal"}
        Where the thrust points, in the orbit's LVLH frame.
    body_axis : ndarray, shape (3,)
        Unit thrust axis in body axes.
    duration_s : float
        Engines on [s].
    thrust_fraction : float
        Of the largest torque-free thrust along ``body_axis`` (ignored when
        ``thrust_N`` is given).
    thrust_N : float or None
        The thrust itself [N].
    """

    direction: BurnDirection
    body_axis: np.ndarray
    duration_s: float
    thrust_fraction: float = 1.0
    thrust_N: float | None = None

    def __post_init__(self) -> None:
        if self.direction not in BURN_DIRECTIONS:
            raise SimulationError(
                f"direction: one of {', '.join(BURN_DIRECTIONS)}, got {self.direction!r}"
            )
        axis = np.asarray(self.body_axis, dtype=float)
        if axis.shape != (3,) or not np.all(np.isfinite(axis)) or not np.any(axis):
            raise SimulationError(f"body_axis: three finite numbers, not all zero, got {axis}")
        object.__setattr__(self, "body_axis", axis / np.linalg.norm(axis))
        if not (math.isfinite(self.duration_s) and self.duration_s > 0):
            raise SimulationError(f"duration_s: must be positive, got {self.duration_s}")
        if not 0.0 < self.thrust_fraction <= 1.0:
            raise SimulationError(f"thrust_fraction: in (0, 1], got {self.thrust_fraction}")
        if self.thrust_N is not None and not (math.isfinite(self.thrust_N) and self.thrust_N > 0):
            raise SimulationError(f"thrust_mN: must be positive, got {self.thrust_N}")

    @property
    def direction_lvlh(self) -> np.ndarray:
        """Unit direction in LVLH components, shape (3,)."""
        return np.array(_LVLH_DIRECTION[self.direction])


def plan_burn(problem: Problem, request: BurnRequest, duration_s: float | None = None) -> BurnPlan:
    """The plan of ``request``: its axis (default the swarm's strongest torque-free one) as
    a unit vector, and its firing time.

    Parameters
    ----------
    problem : Problem
    request : BurnRequest
    duration_s : float, optional
        Engines on [s], for a request that leaves it to its segment (``duration_s``
        None); default the request's.

    Raises
    ------
    SimulationError
        A field that cannot be flown, named (a zero axis, no firing time, ...).
    """
    firing_s = request.duration_s if duration_s is None else duration_s
    if firing_s is None:
        raise SimulationError("duration_s: a burn needs its firing time")
    if request.body_axis is None:
        axis = strongest_axis(problem)
    elif isinstance(request.body_axis, str):
        axis = axis_unit_vector(request.body_axis)
    else:
        axis = np.asarray(request.body_axis, dtype=float)  # the plan normalises it
    return BurnPlan(request.direction, axis, firing_s, request.thrust_fraction, request.thrust_N)


def strongest_axis(problem: Problem) -> np.ndarray:
    """The body direction of the swarm's largest torque-free thrust, shape (3,).

    The first of :func:`~casadi_debris.orbit.swarm_thrust`'s directions
    (ties broken by its order).
    """
    from casadi_debris.orbit import swarm_thrust

    return np.asarray(swarm_thrust(problem).segments[0].direction_body, dtype=float)


def torque_free_thrust_N(allocator: Allocator, axis: np.ndarray) -> float:
    """Largest thrust along ``axis`` with zero torque and no force across it [N] (an LP).

    ``max a.F f  s.t.  B f = 0, (1 - a a^T) F f = 0, 0 <= f <= f_max``.
    """
    a = np.asarray(axis, dtype=float)
    across = (np.eye(3) - np.outer(a, a)) @ allocator.force_map
    limits = allocator.max_thrust_N
    result = linprog(
        -(a @ allocator.force_map),
        A_eq=np.vstack([allocator.torque_map, across]),
        b_eq=np.zeros(6),
        bounds=list(zip(np.zeros_like(limits), limits, strict=True)),
        method="highs",
    )
    if result.status != 0 or result.x is None:
        raise SimulationError(f"torque-free thrust LP failed ({result.message})")
    return max(0.0, -float(result.fun or 0.0))


def burn_thrust_N(allocator: Allocator, plan: BurnPlan, *, strict: bool = True) -> float:
    """The thrust a plan gets from the allocator's engines [N]: its own, or its fraction of
    the largest torque-free thrust along its axis (:func:`torque_free_thrust_N`).

    Raises
    ------
    SimulationError
        The plan's thrust exceeds what the engines give (with ``strict``; otherwise
        that is what it gets), or none can thrust along the axis.
    """
    available = torque_free_thrust_N(allocator, plan.body_axis)
    wanted = plan.thrust_fraction * available if plan.thrust_N is None else plan.thrust_N
    if wanted > available * (1.0 + 1e-9):
        if strict:
            raise SimulationError(
                f"thrust_mN: {wanted * 1e3:.4g} mN asked, the engines give at most "
                f"{available * 1e3:.4g} mN along the axis without torque"
            )
        wanted = available
    if wanted <= 0.0:
        raise SimulationError("no engine left can thrust along the burn's axis")
    return wanted


def burn_offset(body_axis: np.ndarray, direction_lvlh: np.ndarray) -> np.ndarray:
    """q_OB (scalar first) of the least rotation taking ``body_axis`` onto ``direction_lvlh``."""
    rotation, _ = Rotation.align_vectors([direction_lvlh], [body_axis])
    xyzw = rotation.as_quat()
    return np.asarray(xyzw[[3, 0, 1, 2]])


def direction_inertial(problem: Problem, plan: BurnPlan, time_s: np.ndarray) -> np.ndarray:
    """The burn's direction in inertial axes at each time, shape (n, 3)."""
    orbit = CircularOrbit.from_problem(problem)
    return np.asarray(plan.direction_lvlh @ lvlh_matrices(orbit, time_s))


@dataclass(frozen=True, eq=False)
class BurnWindow:
    """The control periods ``start .. stop - 1`` in which the engines fire a burn."""

    start: int
    stop: int
    plan: BurnPlan


def burn_windows(reference: Reference, period_s: float) -> list[BurnWindow]:
    """The burns of a reference's pieces, in periods (those that fire at all)."""
    windows = []
    for piece in reference.pieces:
        if piece.burn is None or piece.firing_s is None:
            continue
        start, stop = (math.ceil(t / period_s - 1e-9) for t in piece.firing_s)
        stop = min(stop, len(reference.time_s) - 1)
        if stop > start:
            windows.append(BurnWindow(start, stop, piece.burn))
    return windows


def attitude_torque_Nm(
    inertia_kgm2: np.ndarray, time_s: np.ndarray, quaternion_BN: np.ndarray
) -> np.ndarray:
    """The control torque an attitude series needs, J alpha + omega x J omega, shape (n, 3)
    [N m]: omega by :func:`~casadi_debris.guidance._targets.body_rates`, alpha its
    derivative by second-order differences (a rigid body, no disturbance).

    Parameters
    ----------
    inertia_kgm2 : ndarray, shape (3, 3)
    time_s : ndarray, shape (n,)
        Increasing, at least three.
    quaternion_BN : ndarray, shape (n, 4)
    """
    rate = body_rates(time_s, quaternion_BN)
    acceleration = np.gradient(rate, time_s, axis=0, edge_order=2)
    inertia = np.asarray(inertia_kgm2, dtype=float)
    return acceleration @ inertia.T + np.cross(rate, rate @ inertia.T)


def attitude_limits(
    problem: Problem,
    time_s: np.ndarray,
    quaternion_BN: np.ndarray,
    force_N: np.ndarray | None = None,
) -> LimitCheck:
    """An attitude series (an LVLH track, a burn's) against the engines' torque set, as a
    slew profile is checked (:func:`~casadi_debris.slews._limits.check_limits`): the torque
    it needs (:func:`attitude_torque_Nm`, the full rigid inertia) within the torques the
    engines give at zero net force, or, where ``force_N`` is given, while they hold that
    net force (a burn's thrust, the set its loop saturates on).

    Parameters
    ----------
    problem : Problem
    time_s : ndarray, shape (n,)
    quaternion_BN : ndarray, shape (n, 4)
    force_N : ndarray, shape (n, 3), optional
        The engines' net force at each time, body axes [N] (zero where none).
    """
    from casadi_debris.dynamics import build_model
    from casadi_debris.slews import check_limits

    model = build_model(problem, modes=[])
    inertia = np.array(model.rigid_inertia(model.nominal_parameters))
    torque = attitude_torque_Nm(inertia, time_s, quaternion_BN)
    return check_limits(model.geometry, time_s, torque, zero_net_force=True, force_N=force_N)


def burn_limits(
    problem: Problem,
    plan: BurnPlan,
    thrust_N: float,
    sample_s: float,
    *,
    engine_limits: tuple[np.ndarray, np.ndarray] | None = None,
) -> LimitCheck:
    """A burn's attitude (the LVLH track holding its axis along its direction, from its
    start on the frame) against the torques the engines add while they give its thrust
    (:func:`attitude_limits`), over its firing, every ``sample_s`` seconds.

    Parameters
    ----------
    problem : Problem
    plan : BurnPlan
    thrust_N : float
        The burn's thrust along its axis [N].
    sample_s : float
        Sampling step of the check [s].
    engine_limits : (ndarray, ndarray), optional
        ``(time_s, max_thrust_N)``, shapes (m,) and (m, n_engines): the thrust limit of
        every engine from each time on (``time_s[0]`` = 0), what the engines have left
        (a partly used first stage, stages spent during the burn;
        :func:`engine_limits_along`). Default: every engine's full stage throughout.
        Where the engines left cannot give the thrust at all, the check fails there
        with a gauge of inf.
    """
    steps = max(2, math.ceil(plan.duration_s / sample_s - 1e-9))
    times = np.linspace(0.0, plan.duration_s, steps + 1)
    offset = burn_offset(plan.body_axis, plan.direction_lvlh)
    attitude = frame_attitude(CircularOrbit.from_problem(problem), offset, times)
    force = np.tile(thrust_N * plan.body_axis, (len(times), 1))
    if engine_limits is None:
        return attitude_limits(problem, times, attitude, force)
    from casadi_debris.dynamics import build_model
    from casadi_debris.slews import check_limits

    model = build_model(problem, modes=[])
    inertia = np.array(model.rigid_inertia(model.nominal_parameters))
    torque = attitude_torque_Nm(inertia, times, attitude)
    limit_times, limits = (np.asarray(a, dtype=float) for a in engine_limits)
    segment = np.searchsorted(limit_times, times, side="right") - 1
    checks: list[tuple[float, LimitCheck]] = []
    for index in np.unique(segment):
        rows = segment == index
        start = float(times[rows][0])
        geometry = _with_limits(model.geometry, limits[index])
        try:
            check = check_limits(
                geometry, times[rows], torque[rows], zero_net_force=True, force_N=force[rows]
            )
        except CasadiDebrisError:
            # The LP is infeasible: the engines left cannot give the burn's force at all.
            check = _cannot_thrust(geometry, start, thrust_N)
        checks.append((start, check))
    return _merged(checks)


def engine_limits_along(
    propulsion: PropulsionState, thrust_N: np.ndarray, period_s: float
) -> tuple[np.ndarray, np.ndarray]:
    """The engines' thrust limits over a run: the state it started with, fired with the
    run's own thrust, each engine's limit changing where a stage runs dry.

    Parameters
    ----------
    propulsion : PropulsionState
        The engines at the start (not changed: a copy is fired).
    thrust_N : ndarray, shape (k, n_engines)
        Thrust of every engine in each control period [N].
    period_s : float
        Control period [s].

    Returns
    -------
    time_s : ndarray, shape (m,)
        0 and each time a limit changed [s].
    max_thrust_N : ndarray, shape (m, n_engines)
        The limits from each of those times on [N].
    """
    state = propulsion.copy()
    times, limits = [0.0], [state.max_thrust_N()]
    thrust = np.asarray(thrust_N, dtype=float)
    done = 0
    while done < len(thrust):
        # Within each active stage's limit as the run flew it (round-off clipped).
        steps, _ = state.advance_series(
            np.clip(thrust[done:], 0.0, limits[-1]), period_s, stop_on_limit_change=True
        )
        done += steps
        now = state.max_thrust_N()
        if not np.array_equal(now, limits[-1]):
            times.append(done * period_s)
            limits.append(now)
        if steps == 0:
            break
    return np.array(times), np.array(limits)


def _with_limits(geometry: Geometry, max_thrust_N: np.ndarray) -> Geometry:
    """``geometry`` with each engine's thrust limit replaced [N]."""
    engines = tuple(
        dataclasses.replace(engine, max_thrust_N=float(limit))
        for engine, limit in zip(geometry.engines, max_thrust_N, strict=True)
    )
    return dataclasses.replace(geometry, engines=engines)


def _cannot_thrust(geometry: Geometry, start_s: float, thrust_N: float) -> LimitCheck:
    """A failed check: from ``start_s`` the engines left cannot give ``thrust_N``."""
    from casadi_debris.geometry import torque_authority
    from casadi_debris.slews import LimitCheck

    return LimitCheck(
        limits_ok=False,
        limits_zero_net_force=True,
        limits_authority_Nm=dict(torque_authority(geometry, zero_net_force=True)),
        worst_axis_ratio=dict.fromkeys(SIGNED_AXES, 0.0),
        worst_torque_set_ratio=math.inf,
        worst_ratio_time_s=start_s,
        limits_note=(
            f"from t = {start_s:.6g} s the engines left cannot give the burn's thrust "
            f"({thrust_N * 1e3:.4g} mN)"
        ),
    )


def _merged(checks: list[tuple[float, LimitCheck]]) -> LimitCheck:
    """One check of a burn from those of its stretches of constant engine limits (each with
    its start time): the worst gauge and when, the largest per-axis ratios, the least
    authority, every note."""
    from casadi_debris.slews import LimitCheck

    if len(checks) == 1:
        return checks[0][1]
    worst = max(checks, key=lambda item: item[1].worst_torque_set_ratio)[1]
    first = checks[0][1]
    notes = [
        (check.limits_note if start == 0.0 else f"from t = {start:.6g} s: {check.limits_note}")
        for start, check in checks
        if check.limits_note
    ]
    return LimitCheck(
        limits_ok=all(check.limits_ok for _, check in checks),
        limits_zero_net_force=True,
        limits_authority_Nm={
            axis: min(check.limits_authority_Nm[axis] for _, check in checks)
            for axis in first.limits_authority_Nm
        },
        worst_axis_ratio={
            axis: max(check.worst_axis_ratio[axis] for _, check in checks)
            for axis in first.worst_axis_ratio
        },
        worst_torque_set_ratio=worst.worst_torque_set_ratio,
        worst_ratio_time_s=worst.worst_ratio_time_s,
        limits_note="; ".join(notes),
    )
