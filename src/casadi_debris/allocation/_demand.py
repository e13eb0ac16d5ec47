"""Demands handed to the allocator: what is accepted, how a tiny one is scaled, and how
close an answer must be to count as met.

Accepted
--------
A torque ``tau`` [N m] (and a net force ``phi`` [N]) of shape (3,), finite,
and with every component at most ``ABSURD_FACTOR`` times the largest value
that component takes over all thrusts within the current limits,
``max_j sum_i |B_ji| f_max_i`` (``|F|`` for the force). No thrust can make more
than that along any axis, so a demand beyond it is at least a million times
beyond the authority in its own direction: a unit mistake, not a control
demand. Anything else raises :class:`DemandError`, which names the argument.

Tiny demands
------------
The solvers' tolerances are absolute (about 1e-10 of an engine's full
thrust), so a demand below a tenth of one engine's torque (or thrust,
``SMALL_DEMAND``) is solved multiplied by a power of two ``2**k`` and its
thrust multiplied back by ``2**-k``. Powers of two only change exponents: the
direction of the demand is kept bit for bit (also for subnormal numbers, which
multiplying by ``2**k`` makes normal), and the least-fuel thrust of ``2**k tau``
is ``2**k`` times that of ``tau`` while no limit binds there (positive
homogeneity). With few engines left a limit can bind at the scaled-up size:
smaller sizes are tried in turn (``SMALL_DEMAND_LEVELS``). A demand of exactly
zero gets exactly zero thrust.

Met demand
----------
An answer counts as meeting ``alpha tau`` (``alpha = 1`` for an exact one) when

    |B f - alpha tau|_inf <= TORQUE_RTOL * max(alpha |tau|_inf, l sum(f)) + eps_tau,

``l = max |B_ji|`` the largest lever arm, so ``l sum(f)`` bounds the torque any
engine sum makes (round-off of ``B f`` scales with it when engine torques
cancel, as for a pure force demand), and ``eps_tau = n (l + 2) 2**-1074`` N m
is the resolution of floating point at the bottom of the subnormal range: the
thrusts and the products and sums of ``B f`` each round to a multiple of
``2**-1074``. Above about 1e-300 N m ``eps_tau`` is below 1e-9 of the demand.
The same holds for the net force with ``|F|``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from casadi_debris.errors import AllocationError, DemandError

# A demand component beyond this many times the largest component any thrust
# within the limits can make is refused.
ABSURD_FACTOR = 1e6
# Relative accuracy promised for a met demand (see the module docstring).
TORQUE_RTOL = 1e-9
# Smallest positive subnormal double, 2**-1074.
SMALLEST_SUBNORMAL = math.ulp(0.0)
# Demands smaller than this (scaled: fraction of one engine's full torque or
# thrust) are solved stretched to this size and scaled back. The solvers'
# tolerances are absolute (DAQP 1e-10 on the equalities): a component below
# 1e-10 of the target can be ignored, so the target must be at least a tenth of
# an engine's torque for the 1e-9 promise (measured: at 1e-2 a component of
# 6e-9 of the demand was dropped, with a few CubeSats failed).
SMALL_DEMAND = 0.1
# Sizes a small demand is stretched to in turn until no limit binds there (with
# few engines left a limit can bind at a tenth of an engine's torque). Below the
# first, polish still removes the residual when the active set is right; when
# it is not, the final check sends the demand to HiGHS at FALLBACK_SIZE.
SMALL_DEMAND_LEVELS = (SMALL_DEMAND, 1e-2, 1e-4, 1e-6)
# Size a demand is stretched to (when smaller) for the HiGHS fallback, whose
# tolerances are absolute as well (1e-10).
FALLBACK_SIZE = 0.5


def _refuse(
    name: str, values: list[float], bound: float, unit: str, row: int | None = None
) -> DemandError:
    """The DemandError for three values that failed ``|value| <= bound``."""
    if not all(map(math.isfinite, values)):
        return DemandError(name, "must be finite", values=values, unit=unit, row=row)
    largest = f"{bound / ABSURD_FACTOR:.6g}{' ' + unit if unit else ''}"
    return DemandError(
        name,
        f"more than {ABSURD_FACTOR:g} times the largest component any thrust within the "
        f"limits can make ({largest}); check the units",
        values=values,
        unit=unit,
        row=row,
        bound=bound,
    )


def as_vector3(value: Any, name: str, bound: float = math.inf, unit: str = "") -> np.ndarray:
    """``value`` as a float array of shape (3,), finite, every component within ``bound``.

    Parameters
    ----------
    value : array_like
    name : str
        Argument name for the message.
    bound : float
        Largest accepted component (``ABSURD_FACTOR`` times the reach) [N m or N].
    unit : str
        Unit of ``value`` for the message.

    Raises
    ------
    DemandError
        Another shape, a non-finite or an absurdly large entry; the message names ``name``.
    """
    array = np.asarray(value, dtype=float)
    if array.shape != (3,):
        raise DemandError(name, f"must have shape (3,), got {array.shape}")
    x, y, z = array.tolist()
    # One chained comparison per component, False for NaN and inf as well: a
    # tenth of np.isfinite's cost on three numbers.
    if not (abs(x) <= bound and abs(y) <= bound and abs(z) <= bound):
        raise _refuse(name, [x, y, z], bound, unit)
    return array


def as_rows3(value: Any, name: str) -> np.ndarray:
    """``value`` as a float array of shape (k, 3).

    Raises
    ------
    DemandError
        Another shape; the message names ``name``.
    """
    rows = np.asarray(value, dtype=float)
    if rows.ndim != 2 or rows.shape[1] != 3:
        raise DemandError(name, f"must have shape (k, 3), got {rows.shape}")
    return rows


def check_rows(rows: np.ndarray, name: str, bound: float, unit: str) -> None:
    """Every row finite and within ``bound`` (see :func:`as_vector3`).

    Raises
    ------
    DemandError
        Naming the first offending row.
    """
    ok = np.abs(rows) <= bound  # False for NaN and inf too
    if ok.all():
        return
    row = int(np.flatnonzero(~ok.all(axis=1))[0])
    raise _refuse(name, rows[row].tolist(), bound, unit, row)


def batch_forces(
    torques: np.ndarray, forces_N: Any, free_force: bool, bound: float
) -> np.ndarray | None:
    """The force rows of a batch: as given, zero by default, None when free.

    Raises
    ------
    AllocationError
        ``forces_N`` together with ``free_force``.
    DemandError
        ``forces_N`` not of the shape of ``torques``, not finite or absurd.
    """
    if forces_N is None:
        return None if free_force else np.zeros_like(torques)
    if free_force:
        raise AllocationError("give either forces_N or free_force, not both")
    forces = np.asarray(forces_N, dtype=float)
    if forces.shape != torques.shape:
        raise DemandError(
            "forces_N", f"must have the shape {torques.shape} of torques_Nm, got {forces.shape}"
        )
    check_rows(forces, "forces_N", bound, "N")
    return forces


def stretch_exponent(wrench: np.ndarray, reference: np.ndarray, size: float) -> int:
    """``k`` such that the largest component of ``2**k wrench / reference`` is in (size, 2 size].

    Parameters
    ----------
    wrench : ndarray, shape (m,)
        Demand in SI, not all zero (subnormal entries allowed).
    reference : ndarray, shape (m,)
        Per-component scale (the allocator's row references).
    size : float
        Wanted size of the largest scaled component.

    Returns
    -------
    int
        Positive for a demand smaller than ``size``.
    """
    # Normalise by the exponent of the largest entry first (exact), so that the
    # division by the references never rounds a subnormal and size / normalised
    # cannot overflow. Powers of two commute with the division, so the largest
    # scaled component is 2**(extra - exponent) normalised, in (size, 2 size]
    # up to one rounding. Scalar Python: a few entries, cheaper than numpy.
    values = wrench.tolist()
    _, exponent = math.frexp(max(map(abs, values)))
    normalised = max(
        abs(math.ldexp(value, -exponent)) / scale
        for value, scale in zip(values, reference.tolist(), strict=True)
    )
    _, extra = math.frexp(size / normalised)
    return extra - exponent


def within_tolerance(
    achieved: list[float],
    demand: list[float],
    alpha: float,
    engine_scale: float,
    floor: float,
) -> bool:
    """Whether ``achieved`` meets ``alpha * demand`` (see the module docstring).

    Parameters
    ----------
    achieved, demand : list of float
        Three components each [N m or N].
    alpha : float
        Fraction of the demand claimed (1 for an exact answer).
    engine_scale : float
        ``l sum(f)``: bound on what any engine sum makes [N m or N].
    floor : float
        Floating-point resolution of ``achieved`` [N m or N].

    Returns
    -------
    bool
        False for a NaN anywhere.
    """
    # Scalar Python on three numbers: a tenth of the cost of numpy's reductions;
    # this runs on every answer.
    a0, a1, a2 = achieved
    d0, d1, d2 = demand
    if alpha != 1.0:
        d0, d1, d2 = alpha * d0, alpha * d1, alpha * d2
    tolerance = TORQUE_RTOL * max(abs(d0), abs(d1), abs(d2), engine_scale) + floor
    # Comparisons written "<=" so that a NaN counts as a miss.
    return abs(a0 - d0) <= tolerance and abs(a1 - d1) <= tolerance and abs(a2 - d2) <= tolerance
