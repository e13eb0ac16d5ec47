"""Slew references: the paper's bang-bang and time/fuel-optimal slews as CasADi OCPs.

- :mod:`~casadi_debris.slews.maneuver`: rest-to-rest targets, eigenaxis limits.
- :mod:`~casadi_debris.slews.bang_bang`: the paper's reference profile.
- :mod:`~casadi_debris.slews.optimal`: time- and fuel-optimal OCPs (torque or
  thruster level; flexible = the vibration left bounded in closed form, or ZV-shaped),
  set by a :class:`SlewOptions`; stated in :mod:`~casadi_debris.slews.ocp_problem`,
  transcribed in :mod:`~casadi_debris.slews.transcription`, started from
  :mod:`~casadi_debris.slews.initial_guess`, the flexible end in
  :mod:`~casadi_debris.slews.modal_window`.
- :mod:`~casadi_debris.slews.global_slew`: time-optimal rigid slews searched
  globally (:mod:`~casadi_debris.slews.multistart`, switch times refined in
  :mod:`~casadi_debris.slews.switch_times`), of a problem or of a plain
  :class:`~casadi_debris.slews.rigid_body.RigidBody`.
- :mod:`~casadi_debris.slews.shaper`: the zero-vibration input shaper.
- :mod:`~casadi_debris.slews.modal`: the array modes' response to held inputs, in
  closed form.
- :mod:`~casadi_debris.slews.propellant`: torque to thrust to propellant.
- :mod:`~casadi_debris.slews.profile`: the common result and its check on the
  flexible model.
"""

from casadi_debris.dynamics import euler_angles_321, quaternion_multiply
from casadi_debris.slews.bang_bang import BangBangTiming, bang_bang_slew, bang_bang_timing
from casadi_debris.slews.maneuver import (
    SlewTarget,
    eigenaxis_acceleration_limit,
    rigid_limit_duration,
    slew_about_axis,
    slew_between,
    torque_limits,
)
from casadi_debris.slews.optimal import fuel_optimal_slew, time_optimal_slew
from casadi_debris.slews.options import SlewOptions
from casadi_debris.slews.profile import SlewProfile, SlewSummary, simulate
from casadi_debris.slews.propellant import least_fuel_thrust, propellant_kg
from casadi_debris.slews.rigid_body import RigidBody
from casadi_debris.slews.shaper import shape, zero_vibration_shaper

__all__ = [
    "BangBangTiming",
    "RigidBody",
    "SlewOptions",
    "SlewProfile",
    "SlewSummary",
    "SlewTarget",
    "bang_bang_slew",
    "bang_bang_timing",
    "eigenaxis_acceleration_limit",
    "euler_angles_321",
    "fuel_optimal_slew",
    "least_fuel_thrust",
    "propellant_kg",
    "quaternion_multiply",
    "rigid_limit_duration",
    "shape",
    "simulate",
    "slew_about_axis",
    "slew_between",
    "time_optimal_slew",
    "torque_limits",
    "zero_vibration_shaper",
]
