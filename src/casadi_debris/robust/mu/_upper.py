"""Structured singular value: upper bound on a frequency grid.

For a structure of full complex blocks, mu(M) <= inf_D sigma_max(D M D^-1)
with D = diag(d_i I) commuting with the structure. The bound is computed by
SLICOT AB13MD (Fan, Tits and Doyle 1991), which also takes real scalar
blocks (with G scalings); for at most three full complex blocks it equals mu
(Doyle 1982), so for the design's {uncertainty, performance} structure it is
exact.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import slycot
from slycot.exceptions import SlycotError

from casadi_debris.errors import SynthesisError
from casadi_debris.robust.mu._blocks import BlockLike, block_structure, expanded


@dataclass(frozen=True, eq=False)
class MuBound:
    """Upper bound of mu per frequency and the D-scales that achieve it.

    Attributes
    ----------
    mu : ndarray, shape (n_omega,)
    scales : ndarray, shape (n_omega, n_scalar_blocks)
        Positive scale d_b of each block (a repeated real scalar counts as
        ``size`` blocks), normalised so the last block's is 1. With real
        blocks these are the scales of the purely complex bound, the ones a
        D-K iteration fits.
    """

    mu: np.ndarray
    scales: np.ndarray

    @property
    def peak(self) -> float:
        """Peak of the bound over the grid."""
        return float(np.max(self.mu))


def _bound(matrix: np.ndarray, sizes: np.ndarray, types: np.ndarray) -> tuple[float, np.ndarray]:
    """AB13MD's bound of one matrix and its D, one scale per block."""
    try:
        bound, d, _, _ = slycot.ab13md(np.asarray(matrix, dtype=complex), sizes, types)
    except SlycotError as error:
        raise SynthesisError(f"mu upper bound (SLICOT AB13MD) failed: {error}") from error
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    block_d = np.asarray(d)[starts]
    return float(bound), block_d / block_d[-1]


def mu_upper_bound(responses: np.ndarray, blocks: Sequence[BlockLike]) -> MuBound:
    """mu upper bound of M(jw) for a structure of full complex and real scalar blocks.

    Parameters
    ----------
    responses : ndarray, shape (n_omega, n, n)
        Closed-loop frequency response, inputs and outputs ordered as ``blocks``.
    blocks : sequence
        Sizes of full complex blocks (sum n), or blocks as
        :func:`casadi_debris.robust.mu.block_structure` takes them,
        e.g. ``[("real", 1), ("complex", 2)]``.

    Returns
    -------
    MuBound

    Examples
    --------
    >>> import numpy as np
    >>> m = np.array([[[1.0, 2.0], [0.0, 1.0]]])
    >>> round(mu_upper_bound(m, [1, 1]).peak, 6)  # diagonal scaling removes the coupling
    1.0
    """
    structure = block_structure(blocks)
    sizes, types = expanded(structure)
    n = int(sizes.sum())
    if responses.ndim != 3 or responses.shape[1:] != (n, n):
        raise SynthesisError(
            f"mu needs responses of shape (n_omega, {n}, {n}), got {responses.shape}"
        )
    complex_types = np.full(len(sizes), 2, dtype=int)
    has_real = bool(np.any(types == 1))
    mu = np.empty(len(responses))
    scales = np.ones((len(responses), len(sizes)))
    for k, matrix in enumerate(responses):
        if not np.all(np.isfinite(matrix)):
            raise SynthesisError("closed-loop response is not finite (unstable or singular)")
        if len(sizes) == 1 and not has_real:
            mu[k] = np.linalg.norm(matrix, 2)
            continue
        mu[k], scales[k] = _bound(matrix, sizes, complex_types)
        if has_real:
            mu[k] = min(mu[k], _bound(matrix, sizes, types)[0])
    return MuBound(mu, scales)


def scaled_norm(matrix: np.ndarray, blocks: Sequence[int], scales: Sequence[float]) -> float:
    """sigma_max(D M D^-1) for D = diag(scales_b I_b).

    Parameters
    ----------
    matrix : ndarray, shape (n, n)
    blocks : sequence of int
        Block sizes (sum n).
    scales : sequence of float
        One positive scale per block.

    Returns
    -------
    float
    """
    d = np.repeat(np.asarray(scales, dtype=float), blocks)
    return float(np.linalg.norm(d[:, None] * matrix / d[None, :], 2))
