"""The attitude module checked against scipy's Rotation, elementary rotation matrices
and each of its two sides (CasADi and numeric) against the other."""

from __future__ import annotations

import math
import warnings

import casadi as ca
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from casadi_debris.dynamics import (
    attitude_error,
    attitude_error_vector,
    axis_angle_quaternion,
    error_quaternion,
    euler_angles_321,
    quaternion_axis_angle,
    quaternion_conjugate,
    quaternion_multiply,
    quaternion_product,
    quaternion_rate,
    quaternion_to_rotation,
    rotation_matrix,
    rotation_to_quaternion,
)
from casadi_debris.errors import InputShapeError

N_RANDOM = 200
ROUND_OFF = 1e-14

_a, _b = ca.SX.sym("a", 4), ca.SX.sym("b", 4)
PRODUCT = ca.Function("product", [_a, _b], [quaternion_product(_a, _b)])
CONJUGATE = ca.Function("conjugate", [_a], [quaternion_conjugate(_a)])
ERROR = ca.Function("error", [_a, _b], [attitude_error_vector(_a, _b)])
MATRIX = ca.Function("matrix", [_a], [rotation_matrix(_a)])


def casadi_rows(function: ca.Function, *rows: np.ndarray) -> np.ndarray:
    """A CasADi Function of (4, 1) columns evaluated on rows of shape (n, 4), shape (n, k)."""
    return np.array(function.map(len(rows[0]))(*(r.T for r in rows))).T


def random_quaternions(rng: np.random.Generator, n: int = N_RANDOM) -> np.ndarray:
    """Uniform random unit quaternions, scalar first, both signs of the scalar part."""
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def scipy_rotation(q: np.ndarray) -> Rotation:
    """scipy's rotation of scalar-first quaternions (converted here, not by the module)."""
    return Rotation.from_quat(np.roll(q, -1, axis=-1))


def scipy_quaternion(rotation: Rotation) -> np.ndarray:
    return np.roll(rotation.as_quat(), 1, axis=-1)


def elementary(axis: int, angle: float) -> np.ndarray:
    """Matrix of a rotation by ``angle`` about coordinate axis ``axis`` (B to N components)."""
    c, s = math.cos(angle), math.sin(angle)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    matrix = np.eye(3)
    matrix[i, i] = matrix[j, j] = c
    matrix[j, i], matrix[i, j] = s, -s
    return matrix


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20240611)


# -- the CasADi side against scipy ----------------------------------------------------------


def test_casadi_product_is_scipy_composition(rng: np.random.Generator) -> None:
    a, b = random_quaternions(rng), random_quaternions(rng)
    expected = scipy_quaternion(scipy_rotation(a) * scipy_rotation(b))
    np.testing.assert_allclose(casadi_rows(PRODUCT, a, b), expected, atol=ROUND_OFF)


def test_casadi_conjugate_is_scipy_inverse(rng: np.random.Generator) -> None:
    q = random_quaternions(rng)
    inverse = scipy_rotation(q).inv()
    conjugate = casadi_rows(CONJUGATE, q)
    np.testing.assert_allclose(
        scipy_rotation(conjugate).as_matrix(), inverse.as_matrix(), atol=ROUND_OFF
    )


def test_casadi_rotation_matrix_is_scipy_matrix(rng: np.random.Generator) -> None:
    q = random_quaternions(rng)
    matrices = np.array(MATRIX.map(N_RANDOM)(q.T)).T.reshape(N_RANDOM, 3, 3).transpose(0, 2, 1)
    np.testing.assert_allclose(matrices, scipy_rotation(q).as_matrix(), atol=ROUND_OFF)


def test_casadi_error_is_doubled_vector_of_scipy_error_rotation(rng: np.random.Generator) -> None:
    reference, q = random_quaternions(rng), random_quaternions(rng)
    error = scipy_quaternion(scipy_rotation(reference).inv() * scipy_rotation(q))
    # Short way round: the vector part of the error quaternion with scalar part >= 0.
    expected = 2.0 * np.sign(error[:, :1]) * error[:, 1:]
    np.testing.assert_allclose(casadi_rows(ERROR, reference, q), expected, atol=ROUND_OFF)
    # Its direction and size: those of scipy's short-way rotation vector.
    rotation_vector = (scipy_rotation(reference).inv() * scipy_rotation(q)).as_rotvec()
    angle = np.linalg.norm(rotation_vector, axis=1, keepdims=True)
    np.testing.assert_allclose(
        casadi_rows(ERROR, reference, q),
        2.0 * np.sin(angle / 2.0) * rotation_vector / angle,
        atol=ROUND_OFF,
    )


# -- the numeric side against the CasADi side ----------------------------------------------


def test_numeric_product_and_error_match_casadi(rng: np.random.Generator) -> None:
    a, b = random_quaternions(rng), random_quaternions(rng)
    np.testing.assert_allclose(
        quaternion_multiply(a, b), casadi_rows(PRODUCT, a, b), atol=ROUND_OFF
    )
    np.testing.assert_allclose(attitude_error(a, b), casadi_rows(ERROR, a, b), atol=ROUND_OFF)
    np.testing.assert_allclose(
        error_quaternion(a, b), casadi_rows(PRODUCT, casadi_rows(CONJUGATE, a), b), atol=ROUND_OFF
    )


