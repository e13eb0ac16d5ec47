"""Attitude: quaternions, rotations and the attitude error.

Conventions (DESIGN.md)
-----------------------
- Quaternions are scalar first, q = [cos(Theta / 2), sin(Theta / 2) e] for a
  rotation by Theta about the unit axis e, and compose by the Hamilton product
  a (x) b. The attitude q_BN takes B components to N components through
  :func:`rotation_matrix`.
- The attitude error of q relative to a reference q_ref is the vector part of
  the error quaternion q_ref^-1 (x) q, doubled, with the sign that takes the
  short way round (error scalar part >= 0):

      e = 2 sign(dq_0) dq_vec,   dq = q_ref^-1 (x) q,

  which equals the small rotation angles [Phi, Theta, Psi] (rad) for small
  errors and stays well defined for a 180 deg error.

Symbolic (CasADi SX), for the model's equations: :func:`quaternion_product`,
:func:`quaternion_conjugate`, :func:`attitude_error_vector`, :func:`rotation_matrix`.
"""

from __future__ import annotations

import casadi as ca


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
