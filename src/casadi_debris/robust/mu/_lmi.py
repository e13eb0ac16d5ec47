"""Mixed mu upper bound with D and G scalings as a linear matrix inequality.

Fan, Tits and Doyle (1991); Young, Newlin and Doyle (1995): for a structure of
real scalar blocks delta_i I_k and full complex blocks,

    mu(M) <= beta  if there are D > 0 and G = G^H with
    M^H D M + j (G M - M^H G) - beta^2 D <= 0,

D commuting with the structure (a full Hermitian k x k block for a repeated
real scalar, d I for a full complex block) and G nonzero only on the real
blocks (a full Hermitian k x k block each). The least such beta is found by
bisection, each step one semidefinite programme (cvxpy with Clarabel).

This is the bound SLICOT AB13MD computes for scalar real blocks; it is kept as
an independent check of AB13MD and for repeated real scalars, which AB13MD
can only bound as independent scalars.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np

from casadi_debris.errors import SynthesisError
from casadi_debris.robust.mu._blocks import Block

# Each feasibility problem is made compact: D is normalised to trace n (the LMI
# is homogeneous in (D, G)), G is bounded, and the margin lambda only needs its
# sign. With M normalised to sigma_max(M) = 1, a G beyond this bound would only
# matter for bounds far below sigma_max; such a bound is reported looser.
_G_CAP = 1e3
_D_FLOOR = 1e-7


def _import_cvxpy() -> Any:
    try:
        import cvxpy
    except ImportError as exc:
        raise SynthesisError(
            "the LMI mu bound needs cvxpy and clarabel: pip install 'casadi_debris[lmi]' "
            "(or pip install cvxpy clarabel)"
        ) from exc
    if "CLARABEL" not in cvxpy.installed_solvers():
        raise SynthesisError("the LMI mu bound needs the Clarabel solver: pip install clarabel")
    return cvxpy


def _selector(start: int, size: int, n: int) -> np.ndarray:
    """E (n x size) with E^T x the block's part of x."""
    selector = np.zeros((n, size))
    selector[start + np.arange(size), np.arange(size)] = 1.0
    return selector


class _Feasibility:
    """The LMI at a given beta^2 as one parametrised cvxpy problem (compiled once)."""

    def __init__(self, matrix: np.ndarray, structure: Sequence[Block]) -> None:
        cp = _import_cvxpy()
        n = matrix.shape[0]
        self.beta2 = cp.Parameter(nonneg=True)
        d_terms, g_terms, constraints = [], [], []
        start = 0
        for block in structure:
            e = _selector(start, block.size, n)
            if block.kind == "complex":
                d = cp.Variable()
                d_terms.append(d * (e @ e.T))
                constraints.append(d >= _D_FLOOR)
            else:
                d_block = cp.Variable((block.size, block.size), hermitian=True)
                g_block = cp.Variable((block.size, block.size), hermitian=True)
                d_terms.append(e @ d_block @ e.T)
                g_terms.append(e @ g_block @ e.T)
                eye = np.eye(block.size)
                constraints.append(d_block >> _D_FLOOR * eye)
                constraints += [g_block << _G_CAP * eye, g_block >> -_G_CAP * eye]
            start += block.size
        d_matrix = cp.sum(d_terms) if len(d_terms) > 1 else d_terms[0]
        lam = cp.Variable()
        constraints += [cp.real(cp.trace(d_matrix)) == n, lam >= -1.0]
        m = cp.Constant(matrix)
        lmi = m.H @ d_matrix @ m - self.beta2 * d_matrix - lam * np.eye(n)
        g_matrix = (cp.sum(g_terms) if len(g_terms) > 1 else g_terms[0]) if g_terms else None
        if g_matrix is not None:
            lmi = lmi + 1j * (g_matrix @ m - m.H @ g_matrix)
        constraints.append((lmi + lmi.H) / 2 << 0)
        self.lam = lam
        self.matrix = matrix
        self.d_matrix = d_matrix
        self.g_matrix = g_matrix
        self.problem = cp.Problem(cp.Minimize(lam), constraints)
        self.solver = cp.CLARABEL
        self.solver_error = cp.error.SolverError

    def feasible(self, beta: float) -> bool:
        """Whether the LMI holds at ``beta`` (the least margin lambda is <= 0)."""
        self.beta2.value = beta**2
        try:
            with warnings.catch_warnings():
                # Inaccurate solves are judged by _verified, not by the solver's word.
                warnings.simplefilter("ignore", UserWarning)
                self.problem.solve(solver=self.solver)
        except self.solver_error:
            return False  # counted as infeasible: the bound only moves on a solved step
        if self.lam.value is None or self.d_matrix.value is None:
            return False
        return self._verified(beta)

    def _verified(self, beta: float) -> bool:
        """Check the solver's D and G in numpy: D > 0 and the LMI <= 0 at ``beta``.

        The solver's status is not trusted either way ("optimal_inaccurate" is
        common near the optimum); a step counts as feasible only when its
        scalings satisfy the inequality as computed here.
        """
        m = self.matrix
        d = np.asarray(self.d_matrix.value, dtype=complex)
        d = (d + d.conj().T) / 2
        lmi = m.conj().T @ d @ m - beta**2 * d
        if self.g_matrix is not None:
            g = np.asarray(self.g_matrix.value, dtype=complex)
            g = (g + g.conj().T) / 2
            lmi = lmi + 1j * (g @ m - m.conj().T @ g)
        lmi = (lmi + lmi.conj().T) / 2
        return bool(
            np.linalg.eigvalsh(d)[0] > 0 and np.linalg.eigvalsh(lmi)[-1] <= 1e-12 * np.trace(d).real
        )


def lmi_upper_bound(
    matrix: np.ndarray, structure: Sequence[Block], low: float = 0.0, rtol: float = 1e-5
) -> float:
    """Least beta of the D-G LMI for one matrix, by bisection.

    Parameters
    ----------
    matrix : ndarray, shape (n, n)
        Complex, inputs and outputs ordered as ``structure``.
    structure : sequence of Block
    low : float
        A known lower bound of mu (the bisection starts there).
    rtol : float
        Relative width of the final bracket.

    Returns
    -------
    float
        The upper end of the final bracket (a certified bound up to the solver's
        tolerance).

    Raises
    ------
    SynthesisError
        cvxpy or Clarabel missing, or a solve failed.
    """
    norm = float(np.linalg.norm(matrix, 2))
    if norm == 0.0:
        return 0.0
    feasibility = _Feasibility(np.asarray(matrix, dtype=complex) / norm, structure)
    lo, hi = max(0.0, min(low / norm, 1.0)) * (1 - rtol), 1.0
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        if feasibility.feasible(mid):
            hi = mid
        else:
            lo = mid
    return hi * norm
