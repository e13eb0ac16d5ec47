"""Physical checks shared by the table readers: inertia and points on hub faces."""

from __future__ import annotations

import numpy as np

from casadi_debris.config.limits import PRINCIPAL_INERTIA_KGM2
from casadi_debris.config.schema import AXIS_NAMES
from casadi_debris.config.table import Table
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


def check_on_face(
    t: Table, name: str, point: np.ndarray, direction: str, hub_size: np.ndarray
) -> None:
    """A hinge must sit on the hub face whose outward normal is its array's direction."""
    axis = AXIS_NAMES.index(direction[1])
    face = hub_size[axis] if direction[0] == "+" else 0.0
    tolerance = 1e-9 * float(np.max(hub_size))
    others = [a for a in range(3) if a != axis]
    on_face = abs(point[axis] - face) <= tolerance and all(
        -tolerance <= point[a] <= hub_size[a] + tolerance for a in others
    )
    if not on_face:
        raise t.error(
            f"{t.path}.{name}",
            f"{list(point)} m is not on the hub face {direction} "
            f"(hub spans 0 .. {list(hub_size)} m); an array extends outward from its face",
        )
