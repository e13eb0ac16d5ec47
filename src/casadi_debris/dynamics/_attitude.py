"""Attitude: quaternions, rotations and the attitude error, symbolic and numeric.

Conventions (DESIGN.md)
-----------------------
- Quaternions are scalar first, q = [cos(Theta / 2), sin(Theta / 2) e] for a
  rotation by Theta about the unit axis e, and compose by the Hamilton product
  a (x) b. The attitude q_BN takes B components to N components through
  :func:`rotation_matrix` (the same matrix as scipy's ``Rotation.as_matrix``).
- The attitude error of q relative to a reference q_ref is the vector part of
  the error quaternion q_ref^-1 (x) q, doubled, with the sign that takes the
  short way round (error scalar part >= 0):

      e = 2 sign(dq_0) dq_vec,   dq = q_ref^-1 (x) q,

  which equals the small rotation angles [Phi, Theta, Psi] (rad) for small
  errors and stays well defined for a 180 deg error.

Two sides, one set of conventions
---------------------------------
- Symbolic (CasADi SX), for the model's equations: :func:`quaternion_product`,
  :func:`quaternion_conjugate`, :func:`attitude_error_vector`,
  :func:`rotation_matrix`.
- Numeric (numpy arrays, scalar first, broadcasting over leading axes), built on
  :class:`scipy.spatial.transform.Rotation`: :func:`quaternion_multiply`,
  :func:`error_quaternion`, :func:`axis_angle_quaternion`, :func:`quaternion_axis_angle`,
  :func:`attitude_error`, :func:`euler_angles_321`, and the kinematics
  :func:`quaternion_rate`. scipy stores quaternions scalar last; the
  conversion happens only in :func:`quaternion_to_rotation` and
  :func:`rotation_to_quaternion`.
"""

from __future__ import annotations

import warnings

import casadi as ca
import numpy as np
import numpy.typing as npt
from scipy.spatial.transform import Rotation

from casadi_debris.errors import InputShapeError

# Column orders between this package's quaternions [w, x, y, z] and scipy's [x, y, z, w].
_SCALAR_LAST = [1, 2, 3, 0]
_SCALAR_FIRST = [3, 0, 1, 2]

# Largest |norm - 1| accepted where a quaternion must be a rotation: rounding in
# stored or computed attitudes passes, a rate [0, omega] or a typo does not.
UNIT_NORM_TOLERANCE = 1e-6


# -- symbolic (CasADi) ---------------------------------------------------------------------


def quaternion_product(a: ca.SX, b: ca.SX) -> ca.SX:
    """Hamilton product a (x) b of scalar-first quaternions, shape (4, 1)."""
    a0, av = a[0], a[1:4]
    b0, bv = b[0], b[1:4]
    return ca.vertcat(a0 * b0 - ca.dot(av, bv), a0 * bv + b0 * av + ca.cross(av, bv))


def quaternion_conjugate(q: ca.SX) -> ca.SX:
    """Inverse of a unit quaternion."""
    return ca.vertcat(q[0], -q[1:4])


def attitude_error_vector(q_reference: ca.SX, q: ca.SX) -> ca.SX:
    """Doubled vector part of q_ref^-1 (x) q, short way round, shape (3, 1).

    Equals the small rotation angles [Phi, Theta, Psi] (rad) from the
    reference to the attitude for small errors; well defined for 180 deg.
    """
    error = quaternion_product(quaternion_conjugate(q_reference), q)
    return 2.0 * ca.if_else(error[0] >= 0, 1.0, -1.0) * error[1:4]


def rotation_matrix(q: ca.SX) -> ca.SX:
    """Direction cosine matrix taking B components to N components, shape (3, 3)."""
    q0, qv = q[0], q[1:4]
    skew = ca.skew(qv)
    return (q0**2 - ca.dot(qv, qv)) * ca.SX.eye(3) + 2 * (qv @ qv.T) + 2 * q0 * skew


# -- numeric (scipy Rotation) --------------------------------------------------------------


