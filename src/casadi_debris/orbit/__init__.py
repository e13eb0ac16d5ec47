"""Orbits of the debris: low-thrust transfers, the atmosphere and orbital lifetime.

Algorithms only (no file I/O, no simulation loop): each is usable on its own from
Python, like ``slew`` and ``allocation``. The Earth's constants come from the
problem (``problem.constants``) or from :mod:`casadi_debris.environment`.
"""

from casadi_debris.orbit._atmosphere import (
    SEASONS,
    SOLAR_CASES,
    SolarActivity,
    density_table,
    geodetic_from_geocentric,
    msis_mean_density,
    solar_case,
)
from casadi_debris.orbit._ballistic import ballistic, drag_area_m2
from casadi_debris.orbit._curves import CaseTrajectory, case_trajectories
from casadi_debris.orbit._deorbit import (
    DV_SEARCH_MAX_M_S,
    STRATEGIES,
    DeorbitCase,
    DeorbitModel,
    DeorbitSettings,
    best_strategy,
)
from casadi_debris.orbit._elements import (
    EARTH_J2,
    cartesian_from_mee,
    keplerian_from_mee,
    mee_circular,
    mee_dynamics,
    mee_from_cartesian,
)
from casadi_debris.orbit._lifetime import REENTRY_PERIGEE_KM, Earth, RetrogradeBurn, propagate_decay
from casadi_debris.orbit._lifetime_mc import (
    CYCLE_MIN_SFU,
    CYCLE_PEAK_SFU,
    DRAG_COEFFICIENT_RANGE,
    LifetimeDraw,
    lifetime_monte_carlo,
)
from casadi_debris.orbit._plan import DeorbitPlan, plan_deorbit
from casadi_debris.orbit._propulsion import DIRECTION_DECIMALS, SwarmThrust, swarm_thrust
from casadi_debris.orbit._swarm_size import minimum_swarm, swarm_of
from casadi_debris.orbit.transfer import TransferPlan, TransferSummary, plan_transfer

__all__ = [
    "CYCLE_MIN_SFU",
    "CYCLE_PEAK_SFU",
    "DIRECTION_DECIMALS",
    "DRAG_COEFFICIENT_RANGE",
    "DV_SEARCH_MAX_M_S",
    "EARTH_J2",
    "REENTRY_PERIGEE_KM",
    "SEASONS",
    "SOLAR_CASES",
    "STRATEGIES",
    "CaseTrajectory",
    "DeorbitCase",
    "DeorbitModel",
    "DeorbitPlan",
    "DeorbitSettings",
    "Earth",
    "LifetimeDraw",
    "RetrogradeBurn",
    "SolarActivity",
    "SwarmThrust",
    "TransferPlan",
    "TransferSummary",
    "ballistic",
    "best_strategy",
    "cartesian_from_mee",
    "case_trajectories",
    "density_table",
    "drag_area_m2",
    "geodetic_from_geocentric",
    "keplerian_from_mee",
    "lifetime_monte_carlo",
    "mee_circular",
    "mee_dynamics",
    "mee_from_cartesian",
    "minimum_swarm",
    "msis_mean_density",
    "plan_deorbit",
    "plan_transfer",
    "propagate_decay",
    "solar_case",
    "swarm_of",
    "swarm_thrust",
]