def test_numeric_functions_broadcast_over_leading_axes(rng: np.random.Generator) -> None:
    a = random_quaternions(rng, 6).reshape(2, 3, 4)
    b = random_quaternions(rng, 1)[0]
    product = quaternion_multiply(a, b)
    assert product.shape == (2, 3, 4)
    np.testing.assert_allclose(product[1, 2], quaternion_multiply(a[1, 2], b), atol=0.0)
    assert attitude_error(b, a).shape == (2, 3, 3)
    assert euler_angles_321(a).shape == (2, 3, 3)
    assert quaternion_multiply(b, b).shape == (4,)


def test_conversion_is_scalar_first() -> None:
    half = math.radians(30.0)
    q = np.array([math.cos(half), 0.0, 0.0, math.sin(half)])  # 60 deg about z
    rotation = quaternion_to_rotation(q)
    np.testing.assert_allclose(rotation.as_rotvec(), [0.0, 0.0, math.radians(60.0)], atol=1e-15)
    np.testing.assert_array_equal(rotation_to_quaternion(rotation), q)


# -- algebra --------------------------------------------------------------------------------


def test_composition_is_associative(rng: np.random.Generator) -> None:
    a, b, c = (random_quaternions(rng) for _ in range(3))
    np.testing.assert_allclose(
        quaternion_multiply(quaternion_multiply(a, b), c),
        quaternion_multiply(a, quaternion_multiply(b, c)),
        atol=ROUND_OFF,
    )
    np.testing.assert_allclose(
        casadi_rows(PRODUCT, casadi_rows(PRODUCT, a, b), c),
        casadi_rows(PRODUCT, a, casadi_rows(PRODUCT, b, c)),
        atol=ROUND_OFF,
    )


def test_conjugate_undoes_the_rotation(rng: np.random.Generator) -> None:
    q = random_quaternions(rng)
    identity = np.tile([1.0, 0.0, 0.0, 0.0], (N_RANDOM, 1))
    np.testing.assert_allclose(
        casadi_rows(PRODUCT, casadi_rows(CONJUGATE, q), q), identity, atol=ROUND_OFF
    )
    np.testing.assert_allclose(error_quaternion(q, q), identity, atol=ROUND_OFF)


# -- axis and angle -------------------------------------------------------------------------


def test_axis_angle_round_trip(rng: np.random.Generator) -> None:
    axis = rng.normal(size=(N_RANDOM, 3))
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    angle = rng.uniform(1e-3, math.pi, N_RANDOM)
    q = axis_angle_quaternion(axis, angle)
    np.testing.assert_allclose(q[:, 0], np.cos(angle / 2), atol=ROUND_OFF)
    np.testing.assert_allclose(q[:, 1:], np.sin(angle / 2)[:, None] * axis, atol=ROUND_OFF)
    back_axis, back_angle = quaternion_axis_angle(q)
    np.testing.assert_allclose(back_angle, angle, rtol=1e-13)
    np.testing.assert_allclose(back_axis, axis, atol=1e-12)
    # The other way round is the short way about the opposite axis; -q is the same rotation.
    back_axis, back_angle = quaternion_axis_angle(-axis_angle_quaternion(axis, 2 * math.pi - angle))
    np.testing.assert_allclose(back_angle, angle, rtol=1e-12)
    np.testing.assert_allclose(back_axis, -axis, atol=1e-11)


def test_axis_of_no_rotation_is_zero() -> None:
    axis, angle = quaternion_axis_angle([1.0, 0.0, 0.0, 0.0])
    np.testing.assert_array_equal(axis, np.zeros(3))
    assert angle == 0.0


# -- the attitude error ---------------------------------------------------------------------


def test_error_is_the_small_angle_euler_error(rng: np.random.Generator) -> None:
    """q = q_ref (x) Rz(psi) Ry(theta) Rx(phi) with small angles: e = [phi, theta, psi]
    to second order in the angles."""
    size = 1e-4
    for reference in random_quaternions(rng, 20):
        angles = rng.uniform(-size, size, 3)
        turn = quaternion_multiply(
            quaternion_multiply(
                axis_angle_quaternion([0.0, 0.0, 1.0], angles[2]),
                axis_angle_quaternion([0.0, 1.0, 0.0], angles[1]),
            ),
            axis_angle_quaternion([1.0, 0.0, 0.0], angles[0]),
        )
        q = quaternion_multiply(reference, turn)
        for sign in (1.0, -1.0):  # q and -q: the same attitude, the same error
            numeric = attitude_error(reference, sign * q)
            symbolic = casadi_rows(ERROR, reference[None], sign * q[None])[0]
            np.testing.assert_allclose(numeric, angles, rtol=0, atol=size**2)
            np.testing.assert_allclose(symbolic, angles, rtol=0, atol=size**2)
            np.testing.assert_allclose(euler_angles_321(turn), angles, rtol=1e-8, atol=1e-15)