def _quaternions(q: npt.ArrayLike, name: str, *, unit: bool = True) -> np.ndarray:
    """``q`` as floats of shape (..., 4), each of unit norm (or, with ``unit=False``,
    not zero), or an error naming it."""
    array = np.asarray(q, dtype=float)
    if array.ndim == 0 or array.shape[-1] != 4:
        raise InputShapeError(f"{name}: expected quaternions of shape (..., 4), got {array.shape}")
    if not np.all(np.isfinite(array)):
        raise InputShapeError(f"{name}: quaternions must be finite")
    norm = np.linalg.norm(array, axis=-1)
    if not unit:
        if np.any(norm == 0.0):
            raise InputShapeError(f"{name}: quaternions must not be zero")
        return array
    deviation = np.abs(norm - 1.0)
    if array.size and float(deviation.max()) > UNIT_NORM_TOLERANCE:
        raise InputShapeError(
            f"{name}: quaternions must have unit norm (off by up to {float(deviation.max()):.3g}); "
            "for q (x) [0, omega] use quaternion_rate"
        )
    return array


def quaternion_to_rotation(q: npt.ArrayLike) -> Rotation:
    """scipy ``Rotation`` of scalar-first quaternions.

    Parameters
    ----------
    q : array_like, shape (4,) or (n, 4)
        Quaternions, scalar first, not zero (scipy normalises them).

    Returns
    -------
    scipy.spatial.transform.Rotation
        One rotation, or a stack of n.
    """
    array = _quaternions(q, "q", unit=False)
    return Rotation.from_quat(array[..., _SCALAR_LAST])


def rotation_to_quaternion(rotation: Rotation) -> np.ndarray:
    """Scalar-first quaternions of a scipy ``Rotation``, shape (4,) or (n, 4).

    The sign is scipy's as it stands (not made canonical), so products keep the
    sign of the Hamilton product.
    """
    return rotation.as_quat()[..., _SCALAR_FIRST]


def _stack(q: np.ndarray) -> Rotation:
    """Rotations of quaternions of shape (..., 4), as one flat stack (scipy < 1.15
    takes at most one leading axis)."""
    return quaternion_to_rotation(q.reshape(-1, 4))


def quaternion_multiply(a: npt.ArrayLike, b: npt.ArrayLike) -> np.ndarray:
    """Hamilton product a (x) b of scalar-first unit quaternions (the rotation b, then a).

    Parameters
    ----------
    a, b : array_like, shape (..., 4)
        Unit quaternions, scalar first; leading axes broadcast.

    Returns
    -------
    ndarray, shape (..., 4)

    Raises
    ------
    InputShapeError
        If a quaternion is not of unit norm (within ``UNIT_NORM_TOLERANCE``):
        the product of rotations is not defined for it. The kinematics
        q (x) [0, omega] / 2 is :func:`quaternion_rate`.
    """
    left, right = np.broadcast_arrays(_quaternions(a, "a"), _quaternions(b, "b"))
    product = rotation_to_quaternion(_stack(left) * _stack(right))
    return product.reshape(left.shape)


def error_quaternion(q_reference: npt.ArrayLike, q: npt.ArrayLike) -> np.ndarray:
    """Error quaternion q_ref^-1 (x) q: the rotation from the reference to q, shape (..., 4).

    Parameters
    ----------
    q_reference, q : array_like, shape (..., 4)
        Unit quaternions, scalar first; leading axes broadcast.
    """
    reference, attitude = np.broadcast_arrays(
        _quaternions(q_reference, "q_reference"), _quaternions(q, "q")
    )
    error = rotation_to_quaternion(_stack(reference).inv() * _stack(attitude))
    return error.reshape(attitude.shape)


def quaternion_rate(q: npt.ArrayLike, omega_rad_s: npt.ArrayLike) -> np.ndarray:
    """Quaternion kinematics q_dot = q (x) [0, omega] / 2, shape (..., 4).

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Attitude q_BN, scalar first.
    omega_rad_s : array_like, shape (..., 3)
        Body rate omega_BN in B (rad/s); leading axes broadcast with ``q``'s.

    Notes
    -----
    Written out rather than composed by scipy: [0, omega] is a rate, not a rotation.
    """
    quaternion = np.asarray(q, dtype=float)
    omega = np.asarray(omega_rad_s, dtype=float)
    if quaternion.ndim == 0 or quaternion.shape[-1] != 4:
        raise InputShapeError(f"q: expected shape (..., 4), got {quaternion.shape}")
    if omega.ndim == 0 or omega.shape[-1] != 3:
        raise InputShapeError(f"omega_rad_s: expected shape (..., 3), got {omega.shape}")
    leading = np.broadcast_shapes(quaternion.shape[:-1], omega.shape[:-1])
    quaternion = np.broadcast_to(quaternion, (*leading, 4))
    omega = np.broadcast_to(omega, (*leading, 3))
    q0, qv = quaternion[..., :1], quaternion[..., 1:]
    scalar = -np.sum(qv * omega, axis=-1, keepdims=True)
    vector = q0 * omega + np.cross(qv, omega)
    return 0.5 * np.concatenate([scalar, vector], axis=-1)


