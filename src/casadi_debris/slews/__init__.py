"""Slew references: the paper's bang-bang and time/fuel-optimal slews as CasADi OCPs.

- :mod:`~casadi_debris.slews._maneuver`: rest-to-rest targets, eigenaxis limits.
- :mod:`~casadi_debris.slews._bang_bang`: the paper's reference profile.
- :mod:`~casadi_debris.slews._optimal`: time- and fuel-optimal OCPs (torque or
  thruster level; flexible = the vibration left bounded in closed form, or ZV-shaped),
  set by a :class:`OptimalSlewSettings`; stated in :mod:`~casadi_debris.slews._ocp_problem`,
  transcribed in :mod:`~casadi_debris.slews._transcription`, started from
  :mod:`~casadi_debris.slews._initial_guess`, the flexible end in
  :mod:`~casadi_debris.slews._modal_window`.
- :mod:`~casadi_debris.slews._global_slew`: time-optimal rigid slews searched
  globally (:mod:`~casadi_debris.slews._multistart`, switch times refined in
  :mod:`~casadi_debris.slews._switch_times`), of a problem or of a plain
  :class:`~casadi_debris.slews._rigid_body.RigidBody`.
- :mod:`~casadi_debris.slews._shaper`: the zero-vibration input shaper.
- :mod:`~casadi_debris.slews._modal`: the array modes' response to held inputs, in
  closed form.
- :mod:`~casadi_debris.slews._propellant`: torque to thrust to propellant.
- :mod:`~casadi_debris.slews._profile`: the common result and its check on the
  flexible model.
"""

from casadi_debris.dynamics import euler_angles_321, quaternion_multiply
from casadi_debris.slews._bang_bang import BangBangTiming, bang_bang_slew, bang_bang_timing
from casadi_debris.slews._global_slew import rigid_body_profile
from casadi_debris.slews._maneuver import (
    SlewTarget,
    eigenaxis_acceleration_limit,
    rigid_limit_duration,
    slew_about_axis,
    slew_between,
    torque_limits,
)
from casadi_debris.slews._modal import ModalResponse, modal_response
from casadi_debris.slews._optimal import fuel_optimal_slew, time_optimal_slew
from casadi_debris.slews._options import OptimalSlewSettings
from casadi_debris.slews._profile import (
    ProfileSummary,
    SlewProfile,
    finish_profile,
    simulate_open_loop,
    vibration_energy,
    zoh_input_function,
)
from casadi_debris.slews._propellant import (
    axis_fuel_rates,
    fuel_weights,
    least_fuel_thrust,
    propellant_kg,
)
from casadi_debris.slews._rigid_body import RigidBody, scaled_rigid_ode
from casadi_debris.slews._shaper import shape, zero_vibration_shaper
from casadi_debris.slews._transcription import (
    COLLOCATION_DEGREE,
    radau_coefficients,
    solve_with_ipopt,
)

__all__ = [
    "COLLOCATION_DEGREE",
    "BangBangTiming",
    "ModalResponse",
    "OptimalSlewSettings",
    "ProfileSummary",
    "RigidBody",
    "SlewProfile",
    "SlewTarget",
    "axis_fuel_rates",
    "bang_bang_slew",
    "bang_bang_timing",
    "eigenaxis_acceleration_limit",
    "euler_angles_321",
    "finish_profile",
    "fuel_optimal_slew",
    "fuel_weights",
    "least_fuel_thrust",
    "modal_response",
    "propellant_kg",
    "quaternion_multiply",
    "radau_coefficients",
    "rigid_body_profile",
    "rigid_limit_duration",
    "scaled_rigid_ode",
    "shape",
    "simulate_open_loop",
    "slew_about_axis",
    "slew_between",
    "solve_with_ipopt",
    "time_optimal_slew",
    "torque_limits",
    "vibration_energy",
    "zero_vibration_shaper",
    "zoh_input_function",
]
