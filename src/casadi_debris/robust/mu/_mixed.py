"""Mixed real/complex mu analysis with an upper and a lower bound per frequency.

The upper bound is the D-G scaling bound of Fan, Tits and Doyle (1991),
mu(M) <= beta if M^H D M + j (G M - M^H G) - beta^2 D <= 0 for some D > 0
commuting with the structure and Hermitian G on its real blocks. SLICOT AB13MD
computes it for full complex blocks and real scalars; on random mixed matrices
it agrees with the LMI solved by cvxpy and Clarabel (:mod:`.mu_lmi`) to 1e-5
and is about 100 times faster, so it is the default. A repeated real scalar
delta I_k needs full k x k D and G blocks, which AB13MD lacks (it bounds k
independent scalars, a larger set); structures with one use the LMI when cvxpy
is installed.

The lower bound is the best destabilising perturbation a local search finds
(:mod:`.mu_lower`); the bound is evaluated from that perturbation, so it holds
whatever the search does, and the perturbation comes with it.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from casadi_debris.errors import SynthesisError
from casadi_debris.robust.mu._blocks import BlockLike, block_structure, total_size
from casadi_debris.robust.mu._lmi import lmi_upper_bound
from casadi_debris.robust.mu._lower import lower_bound
from casadi_debris.robust.mu._upper import mu_upper_bound

_log = logging.getLogger(__name__)

UpperMethod = Literal["auto", "ab13md", "lmi"]


class PeakBounds:
    """The peaks of an upper and a lower bound of mu over a grid, and their gap."""

    upper: np.ndarray
    lower: np.ndarray

    @property
    def peak_upper(self) -> float:
        """Peak of the upper bound."""
        return float(np.max(self.upper))

    @property
    def peak_lower(self) -> float:
        """Peak of the lower bound: no smaller mu is possible anywhere."""
        return float(np.max(self.lower))

    @property
    def gap(self) -> float:
        """Relative gap of the peaks, (peak_upper - peak_lower) / peak_upper."""
        return (self.peak_upper - self.peak_lower) / self.peak_upper if self.peak_upper else 0.0


@dataclass(frozen=True, eq=False)
class MuBounds(PeakBounds):
    """Upper and lower bounds of mu per frequency, and the worst perturbations.

    Attributes
    ----------
    upper : ndarray, shape (n_omega,)
        D-G scaling upper bound.
    lower : ndarray, shape (n_omega,)
        Lower bound (0 where the search found no destabilising perturbation).
    perturbation : ndarray, shape (n_omega, n, n), complex
        Block-diagonal Delta in the structure with sigma_max(Delta) = 1/lower
        and det(I - M Delta) = 0 (zeros where ``lower`` is 0).
    upper_method : str
        "ab13md" or "lmi": what computed ``upper``.
    """

    upper: np.ndarray
    lower: np.ndarray
    perturbation: np.ndarray
    upper_method: str

    @property
    def peak_index(self) -> int:
        """Index of the frequency where the upper bound peaks."""
        return int(np.argmax(self.upper))


def _upper(
    responses: np.ndarray, blocks: Sequence[BlockLike], method: UpperMethod, lower: np.ndarray
) -> tuple[np.ndarray, str]:
    structure = block_structure(blocks)
    repeated_real = any(b.kind == "real" and b.size > 1 for b in structure)
    if method == "auto":
        method = "lmi" if repeated_real else "ab13md"
        if method == "lmi":
            try:
                import cvxpy  # noqa: F401
            except ImportError:
                _log.info("cvxpy missing: repeated real scalars bounded as independent ones")
                method = "ab13md"
    if method == "ab13md":
        return mu_upper_bound(responses, structure).mu, method
    if method != "lmi":
        raise SynthesisError(f"upper: 'auto', 'ab13md' or 'lmi', got {method!r}")
    bound = np.array(
        [lmi_upper_bound(m, structure, low) for m, low in zip(responses, lower, strict=True)]
    )
    return bound, method


def mu_bounds(
    responses: np.ndarray,
    blocks: Sequence[BlockLike],
    *,
    upper: UpperMethod = "auto",
    restarts: int = 2,
    seed: int = 0,
) -> MuBounds:
    """Upper and lower bounds of the mixed real/complex structured singular value.

    Parameters
    ----------
    responses : ndarray, shape (n, n) or (n_omega, n, n)
        One complex matrix or one per frequency (frequencies first), inputs and
        outputs ordered as ``blocks``.
    blocks : sequence
        ``("complex", k)`` full complex k x k blocks, ``("real", k)`` real
        scalars repeated k times, or bare sizes (full complex).
    upper : {"auto", "ab13md", "lmi"}
        Upper-bound method: SLICOT AB13MD, or the D-G LMI (cvxpy and
        Clarabel, ``pip install 'casadi_debris[lmi]'``); "auto" takes AB13MD
        unless a real scalar is repeated.
    restarts : int
        Seeded random starts of the lower-bound search per frequency, besides
        the identity and the previous frequency's perturbation.
    seed : int

    Returns
    -------
    MuBounds
        With a single matrix, arrays of length 1.

    Raises
    ------
    SynthesisError
        Shapes that do not match the structure, a response that is not finite,
        or ``upper="lmi"`` without cvxpy.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.array([[0.5, 2.0], [0.0, 0.5]])
    >>> b = mu_bounds(m, [("real", 1), ("real", 1)])
    >>> round(b.peak_lower, 6), round(b.peak_upper, 6)
    (0.5, 0.5)
    """
    structure = block_structure(blocks)
    n = total_size(structure)
    stack = np.asarray(responses, dtype=complex)
    if stack.ndim == 2:
        stack = stack[None]
    if stack.ndim != 3 or stack.shape[1:] != (n, n):
        raise SynthesisError(
            f"mu_bounds needs shape (n_omega, {n}, {n}) or ({n}, {n}), got {np.shape(responses)}"
        )
    if not np.all(np.isfinite(stack)):
        raise SynthesisError("mu_bounds: a response is not finite")
    lower = np.zeros(len(stack))
    perturbation = np.zeros_like(stack)
    warm: np.ndarray | None = None
    for k, matrix in enumerate(stack):
        lower[k], perturbation[k] = lower_bound(
            matrix, structure, restarts=restarts, seed=seed + k, warm=warm
        )
        warm = perturbation[k] if lower[k] > 0 else None
    upper_bound, method = _upper(stack, structure, upper, lower)
    return MuBounds(upper_bound, lower, perturbation, method)
