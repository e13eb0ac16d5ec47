"""Reference linear programs on the engines themselves (scipy's HiGHS), shared by the
allocation tests.

Each LP is posed in a unit that makes the wrench of order one (mN and mNm for
demands of ordinary size, finer for tiny ones), because HiGHS' tolerances are
absolute; thrust is counted in that unit too (N m per N keeps the maps
unchanged). ``force_N`` is the net force demanded with the torque: zeros for the
allocator's zero net force, None to leave it free.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import linprog

from casadi_debris.geometry import Geometry

MN = 1e3
HIGHS_OPTIONS = {"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10}
ZERO_FORCE = np.zeros(3)


def net_force(free_force: bool) -> np.ndarray | None:
    """The ``force_N`` argument for an allocation with the force free or zero."""
    return None if free_force else ZERO_FORCE


def wrench_rows(geometry: Geometry, free_force: bool) -> np.ndarray:
    """Torque map, with the force map below it unless the force is free."""
    if free_force:
        return geometry.torque_map
    return np.vstack([geometry.torque_map, geometry.force_map])


def scaled_wrench(torque_Nm: np.ndarray, force_N: np.ndarray | None) -> tuple[np.ndarray, float]:
    """The wrench in a unit that makes it of order one, and that unit."""
    wrench = torque_Nm if force_N is None else np.concatenate([torque_Nm, force_N])
    size = float(np.abs(wrench).max())
    unit = min(1.0 / MN, size) if size > 0 else 1.0 / MN
    return wrench / unit, unit


# A thrust bound this many times the (order one) wrench cannot bind a least-fuel or
# largest-alpha answer; HiGHS fails on bounds of 1e17 (status "Unknown") and
# overflows to inf for a subnormal unit, so such bounds are left out.
UNBOUNDED = 1e9


def _thrust_bounds(limits_N: np.ndarray, unit: float) -> list[tuple[float, float | None]]:
    with np.errstate(over="ignore"):
        upper = limits_N / unit
    return [(0.0, None if bound > UNBOUNDED else float(bound)) for bound in upper]


def least_fuel_N(
    geometry: Geometry, limits_N: np.ndarray, torque_Nm: np.ndarray, force_N: np.ndarray | None
) -> float | None:
    """Least sum of thrust [N] meeting the wrench exactly, or None when infeasible."""
    target, unit = scaled_wrench(torque_Nm, force_N)
    result = linprog(
        np.ones(len(limits_N)),
        A_eq=wrench_rows(geometry, force_N is None),
        b_eq=target,
        bounds=_thrust_bounds(limits_N, unit),
        method="highs",
        options=HIGHS_OPTIONS,
    )
    return float(result.fun) * unit if result.status == 0 else None


def least_mass_flow_kg_s(
    geometry: Geometry,
    limits_N: np.ndarray,
    exhaust_velocity_m_s: np.ndarray,
    torque_Nm: np.ndarray,
    force_N: np.ndarray | None,
) -> float | None:
    """Least propellant mass flow ``sum f_i / c_i`` [kg/s] meeting the wrench exactly, or
    None when infeasible.

    The cost is posed as ``c_min / c_i`` (of order one: HiGHS' dual tolerance is absolute).
    """
    target, unit = scaled_wrench(torque_Nm, force_N)
    smallest = float(np.min(exhaust_velocity_m_s))
    result = linprog(
        smallest / np.asarray(exhaust_velocity_m_s, dtype=float),
        A_eq=wrench_rows(geometry, force_N is None),
        b_eq=target,
        bounds=_thrust_bounds(limits_N, unit),
        method="highs",
        options=HIGHS_OPTIONS,
    )
    return float(result.fun) * unit / smallest if result.status == 0 else None


def reaches(
    geometry: Geometry, limits_N: np.ndarray, torque_Nm: np.ndarray, force_N: np.ndarray | None
) -> bool:
    """Whether some 0 <= f <= f_max meets the wrench exactly."""
    return least_fuel_N(geometry, limits_N, torque_Nm, force_N) is not None


def largest_alpha(
    geometry: Geometry,
    limits_N: np.ndarray,
    torque_Nm: np.ndarray,
    force_N: np.ndarray | None,
    *,
    at_most: float | None = 1.0,
) -> float:
    """Largest alpha in [0, at_most] with alpha * wrench reachable.

    ``at_most=None`` leaves alpha uncapped, so that it measures the authority along
    the demand.
    """
    rows = wrench_rows(geometry, force_N is None)
    target, unit = scaled_wrench(torque_Nm, force_N)
    n = len(limits_N)
    result = linprog(
        np.append(np.zeros(n), -1.0),
        A_eq=np.hstack([rows, -target[:, None]]),
        b_eq=np.zeros(len(rows)),
        bounds=[*_thrust_bounds(limits_N, unit), (0.0, at_most)],
        method="highs",
        options=HIGHS_OPTIONS,
    )
    assert result.status == 0, result.message
    return float(result.x[-1])


def support(
    geometry: Geometry, limits_N: np.ndarray, direction: np.ndarray, free_force: bool
) -> tuple[float, np.ndarray]:
    """max direction . B f over the engines' box (and F f = 0 unless free): the value
    [N m] and the thrust [N] that reaches it (posed in mN)."""
    result = linprog(
        -(direction @ geometry.torque_map),
        A_eq=None if free_force else geometry.force_map,
        b_eq=None if free_force else ZERO_FORCE,
        bounds=_thrust_bounds(limits_N, 1.0 / MN),
        method="highs",
        options=HIGHS_OPTIONS,
    )
    assert result.status == 0, result.message
    return -float(result.fun) / MN, result.x / MN
