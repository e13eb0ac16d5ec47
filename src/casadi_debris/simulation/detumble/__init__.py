"""Detumbling the debris: rate damping through the staged engines, and the time-optimal
detumble.

- :func:`simulate_detumble`: the closed loop that brakes the problem's initial tumble, vertex
  by vertex of the engines' authority, with allocation, staging and fuel
  (:class:`DetumbleRunResult`, its figures a :class:`DetumbleRunSummary`).
- :func:`problem_time_optimal_detumble` / :func:`time_optimal_detumble`: the
  time-optimal detumble as an OCP over the polhode-averaged rates
  (:class:`DetumbleOcp`), checked for small tumbles by the full transcription
  :func:`full_time_optimal_detumble`.
- :func:`polhode_averages`: the torque-free precession of the angular momentum and
  means over it (:class:`PrincipalBody`, :class:`PolhodeAverages`).

The rigid body only: at such rates the flexible model is not valid.
"""

from casadi_debris.simulation.detumble._detumble import (
    DEFAULT_GAIN_PER_S,
    DEFAULT_THRESHOLD_RAD_S,
    DETUMBLE_PERIOD_S,
    DetumbleRunResult,
    DetumbleRunSummary,
    held_torque_rates,
    simulate_detumble,
)
from casadi_debris.simulation.detumble._full_ocp import FullDetumbleOcp, full_time_optimal_detumble
from casadi_debris.simulation.detumble._ocp import (
    DetumbleOcp,
    DetumbleOcpSummary,
    problem_time_optimal_detumble,
    time_optimal_detumble,
)
from casadi_debris.simulation.detumble._polhode import (
    PolhodeAverages,
    PrincipalBody,
    polhode_averages,
    polhode_points,
)

__all__ = [
    "DEFAULT_GAIN_PER_S",
    "DEFAULT_THRESHOLD_RAD_S",
    "DETUMBLE_PERIOD_S",
    "DetumbleOcp",
    "DetumbleOcpSummary",
    "DetumbleRunResult",
    "DetumbleRunSummary",
    "FullDetumbleOcp",
    "PolhodeAverages",
    "PrincipalBody",
    "full_time_optimal_detumble",
    "held_torque_rates",
    "polhode_averages",
    "polhode_points",
    "problem_time_optimal_detumble",
    "simulate_detumble",
    "time_optimal_detumble",
]
