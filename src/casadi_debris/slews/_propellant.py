"""Propellant of a slew: from torque to engine thrust to kilograms.

Torque-level profiles (bang-bang, torque-level OCPs) leave open which engines
fire. Their propellant is counted with the *least-fuel* thrust that produces
each torque sample exactly, a linear programme per sample

    minimise  w^T f   subject to  B f = tau,  0 <= f <= f_max,

with w_i = 1 when every engine has one Isp (least total thrust) and
w_i = c_max / c_i otherwise (c_i = I_sp,i g0: least mass flow),

with B the geometry's torque map (3 x n_engines, N m per N) and f_max the
thrust of each engine's active stage; the net force is left free (the paper
counts torque only). All samples are solved together as one block-diagonal LP
(HiGHS). The mass flow of an engine of specific impulse I_sp is f / (I_sp g0),
so the propellant of a thrust history is

    m = sum_i (1 / (I_sp,i g0)) * sum_k f_ik * dt_k.

This is a lower bound for the torque profile (any other allocation burns more);
thruster-level OCPs carry their thrust and use the second formula directly.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from casadi_debris.config import Problem
from casadi_debris.errors import SlewInfeasibleError
from casadi_debris.geometry import Geometry, max_thrust_N

MILLI = 1e3  # N -> mN, N m -> mNm inside the LP


def exhaust_velocity_m_s(problem: Problem) -> float:
    """Effective exhaust velocity I_sp g0 of the engines, m/s.

    Raises
    ------
    ValueError
        When the engines' Isp differ: least total thrust, which the slews
        minimise, is least fuel only for one Isp.
    """
    isp = {engine.isp_s for engine in problem.engines}
    if len(isp) > 1:
        raise ValueError(f"the slews' fuel needs one Isp for all engines, got {sorted(isp)} s")
    return isp.pop() * problem.constants.standard_gravity_m_s2


def fuel_weights(problem: Problem) -> np.ndarray | None:
    """Propellant per newton of each engine relative to the best, ``c_max / c_i``, shape
    (n_engines,); None when every engine has one Isp (least thrust is then least fuel)."""
    isp = np.array([engine.isp_s for engine in problem.engines])
    if np.all(isp == isp[0]):
        return None
    return isp.max() / isp


def least_fuel_thrust(
    geometry: Geometry,
    torque_Nm: np.ndarray,
    weights: np.ndarray | None = None,
    *,
    zero_net_force: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Least-fuel thrust per torque sample, every engine within 0 <= f <= f_max.

    Samples the engines cannot produce (a per-axis torque box is larger than
    the engines' torque set) get the best effort: the LP is elastic,
    B f + s = tau with the shortfall s penalised far above any thrust, so
    those samples return the thrust that comes closest (in the 1-norm) and
    their shortfall.

    Parameters
    ----------
    geometry : Geometry
    torque_Nm : ndarray, shape (n, 3)
        Torque samples in B.
    weights : ndarray, shape (n_engines,), optional
        Cost per newton of each engine, :func:`fuel_weights` (at least 1); default 1
        each, the least total thrust.
    zero_net_force : bool
        Also hold the net force F f at zero (exactly: no thrust at all meets it), as
        the closed loop's allocator does; the shortfall then takes what that costs.

    Returns
    -------
    thrust_N : ndarray, shape (n, n_engines)
        Thrust per engine.
    shortfall_Nm : ndarray, shape (n, 3)
        tau - B f (zero wherever the torque is produced exactly).
    """
    torque = np.atleast_2d(np.asarray(torque_Nm, dtype=float))
    n_samples = torque.shape[0]
    torque_map = geometry.torque_map
    n_engines = torque_map.shape[1]
    limits = max_thrust_N(geometry)
    thrust = np.zeros((n_samples, n_engines))
    # Samples with (numerically) zero torque need no thrust: keep them out of the LP.
    scale = float(np.max(np.abs(torque_map)) * np.max(limits))
    active = np.flatnonzero(np.max(np.abs(torque), axis=1) > 1e-12 * scale)
    if active.size == 0:
        return thrust, np.zeros_like(torque)
    # Per sample: [f (n_engines), s+ (3), s- (3)]; a shortfall costs more than all engines at full
    # thrust on the shortest lever arm would.
    cost_f = np.ones(n_engines) if weights is None else np.asarray(weights, dtype=float)
    penalty = 1e3 * float(np.sum(cost_f * limits)) / scale
    # COO is what hstack builds from mixed formats anyway; naming it types the kron below.
    block = sp.hstack([sp.csr_matrix(torque_map), sp.identity(3), -sp.identity(3)], format="coo")
    right = torque[active] * MILLI
    if zero_net_force:  # rows F f = 0, in units of the torque rows' lever
        force_rows = sp.hstack([sp.csr_matrix(geometry.force_map), sp.csr_matrix((3, 6))])
        block = sp.vstack([block, force_rows], format="coo")
        right = np.hstack([right, np.zeros((active.size, 3))])
    width = n_engines + 6
    a_eq = sp.kron(sp.identity(active.size, format="csr"), block, format="csr")
    cost = np.tile(np.concatenate([cost_f, penalty * np.ones(6)]), active.size)
    upper = np.tile(np.concatenate([limits, np.full(6, np.inf)]), active.size)
    # Solved in mN and mNm: in N the thrusts (~1e-4) sit at HiGHS's feasibility tolerance.
    # scipy-stubs types A_eq as dense and bounds as tuples; HiGHS takes sparse and an (n, 2) array.
    result = linprog(  # type: ignore[call-overload]
        cost,
        A_eq=a_eq,
        b_eq=right.ravel(),
        bounds=np.column_stack([np.zeros(active.size * width), upper * MILLI]),
        method="highs",
    )
    if result.status != 0:  # cannot happen for an elastic LP unless the input is not finite
        raise SlewInfeasibleError(f"least-fuel thrust failed: {result.message}")
    solution = result.x.reshape(active.size, width) / MILLI
    thrust[active] = np.clip(solution[:, :n_engines], 0.0, limits)
    return thrust, torque - thrust @ torque_map.T


