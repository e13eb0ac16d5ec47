"""Disturbance torques from the orbit and the debris' geometry, numeric and CasADi alike.

The debris flies a circular Keplerian orbit (:class:`CircularOrbit`, from the
problem's ``[orbit]``). Four torques act on it, each a function of body-axis
vectors that takes numpy arrays (and returns numbers) or CasADi symbols (and
returns an expression for the compiled closed-loop step):

- :func:`gravity_gradient_torque`: 3 mu / |r|^5 r x (I r);
- :func:`aerodynamic_torque` and :func:`solar_pressure_torque` on the flat
  faces of the hub and the arrays (:func:`debris_panels`);
- :func:`magnetic_torque` of a residual dipole in the Earth's dipole field
  (:func:`dipole_field_T`).

:class:`EnvironmentTorques` evaluates those the problem's ``[environment]``
switches on at a time and an attitude; the closed loop adds them to the
disturbance (:mod:`casadi_debris.simulation`).

Example
-------
>>> import numpy as np
>>> from casadi_debris.environment import gravity_gradient_torque
>>> tau = gravity_gradient_torque(np.diag([100.0, 200.0, 300.0]), [7.0e6, 0.0, 0.0])
>>> float(np.abs(tau).max())
0.0
"""

from __future__ import annotations

from casadi_debris.environment._gravity import EARTH_MU_M3_S2, gravity_gradient_torque
from casadi_debris.environment._magnetic import dipole_axis, dipole_field_T, magnetic_torque
from casadi_debris.environment._orbit import EARTH_ROTATION_RAD_S, CircularOrbit
from casadi_debris.environment._panels import (
    Panel,
    aerodynamic_torque,
    debris_panels,
    solar_pressure_torque,
)
from casadi_debris.environment._sun import SOLAR_PRESSURE_N_M2, sun_direction, sunlit
from casadi_debris.environment._torques import EnvironmentTorques

__all__ = [
    "EARTH_MU_M3_S2",
    "EARTH_ROTATION_RAD_S",
    "SOLAR_PRESSURE_N_M2",
    "CircularOrbit",
    "EnvironmentTorques",
    "Panel",
    "aerodynamic_torque",
    "debris_panels",
    "dipole_axis",
    "dipole_field_T",
    "gravity_gradient_torque",
    "magnetic_torque",
    "solar_pressure_torque",
    "sun_direction",
    "sunlit",
]
