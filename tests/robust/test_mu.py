"""mu upper bound against cases where mu is known exactly."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from casadi_debris.errors import SynthesisError
from casadi_debris.robust.mu import mu_upper_bound, scaled_norm


def _random(rng, n, count):
    return rng.normal(size=(count, n, n)) + 1j * rng.normal(size=(count, n, n))


def test_single_full_block_is_max_singular_value():
    m = _random(np.random.default_rng(1), 4, 5)
    bound = mu_upper_bound(m, [4])
    np.testing.assert_allclose(bound.mu, np.linalg.norm(m, 2, axis=(1, 2)), rtol=1e-12)


def test_two_full_blocks_exact_by_scalar_scaling():
    # For two full blocks mu = min_d sigma_max(D M D^-1) (Doyle 1982): a 1-D convex problem.
    m = _random(np.random.default_rng(2), 9, 8)
    bound = mu_upper_bound(m, [3, 6])
    for matrix, mu, scales in zip(m, bound.mu, bound.scales, strict=True):
        best = minimize_scalar(
            lambda x, mat=matrix: scaled_norm(mat, [3, 6], [np.exp(x), 1.0]),
            bounds=(-20, 20),
            method="bounded",
            options={"xatol": 1e-10},
        ).fun
        assert mu == pytest.approx(best, rel=1e-4)
        assert scaled_norm(matrix, [3, 6], scales) == pytest.approx(mu, rel=1e-4)


def test_rank_one_matrix():
    # For M = a b^*, mu over full complex blocks = sum_i |a_i| |b_i| (block-wise norms).
    rng = np.random.default_rng(3)
    blocks = [2, 3, 1]
    for _ in range(5):
        a = rng.normal(size=6) + 1j * rng.normal(size=6)
        b = rng.normal(size=6) + 1j * rng.normal(size=6)
        m = np.outer(a, b.conj())[None]
        edges = np.cumsum([0, *blocks])
        exact = sum(
            np.linalg.norm(a[s:e]) * np.linalg.norm(b[s:e]) for s, e in itertools.pairwise(edges)
        )
        assert mu_upper_bound(m, blocks).mu[0] == pytest.approx(exact, rel=1e-5)


def test_lower_than_unstructured_and_higher_than_spectral_radius():
    m = _random(np.random.default_rng(4), 9, 10)
    mu = mu_upper_bound(m, [3, 6]).mu
    assert np.all(mu <= np.linalg.norm(m, 2, axis=(1, 2)) * (1 + 1e-9))
    assert np.all(mu >= np.max(np.abs(np.linalg.eigvals(m)), axis=1) * (1 - 1e-9))


def test_bad_shapes_rejected():
    with pytest.raises(SynthesisError, match="shape"):
        mu_upper_bound(np.zeros((2, 4, 4)), [3, 6])
    with pytest.raises(SynthesisError, match="not finite"):
        mu_upper_bound(np.full((1, 9, 9), np.nan), [3, 6])
