"""A plain rigid body for the slew functions: an inertia and a per-axis torque box.

The slew functions take either a :class:`~casadi_debris.config.Problem` (the
debris and its swarm, from which the model, the engines and their torque box
follow) or a :class:`RigidBody` (an inertia matrix and the torque bounds about
each body axis, nothing else), so that a GNC engineer can hand them any body
without writing a problem file.

Equations (Wie, *Space Vehicle Dynamics and Control*, 2nd ed., Sec. 6.3),
body frame B, quaternion scalar first:

    q_dot = 1/2 q (x) [0, omega],   J omega_dot = tau - omega x J omega,
    tau_min,i <= tau_i <= tau_max,i.

Both slew engines scale these: time by a reference time T_s (the eigenaxis
limit of the slew, :mod:`casadi_debris.slews._maneuver`), rates by 1 / T_s and
each torque by its axis' largest bound s_i = max(tau_max,i, -tau_min,i), so
that with w = omega T_s and u_i = tau_i / s_i

    dq/dtau = 1/2 q (x) [0, w],   dw/dtau = T_s^2 J^-1 S u - J^-1 (w x J w),

whose numbers are of order one for any body (:func:`scaled_rigid_ode`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import casadi as ca
import numpy as np

from casadi_debris.dynamics import quaternion_product
from casadi_debris.errors import InputShapeError

# Relative slack of the checks on a measured inertia (symmetry, triangle inequality).
INERTIA_TOLERANCE = 1e-9
N_RIGID_STATE = 7  # q (4), omega (3)


@dataclass(frozen=True)
class RigidBody:
    """A rigid body and the torque box of its actuators.

    Parameters
    ----------
    inertia_kgm2 : array_like, shape (3, 3)
        Inertia about the centre of mass in body axes, kg m^2: symmetric, positive
        definite, principal moments meeting the triangle inequality.
    torque_max_Nm : sequence of 3 floats
        Largest torque about +x, +y, +z, N m (> 0).
    torque_min_Nm : sequence of 3 floats, optional
        Most negative torque about each axis, N m (< 0); default ``-torque_max_Nm``.

    Raises
    ------
    InputShapeError
        A field of the wrong shape, not finite, or unphysical, naming it.

    Examples
    --------
    >>> body = RigidBody(inertia_kgm2=np.eye(3), torque_max_Nm=(1, 1, 1))
    >>> body.lower_Nm
    array([-1., -1., -1.])
    """

    inertia_kgm2: np.ndarray
    torque_max_Nm: np.ndarray
    torque_min_Nm: np.ndarray | None = None

    def __post_init__(self) -> None:
        inertia = _finite_array("inertia_kgm2", self.inertia_kgm2, (3, 3))
        _check_inertia(inertia)
        upper = _finite_array("torque_max_Nm", self.torque_max_Nm, (3,))
        if np.any(upper <= 0.0):
            raise InputShapeError(f"torque_max_Nm: every bound must be > 0, got {upper.tolist()}")
        if self.torque_min_Nm is None:
            lower = -upper
        else:
            lower = _finite_array("torque_min_Nm", self.torque_min_Nm, (3,))
            if np.any(lower >= 0.0):
                raise InputShapeError(
                    f"torque_min_Nm: every bound must be < 0, got {lower.tolist()}"
                )
        # Frozen: the validated copies replace what was given (lists become arrays).
        object.__setattr__(self, "inertia_kgm2", inertia)
        object.__setattr__(self, "torque_max_Nm", upper)
        object.__setattr__(self, "torque_min_Nm", lower)

    @property
    def lower_Nm(self) -> np.ndarray:
        """Most negative torque per axis, N m, shape (3,)."""
        return -self.torque_max_Nm if self.torque_min_Nm is None else self.torque_min_Nm

    @property
    def upper_Nm(self) -> np.ndarray:
        """Largest torque per axis, N m, shape (3,)."""
        return self.torque_max_Nm

    @property
    def torque_scale_Nm(self) -> np.ndarray:
        """s_i = max(tau_max,i, -tau_min,i), N m, shape (3,): the unit of each scaled torque."""
        return np.maximum(self.upper_Nm, -self.lower_Nm)

    def scaled(self, torque_fraction: float) -> RigidBody:
        """The same body with ``torque_fraction`` (in (0, 1]) of each bound."""
        return RigidBody(
            self.inertia_kgm2, torque_fraction * self.upper_Nm, torque_fraction * self.lower_Nm
        )


def _finite_array(
    name: str, value: Sequence[float] | np.ndarray, shape: tuple[int, ...]
) -> np.ndarray:
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InputShapeError(f"{name}: expected numbers of shape {shape}, got {value!r}") from None
    if array.shape != shape:
        raise InputShapeError(f"{name}: expected shape {shape}, got {array.shape}")
    if not np.all(np.isfinite(array)):
        raise InputShapeError(f"{name}: must be finite, got {array.tolist()}")
    return array


def _check_inertia(inertia: np.ndarray) -> None:
    """Raise unless ``inertia`` is symmetric, positive definite and physically possible."""
    size = float(np.max(np.abs(inertia)))
    if size == 0.0 or np.max(np.abs(inertia - inertia.T)) > INERTIA_TOLERANCE * size:
        raise InputShapeError("inertia_kgm2: must be symmetric and non-zero")
    moments = np.linalg.eigvalsh(inertia)
    if moments[0] <= 0.0:
        raise InputShapeError(
            f"inertia_kgm2: must be positive definite, principal moments {moments.tolist()}"
        )
    if moments[0] + moments[1] < moments[2] * (1.0 - INERTIA_TOLERANCE):
        raise InputShapeError(
            "inertia_kgm2: principal moments violate the triangle inequality "
            f"(I1 + I2 >= I3), got {moments.tolist()}"
        )


def scaled_rigid_ode(body: RigidBody, time_scale_s: float) -> ca.Function:
    """The scaled equations of motion (module notes) as a CasADi Function.

    Parameters
    ----------
    body : RigidBody
    time_scale_s : float
        T_s, s (> 0).

    Returns
    -------
    casadi.Function
        ``ode(x, u) -> xdot``: x = [q (4), w = omega T_s (3)], u = tau / s (3), the
        derivative with respect to tau = t / T_s.
    """
    if not math.isfinite(time_scale_s) or time_scale_s <= 0.0:
        raise InputShapeError(f"time_scale_s: must be > 0, got {time_scale_s}")
    x = ca.SX.sym("x", N_RIGID_STATE)
    u = ca.SX.sym("u", 3)
    inertia = ca.DM(body.inertia_kgm2)
    inverse = ca.DM(np.linalg.inv(body.inertia_kgm2))
    drive = ca.DM(
        time_scale_s**2 * np.linalg.inv(body.inertia_kgm2) @ np.diag(body.torque_scale_Nm)
    )
    q, w = x[0:4], x[4:7]
    q_dot = 0.5 * quaternion_product(q, ca.vertcat(0, w))
    w_dot = drive @ u - inverse @ ca.cross(w, inertia @ w)
    return ca.Function("rigid_ode", [x, u], [ca.vertcat(q_dot, w_dot)], ["x", "u"], ["xdot"])