def propellant_kg(problem: Problem, thrust_N: np.ndarray, durations_s: np.ndarray) -> float:
    """Propellant of piecewise-constant thrust: sum_i sum_k f_ik dt_k / (I_sp,i g0), kg.

    Parameters
    ----------
    problem : Problem
    thrust_N : ndarray, shape (n, n_engines)
        Thrust held over each of the n intervals.
    durations_s : ndarray, shape (n,)
        Interval lengths.
    """
    if fuel_weights(problem) is not None:
        g0 = problem.constants.standard_gravity_m_s2
        exhaust = np.array([engine.isp_s * g0 for engine in problem.engines])
        impulse_Ns = np.asarray(durations_s) @ np.asarray(thrust_N)
        return float(np.sum(impulse_Ns / exhaust))
    impulse = float(np.sum(np.asarray(thrust_N).sum(axis=1) * np.asarray(durations_s)))
    return impulse / exhaust_velocity_m_s(problem)


def axis_fuel_rates(
    geometry: Geometry, weights: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Least thrust per unit torque about each signed axis, N per N m: (plus, minus), (3,) each.

    The cost coefficients c_i of the torque-level fuel objective
    sum_i c_i^+ tau_i^+ + c_i^- tau_i^- (tau = tau^+ - tau^-), taken at a small
    torque (no engine bound active). With ``weights`` (:func:`fuel_weights`)
    the thrust is the least-fuel one and is counted in fuel-equivalent newtons.
    """
    # The rates are the limit at vanishing torque, where no thrust bound is active: the
    # LP per signed axis without upper bounds, in units of the strongest lever so that
    # no lever of round-off size (cos 90 deg = 6e-17) decides the scale. An axis the
    # engines cannot torque about is charged the elastic penalty.
    lever = float(np.max(np.abs(geometry.torque_map)))
    torque_map = geometry.torque_map / lever
    n_engines = torque_map.shape[1]
    cost_f = np.ones(n_engines) if weights is None else np.asarray(weights, dtype=float)
    penalty = 1e6 * float(np.max(cost_f))
    a_eq = np.hstack([torque_map, np.eye(3), -np.eye(3)])
    cost = np.concatenate([cost_f, penalty * np.ones(6)])
    thrust = np.empty(6)
    for k, torque in enumerate(np.vstack([np.eye(3), -np.eye(3)])):
        result = linprog(cost, A_eq=a_eq, b_eq=torque, bounds=(0.0, None), method="highs")
        if result.status != 0 or result.fun is None:
            raise SlewInfeasibleError(f"fuel rate LP failed: {result.message}")
        thrust[k] = float(result.fun) / lever
    return thrust[:3], thrust[3:]