def axis_angle_quaternion(axis: npt.ArrayLike, angle_rad: npt.ArrayLike) -> np.ndarray:
    """Quaternion [cos(angle / 2), sin(angle / 2) axis] of a rotation about ``axis``.

    Parameters
    ----------
    axis : array_like, shape (..., 3)
        Unit axis.
    angle_rad : array_like, shape (...)
        Rotation angle (rad); leading axes broadcast with ``axis``'s.

    Returns
    -------
    ndarray, shape (..., 4)
        Scalar first; its scalar part is negative for angles beyond pi.
    """
    unit_axis = np.asarray(axis, dtype=float)
    if unit_axis.ndim == 0 or unit_axis.shape[-1] != 3:
        raise InputShapeError(f"axis: expected shape (..., 3), got {unit_axis.shape}")
    rotation_vector = np.asarray(angle_rad, dtype=float)[..., None] * unit_axis
    rotation = Rotation.from_rotvec(rotation_vector.reshape(-1, 3))
    return rotation_to_quaternion(rotation).reshape((*rotation_vector.shape[:-1], 4))


def quaternion_axis_angle(q: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Axis and angle of the rotation q, the short way round.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Unit quaternions, scalar first.

    Returns
    -------
    axis : ndarray, shape (..., 3)
        Unit axis (zero where the angle is zero).
    angle_rad : ndarray, shape (...)
        Angle in [0, pi]: q and -q give the same rotation.
    """
    quaternion = _quaternions(q, "q")
    rotation_vector = _stack(quaternion).as_rotvec()
    angle = np.linalg.norm(rotation_vector, axis=-1)
    axis = np.divide(
        rotation_vector,
        angle[:, None],
        out=np.zeros_like(rotation_vector),
        where=angle[:, None] > 0.0,
    )
    leading = quaternion.shape[:-1]
    return axis.reshape((*leading, 3)), angle.reshape(leading)


def attitude_error(q_reference: npt.ArrayLike, q: npt.ArrayLike) -> np.ndarray:
    """Doubled vector part of q_ref^-1 (x) q, short way round, shape (..., 3) (rad).

    The numeric twin of :func:`attitude_error_vector`: the small rotation angles
    [Phi, Theta, Psi] from the reference to the attitude for small errors; at
    exactly 180 deg (error scalar part +-0) the vector part is taken as it is.

    Parameters
    ----------
    q_reference, q : array_like, shape (..., 4)
        Unit quaternions, scalar first; leading axes broadcast.
    """
    error = error_quaternion(q_reference, q)
    return 2.0 * np.where(error[..., :1] >= 0.0, 1.0, -1.0) * error[..., 1:]


def euler_angles_321(quaternion_BN: npt.ArrayLike) -> np.ndarray:
    """Roll, pitch, yaw [Phi, Theta, Psi] (rad) of the 3-2-1 sequence; shape (..., 3).

    rotation_matrix(q_BN) = Rz(Psi) Ry(Theta) Rx(Phi): yaw about z, then pitch
    about the new y, then roll about the newest x (Wie, eq. 5.68 ff.; scipy's
    intrinsic "ZYX"). Yaw and roll in [-pi, pi], pitch in [-pi/2, pi/2]. At pitch
    +-90 deg (gimbal lock) only roll -+ yaw is defined; roll is then given as 0.

    Parameters
    ----------
    quaternion_BN : array_like, shape (..., 4)
        Quaternions, scalar first. They are normalised first, so the angles are
        those of the rotation q / |q| (an OCP's quaternions are of unit norm
        only to its tolerance).
    """
    quaternion = _quaternions(quaternion_BN, "quaternion_BN", unit=False)
    with warnings.catch_warnings():
        # At gimbal lock scipy warns that it sets roll to 0; documented above.
        warnings.filterwarnings("ignore", message="Gimbal lock detected", category=UserWarning)
        yaw_pitch_roll = _stack(quaternion).as_euler("ZYX")
    return yaw_pitch_roll[:, ::-1].reshape((*quaternion.shape[:-1], 3))
