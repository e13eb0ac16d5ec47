"""The gravity-gradient torque on a rigid body.

For a body of inertia I (about its centre of gravity) at r from the Earth's
centre, the first-order torque of the Earth's point-mass field is

    tau = 3 mu / |r|^5  r x (I r)  =  3 mu / |r|^3  o3 x (I o3),   o3 = -r / |r|,

all in body components (Wertz, *Spacecraft Attitude Determination and
Control*, eq. 17-34; Hughes, *Spacecraft Attitude Dynamics*, ch. 8).
"""

from __future__ import annotations

from typing import Any

from casadi_debris.environment._algebra import Vector, cross, matvec, norm

EARTH_MU_M3_S2 = 3.986004418e14
"""The Earth's gravitational parameter (WGS 84) [m^3/s^2]."""


def gravity_gradient_torque(
    inertia_kgm2: Any, r_m: Vector, *, mu_m3_s2: float = EARTH_MU_M3_S2
) -> Vector:
    """Gravity-gradient torque 3 mu / |r|^5 r x (I r) [N m], body axes.

    Parameters
    ----------
    inertia_kgm2 : ndarray or casadi matrix, shape (3, 3)
        Inertia about the centre of gravity, body axes.
    r_m : ndarray, shape (3,), or casadi column (3, 1)
        Position of the centre of gravity from the Earth's centre, in body axes [m].
    mu_m3_s2 : float
        The Earth's gravitational parameter.

    Returns
    -------
    ndarray, shape (3,), or casadi column (3, 1)
        Numeric for numeric inputs, a CasADi expression when either input is one.

    Example
    -------
    >>> import numpy as np
    >>> r = 7.0e6 * np.array([np.sqrt(0.5), 0.0, np.sqrt(0.5)])
    >>> tau = gravity_gradient_torque(np.diag([100.0, 200.0, 300.0]), r)
    >>> f"{tau[1]:.4g}"
    '-0.0003486'
    """
    radius = norm(r_m)
    return 3.0 * mu_m3_s2 / radius**5 * cross(r_m, matvec(inertia_kgm2, r_m))
