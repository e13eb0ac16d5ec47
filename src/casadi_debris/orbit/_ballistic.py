"""The debris' ballistic coefficient B = m / (C_D A) from its faces.

The drag area is that of the faces :func:`~casadi_debris.environment.debris_panels`
gives the aerodynamic torque (the hub's six faces, both faces of every array at
its angle), with the same free-molecular model and the same omissions (no
shadowing, the CubeSats' own faces left out): a face of area A and outward
normal n meets the flow (unit velocity of the debris relative to the air,
body axes, v) with ``A max(0, n . v)``.

- Held attitude: the sum of that over the faces, for the given v.
- Tumbling (every direction equally likely): the mean of ``max(0, n . v)``
  over the sphere is 1/4, so the mean area is the faces' total area over 4 (for a
  convex body, its surface over 4, Cauchy's formula; an array counts both faces,
  so half its one-sided area).

C_D defaults to the problem's ``[environment] drag_coefficient`` (2.2, the usual
free-molecular value for a compact satellite, e.g. Vallado, *Fundamentals of
Astrodynamics*, 4th ed., sec. 8.6.2). The mass is the combined body's, CubeSats
included.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.environment import debris_panels
from casadi_debris.errors import InputShapeError
from casadi_debris.geometry import Geometry, build_geometry

Attitude = Literal["tumbling", "held"]


@dataclass(frozen=True)
class Ballistic:
    """What drag sees of the debris.

    Attributes
    ----------
    attitude : {"tumbling", "held"}
    area_m2 : float
        Mean (tumbling) or projected (held) drag area.
    mass_kg : float
    drag_coefficient : float
    """

    attitude: str
    area_m2: float
    mass_kg: float
    drag_coefficient: float

    @property
    def coefficient_kg_m2(self) -> float:
        """B = m / (C_D A) [kg/m^2]."""
        return self.mass_kg / (self.drag_coefficient * self.area_m2)

    def with_mass(self, mass_kg: float) -> Ballistic:
        """The same faces with another mass (propellant burnt, CubeSats added)."""
        return Ballistic(self.attitude, self.area_m2, mass_kg, self.drag_coefficient)


def drag_area_m2(
    problem: Problem, geometry: Geometry, flow_body: np.ndarray | None = None
) -> float:
    """Drag area of the debris' faces [m^2]: mean over tumbling, or for one flow direction.

    Parameters
    ----------
    problem : Problem
    geometry : Geometry
        Of ``problem``.
    flow_body : ndarray, shape (3,), optional
        Direction of the debris' velocity relative to the air in body axes
        (held attitude); None for a tumbling body.
    """
    panels = debris_panels(problem, geometry)
    if flow_body is None:
        return sum(panel.area_m2 for panel in panels) / 4.0
    flow = np.asarray(flow_body, dtype=float)
    if flow.shape != (3,) or not np.all(np.isfinite(flow)) or np.linalg.norm(flow) == 0.0:
        raise InputShapeError(f"flow direction: a non-zero 3-vector, got {flow_body!r}")
    flow = flow / np.linalg.norm(flow)
    return float(
        sum(panel.area_m2 * max(0.0, float(np.dot(panel.normal, flow))) for panel in panels)
    )


def ballistic(
    problem: Problem,
    *,
    geometry: Geometry | None = None,
    flow_body: np.ndarray | None = None,
    drag_coefficient: float | None = None,
    mass_kg: float | None = None,
) -> Ballistic:
    """The debris' drag area, mass and C_D.

    Parameters
    ----------
    problem : Problem
    geometry : Geometry, optional
    flow_body : ndarray, shape (3,), optional
        Held attitude: the flow direction in body axes; None: tumbling.
    drag_coefficient : float, optional
        Default the problem's ``[environment] drag_coefficient``.
    mass_kg : float, optional
        Default the combined body's.

    Example
    -------
    >>> from casadi_debris import load_problem
    >>> b = ballistic(load_problem())
    >>> round(b.area_m2, 2), round(b.coefficient_kg_m2, 1)
    (8.0, 38.0)
    """
    geometry = geometry or build_geometry(problem)
    cd = problem.environment.drag_coefficient if drag_coefficient is None else drag_coefficient
    if not np.isfinite(cd) or cd <= 0.0:
        raise InputShapeError(f"drag coefficient: a positive number, got {cd!r}")
    return Ballistic(
        attitude="tumbling" if flow_body is None else "held",
        area_m2=drag_area_m2(problem, geometry, flow_body),
        mass_kg=geometry.mass_kg if mass_kg is None else float(mass_kg),
        drag_coefficient=float(cd),
    )
