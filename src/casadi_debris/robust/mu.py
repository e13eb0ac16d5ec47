"""Structured singular value: upper bound on a frequency grid.

For a structure of full complex blocks, mu(M) <= inf_D sigma_max(D M D^-1)
with D = diag(d_i I) commuting with the structure. The bound is computed by
SLICOT AB13MD (Fan, Tits and Doyle 1991); for at most three full blocks it
equals mu (Doyle 1982), so for the design's {uncertainty, performance}
structure it is exact.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import slycot

from casadi_debris.errors import SynthesisError


@dataclass(frozen=True, eq=False)
class MuBound:
    """Upper bound of mu per frequency and the D-scales that achieve it.

    Attributes
    ----------
    mu : ndarray, shape (n_omega,)
    scales : ndarray, shape (n_omega, n_blocks)
        Positive scale d_b of each block, normalised so the last block's is 1.
    """

    mu: np.ndarray
    scales: np.ndarray

    @property
    def peak(self) -> float:
        return float(np.max(self.mu))


def mu_upper_bound(responses: np.ndarray, blocks: Sequence[int]) -> MuBound:
    """mu upper bound of M(jw) for square full complex blocks.

    Parameters
    ----------
    responses : ndarray, shape (n_omega, n, n)
        Closed-loop frequency response, inputs and outputs ordered as ``blocks``.
    blocks : sequence of int
        Sizes of the full complex blocks (sum n).

    Returns
    -------
    MuBound
    """
    sizes = np.asarray(blocks, dtype=int)
    n = int(sizes.sum())
    if responses.ndim != 3 or responses.shape[1:] != (n, n):
        raise SynthesisError(
            f"mu needs responses of shape (n_omega, {n}, {n}), got {responses.shape}"
        )
    types = np.full(len(sizes), 2, dtype=int)
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    mu = np.empty(len(responses))
    scales = np.ones((len(responses), len(sizes)))
    for k, matrix in enumerate(responses):
        if not np.all(np.isfinite(matrix)):
            raise SynthesisError("closed-loop response is not finite (unstable or singular)")
        if len(sizes) == 1:
            mu[k] = np.linalg.norm(matrix, 2)
            continue
        bound, d, _, _ = slycot.ab13md(np.asarray(matrix, dtype=complex), sizes, types)
        mu[k] = bound
        block_d = d[starts]
        scales[k] = block_d / block_d[-1]
    return MuBound(mu, scales)


def scaled_norm(matrix: np.ndarray, blocks: Sequence[int], scales: Sequence[float]) -> float:
    """sigma_max(D M D^-1) for D = diag(scales_b I_b)."""
    d = np.repeat(np.asarray(scales, dtype=float), blocks)
    return float(np.linalg.norm(d[:, None] * matrix / d[None, :], 2))
