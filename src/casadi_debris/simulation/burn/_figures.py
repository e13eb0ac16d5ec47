"""What a burn delivered: pointing of the thrust axis, Δv, and propellant split Δv / attitude.

Figures of a :class:`~casadi_debris.simulation.burn.BurnRun`:

- pointing error: angle between the thrust axis and the burn's LVLH direction;
- Δv: the thrust integrated, ``sum |F_k| h / M`` (the analytic ``T t / M``);
  along the direction, ``sum (C_NB,k F_k) . d_N,k h / M`` (pointing losses and the
  frame's turn taken off); from the plant, the change of the body's linear
  momentum over M (flexible arrays included), to be compared with the
  force turned into inertial axes, ``|sum C_NB,k F_k h| / M``; and the rocket
  equation over the propellant the force's impulse takes at the best exhaust
  velocity c, ``c ln(M / (M - m))`` (it differs from ``T t / M`` by the mass burnt);
- propellant split: the Δv share is what the least-fuel allocation of the
  force alone (zero torque) burns over the same time; the attitude share is the
  rest. The force's impulse over the best exhaust velocity bounds the Δv share
  from below;
- arrays: a net force F accelerates the body by a = F / M, so each array
  carries the inertial load ``m_SA a`` at its root and, below its first mode,
  sags quasi-statically by about ``1.566 a / omega_1^2`` at the tip (first
  cantilever mode: tip amplitude per unit base acceleration).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.config import Problem
from casadi_debris.dynamics import quaternion_to_rotation
from casadi_debris.guidance import direction_inertial
from casadi_debris.records import FLATTENED, Record
from casadi_debris.simulation._summary import RunSummary
from casadi_debris.simulation.burn._burn import BurnRun
from casadi_debris.units import ARCSEC_PER_RAD, MN_PER_N

# Tip deflection of a cantilever's first mode per unit base acceleration, times omega_1^2
# (the mode's participation factor with the tip normalised to one).
CANTILEVER_TIP_FACTOR = 1.566
STEADY_FRACTION = 0.5
"""The last half of a burn counts as its steady state."""


@dataclass(frozen=True, kw_only=True)
class BurnRunSummary(Record):
    """Figures of a burn flown while pointing.

    Attributes
    ----------
    problem, problem_sha256 : str
    direction : str
        prograde, retrograde, normal or antinormal (LVLH).
    body_axis : tuple of 3 float
        The thrust axis in body axes.
    burn_s : float
    thrust_mN : float
        Net force magnitude, mean over the burn.
    acceleration_m_s2 : float
        Thrust over the body's mass.
    pointing_max_arcsec, pointing_steady_max_arcsec : float
        Thrust axis against the direction: largest over the burn, over its last half.
    pointing_rms_arcsec, pointing_final_arcsec : float
        RMS over the burn, at its end.
    pointing_requirement_arcsec : float
    meets_pointing : bool
        The largest error below the requirement.
    dv_m_s : float
        ``sum |F| h / M``.
    dv_along_m_s : float
        Along the direction (pointing and the frame's turn taken off).
    dv_plant_m_s : float
        From the plant's linear momentum.
    dv_force_inertial_m_s : float
        ``|sum C_NB F h| / M``, which the plant's must equal.
    dv_rocket_m_s : float
        Rocket equation over ``fuel_dv_bound_kg``.
    fuel_dv_kg, fuel_attitude_kg, fuel_dv_bound_kg : float
        Propellant of the force alone (least fuel), the rest, and the force's impulse
        over the best exhaust velocity.
    attitude_fuel_fraction : float
    array_root_load_N : float
        Inertial load at an array's root (the heaviest array).
    array_tip_deflection_m : float
        Quasi-static first-mode tip deflection (the lowest first bending frequency).
    run : RunSummary
        The closed-loop run's figures (fuel per CubeSat, stage switches, events ...).
    """

    problem: str
    problem_sha256: str
    direction: str
    body_axis: tuple[float, ...]
    burn_s: float
    thrust_mN: float
    acceleration_m_s2: float
    pointing_max_arcsec: float
    pointing_steady_max_arcsec: float
    pointing_rms_arcsec: float
    pointing_final_arcsec: float
    pointing_requirement_arcsec: float
    meets_pointing: bool
    dv_m_s: float
    dv_along_m_s: float
    dv_plant_m_s: float
    dv_force_inertial_m_s: float
    dv_rocket_m_s: float
    fuel_dv_kg: float
    fuel_attitude_kg: float
    fuel_dv_bound_kg: float
    attitude_fuel_fraction: float
    array_root_load_N: float
    array_tip_deflection_m: float
    run: RunSummary = field(metadata=FLATTENED)


@dataclass(frozen=True, eq=False)
class BurnSeries:
    """Per period of a burn (n rows; n + 1 for the pointing error and Δv).

    Attributes
    ----------
    thrust_along_N : ndarray, shape (n,)
        Net force along the thrust axis.
    fuel_dv_kg, fuel_attitude_kg : ndarray, shape (n + 1,)
        Running propellant shares.
    dv_along_m_s : ndarray, shape (n + 1,)
    """

    thrust_along_N: np.ndarray
    fuel_dv_kg: np.ndarray
    fuel_attitude_kg: np.ndarray
    dv_along_m_s: np.ndarray


def burn_summary(
    problem: Problem, burn: BurnRun, allocator: Allocator
) -> tuple[BurnRunSummary, BurnSeries]:
    """The figures and series of a burn (``allocator`` of the problem, full engines)."""
    result, plan = burn.result, burn.plan
    h, mass = result.control_period_s, result.total_mass_kg
    force = result.force_N
    along = force @ plan.body_axis
    rotation = quaternion_to_rotation(result.state[:-1, 0:4])
    force_inertial = rotation.apply(force)
    wanted = direction_inertial(problem, plan, result.time_s[:-1])
    dv_along = np.concatenate([[0.0], np.cumsum(np.einsum("ij,ij->i", force_inertial, wanted))])
    dv_along *= h / mass
    fuel_rate = _force_fuel_rate(allocator, force)
    fuel_dv = np.concatenate([[0.0], np.cumsum(fuel_rate) * h])
    burnt = result.thrust_N / result.propulsion.exhaust_velocity_m_s
    fuel_total = np.concatenate([[0.0], np.cumsum(burnt.sum(axis=1)) * h])
    c_best = float(result.propulsion.exhaust_velocity_m_s.max())
    error_arcsec = burn.pointing_error_rad * ARCSEC_PER_RAD
    steady = error_arcsec[int(len(error_arcsec) * STEADY_FRACTION) :]
    requirement = problem.requirements.pointing_arcsec
    a = float(np.mean(np.abs(along))) / mass
    run = result.summary()
    m_dv = float(fuel_dv[-1])
    m_bound = float(np.abs(along).sum() * h / c_best)
    summary = BurnRunSummary(
        problem=problem.name,
        problem_sha256=problem.sha256,
        direction=plan.direction,
        body_axis=tuple(float(v) for v in plan.body_axis),
        burn_s=float(result.time_s[-1]),
        thrust_mN=float(np.mean(np.linalg.norm(force, axis=1))) * MN_PER_N,
        acceleration_m_s2=a,
        pointing_max_arcsec=float(error_arcsec.max()),
        pointing_steady_max_arcsec=float(steady.max()),
        pointing_rms_arcsec=float(np.sqrt(np.mean(error_arcsec**2))),
        pointing_final_arcsec=float(error_arcsec[-1]),
        pointing_requirement_arcsec=requirement,
        meets_pointing=bool(error_arcsec.max() < requirement),
        dv_m_s=float(np.linalg.norm(force, axis=1).sum() * h / mass),
        dv_along_m_s=float(dv_along[-1]),
        dv_plant_m_s=float(np.linalg.norm(burn.velocity_N_m_s[-1])),
        dv_force_inertial_m_s=float(np.linalg.norm(force_inertial.sum(axis=0)) * h / mass),
        dv_rocket_m_s=c_best * math.log(mass / (mass - m_bound)),
        fuel_dv_kg=m_dv,
        fuel_attitude_kg=float(fuel_total[-1] - m_dv),
        fuel_dv_bound_kg=m_bound,
        attitude_fuel_fraction=float((fuel_total[-1] - m_dv) / fuel_total[-1])
        if fuel_total[-1] > 0
        else 0.0,
        array_root_load_N=max((array.mass_kg * a for array in problem.arrays), default=0.0),
        array_tip_deflection_m=_tip_deflection_m(problem, a),
        run=run,
    )
    series = BurnSeries(along, fuel_dv, fuel_total - fuel_dv, dv_along)
    return summary, series


def _force_fuel_rate(allocator: Allocator, force: np.ndarray) -> np.ndarray:
    """Least-fuel propellant flow of each row's force alone (zero torque) [kg/s], shape (n,)."""
    rows, inverse = np.unique(np.round(force, 15), axis=0, return_inverse=True)
    rates = np.array([allocator.allocate(np.zeros(3), row).fuel_rate_kg_s for row in rows])
    return rates[np.ravel(inverse)]


def _tip_deflection_m(problem: Problem, acceleration_m_s2: float) -> float:
    """Quasi-static first-mode tip deflection under a base acceleration [m] (0 without arrays)."""
    first = [
        mode.omega_rad_s
        for array in problem.arrays
        for mode in array.modes
        if (mode.kind, mode.order) == ("bending", 1)
    ]
    if not first:
        return 0.0
    return CANTILEVER_TIP_FACTOR * acceleration_m_s2 / min(first) ** 2
