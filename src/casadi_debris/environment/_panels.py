"""The debris as flat plates, and the aerodynamic and solar-pressure torques on them.

The hub is a box of six faces; every array is a thin plate with two faces (its
normal at the array's angle theta_SA and the opposite). A face has an area A,
an outward unit normal n and a centre c (body axes, from the centre of
gravity); the force on it acts at c. Shadowing of one face by another (the
arrays by the hub, the hub by the arrays or the CubeSats) is left out: every
face that looks into the flow or the light takes its full force. The CubeSats'
own faces are left out too.

Aerodynamic (free-molecular, flow along the velocity v of the debris relative
to the atmosphere, body axes), for each face with cos a = n . v_hat > 0:

    F = -1/2 rho C_D |v|^2 A cos a v_hat

Solar radiation pressure (Wertz, eq. 17-49; s the unit vector to the Sun, body
axes, P the pressure, rho_s and rho_d the specular and diffuse
reflectivities), for each face with cos b = n . s > 0:

    F = -P A cos b [(1 - rho_s) s + 2 (rho_s cos b + rho_d / 3) n]

The torque is the sum of c x F over the faces.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.environment._algebra import (
    Vector,
    as_vector,
    cross,
    dot,
    norm,
    positive_part,
    symbolic,
    zeros,
)
from casadi_debris.geometry import Geometry, array_axes


@dataclass(frozen=True)
class Panel:
    """One flat face.

    Attributes
    ----------
    name : str
        E.g. ``hub +x``, ``array 1 front``.
    area_m2 : float
    normal : vector
        Outward unit normal, body axes (an array face's may be a CasADi
        expression of its angle).
    centre_m : ndarray, shape (3,)
        Centre of pressure from the centre of gravity, body axes.
    """

    name: str
    area_m2: float
    normal: Any
    centre_m: np.ndarray


def debris_panels(
    problem: Problem, geometry: Geometry, array_angles_rad: list[Any] | None = None
) -> tuple[Panel, ...]:
    """The hub's six faces and both faces of every array.

    Parameters
    ----------
    problem : Problem
    geometry : Geometry
        Of ``problem`` (the centre of gravity and the hinges).
    array_angles_rad : list of float or casadi scalar, optional
        theta_SA of each array (default the problem's angles).
    """
    size = problem.hub.size_m
    centre = 0.5 * size - geometry.cog_corner_m  # the box's centre from the CoG
    panels = []
    for axis in range(3):
        others = [a for a in range(3) if a != axis]
        area = float(size[others[0]] * size[others[1]])
        for sign, label in ((1.0, "+"), (-1.0, "-")):
            outward = np.zeros(3)
            outward[axis] = sign
            face = centre + 0.5 * size[axis] * outward
            panels.append(Panel(f"hub {label}{'xyz'[axis]}", area, outward, face))
    for index, array in enumerate(problem.arrays):
        angle = np.radians(array.angle_deg) if array_angles_rad is None else array_angles_rad[index]
        _, _, plate_normal = array_axes(array.direction, angle)
        normal: Any = (
            plate_normal if symbolic(angle) else np.asarray(plate_normal, dtype=float).ravel()
        )
        middle = geometry.hinges_m[index] + 0.5 * array.length_m * array.direction
        area = float(array.length_m * array.width_m)
        panels.append(Panel(f"array {index + 1} front", area, normal, middle))
        panels.append(Panel(f"array {index + 1} back", area, -normal, middle))
    return tuple(panels)


def aerodynamic_torque(
    panels: tuple[Panel, ...],
    velocity_m_s: Vector,
    density_kg_m3: float,
    drag_coefficient: float,
) -> Vector:
    """Sum of c x F of the free-molecular drag on every face looking into the flow [N m].

    Parameters
    ----------
    panels : tuple of Panel
    velocity_m_s : vector
        Velocity of the debris relative to the atmosphere, body axes.
    density_kg_m3, drag_coefficient : float
    """
    casadi = symbolic(velocity_m_s, *(p.normal for p in panels))
    speed = norm(velocity_m_s)
    flow = as_vector(velocity_m_s, casadi) / speed
    torque = zeros(casadi)
    for panel in panels:
        facing = positive_part(dot(as_vector(panel.normal, casadi), flow))
        force = -0.5 * density_kg_m3 * drag_coefficient * speed**2 * panel.area_m2 * facing * flow
        torque = torque + cross(as_vector(panel.centre_m, casadi), force)
    return torque


def solar_pressure_torque(
    panels: tuple[Panel, ...],
    sun: Vector,
    pressure_N_m2: float,
    specular_reflectivity: float,
    diffuse_reflectivity: float,
    sunlit: Any = 1.0,
) -> Vector:
    """Sum of c x F of the sunlight's pressure on every lit face [N m].

    Parameters
    ----------
    panels : tuple of Panel
    sun : vector
        Unit vector to the Sun, body axes.
    pressure_N_m2 : float
        At the debris' distance from the Sun (4.56e-6 at 1 AU).
    specular_reflectivity, diffuse_reflectivity : float
        Fractions of the light reflected; the rest is absorbed.
    sunlit : float or casadi scalar
        1 in sunlight, 0 in the Earth's shadow.
    """
    casadi = symbolic(sun, sunlit, *(p.normal for p in panels))
    s = as_vector(sun, casadi)
    torque = zeros(casadi)
    for panel in panels:
        normal = as_vector(panel.normal, casadi)
        lit = positive_part(dot(normal, s))
        push = (1.0 - specular_reflectivity) * s + 2.0 * (
            specular_reflectivity * lit + diffuse_reflectivity / 3.0
        ) * normal
        force = -pressure_N_m2 * panel.area_m2 * lit * push
        torque = torque + cross(as_vector(panel.centre_m, casadi), force)
    return sunlit * torque
