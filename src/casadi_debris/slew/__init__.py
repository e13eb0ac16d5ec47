"""Slew references: the paper's bang-bang and time/fuel-optimal slews as CasADi OCPs.

- :mod:`~casadi_debris.slew.maneuver`: rest-to-rest targets, eigenaxis limits.
- :mod:`~casadi_debris.slew.bang_bang`: the paper's reference profile.
- :mod:`~casadi_debris.slew.optimal`: time- and fuel-optimal OCPs (torque or
  thruster level; flexible = the vibration left bounded in closed form, or ZV-shaped),
  set by a :class:`SlewOptions`; stated in :mod:`~casadi_debris.slew.ocp_problem`,
  transcribed in :mod:`~casadi_debris.slew.transcription`, started from
  :mod:`~casadi_debris.slew.initial_guess`, the flexible end in
  :mod:`~casadi_debris.slew.modal_window`.
- :mod:`~casadi_debris.slew.global_slew`: time-optimal rigid slews searched
  globally (:mod:`~casadi_debris.slew.multistart`, switch times refined in
  :mod:`~casadi_debris.slew.switch_times`), of a problem or of a plain
  :class:`~casadi_debris.slew.rigid_body.RigidBody`.
- :mod:`~casadi_debris.slew.shaper`: the zero-vibration input shaper.
- :mod:`~casadi_debris.slew.modal`: the array modes' response to held inputs, in
  closed form.
- :mod:`~casadi_debris.slew.propellant`: torque to thrust to propellant.
- :mod:`~casadi_debris.slew.profile`: the common result and its check on the
  flexible model.
"""

from casadi_debris.model.attitude import euler_angles_321, quaternion_multiply
from casadi_debris.slew.bang_bang import BangBangTiming, bang_bang_slew, bang_bang_timing
from casadi_debris.slew.maneuver import (
    SlewTarget,
    eigenaxis_acceleration_limit,
    rigid_limit_duration,
    slew_about_axis,
    slew_between,
    torque_limits,
)
from casadi_debris.slew.optimal import fuel_optimal_slew, time_optimal_slew
from casadi_debris.slew.options import SlewOptions
from casadi_debris.slew.profile import SlewProfile, SlewSummary, simulate
from casadi_debris.slew.propellant import least_fuel_thrust, propellant_kg
from casadi_debris.slew.rigid_body import RigidBody
from casadi_debris.slew.shaper import shape, zero_vibration_shaper

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
