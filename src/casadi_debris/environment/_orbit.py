"""A circular Keplerian orbit: position and velocity in the inertial frame, and the LVLH frame.

The inertial frame N is the Earth-centred one of the problem (x to the vernal
equinox, z along the Earth's spin axis). A circular orbit of radius ``a`` with
inclination ``i``, right ascension of the ascending node ``Omega`` and argument
of latitude ``u(t) = u0 + n t`` (mean motion ``n = sqrt(mu / a^3)``) is

    r_N(t) = a Q [cos u, sin u, 0],   v_N(t) = a n Q [-sin u, cos u, 0],
    Q = R3(-Omega) R1(-i)

(Q's columns: the node direction, the in-plane normal to it, the orbit normal).
The LVLH frame O has o3 towards the Earth's centre (nadir), o2 against the
orbit normal and o1 = o2 x o3 along the velocity.

Times may be floats, numpy arrays of shape (n,) (positions then (n, 3)) or
CasADi symbols (columns (3, 1)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from casadi_debris.config import Problem
from casadi_debris.environment._algebra import symbolic
from casadi_debris.units import M_PER_KM

EARTH_ROTATION_RAD_S = 7.2921159e-5
"""The Earth's spin rate (sidereal day 86 164.1 s) [rad/s]."""


def _rotation_x(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _rotation_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@dataclass(frozen=True)
class CircularOrbit:
    """A circular orbit propagated analytically.

    Attributes
    ----------
    radius_m : float
        From the Earth's centre.
    inclination_rad, raan_rad : float
    argument_of_latitude_rad : float
        From the ascending node at t = 0.
    mu_m3_s2 : float
        The Earth's gravitational parameter.

    Example
    -------
    >>> orbit = CircularOrbit(radius_m=7_063_137.0, inclination_rad=1.712)
    >>> round(orbit.period_s / 60.0, 1)
    98.5
    """

    radius_m: float
    inclination_rad: float
    raan_rad: float = 0.0
    argument_of_latitude_rad: float = 0.0
    mu_m3_s2: float = 3.986004418e14

    @classmethod
    def from_problem(cls, problem: Problem) -> CircularOrbit:
        """The problem's ``[orbit]`` above its ``[constants]`` Earth."""
        orbit, constants = problem.orbit, problem.constants
        return cls(
            radius_m=(constants.earth_radius_km + orbit.altitude_km) * M_PER_KM,
            inclination_rad=math.radians(orbit.inclination_deg),
            raan_rad=math.radians(orbit.raan_deg),
            argument_of_latitude_rad=math.radians(orbit.argument_of_latitude_deg),
            mu_m3_s2=constants.earth_mu_km3_s2 * M_PER_KM**3,
        )

    @property
    def mean_motion_rad_s(self) -> float:
        """n = sqrt(mu / a^3)."""
        return math.sqrt(self.mu_m3_s2 / self.radius_m**3)

    @property
    def period_s(self) -> float:
        """2 pi / n."""
        return 2.0 * math.pi / self.mean_motion_rad_s

    @property
    def speed_m_s(self) -> float:
        """Circular speed a n."""
        return self.radius_m * self.mean_motion_rad_s

    @property
    def plane(self) -> np.ndarray:
        """Q = R3(-Omega) R1(-i) (written as rotations taking the orbit plane to N), (3, 3)."""
        return _rotation_z(self.raan_rad) @ _rotation_x(self.inclination_rad)

    @property
    def normal(self) -> np.ndarray:
        """Unit orbit normal r x v / |r x v| in N, shape (3,)."""
        return self.plane[:, 2]

    def argument_of_latitude(self, time_s: Any) -> Any:
        """u(t) = u0 + n t [rad]."""
        return self.argument_of_latitude_rad + self.mean_motion_rad_s * time_s

    def position_m(self, time_s: Any) -> Any:
        """r_N(t): (3,) for a float, (n, 3) for an array, (3, 1) for a CasADi symbol."""
        return self._in_plane(time_s, self.radius_m, phase=0.0)

    def velocity_m_s(self, time_s: Any) -> Any:
        """v_N(t), shaped as :meth:`position_m`."""
        return self._in_plane(time_s, self.speed_m_s, phase=math.pi / 2)

    def _in_plane(self, time_s: Any, length: float, phase: float) -> Any:
        u = self.argument_of_latitude(time_s) + phase
        if symbolic(time_s):
            return length * ca.mtimes(ca.DM(self.plane[:, :2]), ca.vertcat(ca.cos(u), ca.sin(u)))
        u = np.asarray(u, dtype=float)
        in_plane = np.stack([np.cos(u), np.sin(u)], axis=-1)
        return length * in_plane @ self.plane[:, :2].T

    def lvlh_matrix(self, time_s: float) -> np.ndarray:
        """C_ON: rows o1 (along track), o2 (anti-normal), o3 (nadir) in N, shape (3, 3).

        ``C_ON @ w_N`` gives the LVLH components of a vector w.
        """
        position = np.asarray(self.position_m(float(time_s)))
        o3 = -position / np.linalg.norm(position)
        o2 = -self.normal
        return np.array([np.cross(o2, o3), o2, o3])
