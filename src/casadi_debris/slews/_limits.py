"""Every slew profile checked against the actuators that fly it, over its whole time grid.

A profile's torque tau(t) is the control torque: with the body rate omega and
acceleration alpha it is tau = J alpha + omega x J omega (the gyroscopic torque
included), so checking tau checks everything the engines must give.

The test is the gauge of tau in the engines' torque set
T = {B f : 0 <= f <= f_max (, F f = 0)}: g(tau) = 1 / max {s : s tau in T}, one
linear programme per distinct sample (all of them solved together, block-diagonal,
by HiGHS). g <= 1 is exactly "the allocator can give tau", so a profile passes
when its gauge is at most 1 at every sample (within ``RATIO_TOLERANCE``) and every
thrust check holds.

The per-signed-axis ratios tau_i / A_+i (tau_i > 0), -tau_i / A_-i (tau_i < 0),
A the largest *pure* torque about each signed axis
(:func:`~casadi_debris.geometry.torque_authority`), are reported as information
only: a torque of T can exceed A_+i on its i component when it has others (the set
reaches past its pure-axis points in combined directions; a skewed swarm reached
7.5 x A_+x at gauge 1), and a torque inside the per-axis box can lie outside T
(the paper's box corners need twice the engines' thrust). For a pure-axis torque
the two measures are equal.

The net-force rule is the allocator's that flies the profile: the closed loop's
allocator keeps the net force zero, so torque-level profiles (which it flies) are
checked at zero net force; a thruster-level profile carries its own thrust and is
checked with the rule it was solved with (``zero_net_force``). At thruster level
every thrust must also lie within 0 <= f <= f_max and the torque must be B f (and
the net force F f zero when asked).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from casadi_debris.config import AXIS_NAMES, SIGNED_AXES
from casadi_debris.errors import CasadiDebrisError
from casadi_debris.geometry import Authority, Geometry, max_thrust_N, torque_authority
from casadi_debris.records import OPTIONAL, Record

# Relative slack on every ratio and bound: IPOPT meets its bounds to about 1e-8, HiGHS
# its constraints to 1e-9 of the scaled data.
RATIO_TOLERANCE = 1e-6
# Thrust in units of the largest engine, torque in units of the largest lever times it.
ZERO_TORQUE = 1e-12
# Samples per block-diagonal LP of the torque-set gauge.
LP_BLOCK = 64


@dataclass(frozen=True)
class LimitCheck(Record):
    """How much of the actuators' authority a profile uses, worst over its time grid.

    Attributes
    ----------
    limits_ok : bool
        The torque-set gauge <= 1 at every sample and every thrust check passed (within
        ``RATIO_TOLERANCE``); the per-axis ratios do not enter (module notes).
    limits_zero_net_force : bool
        The torque set and authority were those at zero net force.
    limits_authority_Nm : dict
        Largest pure torque about each signed axis (``"+x"`` ... ``"-z"``), N m.
    worst_axis_ratio : dict
        Per signed axis, the largest torque need over the pure torque about it
        (information: above 1 is flyable when the gauge is at most 1).
    worst_torque_set_ratio : float
        Largest gauge of the torque in the engines' torque set (1 = at its boundary):
        the test.
    worst_ratio_time_s : float
        When the largest gauge occurs, s from the slew's start.
    max_thrust_ratio : float or None
        Thruster level: largest f_i / f_max,i (None, and no JSON key, at torque level).
    min_thrust_N : float or None
        Thruster level: the smallest thrust, N (must not be negative).
    torque_map_residual_Nm : float or None
        Thruster level: largest |tau - B f|, N m.
    max_net_force_N : float or None
        Thruster level: largest |F f|, N (must be zero with ``limits_zero_net_force``).
    limits_note : str
        What failed, with the figures; empty when ``limits_ok``.
    """

    limits_ok: bool
    limits_zero_net_force: bool
    limits_authority_Nm: dict[str, float]
    worst_axis_ratio: dict[str, float]
    worst_torque_set_ratio: float
    worst_ratio_time_s: float
    max_thrust_ratio: float | None = field(default=None, metadata=OPTIONAL)
    min_thrust_N: float | None = field(default=None, metadata=OPTIONAL)
    torque_map_residual_Nm: float | None = field(default=None, metadata=OPTIONAL)
    max_net_force_N: float | None = field(default=None, metadata=OPTIONAL)
    limits_note: str = field(default="")


def axis_ratios(authority_Nm: Authority, torque_Nm: np.ndarray) -> np.ndarray:
    """Need over authority about each signed axis, shape (n, 6) (``SIGNED_AXES`` order).

    Parameters
    ----------
    authority_Nm : Authority
        Largest pure torque about ``"+x"`` ... ``"-z"``, N m (>= 0).
    torque_Nm : ndarray, shape (n, 3)
    """
    torque = np.atleast_2d(np.asarray(torque_Nm, dtype=float))
    ratios = np.zeros((torque.shape[0], len(SIGNED_AXES)))
    for column, name in enumerate(SIGNED_AXES):
        sign = 1.0 if name[0] == "+" else -1.0
        need = np.maximum(sign * torque[:, AXIS_NAMES.index(name[1])], 0.0)
        limit = authority_Nm[name]
        with np.errstate(divide="ignore", invalid="ignore"):
            ratios[:, column] = np.where(need > 0.0, need / limit if limit > 0 else np.inf, 0.0)
    return ratios


def torque_set_ratio(
    geometry: Geometry,
    torque_Nm: np.ndarray,
    zero_net_force: bool,
    force_N: np.ndarray | None = None,
) -> np.ndarray:
    """Gauge of each torque in the engines' torque set (module notes), shape (n,).

    0 for a zero torque, inf for one the engines cannot make in any amount.

    Parameters
    ----------
    geometry : Geometry
    torque_Nm : ndarray, shape (n, 3)
    zero_net_force : bool
        The allocator's net-force rule.
    force_N : ndarray, shape (n, 3), optional
        With ``zero_net_force``: the net force the engines hold at each sample instead of
        zero (a burn's thrust), N; the set is then the torques they can add to it,
        {B f : 0 <= f <= f_max, F f = force}, which holds the zero torque when the force
        can be given without torque.

    Raises
    ------
    CasadiDebrisError
        HiGHS failed on the linear programme (always feasible at zero force; with a
        ``force_N`` the engines cannot give, infeasible).
    """
    torque = np.atleast_2d(np.asarray(torque_Nm, dtype=float))
    gauge = np.zeros(torque.shape[0])
    limits = max_thrust_N(geometry)
    unit_f = float(np.max(limits)) if limits.size and np.max(limits) > 0 else 0.0
    if unit_f == 0.0:
        gauge[np.max(np.abs(torque), axis=1) > 0.0] = np.inf
        return gauge
    unit_tau = float(np.max(np.abs(geometry.torque_map))) * unit_f
    scaled = torque / unit_tau
    active = np.flatnonzero(np.max(np.abs(scaled), axis=1) > ZERO_TORQUE)
    if active.size == 0:
        return gauge
    force = np.zeros_like(torque) if force_N is None else np.atleast_2d(force_N) / unit_f
    rows = np.hstack([scaled, force])[active]
    distinct, inverse = np.unique(rows, axis=0, return_inverse=True)
    # The samples' LPs are independent: solved in blocks of LP_BLOCK, since HiGHS' cost grows
    # faster than the size of one block-diagonal LP (a long profile has thousands).
    scale = np.concatenate(
        [
            _largest_scales(geometry, chunk[:, :3], limits / unit_f, zero_net_force, chunk[:, 3:])
            for chunk in np.array_split(distinct, math.ceil(len(distinct) / LP_BLOCK))
        ]
    )
    with np.errstate(divide="ignore"):
        gauge[active] = np.where(scale > 0.0, 1.0 / scale, np.inf)[np.ravel(inverse)]
    return gauge


def _largest_scales(
    geometry: Geometry,
    torques: np.ndarray,
    limits: np.ndarray,
    zero_net_force: bool,
    forces: np.ndarray,
) -> np.ndarray:
    """max s with s tau_k = B u, 0 <= u <= limits (, F u = force_k), per row of ``torques``
    (scaled units: B in units of the largest lever, u and the forces of the largest
    thrust)."""
    n_engines = geometry.torque_map.shape[1]
    torque_map = geometry.torque_map / float(np.max(np.abs(geometry.torque_map)))
    # Each direction at unit size, round-off components cleared: HiGHS drops coefficients
    # under 1e-9, and a small torque's column would be dropped whole (an unbounded s).
    sizes = np.max(np.abs(torques), axis=1)
    torques = torques / sizes[:, None]
    torques = np.where(np.abs(torques) < 1e-12, 0.0, torques)
    count = torques.shape[0]
    width = n_engines + 1
    blocks, right = [], []
    for row, force in zip(torques, forces, strict=True):
        # per sample: [u (n_engines), s]; B u - s tau = 0 (, F u = force)
        block = np.hstack([torque_map, -row[:, None]])
        right.append(np.zeros(3))
        if zero_net_force:
            block = np.vstack([block, np.hstack([geometry.force_map, np.zeros((3, 1))])])
            right.append(force)
        blocks.append(sp.csr_matrix(block))
    a_eq = sp.block_diag(blocks, format="csr")
    cost = np.tile(np.concatenate([np.zeros(n_engines), [-1.0]]), count)
    upper = np.tile(np.concatenate([limits, [np.inf]]), count)
    result = linprog(  # type: ignore[call-overload]
        cost,
        A_eq=a_eq,
        b_eq=np.concatenate(right),
        bounds=np.column_stack([np.zeros(count * width), upper]),
        method="highs",
    )
    if result.status != 0 or result.x is None:
        raise CasadiDebrisError(f"torque-set LP of the slew check failed: {result.message}")
    return np.asarray(result.x).reshape(count, width)[:, -1] / sizes


def authority_use(geometry: Geometry, torque_Nm: np.ndarray, zero_net_force: bool) -> np.ndarray:
    """The share of the engines' authority each torque needs, shape (n,): its gauge in the
    torque set (:func:`torque_set_ratio`), 1 the most the engines give (module notes).

    Convex and positively homogeneous, so a sizing rule may scale a profile by it.

    Parameters
    ----------
    geometry : Geometry
    torque_Nm : ndarray, shape (n, 3)
    zero_net_force : bool
        The allocator's net-force rule.
    """
    return torque_set_ratio(geometry, torque_Nm, zero_net_force)


def check_limits(
    geometry: Geometry,
    time_s: np.ndarray,
    torque_Nm: np.ndarray,
    *,
    zero_net_force: bool,
    thrust_N: np.ndarray | None = None,
    force_N: np.ndarray | None = None,
) -> LimitCheck:
    """The profile's torque (and thrust) against the engines (module notes).

    Parameters
    ----------
    geometry : Geometry
        The engines: torque and force maps, thrust limits.
    time_s : ndarray, shape (n,)
        The profile's time grid, s.
    torque_Nm : ndarray, shape (n, 3)
        Control torque at each instant (J alpha + omega x J omega), N m.
    zero_net_force : bool
        The net-force rule of the allocator that flies the profile.
    thrust_N : ndarray, shape (n, n_engines), optional
        Thruster level: the profile's own thrust at each instant, N.
    force_N : ndarray, shape (n, 3), optional
        With ``zero_net_force``: the net force the engines hold at each instant instead
        of zero (a burn's), N (:func:`torque_set_ratio`).

    Returns
    -------
    LimitCheck
    """
    authority = torque_authority(geometry, zero_net_force=zero_net_force)
    per_axis = axis_ratios(authority, torque_Nm)
    gauge = torque_set_ratio(geometry, torque_Nm, zero_net_force, force_N)
    at = int(np.argmax(gauge)) if len(gauge) else 0
    worst_axis = dict(zip(SIGNED_AXES, per_axis.max(axis=0, initial=0.0).tolist(), strict=True))
    notes = []
    worst_set = float(np.max(gauge, initial=0.0))
    if not worst_set <= 1.0 + RATIO_TOLERANCE:  # NaN fails too
        notes.append(f"the torque needs {worst_set:.4g} x the engines' torque set")
    thrust = _thrust_figures(geometry, torque_Nm, thrust_N, zero_net_force, notes)
    return LimitCheck(
        limits_ok=not notes,
        limits_zero_net_force=zero_net_force,
        limits_authority_Nm=dict(authority),
        worst_axis_ratio=worst_axis,
        worst_torque_set_ratio=worst_set,
        worst_ratio_time_s=float(np.asarray(time_s)[at]) if len(gauge) else 0.0,
        **thrust,
        limits_note="; ".join(notes),
    )


def _thrust_figures(
    geometry: Geometry,
    torque_Nm: np.ndarray,
    thrust_N: np.ndarray | None,
    zero_net_force: bool,
    notes: list[str],
) -> dict[str, float | None]:
    """Thruster level: bounds, torque = B f and net force; failures appended to ``notes``."""
    if thrust_N is None:
        return {}
    thrust = np.atleast_2d(np.asarray(thrust_N, dtype=float))
    limits = max_thrust_N(geometry)
    unit = float(np.max(limits)) if limits.size else 1.0
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(limits > 0, thrust / limits, np.where(thrust > 0, np.inf, 0.0))
    most = float(np.max(ratio, initial=0.0))
    least = float(np.min(thrust, initial=0.0))
    residual = float(np.max(np.abs(thrust @ geometry.torque_map.T - torque_Nm), initial=0.0))
    force = float(np.max(np.linalg.norm(thrust @ geometry.force_map.T, axis=1), initial=0.0))
    lever = float(np.max(np.abs(geometry.torque_map)))
    if most > 1.0 + RATIO_TOLERANCE:
        notes.append(f"a thrust reaches {most:.4g} x its engine's limit")
    if least < -RATIO_TOLERANCE * unit:
        notes.append(f"a thrust is negative ({least * 1e3:.3g} mN)")
    if residual > RATIO_TOLERANCE * unit * lever:
        notes.append(f"the torque differs from B f by {residual * 1e3:.3g} mNm")
    if zero_net_force and force > RATIO_TOLERANCE * unit:
        notes.append(f"the net force reaches {force * 1e3:.3g} mN (asked zero)")
    return {
        "max_thrust_ratio": most,
        "min_thrust_N": least,
        "torque_map_residual_Nm": residual,
        "max_net_force_N": force,
    }


def box_authority(lower_Nm: np.ndarray, upper_Nm: np.ndarray) -> Authority:
    """A per-axis torque box (N m, shape (3,) each) as the authority about each signed axis
    (actuators without a net force)."""
    signed = np.column_stack(
        [np.asarray(upper_Nm, dtype=float), -np.asarray(lower_Nm, dtype=float)]
    )
    return Authority(signed.ravel(), zero_net_force=False)


def box_check(
    time_s: np.ndarray, torque_Nm: np.ndarray, lower_Nm: np.ndarray, upper_Nm: np.ndarray
) -> LimitCheck:
    """A torque against a per-axis box (a rigid body without engines: the box is its
    actuators, and its gauge is the largest per-axis ratio)."""
    authority = box_authority(lower_Nm, upper_Nm)
    per_axis = axis_ratios(authority, torque_Nm)
    worst_each = per_axis.max(axis=1)
    worst_axis = dict(zip(SIGNED_AXES, per_axis.max(axis=0, initial=0.0).tolist(), strict=True))
    worst = float(np.max(worst_each, initial=0.0))
    ok = worst <= 1.0 + RATIO_TOLERANCE
    return LimitCheck(
        limits_ok=ok,
        limits_zero_net_force=False,
        limits_authority_Nm=dict(authority),
        worst_axis_ratio=worst_axis,
        worst_torque_set_ratio=worst,
        worst_ratio_time_s=float(np.asarray(time_s)[int(np.argmax(worst_each))])
        if len(worst_each)
        else 0.0,
        limits_note="" if ok else f"the torque needs {worst:.4g} x the box",
    )


def unchecked() -> LimitCheck:
    """The check of a profile built without one (never passes)."""
    return LimitCheck(
        limits_ok=False,
        limits_zero_net_force=False,
        limits_authority_Nm={},
        worst_axis_ratio={},
        worst_torque_set_ratio=math.nan,
        worst_ratio_time_s=math.nan,
        limits_note="not checked",
    )
