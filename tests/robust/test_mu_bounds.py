"""Mixed real/complex mu: both bounds against cases with a known answer."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from casadi_debris.errors import SynthesisError
from casadi_debris.robust import mu_bounds
from casadi_debris.robust.mu import block_structure

MIXED = (
    [("real", 1), ("real", 1), ("complex", 2)],
    [("real", 1), ("complex", 1), ("complex", 2)],
    [("real", 2), ("complex", 1)],
    [("complex", 1), ("complex", 1), ("complex", 1)],
)


def _random(rng, n, count=1):
    return rng.normal(size=(count, n, n)) + 1j * rng.normal(size=(count, n, n))


def _assert_destabilising(bounds, responses, blocks):
    structure = block_structure(blocks)
    for matrix, lower, delta in zip(responses, bounds.lower, bounds.perturbation, strict=True):
        assert lower > 0
        n = len(matrix)
        assert np.linalg.norm(delta, 2) == pytest.approx(1 / lower, rel=1e-9)
        assert abs(np.linalg.det(np.eye(n) - matrix @ delta)) < 1e-8 * max(1.0, lower) ** n
        start = 0
        for block in structure:
            part = slice(start, start + block.size)
            outside = delta[part].copy()
            outside[:, part] = 0
            assert np.allclose(outside, 0)
            if block.kind == "real":
                value = delta[start, start]
                assert abs(value.imag) < 1e-12 * abs(value)
                assert np.allclose(delta[part, part], value * np.eye(block.size))
            start += block.size


def test_one_full_complex_block_is_max_singular_value():
    m = _random(np.random.default_rng(1), 4, 5)
    bounds = mu_bounds(m, [("complex", 4)])
    sigma = np.linalg.norm(m, 2, axis=(1, 2))
    np.testing.assert_allclose(bounds.upper, sigma, rtol=1e-10)
    np.testing.assert_allclose(bounds.lower, sigma, rtol=1e-8)
    _assert_destabilising(bounds, m, [("complex", 4)])


def test_rank_one_complex_scalars_closed_form():
    # M = a b^H over complex scalar blocks: mu = sum_i |a_i b_i| (Packard and Doyle 1993).
    rng = np.random.default_rng(2)
    for _ in range(4):
        a, b = _random(rng, 5)[0][:2]
        m = np.outer(a, b.conj())
        exact = float(np.sum(np.abs(a * b)))
        bounds = mu_bounds(m, [("complex", 1)] * 5)
        assert bounds.upper[0] == pytest.approx(exact, rel=1e-5)
        assert bounds.lower[0] == pytest.approx(exact, rel=1e-8)


def _brute_force_real(m, k, points=41):
    """max rho_R(M diag(delta)) over a grid of [-1, 1]^k (real M: real eigenvalues are generic)."""
    best = 0.0
    for delta in itertools.product(np.linspace(-1, 1, points), repeat=k):
        values = np.linalg.eigvals(m * np.array(delta)[None, :])
        real = np.abs(values.imag) <= 1e-9 * np.maximum(np.abs(values), 1e-300)
        if np.any(real):
            best = max(best, float(np.max(np.abs(values[real]))))
    return best


@pytest.mark.parametrize("seed", range(4))
def test_real_scalars_against_brute_force(seed):
    rng = np.random.default_rng(10 + seed)
    k = 2 + seed % 2
    m = rng.normal(size=(k, k))
    brute = _brute_force_real(m, k, points=41 if k == 2 else 21)
    bounds = mu_bounds(m, [("real", 1)] * k)
    assert brute <= bounds.upper[0] * (1 + 1e-6)
    assert bounds.lower[0] <= bounds.upper[0] * (1 + 1e-6)
    # The grid is a lower bound as well; the search must reach it to the grid's resolution.
    assert bounds.lower[0] >= brute * (1 - 2e-2)
    _assert_destabilising(bounds, m[None], [("real", 1)] * k)


@pytest.mark.parametrize("blocks", MIXED)
def test_lower_below_upper_on_mixed_structures(blocks):
    n = sum(size for _, size in blocks)
    m = _random(np.random.default_rng(20 + n), n, 6)
    bounds = mu_bounds(m, blocks)
    assert np.all(bounds.lower <= bounds.upper * (1 + 1e-6))
    assert np.all(bounds.upper <= np.linalg.norm(m, 2, axis=(1, 2)) * (1 + 1e-9))
    positive = bounds.lower > 0
    _assert_destabilising(
        type(bounds)(
            bounds.upper[positive],
            bounds.lower[positive],
            bounds.perturbation[positive],
            bounds.upper_method,
        ),
        m[positive],
        blocks,
    )
    assert 0.0 <= bounds.gap < 1.0


def test_ab13md_is_the_dg_lmi_bound():
    pytest.importorskip("cvxpy", reason="the LMI cross-check needs cvxpy (pip install '.[lmi]')")
    rng = np.random.default_rng(30)
    blocks = [("real", 1), ("real", 1), ("complex", 2)]
    m = _random(rng, 4, 3)
    ab13md = mu_bounds(m, blocks, upper="ab13md")
    lmi = mu_bounds(m, blocks, upper="lmi")
    assert lmi.upper_method == "lmi"
    np.testing.assert_allclose(ab13md.upper, lmi.upper, rtol=5e-5)


def test_repeated_real_scalar_uses_full_scalings():
    pytest.importorskip("cvxpy", reason="the LMI bound needs cvxpy (pip install '.[lmi]')")
    m = _random(np.random.default_rng(0), 3, 3)
    blocks = [("real", 2), ("complex", 1)]
    auto = mu_bounds(m, blocks)
    independent = mu_bounds(m, blocks, upper="ab13md")
    assert auto.upper_method == "lmi"
    assert np.all(auto.upper <= independent.upper * (1 + 1e-5))
    assert np.all(auto.lower <= auto.upper * (1 + 1e-6))


def test_single_matrix_and_bad_shapes():
    m = _random(np.random.default_rng(5), 3)[0]
    assert mu_bounds(m, [3]).upper.shape == (1,)
    with pytest.raises(SynthesisError, match="shape"):
        mu_bounds(m, [2])
    with pytest.raises(SynthesisError, match="finite"):
        mu_bounds(np.full((3, 3), np.nan), [3])
    with pytest.raises(SynthesisError, match="upper"):
        mu_bounds(m, [3], upper="bogus")  # type: ignore[arg-type]
