"""The Sun's direction over a year and the Earth's cylindrical shadow.

The Sun moves along the ecliptic at a uniform rate (a circular Earth orbit, the
equation of centre's 2 deg left out):

    lambda(t) = lambda0 + 2 pi t / year,
    s_N = [cos lambda, cos eps sin lambda, sin eps sin lambda],   eps = 23.44 deg,

the same direction seen from the Earth and from the debris (the parallax is
below 2e-4 rad). The debris is in the Earth's shadow when it is behind the
Earth (r . s < 0) within one Earth radius of the Earth-Sun line (a cylinder:
penumbra and the umbra's taper left out).
"""

from __future__ import annotations

import math
from typing import Any

from casadi_debris.environment._algebra import Vector, cross, dot, norm, select, stack, trig

OBLIQUITY_RAD = math.radians(23.44)
"""The tilt of the ecliptic to the equator."""
YEAR_S = 365.25 * 86_400.0
SOLAR_PRESSURE_N_M2 = 4.56e-6
"""The sunlight's pressure on an absorbing surface at 1 AU (1361 W/m^2 / c) [N/m^2]."""


def sun_direction(time_s: Any, longitude_at_zero_rad: float = 0.0) -> Vector:
    """Unit vector from the Earth (and the debris) to the Sun, inertial axes.

    Parameters
    ----------
    time_s : float or casadi scalar
    longitude_at_zero_rad : float
        Ecliptic longitude of the Sun at t = 0 (0: vernal equinox).
    """
    cos_l, sin_l = trig(longitude_at_zero_rad + 2.0 * math.pi * time_s / YEAR_S)
    return stack([cos_l, math.cos(OBLIQUITY_RAD) * sin_l, math.sin(OBLIQUITY_RAD) * sin_l])


def sunlit(r_m: Vector, sun: Vector, earth_radius_m: float) -> Any:
    """1 in sunlight, 0 in the Earth's cylindrical shadow.

    Parameters
    ----------
    r_m : vector
        Position from the Earth's centre.
    sun : vector
        Unit vector to the Sun, same axes.
    earth_radius_m : float
    """
    behind = dot(r_m, sun) < 0.0
    inside = norm(cross(r_m, sun)) < earth_radius_m
    return select(behind * inside, 0.0, 1.0)
