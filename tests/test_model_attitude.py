"""The attitude module's CasADi functions checked against scipy's Rotation."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from casadi_debris.model.attitude import (
    attitude_error_vector,
    quaternion_conjugate,
    quaternion_product,
    rotation_matrix,
)

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


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20240611)


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


def test_casadi_composition_is_associative(rng: np.random.Generator) -> None:
    a, b, c = (random_quaternions(rng) for _ in range(3))
    np.testing.assert_allclose(
        casadi_rows(PRODUCT, casadi_rows(PRODUCT, a, b), c),
        casadi_rows(PRODUCT, a, casadi_rows(PRODUCT, b, c)),
        atol=ROUND_OFF,
    )
