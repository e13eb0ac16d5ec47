"""Physical checks shared by the table readers and the commands: inertia, points on hub
faces, the transfer ending on the debris' orbit."""

from __future__ import annotations

import numpy as np

from casadi_debris.config._schema import AXIS_NAMES, Problem
from casadi_debris.config._table import Table
from casadi_debris.config.limits import PRINCIPAL_INERTIA_KGM2
from casadi_debris.errors import ProblemFileError

TRIANGLE_TOLERANCE = 0.02


def check_inertia(inertia: np.ndarray, key: str, source: str | None = None) -> None:
    """Raise unless ``inertia`` is a physical rigid-body inertia.

    Parameters
    ----------
    inertia : ndarray, shape (3, 3) or (3,)
        Full matrix, or principal moments [kg m^2].
    key : str
        Dotted name for the message.

    Raises
    ------
    ProblemFileError
        Not symmetric, not positive definite, a principal moment below
        ``limits.PRINCIPAL_INERTIA_KGM2.low``, or principal moments violating
        the triangle inequality (I1 <= I2 + I3 for every permutation) by more
        than ``TRIANGLE_TOLERANCE``: a thin plate sits on the equality, and
        published values are rounded (the paper's array, 80 > 17 + 62, is one).
    """
    matrix = np.diag(inertia) if inertia.ndim == 1 else inertia
    scale = float(np.max(np.abs(matrix)))
    if not np.allclose(matrix, matrix.T, rtol=0.0, atol=1e-9 * scale):
        raise ProblemFileError(key, "inertia must be symmetric", source)
    moments = np.linalg.eigvalsh(matrix)
    if moments[0] <= 0:
        raise ProblemFileError(
            key, f"inertia must be positive definite (principal moments {moments})", source
        )
    if moments[0] < PRINCIPAL_INERTIA_KGM2.low:
        raise ProblemFileError(
            key,
            f"smallest principal moment {moments[0]:.3g} kg m^2 is below "
            f"{PRINCIPAL_INERTIA_KGM2.low:g} (the model inverts the inertia)",
            source,
        )
    if moments[2] > (moments[0] + moments[1]) * (1.0 + TRIANGLE_TOLERANCE):
        raise ProblemFileError(
            key,
            "principal moments violate the triangle inequality "
            f"({moments[2]:.4g} > {moments[0]:.4g} + {moments[1]:.4g})",
            source,
        )


def _faces_holding(point: np.ndarray, hub_size: np.ndarray) -> list[tuple[int, float]]:
    """The hub faces (axis, outward sign) the point lies on, within round-off."""
    tolerance = 1e-9 * float(np.max(hub_size))
    inside = [-tolerance <= point[a] <= hub_size[a] + tolerance for a in range(3)]
    faces = []
    for axis in range(3):
        others = [a for a in range(3) if a != axis]
        if not all(inside[a] for a in others):
            continue
        if abs(point[axis]) <= tolerance:
            faces.append((axis, -1.0))
        if abs(point[axis] - hub_size[axis]) <= tolerance:
            faces.append((axis, +1.0))
    return faces


def check_on_surface(
    t: Table, name: str, point: np.ndarray, direction: np.ndarray, hub_size: np.ndarray
) -> None:
    """A hinge must sit on a hub face, and its array extend outward from that face.

    Raises naming ``name`` (the hinge) when the point is on no face, and
    ``direction`` when the array would extend into the hub.
    """
    faces = _faces_holding(point, hub_size)
    spans = f"(hub spans 0 .. {hub_size.tolist()} m)"
    if not faces:
        raise t.error(t.key(name), f"{point.tolist()} m is not on the hub's surface {spans}")
    if not any(sign * direction[axis] > 1e-9 for axis, sign in faces):
        raise t.error(
            t.key("direction"),
            f"{direction.tolist()} does not point out of the hub from the hinge at "
            f"{point.tolist()} m; an array extends outward from the face its hinge is on",
        )


def check_outside_hub(
    t: Table, name: str, point: np.ndarray, face: str | None, hub_size: np.ndarray
) -> None:
    """A CubeSat's CoG cannot lie inside the hub, and lies on or beyond its ``face`` if given."""
    tolerance = 1e-9 * float(np.max(hub_size))
    if np.all(point > tolerance) and np.all(point < hub_size - tolerance):
        raise t.error(
            t.key(name), f"{point.tolist()} m lies inside the hub (0 .. {hub_size.tolist()} m)"
        )
    if face is None:
        return
    axis = AXIS_NAMES.index(face[1])
    plane = hub_size[axis] if face[0] == "+" else 0.0
    beyond = point[axis] >= plane - tolerance if face[0] == "+" else point[axis] <= tolerance
    others = [a for a in range(3) if a != axis]
    within = all(-tolerance <= point[a] <= hub_size[a] + tolerance for a in others)
    if not (beyond and within):
        raise t.error(
            t.key(name),
            f"{point.tolist()} m is not on or above the hub face {face} "
            f"(hub spans 0 .. {hub_size.tolist()} m)",
        )


# The transfer's end and the debris' orbit are one orbit written twice (to round-off).
TRANSFER_END_TOLERANCE = 1e-9


def check_transfer_end(problem: Problem) -> None:
    """Raise unless the ``[transfer]`` ends on the debris' ``[orbit]``.

    The transfer brings the CubeSats to the debris, so its end and the debris' orbit are
    the same orbit written twice; a problem that changes one and not the other would
    charge a transfer to where the debris is not.

    Raises
    ------
    ProblemFileError
        ``transfer.to_altitude_km`` or ``transfer.to_inclination_deg`` differs from
        ``orbit.altitude_km`` or ``orbit.inclination_deg``.
    """
    transfer, orbit = problem.transfer, problem.orbit
    pairs = (
        ("altitude_km", "km", transfer.to_altitude_km, orbit.altitude_km),
        ("inclination_deg", "deg", transfer.to_inclination_deg, orbit.inclination_deg),
    )
    for name, unit, end, debris in pairs:
        if abs(end - debris) > TRANSFER_END_TOLERANCE * max(1.0, abs(debris)):
            raise ProblemFileError(
                f"transfer.to_{name}",
                f"is {end:g} {unit} but the debris' orbit.{name} is {debris:g} {unit}; the "
                "transfer ends at the debris' orbit: give both the same value",
                problem.source,
            )
