"""Thrusting while pointing: a transfer or deorbit burn flown by the closed attitude loop.

- :func:`simulate_burn`: the burn's thrust axis held along its LVLH direction while
  the engines deliver the force and the controller's torque together
  (:class:`BurnRun`).
- :func:`burn_summary`: what the burn delivered: pointing of the thrust axis, Δv, the
  propellant split between Δv and attitude, the arrays' load
  (:class:`BurnRunSummary`, :class:`BurnSeries`).

The loop is :mod:`casadi_debris.simulation`'s; the burn plan is
:mod:`casadi_debris.guidance`'s.
"""

from casadi_debris.simulation.burn._burn import (
    BURN_PERIOD_S,
    BurnRun,
    burn_reference,
    first_stage_left,
    pointing_error_rad,
    simulate_burn,
)
from casadi_debris.simulation.burn._figures import BurnRunSummary, BurnSeries, burn_summary

__all__ = [
    "BURN_PERIOD_S",
    "BurnRun",
    "BurnRunSummary",
    "BurnSeries",
    "burn_reference",
    "burn_summary",
    "first_stage_left",
    "pointing_error_rad",
    "simulate_burn",
]
