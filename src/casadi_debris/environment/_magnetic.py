"""The Earth's dipole field and the torque on a residual magnetic dipole.

The field of a dipole whose northern pole (where field lines enter the Earth)
points along the unit vector ``k`` is

    B(r) = B0 (R / |r|)^3 [k - 3 (k . r_hat) r_hat]

(B0 the field at the equator's surface, R the Earth's radius): B0 k at the
magnetic equator, -2 B0 k over the northern magnetic pole. ``k`` turns with the
Earth: at colatitude ``theta_m`` and east longitude ``phi_m``,

    k_N(t) = [sin theta_m cos a(t), sin theta_m sin a(t), cos theta_m],
    a(t) = phi_m + theta_G0 + omega_E t

(theta_G0 the Greenwich angle at t = 0; theta_m = 0 aligns the dipole with the
spin axis). A residual dipole m
(A m^2) in that field feels the torque m x B.
"""

from __future__ import annotations

import math
from typing import Any

from casadi_debris.environment._algebra import (
    Vector,
    as_vector,
    cross,
    dot,
    norm,
    stack,
    symbolic,
    trig,
)
from casadi_debris.environment._orbit import EARTH_ROTATION_RAD_S


def dipole_axis(
    time_s: Any, tilt_rad: float, longitude_rad: float, greenwich_at_zero_rad: float = 0.0
) -> Vector:
    """k_N(t): unit vector to the dipole's northern pole, inertial axes."""
    cos_a, sin_a = trig(longitude_rad + greenwich_at_zero_rad + EARTH_ROTATION_RAD_S * time_s)
    sin_t = math.sin(tilt_rad)
    return stack([sin_t * cos_a, sin_t * sin_a, math.cos(tilt_rad)])


def dipole_field_T(
    r_m: Vector, axis: Vector, field_equator_T: float, earth_radius_m: float
) -> Vector:
    """B = B0 (R/|r|)^3 [k - 3 (k . r_hat) r_hat] in tesla, in the axes of ``r_m`` and ``axis``.

    Parameters
    ----------
    r_m : vector
        Position from the Earth's centre [m].
    axis : vector
        Unit vector k to the dipole's northern pole, same axes.
    field_equator_T : float
        B0.
    earth_radius_m : float
        R.
    """
    casadi = symbolic(r_m, axis)
    r_m, axis = as_vector(r_m, casadi), as_vector(axis, casadi)
    radius = norm(r_m)
    r_hat = r_m / radius
    return (
        field_equator_T * (earth_radius_m / radius) ** 3 * (axis - 3.0 * dot(axis, r_hat) * r_hat)
    )


def magnetic_torque(dipole_Am2: Vector, field_T: Vector) -> Vector:
    """m x B [N m], both in body axes."""
    return cross(dipole_Am2, field_T)