@pytest.mark.parametrize("degrees", [179.0, 180.0 - 1e-6, 180.0 + 1e-6, 181.0, 200.0])
def test_error_takes_the_short_way_round(degrees: float) -> None:
    """Past 180 deg about +z the error points about -z: the short way, of size 2 sin(short / 2)."""
    reference = axis_angle_quaternion([0.6, 0.0, 0.8], 0.7)
    angle = math.radians(degrees)
    q = quaternion_multiply(reference, axis_angle_quaternion([0.0, 0.0, 1.0], angle))
    short = angle if angle <= math.pi else angle - 2.0 * math.pi
    expected = [0.0, 0.0, 2.0 * math.sin(short / 2.0)]
    for sign in (1.0, -1.0):
        np.testing.assert_allclose(attitude_error(reference, sign * q), expected, atol=1e-13)
        np.testing.assert_allclose(
            casadi_rows(ERROR, reference[None], sign * q[None])[0], expected, atol=1e-13
        )


def test_half_turn_error_is_well_defined() -> None:
    half_turn = np.array([0.0, 0.0, 0.0, 1.0])
    identity = np.array([1.0, 0.0, 0.0, 0.0])
    np.testing.assert_array_equal(attitude_error(identity, half_turn), [0.0, 0.0, 2.0])
    np.testing.assert_array_equal(casadi_rows(ERROR, identity[None], half_turn[None])[0], [0, 0, 2])


# -- Euler angles ---------------------------------------------------------------------------


def test_euler_angles_321_recover_the_sequence(rng: np.random.Generator) -> None:
    """Rz(psi) Ry(theta) Rx(phi) from elementary matrices, back to [phi, theta, psi]."""
    for _ in range(50):
        phi, psi = rng.uniform(-math.pi, math.pi, 2)
        theta = rng.uniform(-math.pi / 2, math.pi / 2)
        matrix = elementary(2, psi) @ elementary(1, theta) @ elementary(0, phi)
        q = scipy_quaternion(Rotation.from_matrix(matrix))
        # The module's direction cosine matrix is the same rotation.
        np.testing.assert_allclose(np.array(MATRIX(q)), matrix, atol=ROUND_OFF)
        np.testing.assert_allclose(euler_angles_321(q), [phi, theta, psi], atol=1e-12)
        np.testing.assert_allclose(euler_angles_321(-q), [phi, theta, psi], atol=1e-12)


def test_euler_angles_of_a_slightly_non_unit_quaternion_are_its_rotations() -> None:
    q = axis_angle_quaternion([0.0, 0.0, 1.0], 0.5)
    np.testing.assert_allclose(euler_angles_321(q * (1 + 1e-7)), [0.0, 0.0, 0.5], atol=1e-15)


def test_euler_angles_at_gimbal_lock_without_warning() -> None:
    q = quaternion_multiply(
        axis_angle_quaternion([0.0, 0.0, 1.0], 0.4),
        axis_angle_quaternion([0.0, 1.0, 0.0], math.pi / 2),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        angles = euler_angles_321(q)
    np.testing.assert_allclose(angles, [0.0, math.pi / 2, 0.4], atol=1e-7)


# -- kinematics -----------------------------------------------------------------------------


def test_quaternion_rate_is_the_derivative_about_a_fixed_axis(rng: np.random.Generator) -> None:
    start = random_quaternions(rng, 1)[0]
    axis = np.array([2.0, -1.0, 2.0]) / 3.0
    rate = 0.3  # rad/s
    times = np.array([1.0, 2.0, 5.0])
    q = quaternion_multiply(start, axis_angle_quaternion(axis, rate * times))
    # d/dt of q0 (x) [cos(w t / 2), sin(w t / 2) e], in closed form.
    derivative = quaternion_multiply(start, axis_angle_quaternion(axis, rate * times + math.pi))
    np.testing.assert_allclose(
        quaternion_rate(q, rate * axis), 0.5 * rate * derivative, atol=ROUND_OFF
    )
    pure = np.concatenate([[0.0], rate * axis])
    np.testing.assert_allclose(
        quaternion_rate(q, rate * axis),
        0.5 * casadi_rows(PRODUCT, q, np.tile(pure, (3, 1))),
        atol=ROUND_OFF,
    )


# -- bad input ------------------------------------------------------------------------------


def test_product_refuses_a_rate_quaternion() -> None:
    with pytest.raises(InputShapeError, match="quaternion_rate"):
        quaternion_multiply([1.0, 0.0, 0.0, 0.0], [0.0, 0.1, 0.0, 0.0])


@pytest.mark.parametrize(
    "call",
    [
        lambda: quaternion_multiply([1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]),
        lambda: attitude_error([1.0, 0.0, 0.0, 0.0], [np.nan, 0.0, 0.0, 1.0]),
        lambda: euler_angles_321([0.0, 0.0, 0.0, 0.0]),
        lambda: quaternion_rate([1.0, 0.0, 0.0, 0.0], [0.1, 0.0]),
    ],
)
def test_bad_quaternions_are_refused(call) -> None:
    with pytest.raises(InputShapeError):
        call()
