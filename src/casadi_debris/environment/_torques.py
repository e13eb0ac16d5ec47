"""The environment torques of a problem, together, at a time and an attitude.

:class:`EnvironmentTorques` ties the orbit (:mod:`~casadi_debris.environment._orbit`)
to the torques the problem's ``[environment]`` switches on, all in body axes:

- gravity gradient (:mod:`~casadi_debris.environment._gravity`) from the
  position r_B = [NB]^T r_N;
- aerodynamic (:mod:`~casadi_debris.environment._panels`) from the velocity
  relative to an atmosphere turning with the Earth, v_N - omega_E z x r_N;
- solar pressure from the Sun's direction (:mod:`~casadi_debris.environment._sun`),
  off in the Earth's shadow when ``eclipse`` is on;
- magnetic (:mod:`~casadi_debris.environment._magnetic`) from the dipole field at r.

Everything takes floats and numpy arrays or CasADi symbols alike.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from casadi_debris.config import ENVIRONMENT_TORQUES, Environment, Problem
from casadi_debris.environment._algebra import Vector, as_vector, cross, matvec, symbolic, zeros
from casadi_debris.environment._gravity import gravity_gradient_torque
from casadi_debris.environment._magnetic import dipole_axis, dipole_field_T, magnetic_torque
from casadi_debris.environment._orbit import EARTH_ROTATION_RAD_S, CircularOrbit
from casadi_debris.environment._panels import (
    Panel,
    aerodynamic_torque,
    debris_panels,
    solar_pressure_torque,
)
from casadi_debris.environment._sun import sun_direction, sunlit
from casadi_debris.geometry import Geometry
from casadi_debris.units import M_PER_KM


@dataclass(frozen=True, eq=False)
class EnvironmentTorques:
    """The problem's environment torques on the debris.

    Attributes
    ----------
    settings : Environment
        The problem's ``[environment]``.
    orbit : CircularOrbit
    earth_radius_m : float
    problem : Problem
    geometry : Geometry
    """

    settings: Environment
    orbit: CircularOrbit
    earth_radius_m: float
    problem: Problem
    geometry: Geometry

    @classmethod
    def of(cls, problem: Problem, geometry: Geometry) -> EnvironmentTorques:
        """From the problem's ``[orbit]``, ``[constants]`` and ``[environment]``."""
        return cls(
            settings=problem.environment,
            orbit=CircularOrbit.from_problem(problem),
            earth_radius_m=problem.constants.earth_radius_km * M_PER_KM,
            problem=problem,
            geometry=geometry,
        )

    @property
    def active(self) -> bool:
        """Whether any torque is switched on."""
        return bool(self.settings.torques)

    def panels(self, array_angles_rad: list[Any] | None = None) -> tuple[Panel, ...]:
        """The debris' faces (arrays at the given angles, default the problem's)."""
        return debris_panels(self.problem, self.geometry, array_angles_rad)

    def torques(
        self,
        time_s: Any,
        dcm_NB: Any,
        inertia_kgm2: Any,
        array_angles_rad: list[Any] | None = None,
        which: tuple[str, ...] | None = None,
    ) -> dict[str, Vector]:
        """Each torque [N m], body axes, by name.

        Parameters
        ----------
        time_s : float or casadi scalar
        dcm_NB : ndarray or casadi matrix, shape (3, 3)
            Takes body components to inertial ones (the attitude's rotation matrix).
        inertia_kgm2 : ndarray or casadi matrix, shape (3, 3)
            About the centre of gravity, body axes (for the gravity gradient).
        array_angles_rad : list, optional
            theta_SA of each array (default the problem's).
        which : tuple of str, optional
            The torques to compute (default those the problem switches on).
        """
        names = self.settings.torques if which is None else which
        casadi = symbolic(time_s, dcm_NB, inertia_kgm2, *(array_angles_rad or []))
        dcm = as_vector(dcm_NB, casadi)
        to_body = dcm.T
        r_N = as_vector(self.orbit.position_m(time_s), casadi)
        s = self.settings
        out: dict[str, Vector] = {}
        panels = None
        if {"aerodynamic", "solar_pressure"} & set(names):
            panels = self.panels(array_angles_rad)
        for name in ENVIRONMENT_TORQUES:
            if name not in names:
                continue
            if name == "gravity_gradient":
                out[name] = gravity_gradient_torque(
                    inertia_kgm2, matvec(to_body, r_N), mu_m3_s2=self.orbit.mu_m3_s2
                )
            elif name == "aerodynamic":
                v_N = as_vector(self.orbit.velocity_m_s(time_s), casadi)
                wind = cross(as_vector(np.array([0.0, 0.0, EARTH_ROTATION_RAD_S]), casadi), r_N)
                out[name] = aerodynamic_torque(
                    panels or (), matvec(to_body, v_N - wind), s.density_kg_m3, s.drag_coefficient
                )
            elif name == "solar_pressure":
                sun_N = sun_direction(time_s, math.radians(s.sun_longitude_deg))
                lit = sunlit(r_N, sun_N, self.earth_radius_m) if s.eclipse else 1.0
                out[name] = solar_pressure_torque(
                    panels or (),
                    matvec(to_body, sun_N),
                    s.solar_pressure_N_m2,
                    s.specular_reflectivity,
                    s.diffuse_reflectivity,
                    lit,
                )
            else:
                axis = dipole_axis(
                    time_s,
                    math.radians(s.dipole_tilt_deg),
                    math.radians(s.dipole_longitude_deg),
                    math.radians(s.greenwich_angle_deg),
                )
                field = dipole_field_T(r_N, axis, s.field_equator_T, self.earth_radius_m)
                out[name] = magnetic_torque(s.residual_dipole_Am2, matvec(to_body, field))
        return out

    def total(
        self,
        time_s: Any,
        dcm_NB: Any,
        inertia_kgm2: Any,
        array_angles_rad: list[Any] | None = None,
    ) -> Vector:
        """The sum of the switched-on torques [N m], body axes (zero when none)."""
        casadi = symbolic(time_s, dcm_NB, inertia_kgm2, *(array_angles_rad or []))
        total = zeros(casadi)
        for torque in self.torques(time_s, dcm_NB, inertia_kgm2, array_angles_rad).values():
            total = total + torque
        return total

    def function(self) -> ca.Function:
        """``environment(t, dcm_NB, J, angles) -> tau`` as a CasADi Function (SX).

        ``angles`` holds theta_SA of each array (size 0 without arrays).
        """
        t = ca.SX.sym("t")
        dcm = ca.SX.sym("dcm_NB", 3, 3)
        inertia = ca.SX.sym("J", 3, 3)
        angles = ca.SX.sym("angles", len(self.problem.arrays))
        tau = self.total(t, dcm, inertia, [angles[i] for i in range(angles.numel())])
        return ca.Function(
            "environment", [t, dcm, inertia, angles], [tau], ["t", "dcm_NB", "J", "angles"], ["tau"]
        )
